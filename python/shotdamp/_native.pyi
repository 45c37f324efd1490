"""Type stubs of shotdamp's native module (the Rust library behind the package)."""

from os import PathLike
from typing import Any, Callable, Dict, List, Literal, Mapping, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

from . import Table

__version__: str

_Floats = Union[Sequence[float], npt.NDArray[np.floating[Any]], npt.NDArray[np.integer[Any]]]
_Path = Union[str, "PathLike[str]"]
_Progress = Callable[[int, int], object]
_Steady = Mapping[str, Union[str, int, float, bool]]

class Structure:
    """The bare primary structure (docs/model.md section 1): the keys of an experiment file's
    ``[structure]`` table, checked as the command line checks them."""

    def __init__(
        self,
        *,
        masses_kg: Optional[_Floats] = None,
        mass_matrix_kg: Optional[Union[Sequence[Sequence[float]], npt.NDArray[np.floating[Any]]]] = None,
        chain_stiffness_n_per_m: Optional[_Floats] = None,
        stiffness_matrix_n_per_m: Optional[Union[Sequence[Sequence[float]], npt.NDArray[np.floating[Any]]]] = None,
        fit: Optional[Mapping[str, Any]] = None,
        ground_stiffness_n_per_m: Optional[_Floats] = None,
        finite_element: Optional[Mapping[str, Any]] = None,
        modal_ratios: Optional[_Floats] = None,
        rayleigh_alpha: Optional[float] = None,
        rayleigh_beta: Optional[float] = None,
    ) -> None: ...
    @property
    def dof(self) -> int:
        """Number of masses."""
    @property
    def masses_kg(self) -> npt.NDArray[np.float64]:
        """Masses, kg (a full mass matrix's diagonal)."""
    @property
    def mass_matrix(self) -> npt.NDArray[np.float64]:
        """Mass matrix, kg (diagonal for lumped masses)."""
    @property
    def stiffness(self) -> npt.NDArray[np.float64]:
        """Stiffness matrix, N/m."""
    @property
    def damping(self) -> npt.NDArray[np.float64]:
        """Damping matrix, N s/m."""
    def modes(self, dampers: Optional[Sequence["Damper"]] = None) -> Dict[str, npt.NDArray[Any]]:
        """Modes of the bare structure: ``mode``, ``freq_hz``, ``omega_rad_s``,
        ``damping_ratio``, ``modal_mass_kg``, ``modal_stiffness_n_per_m``, ``mass_ratio`` (Eq. 13
        for ``dampers``), ``reference_mass`` (1-based) and ``shape`` (one row per mode)."""
    def frf(
        self, freq_hz: _Floats, *, force_mass: int = 1, dampers: Optional[Sequence["Damper"]] = None
    ) -> npt.NDArray[np.float64]:
        """Exact linear compliance (m/N), frequencies x masses; damper masses stuck when given."""
    def reduction(self, freq_hz: Optional[_Floats] = None, *, force_point: int = 1) -> Dict[str, Any]:
        """A finite-element structure's reduction against its full model: ``frequencies`` and
        (with ``freq_hz``) ``compliance`` Tables, and ``largest``, the largest difference of
        the compliance relative to each point's peak."""

class Damper:
    """One container of shot: the keys of an experiment file's ``dampers`` entry."""

    def __init__(
        self,
        *,
        mass: int,
        clearance_mm: Union[float, Literal["inf"]],
        mass_ratio: Optional[float] = None,
        mass_kg: Optional[float] = None,
        bed: Optional[Literal["plastic", "restitution", "column"]] = None,
        grains: Optional[int] = None,
        restitution: Optional[float] = None,
        stick_speed_m_s: Optional[float] = None,
        direction: Optional[Literal["vertical", "horizontal"]] = None,
    ) -> None: ...
    @staticmethod
    def from_dict(keys: Mapping[str, Any]) -> "Damper": ...
    def to_dict(self) -> Dict[str, Any]: ...

class Orbit:
    """A periodic orbit and its certificate."""

    @property
    def freq_hz(self) -> float: ...
    @property
    def period(self) -> int:
        """Period in forcing periods."""
    @property
    def residual(self) -> float:
        """Max-norm of P(u) - u relative to the amplitude scale."""
    @property
    def stable(self) -> bool: ...
    @property
    def smooth(self) -> bool:
        """No graze and no simultaneous impacts on the orbit."""
    @property
    def spectral_radius(self) -> float:
        """Largest multiplier modulus."""
    @property
    def phase(self) -> float:
        """Forcing phase of the section, rad."""
    @property
    def iterations(self) -> int: ...
    @property
    def attempts(self) -> int: ...
    @property
    def multipliers(self) -> npt.NDArray[np.complex128]:
        """Floquet multipliers, largest modulus first."""
    @property
    def section(self) -> List[npt.NDArray[np.float64]]:
        """Displacements (m) and velocities (m/s) of the masses at the section."""

