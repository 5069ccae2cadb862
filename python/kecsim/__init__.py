"""kecsim: railway vehicle dynamics with the knife-edge-equivalent contact (KEC) method.

A run, a contact sweep and the profiles of a scene, as numpy arrays::

    import kecsim
    r = kecsim.run("scene.toml", {"simulation.speed_m_s": 15.0, "simulation.duration_s": 5.0})
    y = r.wheelsets["ws1"]["y_mm"]          # the CSV's columns, one value per output sample
    print(r.summary["max_abs_y_mm"])         # the keys of `kecsim run --json`

``scene`` is a path (str or os.PathLike) or TOML text; ``overrides`` maps key paths
(``"simulation.speed_m_s"``, array entries by index) to values, as a study's axes do.

Overrides are bounded, and refused with a :class:`ScenarioError` naming the key and the limit: a
key path of at most 256 characters and 16 parts; a value nested at most 32 levels (lists in
lists), of at most 100 000 entries in all, each string at most 4096 characters and all at most
1 000 000; an integer
within 64 bits; at most 1000 overrides. A value with no TOML form (bytes, a dict, an object)
raises a ScenarioError that is also a TypeError. Messages show a long key or value by its
beginning.
"""

from ._errors import BuildError, Interrupted, KecsimError, OutputError, ScenarioError
from ._kecsim import (
    RunResult,
    __version__,
    contact_sweep,
    csv_columns,
    default_scene,
    has_viewer,
    profiles,
)
from ._kecsim import run as _run


def run(scene, overrides=None, **options):
    """Runs a scene as ``kecsim run`` does and returns a :class:`RunResult`.

    Parameters
    ----------
    scene : str or os.PathLike
        A scenario file, or the scenario as TOML text (relative paths in text start from the
        current directory). ``kecsim.default_scene()`` is the one ``kecsim run`` runs.
    overrides : dict, optional
        Key path → value (number, str, bool or a list of them), applied in order:
        ``{"simulation.speed_m_s": 15.0}``. A key the scenario does not take raises
        :class:`ScenarioError` naming it.
    contact : str, optional
        A contact model instead of the scenario's: ``kec``, ``lookup``, ``lookup2``,
        ``online`` or ``elastic``.
    threads : int, optional
        Threads of the run (default: two on a machine with two cores or more); the results are
        the same to the last bit on any number.
    progress : callable, optional
        ``progress(t_s, duration_s)`` at every output sample, called on the thread that called
        ``run`` (the run waits for its answer). Its answer: ``None`` or a true value goes on;
        any other value — anything whose ``bool()`` is False: ``False``, ``numpy.False_``,
        ``0`` — stops the run, which then returns what it computed (``interrupted`` True). An
        exception it raises (or a ``bool()`` of its answer raises) stops the run and is raised.
        Once a stop is asked — by its answer, its exception or Ctrl-C — it is never called
        again; it is not called while a Ctrl-C is pending.
    save : str or os.PathLike, optional
        Record the run to this ``.rrd`` file (a package built with the viewer only:
        ``kecsim.has_viewer()``). Guarded as ``kecsim run --save``: refused with
        :class:`OutputError` (before the run, nothing written) where it is a file the scene
        reads (the scenario, a profile: by any name or link), read-only, or being written by
        another run — another process or another thread of this one; locked while the run
        records.

    The GIL is released while the run goes. Ctrl-C stops it at its next step and raises
    :class:`Interrupted`, whose ``.result`` holds what it computed — also while ``progress``
    runs (Python's handler interrupts the callback; the run stops within a step). A run that
    fails (a derailment, the integrator) returns normally: ``result.failure`` and
    ``result.summary["outcome"]`` say so.
    """
    unknown = set(options) - {"contact", "threads", "progress", "save"}
    if unknown:
        raise TypeError(
            "kecsim.run: unknown option(s) %s; expected contact, threads, progress, save"
            % ", ".join(sorted(unknown))
        )
    if "save" in options and options["save"] is not None:
        import os

        options["save"] = os.fspath(options["save"])
    return _run(scene, overrides, **options)


__all__ = [
    "run",
    "contact_sweep",
    "profiles",
    "default_scene",
    "csv_columns",
    "has_viewer",
    "RunResult",
    "KecsimError",
    "ScenarioError",
    "BuildError",
    "OutputError",
    "Interrupted",
    "__version__",
]
