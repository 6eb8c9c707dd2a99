"""One exception type, naming the parameter, everywhere (issue 13, item 7).

Every public function and method in the registry below is called with random bad values
for each of its parameters in turn (the others valid): strings, None, complex numbers,
objects, mappings, sets, bytes, lists of strings, ragged and nested lists, ints beyond 64
bits, NaN/inf, bool and datetime arrays, callables, non-integral floats, negative ints. A
call either succeeds (where the parameter's kind accepts such a value) or raises
:class:`mc.MechanismError`; for values of the wrong type the message names the parameter.
Never an OverflowError, TypeError, AttributeError, IndexError or numpy's ValueError. A
meta-test keeps the registry complete: a new public callable must be added here (or to the
list of those owned elsewhere, with the reason). The worked examples, case by case, are in
tests/test_errors_examples.py.
"""

from __future__ import annotations

import ast
import functools
import inspect
import math
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import multicrank as mc
import multicrank.reference as ref

# --------------------------------------------------------------------------- bad values
CATEGORIES: dict[str, st.SearchStrategy] = {
    "text": st.text(max_size=8),
    "none": st.none(),
    "complex": st.complex_numbers(max_magnitude=1e3, allow_nan=False).filter(lambda z: z.imag != 0),
    "object": st.builds(object),
    "mapping": st.dictionaries(st.text(max_size=3), st.floats(-1, 1), max_size=2),
    "set": st.frozensets(st.integers(0, 5), min_size=1, max_size=3),
    "bytes": st.binary(min_size=1, max_size=4),
    "text_list": st.lists(st.text(min_size=1, max_size=3), min_size=1, max_size=3),
    "ragged": st.lists(st.floats(0, 0.5), min_size=1, max_size=3).map(lambda a: [a, [*a, 0.25]]),
    "nested": st.floats(0, 0.5).map(lambda x: [[[x, x]], [[x, x]]]),
    "huge": st.one_of(st.integers(2**64, 2**200), st.integers(-(2**200), -(2**63) - 1)),
    "nonfinite": st.sampled_from([math.nan, math.inf, -math.inf]),
    "bool_array": st.lists(st.booleans(), min_size=1, max_size=3).map(np.array),
    "datetime": st.just(np.array(["2020-01-01"], dtype="datetime64[D]")),
    "callable": st.just(len),
    "float": st.floats(-10, 10).filter(lambda x: x != int(x)),
    "negative": st.integers(-10, -1),
}
# Categories whose values are of the wrong type for every parameter that does not accept
# them: the message must name the parameter.
WRONG_TYPE = {"text", "none", "complex", "object", "mapping", "set", "bytes", "text_list", "ragged", "nested"}
WRONG_TYPE |= {"bool_array", "datetime", "callable"}

# Categories not drawn for a kind: a random string is a fine path, and would be written to.
NOT_DRAWN: dict[str, set[str]] = {"path_or_none": {"text"}, "path": {"text"}}

# What each kind of parameter may accept (a call may still refuse such a value, by name).
KINDS: dict[str, set[str]] = {
    "real": {"float", "negative", "nested", "huge"},  # finite reals of any shape (2**63 is a uint64)
    "ratio": {"float", "nested"},  # 0 <= λ < 1
    "angles": {"float", "negative", "nonfinite", "nested", "huge"},  # φ: NaN gives NaN
    "angles_or_none": {"none", "float", "negative", "nonfinite", "nested", "huge"},
    "positive_list": set(),  # a 1-D sequence of finite quantities > 0
    "node_list": set(),  # a 1-D sequence of node indices
    "positive_list_or_none": {"none"},
    "count": set(),  # an integer >= some minimum
    "option": set(),  # one of a few strings
    "option_or_none": {"none"},  # one of a few strings, or None for none
    "phases": {"none"},
    "threshold": {"none", "huge"},  # huge means serial
    "label": {"text"},
    "label_or_none": {"text", "none"},
    "flag": set(),
    "path_or_none": {"none"},
    "path": set(),  # a file to read
    "outputs": set(),
    "outputs_or_none": {"none"},  # None: the default outputs
    "designs": set(),
    "axes_or_none": {"none"},
    "frame": set(),
    "rng": set(),
    "nonnegative": {"float", "huge"},
    "angle_list": set(),  # a 1-D array of angles
    "banks": {"ragged"},  # one 1-D array per throw
    "passthrough": {"none"},
    # the machine in motion
    "machine": set(),
    "cylinders": set(),
    "cylinder": set(),
    "positive": {"float", "huge"},  # a finite quantity > 0 (a mass, an inertia, a speed)
    "positive_or_none": {"none", "float", "huge"},
    "positive_or_inf": {"float", "huge", "nonfinite"},
    "count_or_none": {"none"},
    "range_or_none": {"none"},
    "positions_or_none": {"none"},  # increasing axial positions [m], at least two
    "shaft_or_none": {"none"},  # an mc.Shaft with a node per cylinder; None: the machine's own, or none
    "pressure": {"none", "callable"},  # the callable is called (and refused) when the machine runs
    "firing": {"none"},
    "load": {"none", "callable", "float", "negative", "huge"},  # "balance", a torque [N·m], a callable
    "times": set(),  # increasing instants [s]
    "fraction": {"float"},  # 0 < x < 1
    "assembly": set(),  # an openTorsion model
}