class Steady:
    """The steady state of one frequency."""

    @property
    def freq_hz(self) -> float: ...
    @property
    def converged(self) -> bool: ...
    @property
    def period(self) -> int: ...
    @property
    def transient_periods(self) -> int: ...
    @property
    def stop(self) -> str:
        """Why the point has no steady state ("" when it has one)."""
    @property
    def orbit(self) -> Optional[Orbit]: ...
    @property
    def motion(self) -> str:
        """"periodic", "quasi-periodic", "chaotic", "transient", "chatter" or "aperiodic"."""
    @property
    def lyapunov_per_s(self) -> Optional[float]:
        """Largest Lyapunov exponent of a point with no certified orbit, 1/s."""
    @property
    def lyapunov_half_width(self) -> Optional[float]: ...
    @property
    def measured_periods(self) -> int: ...
    @property
    def interval_met(self) -> bool: ...
    @property
    def compliance(self) -> npt.NDArray[np.float64]:
        """Half peak-to-peak displacement over the force, m/N, per mass; at a point with no
        certified orbit the 95th percentile of the per-period amplitudes over the force."""
    @property
    def compliance_half_width(self) -> npt.NDArray[np.float64]:
        """Half-width of the compliance's 95 % interval, m/N (NaN at a certified orbit)."""
    @property
    def amplitude_m(self) -> npt.NDArray[np.float64]: ...
    @property
    def bottom_impacts(self) -> npt.NDArray[np.float64]: ...
    @property
    def top_impacts(self) -> npt.NDArray[np.float64]: ...
    @property
    def max_flight_m(self) -> npt.NDArray[np.float64]: ...

class System:
    """A structure with dampers driven by ``force_n`` sin(omega t) on ``force_mass``, or by its
    supports accelerating as ``base_acceleration_m_s2`` sin(omega t) (amplitudes then relative
    to the supports, per m/s^2)."""

    def __init__(
        self,
        structure: Structure,
        dampers: Optional[Sequence[Damper]] = None,
        *,
        force_mass: Optional[int] = None,
        force_n: Optional[float] = None,
        base_acceleration_m_s2: Optional[float] = None,
    ) -> None: ...
    @property
    def dof(self) -> int: ...
    @property
    def containers(self) -> int: ...
    def steady_state(self, freq_hz: float, *, steady: Optional[_Steady] = None) -> Steady: ...
    def sweep(
        self,
        freq_hz: _Floats,
        *,
        start: Literal["rest", "up", "down"] = "rest",
        steady: Optional[_Steady] = None,
        curve: str = "sweep",
        jobs: Optional[int] = None,
        progress: Optional[_Progress] = None,
    ) -> Table: ...
    def impulse(
        self,
        *,
        struck_mass: int = 1,
        initial_velocity_m_s: Optional[float] = None,
        impulse_n_s: Optional[float] = None,
        duration_s: Optional[float] = None,
        sample_rate_hz: Optional[float] = None,
    ) -> Dict[str, Any]: ...

class Experiment:
    """One experiment of a file, on one model of the structure."""

    @property
    def id(self) -> str: ...
    @property
    def key(self) -> str: ...
    @property
    def model(self) -> Optional[str]: ...
    @property
    def title(self) -> str: ...
    @property
    def figure(self) -> str: ...
    @property
    def kind(self) -> str: ...
    @property
    def cases(self) -> List[str]: ...
    @property
    def force_mass(self) -> Optional[int]: ...
    @property
    def force_n(self) -> Optional[float]: ...
    @property
    def base_acceleration_m_s2(self) -> Optional[float]: ...
    @property
    def structure(self) -> Structure: ...
    @property
    def freq_hz(self) -> Optional[npt.NDArray[np.float64]]: ...
    def system(self, case: str) -> System: ...

def load(path: _Path, *, reference: _Path = "reference") -> List[Experiment]: ...
def run_experiment(
    files: Union[_Path, Sequence[_Path]],
    *,
    out: _Path = "runs",
    reference: _Path = "reference",
    jobs: Optional[int] = None,
    full_csv: bool = False,
    progress: Optional[_Progress] = None,
) -> Dict[str, Any]: ...
def design(
    files: Union[_Path, Sequence[_Path]],
    *,
    out: _Path = "design-runs",
    reference: _Path = "reference",
    jobs: Optional[int] = None,
    store: bool = False,
    time_limit: Optional[float] = None,
    progress: Optional[_Progress] = None,
) -> Dict[str, Any]: ...
def report(
    out: _Path = "reports",
    *,
    root: _Path = ".",
    experiments: Optional[_Path] = None,
    reference: Optional[_Path] = None,
    studies: Optional[_Path] = None,
    designs: Optional[_Path] = None,
    jobs: Optional[int] = None,
    full_csv: bool = False,
    bless: bool = False,
    progress: Optional[_Progress] = None,
) -> Dict[str, Any]: ...
def study(
    path: _Path,
    *,
    out: Optional[_Path] = None,
    reference: _Path = "reference",
    shard: Optional[Union[Tuple[int, int], str]] = None,
    jobs: Optional[int] = None,
    progress: Optional[_Progress] = None,
) -> Dict[str, Any]: ...
def study_merge(dir: _Path) -> Dict[str, Any]: ...
