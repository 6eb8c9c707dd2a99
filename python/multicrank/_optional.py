"""Optional dependencies: imported where they are used, with a clear message when missing.

multicrank itself depends on numpy, scipy, pandas, click and tqdm only (scipy is imported
where it is used, so that ``import multicrank`` stays light). The rest are extras of the
distribution, imported through :func:`require`:

======== ==================================== ==========================================
extra    modules                              needed by
======== ==================================== ==========================================
report   matplotlib                           ``multicrank report`` / ``write_report``
parquet  pyarrow                              ``sweep(..., out=...)``, ``multicrank sweep``
xarray   xarray                               ``to_xarray``
dask     dask[dataframe], distributed         sweeps of a dask DataFrame on a cluster
symbolic sympy                                :mod:`multicrank.symbolic`
torsion  opentorsion                          ``to_opentorsion``
======== ==================================== ==========================================
"""

from __future__ import annotations

import importlib
from types import ModuleType

__all__ = ["EXTRAS", "OptionalDependencyError", "require"]

#: What each extra of the distribution is for, as the error message names it.
EXTRAS = {
    "report": "the report",
    "parquet": "a sweep to Parquet",
    "xarray": "to_xarray",
    "dask": "a sweep on Dask",
    "symbolic": "SymPy expressions (multicrank.symbolic)",
    "torsion": "to_opentorsion",
}


class OptionalDependencyError(ImportError):
    """An optional dependency is not installed; the message says which extra provides it."""


def require(module: str, extra: str) -> ModuleType:
    """Import ``module`` (e.g. "pyarrow.parquet"), which the extra ``extra`` installs.

    Raises :class:`OptionalDependencyError` (an ImportError) with a message such as
    ``the report needs matplotlib: pip install "multicrank[report]"`` when it is missing.
    """
    if extra not in EXTRAS:
        raise ValueError(f"unknown extra {extra!r}; known: {', '.join(EXTRAS)}")
    try:
        return importlib.import_module(module)
    except ImportError as error:
        package = module.partition(".")[0]
        raise OptionalDependencyError(
            f'{EXTRAS[extra]} needs {package}: pip install "multicrank[{extra}]"', name=package
        ) from error