ENGINE = mc.Engine.inline(4, crank_ratio=0.3, inclination=1.0, u1=0.5, u2=0.1)
CYLINDER = mc.Cylinder(
    crank_radius=0.05, rod_length=0.2, piston_mass=1.0, rod_mass=1.0, rod_cg=0.05, crank_mass=1.0, crank_cg_radius=0.02
)
MACHINE = mc.Machine([CYLINDER], shaft_inertia=0.5, rpm=600.0)
SHAFT = mc.Shaft([0.5, 0.2], [1e4], cylinder_nodes=[0], damping=[0.5])
SHAFT_FILE = Path(__file__).resolve().parents[1] / "docs" / "machines" / "v8-cross.toml"  # with a [shaft]
CYLINDER_KINDS = {
    "crank_radius": (0.05, "positive"),
    "rod_length": (0.2, "positive"),
    "piston_mass": (1.0, "real"),
    "rod_mass": (1.0, "real"),
    "rod_cg": (0.05, "real"),
    "rod_inertia": (None, "positive_or_none"),
    "crank_mass": (1.0, "real"),
    "crank_cg_radius": (0.02, "real"),
    "counterweight_mass": (0.0, "real"),
    "counterweight_radius": (0.0, "real"),
    "bore": (0.0, "real"),
    "phase": (0.0, "real"),
    "inclination": (1.0, "real"),
    "pressure": (None, "pressure"),
    "pressure_crank_end": (None, "pressure"),
    "piston_rod_diameter": (0.0, "real"),
    "axial_position": (0.0, "real"),
}
DESIGN = dict(crank_ratio=0.3, inclination=1.0, u1=0.5, u2=0.1)
DESIGN_KINDS = dict(crank_ratio="ratio", inclination="real", u1="real", u2="real")
GRID_RESULT = mc.sweep(mc.design_grid(crank_ratio=[0.2, 0.3], inclination=1.0, u1=0.5, u2=[0.1, 0.2]), phi=16)


def _sweep(**kwargs: Any) -> Any:
    return mc.sweep(**kwargs)


def _quiet(function: Callable[..., Any]) -> Callable[..., Any]:
    """The reference is plain numpy: φ = inf gives NaN with numpy's RuntimeWarning."""

    @functools.wraps(function)
    def call(*args: Any, **kwargs: Any) -> Any:
        with np.errstate(invalid="ignore", over="ignore"):
            return function(*args, **kwargs)

    return call


def _polar(bearing: Any) -> Any:
    """BearingLoads.polar of MACHINE's loads, its figure closed (``ax``, where to draw, is
    matplotlib's own)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    ax = mc.bearing_loads(MACHINE, phi=[0.0, 1.0]).polar(bearing)
    plt.close(ax.figure)
    return ax


def _machine_to_opentorsion(
    orders: Any, shaft: Any, rpm: Any, max_order: Any, part: Any, mean: Any, dofs: Any, node: Any
) -> Any:
    """to_opentorsion's machine form, every keyword given (None where the call would leave it)."""
    return mc.to_opentorsion(
        orders, shaft=shaft, rpm=rpm, max_order=max_order, part=part, mean=mean, dofs=dofs, node=node
    )


def _threshold(threshold: Any) -> None:
    before = mc.get_parallel_threshold()
    try:
        mc.set_parallel_threshold(threshold)
    finally:
        mc.set_parallel_threshold(before)


