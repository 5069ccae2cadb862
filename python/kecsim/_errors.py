"""The exceptions of kecsim (raised by the native module, importable from ``kecsim``)."""


class KecsimError(Exception):
    """Base of kecsim's own errors."""


class ScenarioError(KecsimError, ValueError):
    """The scenario (file or TOML text) or an override is not valid.

    The message names the file (``<string>`` for TOML text), the line and the key.
    """


class OverrideTypeError(ScenarioError, TypeError):
    """An override whose key or value has no TOML form (bytes, a dict, an object, a key that is
    not a str): a :class:`ScenarioError`, and a ``TypeError`` as before."""


class OutputError(KecsimError, ValueError):
    """A file kecsim was asked to write (``save=``) that it must not or cannot write: a file the
    scene reads (the scenario, a profile, by any name or link), read-only, or being written by
    another run (another process, or another thread of this one). The message names the file,
    and the input or the lock's holder (pid); nothing was written."""


class BuildError(KecsimError):
    """A valid scenario whose run cannot be built (the contact model, the vehicle, the track's
    extent): the message names the scenario and what to check."""


class Interrupted(KeyboardInterrupt):
    """Ctrl-C during ``kecsim.run``: the run stopped at its next step.

    ``.result`` is the :class:`RunResult` of what it computed up to there
    (``result.interrupted`` is True).
    """

    result = None
