"""shotdamp: impact dampers with granular materials on a multi-mass structure.

Replicates Araki et al. (1997), "Impact damper with granular materials for multibody
system": an exact event-driven simulator of a structure carrying containers of lead shot
(each bed one mass that lifts off, flies and lands), certified periodic orbits with their
Floquet multipliers, sweeps, impulse responses, and the paper's whole report.

Structures and dampers take the keys of an experiment file (docs/experiment-format.md of
the repository), checked by the same code: a bad value raises ``ValueError`` with the
command line's message. Long computations release the interpreter lock (two threads use
two cores) and stop on Ctrl-C at their next simulated point.

>>> import numpy as np, shotdamp as sd
>>> paper = sd.Structure(masses_kg=[0.74, 0.71, 0.64],
...                      chain_stiffness_n_per_m=[24.3e3, 21.8e3, 19.8e3],
...                      modal_ratios=[0.01, 0.01, 0.01])
>>> one = sd.System(paper, [sd.Damper(mass=2, mass_ratio=0.1, clearance_mm=0.3)], force_n=2.6)
>>> table = one.sweep(np.arange(44.0, 56.01, 0.5))
>>> bool(table["c2"].max() > 0)
True
"""

from __future__ import annotations

from typing import Any, Dict, Iterator, List, Mapping


class Table(Mapping[str, Any]):
    """A table as the command line writes it to CSV: columns by name (numpy arrays; a list
    of str for text), in the CSV's order, with its file name and description.

    ``to_pandas()`` and ``to_polars()`` give a DataFrame when that library is installed.
    """

    def __init__(self, columns: Dict[str, Any], name: str = "", description: str = ""):
        self.name: str = name
        self.description: str = description
        self._columns: Dict[str, Any] = dict(columns)

    def __getitem__(self, key: str) -> Any:
        return self._columns[key]

    def __iter__(self) -> Iterator[str]:
        return iter(self._columns)

    def __len__(self) -> int:
        return len(self._columns)

    @property
    def columns(self) -> List[str]:
        """Column names, in order."""
        return list(self._columns)

    @property
    def rows(self) -> int:
        """Number of rows."""
        first = next(iter(self._columns.values()), [])
        return len(first)

    def to_pandas(self) -> Any:
        """A pandas DataFrame of the columns (needs pandas)."""
        import numpy as np
        import pandas as pd

        return pd.DataFrame({k: np.asarray(v) for k, v in self._columns.items()})

    def to_polars(self) -> Any:
        """A polars DataFrame of the columns (needs polars)."""
        import polars as pl

        return pl.DataFrame(self._columns)

    def __repr__(self) -> str:
        return f"Table({self.name or 'table'!r}, rows={self.rows}, columns={self.columns})"


from ._native import (  # noqa: E402  (Table first: the native module builds Tables)
    Damper,
    Experiment,
    Orbit,
    Steady,
    Structure,
    System,
    __version__,
    load,
    report,
    run_experiment,
    design,
    study,
    study_merge,
)

__all__ = [
    "Damper",
    "Experiment",
    "Orbit",
    "Steady",
    "Structure",
    "System",
    "Table",
    "__version__",
    "load",
    "report",
    "run_experiment",
    "design",
    "study",
    "study_merge",
]