# name: (callable, {parameter: (valid value, kind)})
REGISTRY: dict[str, tuple[Callable[..., Any], dict[str, tuple[Any, str]]]] = {
    "crank_phases": (
        mc.crank_phases,
        {"cranks": (3, "count"), "strokes": (2, "count"), "acting": ("single", "option")},
    ),
    "surviving_harmonics": (
        mc.surviving_harmonics,
        {"cranks": (3, "count"), "strokes": (4, "count"), "acting": ("double", "option"), "n_max": (24, "count")},
    ),
    "paper_coefficient": (mc.paper_coefficient, {"i": (2, "count"), "j": (3, "count")}),
    "lambda_coefficients": (
        mc.lambda_coefficients,
        {"crank_ratio": (0.3, "ratio"), "n_max": (8, "count"), "method": ("paper", "option")},
    ),
    "harmonic_table": (
        mc.harmonic_table,
        {"strokes": (2, "count"), "acting": ("single", "option"), "k_max": (4, "count"), "n_max": (6, "count")},
    ),
    "fourier_coefficients": (
        mc.fourier_coefficients,
        {**{k: (v, DESIGN_KINDS[k]) for k, v in DESIGN.items()}, "phases": (None, "phases"), "n_max": (8, "count")},
    ),
    "dimensionless_moments": (
        mc.dimensionless_moments,
        {
            "crank_radius": (0.1, "real"),
            "rod_length": (0.4, "real"),
            "rod_cg": (0.1, "real"),
            "piston_mass": (1.0, "real"),
            "rod_mass": (1.0, "real"),
            "crank_mass": (0.5, "real"),
            "crank_cg_radius": (0.05, "real"),
            "counterweight_mass": (0.5, "real"),
            "counterweight_radius": (0.05, "real"),
            "shaft_inertia": (1.0, "real"),
            "rpm": (100.0, "real"),
            "g": (9.81, "real"),
        },
    ),
    "uniform_grid": (
        mc.uniform_grid,
        {"count": (10, "count"), "start": (0.0, "real"), "stop": (1.0, "real"), "endpoint": (False, "flag")},
    ),
    "UniformGrid": (mc.UniformGrid, {"count": (10, "count"), "start": (0.0, "real"), "step": (0.1, "real")}),
    "set_parallel_threshold": (_threshold, {"threshold": (1000, "threshold")}),
    "Engine": (
        mc.Engine,
        {
            "phase": ([0.0, 1.0], "real"),
            **{k: (v, DESIGN_KINDS[k]) for k, v in DESIGN.items()},
            "name": ("x", "label"),
        },
    ),
    "Engine.inline": (
        mc.Engine.inline,
        {
            "cranks": (3, "count"),
            "strokes": (2, "count"),
            "acting": ("single", "option"),
            **{k: (v, DESIGN_KINDS[k]) for k, v in DESIGN.items()},
            "name": (None, "label_or_none"),
        },
    ),
    "Engine.from_throws": (
        mc.Engine.from_throws,
        {
            "throws": ([0.0, 1.0], "angle_list"),
            "banks": ([[0.5], [0.5, 1.0]], "banks"),
            "crank_ratio": (0.3, "ratio"),
            "u1": (0.5, "real"),
            "u2": (0.1, "real"),
            "name": ("x", "label"),
        },
    ),
    "Engine.replace": (ENGINE.replace, {"u1": (0.4, "real"), "name": ("y", "label")}),
    "Engine.potential_energy": (ENGINE.potential_energy, {"phi": ([0.1], "angles")}),
    "Engine.generalized_force": (
        ENGINE.generalized_force,
        {"phi": ([0.1], "angles"), "method": ("series", "option")},
    ),
    "Engine.force_derivative": (ENGINE.force_derivative, {"phi": ([0.1], "angles")}),
    "Engine.fourier_coefficients": (ENGINE.fourier_coefficients, {"n_max": (8, "count")}),
    "Engine.surviving_harmonics": (ENGINE.surviving_harmonics, {"n_max": (8, "count")}),
    "Engine.harmonic_sensitivity": (
        ENGINE.harmonic_sensitivity,
        {
            "u1_rel": (0.01, "nonnegative"),
            "u2_rel": (0.01, "nonnegative"),
            "phase": (0.01, "nonnegative"),
            "n_max": (8, "count"),
        },
    ),
    "Engine.perturbed": (
        ENGINE.perturbed,
        {
            "rng": (np.random.default_rng(0), "rng"),
            "u1_rel": (0.01, "nonnegative"),
            "u2_rel": (0.01, "nonnegative"),
            "phase": (0.01, "nonnegative"),
        },
    ),
    "DesignGrid": (
        mc.DesignGrid,
        {
            "crank_ratio": ([0.2, 0.3], "ratio"),
            "inclination": (1.0, "real"),
            "u1": (0.5, "real"),
            "u2": (0.1, "real"),
            "cranks": ([1, 2], "count"),
            "strokes": (2, "count"),
            "acting": ("single", "option"),
        },
    ),
    "sweep": (
        _sweep,
        {
            "designs": ({"crank_ratio": [0.3], "inclination": [1.0], "u1": [0.5], "u2": [0.1]}, "designs"),
            "phi": (16, "count"),
            "outputs": (["force_rms"], "outputs"),
            "method": ("exact", "option"),
            "out": (None, "path_or_none"),
            "resume": (False, "flag"),
            "progress": (False, "flag"),
            "chunk_size": (10, "count"),
            "curves": (False, "flag"),
            "passthrough": (None, "passthrough"),
        },
    ),
    "to_xarray": (
        mc.to_xarray,
        {"result": (GRID_RESULT, "frame"), "axes": ({"crank_ratio": [0.2, 0.3], "u2": [0.1, 0.2]}, "axes_or_none")},
    ),
    "IndicatorDiagram": (
        mc.IndicatorDiagram,
        {
            "angle": (np.linspace(0, 2 * math.pi, 9), "angle_list"),
            "pressure": (np.r_[np.cos(np.linspace(0, 2 * math.pi, 8, endpoint=False)), 1.0] * 1e5, "angle_list"),
            "cycle": (2 * math.pi, "option"),
            "kind": ("linear", "option"),
            "closure_tolerance": (1e-6, "nonnegative"),
        },
    ),
    "reference.lambda_coefficients": (
        ref.lambda_coefficients,
        {"crank_ratio": (0.3, "ratio"), "n_max": (8, "count"), "method": ("exact", "option")},
    ),
}
for _name in ("potential_energy", "generalized_force", "force_derivative", "energy_extrema", "speed_fluctuation"):
    _params: dict[str, tuple[Any, str]] = {k: (v, DESIGN_KINDS[k]) for k, v in DESIGN.items()}
    if _name not in ("energy_extrema", "speed_fluctuation"):
        _params = {"phi": ([0.1, 0.2], "angles"), **_params}
    _params["phases"] = (None, "phases")
    _params["parallel_threshold"] = (None, "threshold")
    if _name == "generalized_force":
        _params["method"] = ("exact", "option")
    REGISTRY[_name] = (getattr(mc, _name), _params)
    if _name in ("potential_energy", "generalized_force"):
        _ref_params = {k: v for k, v in _params.items() if k != "parallel_threshold"}
        REGISTRY[f"reference.{_name}"] = (_quiet(getattr(ref, _name)), _ref_params)
