"""Optional dependencies (the extras report, parquet, xarray, dask): multicrank works without
them, and each place that needs one says which extra installs it.

A missing module is simulated with ``sys.modules[name] = None``, which makes its import
fail as if it were not installed.
"""

from __future__ import annotations

import json
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import multicrank as mc
from multicrank._optional import EXTRAS, OptionalDependencyError, require

OPTIONAL = ("matplotlib", "pyarrow", "xarray", "dask", "distributed")


def message(package: str, extra: str) -> str:
    return f'{EXTRAS[extra]} needs {package}: pip install "multicrank[{extra}]"'


def hide(monkeypatch: pytest.MonkeyPatch, *modules: str) -> None:
    """Make the modules (and their submodules already imported) unimportable."""
    for name in list(sys.modules):
        if name in modules or name.partition(".")[0] in modules:
            monkeypatch.setitem(sys.modules, name, None)
    for name in modules:
        monkeypatch.setitem(sys.modules, name, None)


@pytest.mark.parametrize(
    "module, extra",
    [
        ("matplotlib", "report"),
        ("matplotlib.pyplot", "report"),
        ("pyarrow", "parquet"),
        ("pyarrow.parquet", "parquet"),
        ("xarray", "xarray"),
        ("dask.dataframe", "dask"),
        ("distributed", "dask"),
    ],
)
def test_require_names_the_extra(monkeypatch, module, extra):
    package = module.partition(".")[0]
    assert require(module, extra).__name__ == module  # installed here (the test extra has them all)
    hide(monkeypatch, package)
    with pytest.raises(OptionalDependencyError) as caught:
        require(module, extra)
    assert str(caught.value) == message(package, extra)
    assert isinstance(caught.value, ImportError) and caught.value.name == package


def test_every_extra_is_named_in_the_messages():
    assert set(EXTRAS) == {"report", "parquet", "xarray", "dask", "symbolic", "torsion"}
    with pytest.raises(ValueError, match="unknown extra"):
        require("numpy", "plots")


def test_symbolic_without_sympy(monkeypatch):
    from multicrank import symbolic

    hide(monkeypatch, "sympy")
    with pytest.raises(ImportError, match=r'pip install "multicrank\[symbolic\]"'):
        symbolic.gravity(cranks=2)


def test_to_xarray_without_xarray(monkeypatch):
    result = mc.sweep(mc.design_grid(crank_ratio=[0.2, 0.3], inclination=0.5, u1=0.1, u2=0.0), phi=16)
    hide(monkeypatch, "xarray")
    with pytest.raises(ImportError, match=r'to_xarray needs xarray: pip install "multicrank\[xarray\]"'):
        mc.to_xarray(result)


def test_parquet_sweep_without_pyarrow(monkeypatch, tmp_path):
    designs = {"crank_ratio": [0.3], "inclination": [0.0], "u1": [1.0], "u2": [0.0]}
    hide(monkeypatch, "pyarrow")
    with pytest.raises(ImportError, match=r'needs pyarrow: pip install "multicrank\[parquet\]"'):
        mc.sweep(designs, out=tmp_path / "r.parquet")
    assert list(tmp_path.iterdir()) == []  # nothing written


def test_report_without_matplotlib(monkeypatch, tmp_path):
    from multicrank.report import write_report

    hide(monkeypatch, "matplotlib")
    with pytest.raises(ImportError, match=r'report needs matplotlib: pip install "multicrank\[report\]"'):
        write_report(tmp_path / "report", progress=False)
    assert not (tmp_path / "report").exists()


def _run_without(modules: tuple[str, ...], code: str, *args: str) -> subprocess.CompletedProcess:
    hidden = "".join(f"sys.modules[{m!r}] = None; " for m in modules)
    return subprocess.run(
        [sys.executable, "-c", f"import sys; {hidden}\n{textwrap.dedent(code)}", *args],
        capture_output=True,
        text=True,
        timeout=300,
    )


@pytest.mark.parametrize(
    "hidden, args, expected",
    [
        ("matplotlib", ["report", "--no-progress"], message("matplotlib", "report")),
        (
            "pyarrow",
            ["sweep", "--crank-ratio", "0.2", "--inclination", "0", "--u1", "0.1", "--no-progress"],
            message("pyarrow", "parquet"),
        ),
    ],
)
def test_cli_says_which_extra_in_one_line(tmp_path, hidden, args, expected):
    out = tmp_path / "out"
    result = _run_without((hidden,), "from multicrank.cli import main\nmain()", *args, "--out", str(out))
    assert result.returncode == 2
    assert result.stderr.strip().splitlines() == [f"Error: {expected}"]
    assert not out.exists() and list(tmp_path.iterdir()) == []


def test_the_core_works_without_any_extra():
    code = """
        import json
        import numpy as np
        import multicrank as mc
        design = dict(crank_ratio=0.3, inclination=np.pi / 2, u1=0.01, u2=0.002, phases=mc.crank_phases(3))
        grid = mc.design_grid(crank_ratio=[0.2, 0.3], inclination=0.5, u1=0.1, u2=0.0, cranks=[1, 3])
        loaded = {m.partition(".")[0] for m, module in sys.modules.items() if module is not None}
        print(json.dumps({
            "force": mc.generalized_force(np.linspace(0, 6, 7), **design).tolist(),
            "delta": float(mc.speed_fluctuation(**design)),
            "table": mc.harmonic_table().to_numpy().tolist(),
            "sweep": mc.sweep(grid, phi=32)["energy_range"].tolist(),
            "extras loaded": sorted(loaded & {"matplotlib", "pyarrow", "xarray", "dask", "distributed"}),
        }))
    """
    result = _run_without(OPTIONAL, code)
    assert result.returncode == 0, result.stderr
    got = json.loads(result.stdout)
    design = dict(crank_ratio=0.3, inclination=np.pi / 2, u1=0.01, u2=0.002, phases=mc.crank_phases(3))
    grid = mc.design_grid(crank_ratio=[0.2, 0.3], inclination=0.5, u1=0.1, u2=0.0, cranks=[1, 3])
    assert got == {
        "force": mc.generalized_force(np.linspace(0, 6, 7), **design).tolist(),
        "delta": float(mc.speed_fluctuation(**design)),
        "table": mc.harmonic_table().to_numpy().tolist(),
        "sweep": mc.sweep(grid, phi=32)["energy_range"].tolist(),
        "extras loaded": [],
    }
