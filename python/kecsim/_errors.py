"""The exceptions of kecsim (raised by the native module, importable from ``kecsim``)."""


class KecsimError(Exception):
    """Base of kecsim's own errors."""


class ScenarioError(KecsimError, ValueError):
    """The scenario (file or TOML text) or an override is not valid.

    The message names the file (``<string>`` for TOML text), the line and the key.
    """


class BuildError(KecsimError):
    """A valid scenario whose run cannot be built (the contact model, the vehicle, the track's
    extent): the message names the scenario and what to check."""


class Interrupted(KeyboardInterrupt):
    """Ctrl-C during ``kecsim.run``: the run stopped at its next step.

    ``.result`` is the :class:`RunResult` of what it computed up to there
    (``result.interrupted`` is True).
    """

    result = None