REGISTRY["design_grid"] = (mc.design_grid, REGISTRY["DesignGrid"][1])
MACHINE_KINDS = {
    "shaft_inertia": (0.5, "positive"),
    "g": (9.81, "real"),
    "rpm": (600.0, "positive_or_none"),
    "rpm_range": (None, "range_or_none"),
    "delta_target": (None, "positive_or_none"),
    "main_bearings": (None, "positions_or_none"),
    "shaft": (None, "shaft_or_none"),
    "load_law": (None, "option_or_none"),  # "propeller" needs the rpm, 600 here
}
REGISTRY.update(
    {
        "Cylinder": (mc.Cylinder, CYLINDER_KINDS),
        "Machine": (
            mc.Machine,
            {
                "cylinders": ([CYLINDER], "cylinders"),
                "strokes": (2, "count"),
                "name": ("x", "label"),
                "note": ("", "label"),
                **MACHINE_KINDS,
            },
        ),
        "Machine.from_layout": (
            mc.Machine.from_layout,
            {
                "layout": ("v-twin-90", "option"),
                "cylinder": (CYLINDER, "cylinder"),
                "strokes": (None, "count_or_none"),
                "firing": (None, "firing"),
                "cylinder_spacing": (None, "positive_or_none"),
                "name": (None, "label_or_none"),
                "note": (None, "label_or_none"),
                **MACHINE_KINDS,
            },
        ),
        "Machine.engine": (MACHINE.engine, {"rpm": (None, "positive_or_none")}),
        "Machine.load_factor": (MACHINE.load_factor, {"rpm": (30.0, "positive")}),
        "Machine.replace": (MACHINE.replace, {"shaft_inertia": (0.6, "positive"), "name": ("y", "label")}),
        "Cylinder.replace": (CYLINDER.replace, {"crank_radius": (0.04, "positive"), "bore": (0.1, "real")}),
        "Layout": (
            mc.Layout,
            {
                "name": ("x", "label"),
                "note": ("", "label"),
                "throws": ((0.0, 180.0), "angle_list"),
                "banks": (((0.0,), (90.0,)), "banks"),
                "strokes": (None, "count_or_none"),
            },
        ),
        "layout_engine": (
            mc.layout_engine,
            {
                "name": ("boxer-2", "option"),
                **{k: (v, DESIGN_KINDS[k]) for k, v in DESIGN.items() if k != "inclination"},
            },
        ),
        "PowerLawLoad": (
            mc.PowerLawLoad,
            {
                "torque": (10.0, "real"),
                "speed": (None, "positive_or_none"),  # deprecated: ω_n [rad/s] instead of rpm
                "exponent": (2.0, "positive"),
                "rpm": (600.0, "positive"),
            },
        ),
        "steady_state": (
            mc.steady_state,
            {
                "machine": (MACHINE, "machine"),
                "rpm": (600.0, "positive_or_none"),  # None: the machine's own
                "load": ("balance", "load"),
                "drive": (None, "load"),
                "gravity": (True, "flag"),
                "min_speed_ratio": (1e-3, "fraction"),
                "points": (None, "count_or_none"),
            },
        ),
        "flywheel_inertia": (
            mc.flywheel_inertia,
            {
                "machine": (MACHINE, "machine"),
                "delta": (0.05, "fraction"),
                "rpm": (600.0, "positive_or_none"),  # None: the machine's own
                "load": ("balance", "load"),
                "drive": (None, "load"),
                "gravity": (True, "flag"),
                "min_speed_ratio": (1e-3, "fraction"),
            },
        ),
        "simulate": (
            mc.simulate,
            {
                "machine": (MACHINE, "machine"),
                "t_eval": (np.linspace(0.0, 0.01, 3), "times"),
                "rpm0": (600.0, "real"),
                "phi0": (0.0, "real"),
                "load": (None, "load"),
                "drive": (None, "load"),
                "gravity": (True, "flag"),
                "rtol": (1e-8, "fraction"),
                "atol": (1e-8, "positive"),
                "method": ("DOP853", "option"),
                "max_step": (math.inf, "positive_or_inf"),
                "balance_speed": (None, "positive_or_none"),
                "progress": (False, "flag"),
                "omega0": (None, "positive_or_none"),  # deprecated: rpm0 in rad/s
                "balance_rpm": (None, "positive_or_none"),
            },
        ),
        "torque_orders": (
            mc.torque_orders,
            {
                "machine": (MACHINE, "machine"),
                "rpm": (600.0, "positive"),
                "max_order": (6, "count"),
                "gravity": (True, "flag"),
            },
        ),
        "shaking_forces": (
            mc.shaking_forces,
            {
                "machine": (MACHINE, "machine"),
                "rpm": (600.0, "positive_or_none"),
                "max_order": (6, "count"),
                "steady": (False, "flag"),
            },
        ),
        "bearing_loads": (
            mc.bearing_loads,
            {
                "machine": (MACHINE, "machine"),
                "rpm": (600.0, "positive_or_none"),
                "phi": (None, "angles_or_none"),
                "steady": (False, "flag"),
                "gravity": (True, "flag"),
            },
        ),
        # a bearing's number, 0 <= bearing < bearings (a bool is refused too: test_errors_examples)
        "BearingLoads.polar": (_polar, {"bearing": (1, "count")}),
        "Shaft": (
            mc.Shaft,
            {
                "inertia": ([1.0, 2.0, 0.5], "positive_list"),
                "stiffness": ([1e4, 2e4], "positive_list"),
                "cylinder_nodes": ([0, 1], "node_list"),
                "damping": (None, "positive_list_or_none"),
                "node_damping": (None, "positive_list_or_none"),
            },
        ),
        "Shaft.modes": (SHAFT.modes, {"count": (None, "count_or_none")}),
        "to_opentorsion": (
            mc.to_opentorsion,
            {
                "orders": (mc.torque_orders(MACHINE, 600.0, max_order=3), "frame"),
                "dofs": (3, "count"),
                "node": (1, "count"),
                "part": ("total", "option"),
                "mean": (False, "flag"),
                # the machine form's: refused by name with a table
                "shaft": (None, "passthrough"),
                "rpm": (None, "passthrough"),
                "max_order": (None, "passthrough"),
            },
        ),
        "to_opentorsion (a machine)": (
            _machine_to_opentorsion,
            {
                "orders": (MACHINE, "machine"),
                "shaft": (SHAFT, "shaft_or_none"),
                "rpm": (None, "positive_or_none"),  # None: the machine's own
                "max_order": (3, "count_or_none"),  # None: 12
                "part": ("total", "option"),
                "mean": (False, "flag"),
                # the table form's: refused by name with a machine
                "dofs": (None, "passthrough"),
                "node": (None, "passthrough"),
            },
        ),
        "Shaft.from_opentorsion": (
            mc.Shaft.from_opentorsion,
            {
                "assembly": (mc.to_opentorsion(MACHINE, shaft=SHAFT, max_order=1).assembly, "assembly"),
                "cylinder_nodes": ([1], "node_list"),
            },
        ),
        "Shaft.from_toml": (mc.Shaft.from_toml, {"path": (SHAFT_FILE, "path")}),
    }
)

