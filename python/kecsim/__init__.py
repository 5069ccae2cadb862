"""kecsim: railway vehicle dynamics with the knife-edge-equivalent contact (KEC) method.

A run, a contact sweep and the profiles of a scene, as numpy arrays::

    import kecsim
    r = kecsim.run("scene.toml", {"simulation.speed_m_s": 15.0, "simulation.duration_s": 5.0})
    y = r.wheelsets["ws1"]["y_mm"]          # the CSV's columns, one value per output sample
    print(r.summary["max_abs_y_mm"])         # the keys of `kecsim run --json`

``scene`` is a path (str or os.PathLike) or TOML text; ``overrides`` maps key paths
(``"simulation.speed_m_s"``, array entries by index) to values, as a study's axes do.
"""

from ._errors import BuildError, Interrupted, KecsimError, ScenarioError
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
        ``progress(t_s, duration_s)`` at every output sample, from the run's thread; returning
        ``False`` stops the run, which then returns what it computed (``interrupted`` True).
    save : str or os.PathLike, optional
        Record the run to this ``.rrd`` file (a package built with the viewer only:
        ``kecsim.has_viewer()``).

    The GIL is released while the run goes. Ctrl-C stops it at its next step and raises
    :class:`Interrupted`, whose ``.result`` holds what it computed. A run that fails (a
    derailment, the integrator) returns normally: ``result.failure`` and
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
    "Interrupted",
    "__version__",
]
