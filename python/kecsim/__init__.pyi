"""Type stubs of the kecsim package."""

import os
from typing import Any, Callable, Dict, List, Mapping, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

__version__: str

Scene = Union[str, "os.PathLike[str]"]
OverrideValue = Union[float, int, str, bool, Sequence[Union[float, int, str, bool]]]
Array = npt.NDArray[np.float64]

class KecsimError(Exception): ...
class ScenarioError(KecsimError, ValueError): ...
class BuildError(KecsimError): ...
class OutputError(KecsimError, ValueError): ...

class Interrupted(KeyboardInterrupt):
    result: Optional["RunResult"]

class RunResult:
    """What ``run`` returns."""

    @property
    def wheelsets(self) -> Dict[str, Dict[str, Array]]:
        """Wheelset name → the CSV's column name → values, one per output sample."""
    @property
    def summary(self) -> Dict[str, Any]:
        """The keys of ``kecsim run --json``."""
    @property
    def interrupted(self) -> bool:
        """The run was stopped (Ctrl-C, or ``progress`` returned False)."""
    @property
    def failure(self) -> Optional[str]:
        """Why the run failed (a derailment, the integrator), or None."""

def run(
    scene: Scene,
    overrides: Optional[Mapping[str, OverrideValue]] = None,
    *,
    contact: Optional[str] = None,
    threads: Optional[int] = None,
    progress: Optional[Callable[[float, float], Any]] = None,
    save: Optional[Union[str, "os.PathLike[str]"]] = None,
) -> RunResult:
    """Runs a scene as ``kecsim run`` does (see the package's docstring)."""

def contact_sweep(
    scene: Scene,
    overrides: Optional[Mapping[str, OverrideValue]] = None,
    *,
    step_mm: Optional[float] = None,
    y_max_mm: Optional[float] = None,
) -> Dict[str, Any]:
    """The contact geometry sweep over y of the scene's wheel–rail pair, its options checked as
    ``kecsim contact --step --y-max`` checks them (``step_mm`` in (0, 0.25], ``y_max_mm``
    positive and within the flange climb; ValueError otherwise).

    ``{"table": {column: array}`` (the columns of ``kecsim contact --csv``; NaN where the CSV
    has an empty cell), ``"conicity": {"amplitude_mm", "annex_b", "regression"}`` (EN 15302,
    arrays), ``"report": str``}.
    """

def profiles(
    scene: Scene, overrides: Optional[Mapping[str, OverrideValue]] = None
) -> Dict[str, Dict[str, Any]]:
    """``{"wheel": {...}, "rail": {...}}``, each ``{"name", "source", "y_mm", "z_mm"}``: the
    profile's points as its file holds them (a left-side profile, mm)."""

def default_scene() -> str:
    """The scenario ``kecsim run`` runs without arguments, as TOML text."""

def csv_columns() -> List[str]:
    """The columns of a wheelset's time series, in the CSV's order."""

def has_viewer() -> bool:
    """Whether this build can ``save=`` a recording."""