REGISTRY.update(
    {
        "MachineGrid": (
            mc.MachineGrid,
            {
                "machine": (MACHINE, "machine"),
                "shaft_inertia": ([0.5, 0.6], "positive"),
                "rpm": (600.0, "positive"),
                "pressure_scale": ([0.5, 1.0], "real"),
                "piston_mass": ([0.1, 0.2], "positive"),
            },
        ),
        "motion_sweep": (
            mc.motion_sweep,
            {
                "machine": (MACHINE, "machine"),
                "designs": (pd.DataFrame({"shaft_inertia": [0.6]}), "designs"),
                "outputs": (["delta"], "outputs_or_none"),
                "load": ("balance", "load"),
                "delta_target": (None, "positive_or_none"),  # a float is refused by name: outputs ask no flywheel
                "out": (None, "path_or_none"),
                "resume": (False, "flag"),
                "chunk_size": (None, "count_or_none"),
                "progress": (False, "flag"),
                "passthrough": ((), "passthrough"),
                "delta": (None, "positive_or_none"),  # deprecated: delta_target
            },
        ),
    }
)

REGISTRY.update(
    {
        "firing_orders": (
            mc.firing_orders,
            {
                "machine": (MACHINE, "machine"),
                "shaft": (None, "shaft_or_none"),
                "rank_by": ("delta", "option"),
                "rpm": (None, "positive_or_none"),
                "max_order": (3, "count"),
                "modes": (2, "count"),
                "max_candidates": (10, "count"),
                "progress": (False, "flag"),
            },
        ),
        "torsional_merit": (
            mc.torsional_merit,
            {
                "machine": (MACHINE, "machine"),
                "shaft": (mc.Shaft([0.1, 0.2, 0.5], [1e4, 2e4], cylinder_nodes=[0]), "shaft_or_none"),
                "modes": (2, "count"),
                "max_order": (4, "count"),
                "rpm_range": (None, "range_or_none"),
            },
        ),
        "optimize_counterweights": (
            mc.optimize_counterweights,
            {
                "machine": (MACHINE, "machine"),
                "objective": ("delta", "option"),
                "bounds": (None, "range_or_none"),
                "rpm": (None, "positive_or_none"),
                # a finite force >= 0 [N]: a float may be a limit nothing meets (refused by name)
                "max_bearing_load": (None, "positive_or_none"),
                "max_free_force": (None, "positive_or_none"),
                "max_free_moment": (None, "positive_or_none"),
                "seed": (0, "count"),
                "maxiter": (2, "count"),
                "progress": (False, "flag"),
            },
        ),
    }
)

CASES = [(name, parameter) for name, (_, params) in REGISTRY.items() for parameter in params]

# Refusals that may name another parameter than the one given a bad value (each refusal
# names one, as data: ``error.parameter``), and why: two values checked together, where the
# refusal names the other (the one whose rule it states), and a former name checked as the
# name it now has.
ALSO_NAMED: dict[tuple[str, str], set[str]] = {
    # rod_length > crank_radius: a crank as long as its rod is refused as rod_length's
    ("dimensionless_moments", "crank_radius"): {"rod_length"},
    ("Cylinder", "crank_radius"): {"rod_length"},
    ("Cylinder.replace", "crank_radius"): {"rod_length"},
    # a load that fixes the speed itself refuses the rpm given beside it
    ("steady_state", "load"): {"rpm"},
    ("flywheel_inertia", "load"): {"rpm"},
    # delta, delta_target's name of 0.1, is checked as delta_target
    ("motion_sweep", "delta"): {"delta_target"},
}

# Public callables not in the registry, and why.
OWNED_ELSEWHERE = {
    # results, made by steady_state, flywheel_inertia, simulate, optimize_counterweights,
    # shaking_forces and bearing_loads from checked input
    "BearingLoads",
    "ShakingForces",
    "CounterweightOptimum",
    "FlywheelInertia",
    "SteadyState",
    "Transient",
    "StallError",
    "TorsionalModel",  # to_opentorsion's, where exported
    # no user input
    "get_parallel_threshold",
    "EnergyExtrema",
    "MechanismError",
}


def test_registry_covers_every_public_callable():
    public = {name for name in mc.__all__ if callable(getattr(mc, name))}
    missing = public - set(REGISTRY) - OWNED_ELSEWHERE
    assert not missing, f"add these to REGISTRY in tests/test_errors.py: {sorted(missing)}"
    for name, (function, params) in REGISTRY.items():
        signature = inspect.signature(function)
        if any(p.kind is p.VAR_KEYWORD for p in signature.parameters.values()):
            continue
        # every parameter a user can pass is exercised (self and the like are not parameters here)
        assert set(params) == set(signature.parameters), name


def _call(name: str, parameter: str, value: Any) -> Any:
    function, params = REGISTRY[name]
    kwargs = {k: v for k, (v, _) in params.items()}
    kwargs[parameter] = value
    return function(**kwargs)


@pytest.mark.parametrize("name, parameter", CASES)
def test_valid_call(name, parameter):
    """The registry's valid values are valid (so that a refusal below is the bad value's)."""
    function, params = REGISTRY[name]
    function(**{k: v for k, (v, _) in params.items()})


@pytest.mark.parametrize("name, parameter", CASES)
@settings(max_examples=40, suppress_health_check=[HealthCheck.too_slow])  # st.text builds its tables once
@given(data=st.data())
def test_bad_values_raise_mechanism_error_naming_the_parameter(name, parameter, data):
    kind = REGISTRY[name][1][parameter][1]
    category = data.draw(st.sampled_from(sorted(set(CATEGORIES) - NOT_DRAWN.get(kind, set()))), label="category")
    value = data.draw(CATEGORIES[category], label="value")
    try:
        _call(name, parameter, value)
    except mc.MechanismError as error:
        if category in WRONG_TYPE:
            assert parameter in str(error), f"{name}({parameter}={value!r}): {error}"
        # Every refusal names its parameter as data, the one the registry was given a bad value for.
        named = {parameter} | ALSO_NAMED.get((name, parameter), set())
        assert error.parameter in named, f"{name}({parameter}={value!r}): parameter {error.parameter!r}: {error}"
    except Exception as error:  # pragma: no cover - the failure being tested for
        pytest.fail(f"{name}({parameter}={value!r}) raised {type(error).__name__}: {error}")
    else:
        assert category in KINDS[kind], f"{name}({parameter}={value!r}) was accepted"


# --------------------------------------------------------------------- no message is parsed
PACKAGE = Path(mc.__file__).resolve().parent
#: What reads a text: a method of str, a regular expression's search, a comparison.
TEXT_READERS = {
    *(name for name in dir(str) if not name.startswith("_")),
    "search", "match", "fullmatch", "sub", "subn", "findall", "finditer",
}  # fmt: skip


def _error_names(function: ast.AST) -> set[str]:
    """The names an error is bound to in ``function``: ``except … as name`` and parameters
    annotated as an error or exception."""
    names = {node.name for node in ast.walk(function) if isinstance(node, ast.ExceptHandler) and node.name}
    if isinstance(function, ast.FunctionDef | ast.AsyncFunctionDef):
        for argument in [*function.args.args, *function.args.kwonlyargs, *function.args.posonlyargs]:
            annotation = ast.unparse(argument.annotation) if argument.annotation else ""
            if "Error" in annotation or "Exception" in annotation:
                names.add(argument.arg)
    return names


def _is_message(node: ast.AST, errors: set[str], texts: set[str]) -> bool:
    """Whether ``node`` is an error's message: ``str(error)``, ``repr(error)``, ``error.args``
    (or a part of it), an f-string of the error alone, or a name in ``texts`` bound to one."""
    if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id in ("str", "repr"):
        return len(node.args) == 1 and isinstance(node.args[0], ast.Name) and node.args[0].id in errors
    if isinstance(node, ast.Attribute) and node.attr == "args":
        return isinstance(node.value, ast.Name) and node.value.id in errors
    if isinstance(node, ast.Subscript):
        return _is_message(node.value, errors, texts)
    if isinstance(node, ast.JoinedStr) and len(node.values) == 1:
        value = node.values[0]
        return isinstance(value, ast.FormattedValue) and isinstance(value.value, ast.Name) and value.value.id in errors
    return isinstance(node, ast.Name) and node.id in texts


def _message_reads(tree: ast.AST) -> list[str]:
    """Where a module reads an error's message (:func:`_is_message`) — searches, slices or
    compares it, or hands it to a regular expression —: anything but showing it."""
    found = []
    for function in ast.walk(tree):
        if not isinstance(function, ast.FunctionDef | ast.AsyncFunctionDef | ast.Module):
            continue
        errors = _error_names(function)
        texts: set[str] = set()
        for node in ast.walk(function):  # the names bound to a message
            if isinstance(node, ast.Assign | ast.NamedExpr) and _is_message(node.value, errors, texts):
                targets = node.targets if isinstance(node, ast.Assign) else [node.target]
                texts |= {target.id for target in targets if isinstance(target, ast.Name)}
        for node in ast.walk(function):
            if isinstance(node, ast.Attribute) and node.attr in TEXT_READERS:
                read = _is_message(node.value, errors, texts)
            elif isinstance(node, ast.Subscript):
                read = _is_message(node.value, errors, texts)
            elif isinstance(node, ast.Compare):
                read = any(_is_message(n, errors, texts) for n in [node.left, *node.comparators])
            elif isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and node.func.attr in TEXT_READERS:
                read = any(_is_message(argument, errors, texts) for argument in node.args)
            else:
                read = False
            if read:
                found.append(f"line {node.lineno}: {ast.unparse(node)}")
    return sorted(set(found))  # a function's nodes are the module's too


def test_no_module_parses_an_error_message():
    """Which parameter an error is about is its data (``error.parameter``): no module of the
    package searches, slices or compares an error's message to find out (the command line
    re-parsed it to name the option, as did Shaft.from_opentorsion and the motion sweep's
    row errors)."""
    reads = {}
    for path in sorted(PACKAGE.rglob("*.py")):
        found = _message_reads(ast.parse(path.read_text(encoding="utf-8")))
        if found:
            reads[str(path.relative_to(PACKAGE))] = found
    assert not reads, reads


@pytest.mark.parametrize(
    "source",
    [
        "def f():\n    try: g()\n    except E as error:\n        text = str(error)\n        return text.endswith('')",
        "def f():\n    try: g()\n    except E as error:\n        return pattern.sub(h, str(error))",
        "def f(error: MechanismError):\n    return str(error).removeprefix('design 0: ')",
        "def f():\n    try: g()\n    except E as error:\n        return 'max_order' in error.args[0]",
    ],
)
def test_the_message_check_sees_a_parse(source):
    """The check above finds what the package did before errors carried their parameter."""
    assert _message_reads(ast.parse(source))


def test_the_message_check_lets_a_message_be_shown():
    source = (
        "def f():\n    try: g()\n    except E as error:\n"
        "        raise UserError(f'--shaft {path}: {error}') from None\n"
        "    except F as error:\n        raise refused('assembly', str(error))\n"
    )
    assert not _message_reads(ast.parse(source))
