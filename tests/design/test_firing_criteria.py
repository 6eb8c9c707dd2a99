"""mc.firing_orders' criteria beside δ: each row's free moments and bearing load against
mc.shaking_forces and mc.bearing_loads of its machine, its torsional merit against
mc.torsional_merit of its machine, its torsional criteria of major and minor orders against a
brute force from its phases (each cylinder's own torque sampled and transformed by numpy's FFT,
weighted by mass-normalised shapes from numpy's eigen solver, majors by exact rationals), the
Pareto marks against a brute-force pairwise comparison written here, rank_by, and the rows that
a rigid shaft cannot tell apart but the shaft's vector sums can."""

from __future__ import annotations

import cmath
import math
from fractions import Fraction
from itertools import product

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import multicrank as mc
from multicrank.design import criteria

from ..torsion.test_merit import chain, cylinder_torque
from ..torsion.test_merit_modal import normalised_shapes

INLINE_4 = mc.presets.MACHINES["inline-4"]
SHAFT_4 = mc.Shaft([0.02, 0.02, 0.02, 0.02, 0.3], [3e5, 3e5, 3e5, 4e5], cylinder_nodes=[0, 1, 2, 3])
CRITERIA = ["delta", "free_moment_1", "free_moment_2", "max_bearing_load", "torsional_major", "torsional_minor"]
RANKINGS = [*CRITERIA, "torsional_merit"]


def v6_two_stroke() -> mc.Machine:
    """A two-stroke 60° V6, placed along the shaft, its cylinders unlike (so that the throws'
    order matters), with a shaft of a node per throw and a flywheel."""
    cylinder = mc.presets.MACHINES["marine-2t-twin"].cylinders[0]
    small = cylinder.replace(crank_radius=0.05, rod_length=0.2, rod_cg=0.13, piston_mass=2.0, rod_mass=2.5, bore=0.1)
    machine = mc.Machine.from_layout("v6-60", small, shaft_inertia=1.0, strokes=2, rpm=1500, cylinder_spacing=0.15)
    machine = machine.replace(
        cylinders=[c.replace(piston_mass=2.0 + 0.3 * j) for j, c in enumerate(machine.cylinders)],
        rpm_range=(600, 2400),
    )
    shaft = mc.Shaft([0.05, 0.05, 0.05, 1.5], [4e5, 4e5, 6e5], cylinder_nodes=list(machine.throw_index))
    return machine.replace(shaft=shaft)


def brute_pareto(rows: list[list[float]]) -> list[bool]:
    """Pairwise, with NaN worst and values equal to 1e-8 of the column's largest equal."""
    columns = np.array(rows, dtype=float).T
    scaled = []
    for column in columns:
        finite = np.isfinite(column)
        scale = (np.abs(column[finite]).max() if finite.any() else 0.0) or 1.0
        scaled.append([round(v / (1e-8 * scale)) if math.isfinite(v) else math.inf for v in column])
    points = list(zip(*scaled, strict=True))
    front = []
    for i, a in enumerate(points):
        dominated = False
        for j, b in enumerate(points):
            no_worse = all(y <= x for x, y in zip(a, b, strict=True))
            if j != i and no_worse and any(y < x for x, y in zip(a, b, strict=True)):
                dominated = True
        front.append(not dominated)
    return front


@given(
    rows=st.integers(0, 40).flatmap(
        lambda n: st.lists(st.lists(st.integers(0, 3), min_size=3, max_size=3), min_size=n, max_size=n)
    ),
    block=st.integers(1, 8),
)
def test_pareto_marks_match_a_pairwise_comparison_of_any_scores(rows, block):
    """Ties, repeated rows and fronts larger than a block (small values in few columns make
    all three common); blocks of one row up to more than the rows."""
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(criteria, "_BLOCK", block)
        found = criteria.pareto_front(np.array(rows, dtype=np.int64).reshape(len(rows), 3))
    assert found.tolist() == (brute_pareto(rows) if rows else [])


@pytest.mark.parametrize("case", ["inline-4", "v6-2t"])
def test_every_row_s_criteria_are_those_of_its_machine(case):
    machine = INLINE_4.replace(shaft=SHAFT_4) if case == "inline-4" else v6_two_stroke()
    table = mc.firing_orders(machine, max_order=8)
    rpm = table.attrs["rpm"]
    low, high = table.attrs["speed_range"]
    assert (low, high) == machine.rpm_range
    for _, row in table.iterrows():
        orders = mc.shaking_forces(row["machine"], rpm).orders
        moment = orders["moment_forward"] + orders["moment_backward"]
        assert row["free_moment_1"] == pytest.approx(moment.get(1.0, 0.0), rel=1e-9, abs=1e-9)
        assert row["free_moment_2"] == pytest.approx(moment.get(2.0, 0.0), rel=1e-9, abs=1e-9)
        loads = mc.bearing_loads(row["machine"], rpm)
        assert row["max_bearing_load"] == pytest.approx(loads.magnitude.max(), rel=1e-9)
        merit = mc.torsional_merit(row["machine"], modes=1, max_order=8, rpm_range=(low, high))
        assert row["torsional_merit"] == pytest.approx(merit["excitation"].max() if len(merit) else 0.0, rel=1e-9)
        major, minor = brute_torsion(row["machine"], machine.shaft, 2, 8, (low, high))
        assert row["torsional_major"] == pytest.approx(major, rel=2e-3, abs=1e-6 * max(major, minor))
        assert row["torsional_minor"] == pytest.approx(minor, rel=2e-3, abs=1e-6 * max(major, minor))
    assert table["pareto"].tolist() == brute_pareto(table[CRITERIA].to_numpy().tolist())
    assert table["pareto"].any()


def test_firings_alike_on_a_rigid_shaft_are_separate_rows_where_the_frame_tells_them_apart():
    table = mc.firing_orders(INLINE_4)
    assert table.attrs["distinct"] == 4
    # 1-2+3-4 and 1+4-3-2 run alike (one δ) but load the bearings differently.
    pair = table.set_index("firing").loc[["1-2+3-4", "1+4-3-2"]]
    assert pair["delta"].iloc[0] == pair["delta"].iloc[1]
    assert pair["max_bearing_load"].iloc[0] > 1.2 * pair["max_bearing_load"].iloc[1]
    # Without the places along the shaft the frame cannot tell them apart either: one row.
    unplaced = INLINE_4.replace(cylinders=[c.replace(axial_position=0.0) for c in INLINE_4.cylinders])
    assert mc.firing_orders(unplaced).attrs["distinct"] == 3


@pytest.mark.parametrize("criterion", RANKINGS)
def test_rank_by_sorts_by_any_criterion_ties_kept_in_the_candidates_order(criterion):
    machine = v6_two_stroke()
    table = mc.firing_orders(machine, rank_by=criterion, max_order=8)
    values = table[criterion].to_numpy()
    scale = np.nanmax(np.abs(values))
    assert np.all(np.diff(values) >= -1e-8 * scale)
    assert table.attrs["rank_by"] == criterion
    assert set(table["firing"]) == set(mc.firing_orders(machine, max_order=8)["firing"])


def test_without_a_shaft_there_is_no_torsional_merit():
    table = mc.firing_orders(INLINE_4)
    assert not {"torsional_merit", "torsional_major", "torsional_minor"} & set(table.columns)
    assert table.attrs["criteria"] == tuple(CRITERIA[:-2])
    assert table.attrs["speed_range"] is None
    # The shaft given to the call counts as the machine's own.
    given = mc.firing_orders(INLINE_4, shaft=SHAFT_4)
    own = mc.firing_orders(INLINE_4.replace(shaft=SHAFT_4))
    assert given.drop(columns="machine").equals(own.drop(columns="machine"))


def test_a_machine_without_a_speed_range_weighs_resonances_up_to_its_speed():
    machine = INLINE_4.replace(rpm_range=None, shaft=SHAFT_4)
    table = mc.firing_orders(machine)
    assert table.attrs["speed_range"] == (0.0, machine.rpm)
    for _, row in table.iterrows():
        merit = mc.torsional_merit(row["machine"], modes=1, rpm_range=(1e-3, machine.rpm))
        assert row["torsional_merit"] == pytest.approx(merit["excitation"].max(), rel=1e-9)


@pytest.mark.parametrize(
    ("kwargs", "named"),
    [
        ({"rank_by": "smoothness"}, "rank_by"),
        ({"rank_by": "torsional_merit"}, "shaft"),
        ({"rank_by": "torsional_minor"}, "shaft"),
        ({"shaft": SHAFT_4, "modes": 0}, "modes"),
        ({"shaft": "stiff"}, "shaft"),
        ({"shaft": mc.Shaft([1.0, 1.0], [1e5], cylinder_nodes=[0, 0])}, "cylinder_nodes"),
    ],
)
def test_bad_input_is_refused_by_name(kwargs, named):
    with pytest.raises(mc.MechanismError, match=named):
        mc.firing_orders(INLINE_4, **kwargs)


def major_order(machine: mc.Machine, order: float) -> bool:
    """Whether every cylinder fires in phase for ``order``, by exact rationals of the firing
    angles in degrees (the layouts' phases are whole degrees)."""
    firing = [Fraction(round(math.degrees(-c.phase) % math.degrees(machine.cycle))) for c in machine.cylinders]
    return all((Fraction(order) * (t - firing[0]) / 360).denominator == 1 for t in firing)


def brute_torsion(
    machine: mc.Machine, shaft: mc.Shaft, modes: int, highest: int, window: tuple[float, float]
) -> tuple[float, float]:
    """The largest abs(Σ_j φ_j T_ν,j) over the (mode, order) resonances in ``window`` [1/min]
    of the major and of the minor orders: φ mass-normalised (numpy), T_ν,j the FFT of
    cylinder j's own torque at its own phase (no shift theorem), gas and gravity sampled once
    and the inertia torque once per (rad/s)²."""
    frequency, shapes = normalised_shapes(shaft)
    points = 2**13
    phi = machine.cycle * np.arange(points) / points
    parts = []
    for j in range(len(machine)):
        base = cylinder_torque(machine, j, phi, 0.0)
        inertia = cylinder_torque(machine, j, phi, 30 / math.pi) - base  # at ω = 1 rad/s
        parts.append((np.fft.rfft(base) / points * 2, np.fft.rfft(inertia) / points * 2))
    step = 0.5 if machine.strokes == 4 else 1.0
    found = {True: 0.0, False: 0.0}
    for mode in range(modes):
        weights = shapes[list(shaft.cylinder_nodes), mode]
        for order in np.arange(step, highest + step / 2, step):
            speed = 60 * frequency[mode] / order
            if not window[0] <= speed <= window[1]:
                continue
            omega = speed * math.pi / 30
            k = round(order * machine.cycle / (2 * math.pi))
            value = abs(
                sum(w * (base[k] + inertia[k] * omega**2) for w, (base, inertia) in zip(weights, parts, strict=True))
            )
            major = major_order(machine, order)
            found[major] = max(found[major], value)
    return found[True], found[False]


def test_firing_orders_whose_minor_vector_sums_differ_are_separate_rows():
    """An in-line six (four-stroke) with a flywheel at one end: its 32 phase assignments, made
    here, fall into as many rows as they have distinct vector sums over every order and the
    two modes (relative amplitudes from numpy's eigen solver, sums by Python's complex numbers)
    — firing orders that run alike on a rigid shaft but excite the shaft differently are not
    merged. Where a major order resonates in the speed range, torsional_major is the same in
    every row and torsional_minor tells them apart."""
    six = mc.presets.MACHINES["inline-6"]
    # So stiff that no order up to 12 resonates in the speed range: only the sums tell rows apart.
    stiff = six.replace(shaft=chain(six, throw=0.05, flywheel=1.5, stiffness=2e9))
    shaft = stiff.shaft
    _, shapes = normalised_shapes(shaft)
    relative = shapes[list(shaft.cylinder_nodes), :2]
    relative = relative / np.abs(relative).max(axis=0)
    orders = np.arange(0.5, 12.25, 0.5)

    def signature(phases: list[float]) -> tuple[float, ...]:
        sums = []
        for mode in range(2):
            for order in orders:
                total = sum(
                    a * cmath.exp(1j * order * ((-p) % (4 * math.pi)))
                    for a, p in zip(relative[:, mode], phases, strict=True)
                )
                sums.append(round(abs(total), 6))
        return tuple(sums)

    base = [c.phase for c in stiff.cylinders]
    candidates = {signature([base[0]] + [p + 2 * math.pi * b for p, b in zip(base[1:], bits, strict=True)])
                  for bits in product((0, 1), repeat=5)}  # fmt: skip
    table = mc.firing_orders(stiff, modes=2, max_order=12)
    assert (table[["torsional_major", "torsional_minor", "torsional_merit"]].to_numpy() == 0).all()
    rows = {signature(list(p)) for p in table["phases"]}
    assert rows == candidates
    assert len(table) >= len(candidates) > 1
    machine = six.replace(shaft=chain(six, throw=0.05, flywheel=1.5, stiffness=2e6))
    table = mc.firing_orders(machine, modes=2, max_order=12)
    # The rows with the even firing's major orders (by exact rationals) share its major part.
    even = [major_order(machine, order) for order in orders]
    alike = table[[[major_order(m, order) for order in orders] == even for m in table["machine"]]]
    majors = alike["torsional_major"].to_numpy()
    minors = alike["torsional_minor"].to_numpy()
    assert len(alike) > 1 and majors.max() > 0 and np.ptp(majors) <= 1e-9 * majors.max()
    assert np.ptp(minors) > 0.1 * minors.max()
    ranked = mc.firing_orders(machine, modes=2, max_order=12, rank_by="torsional_minor")
    assert np.all(np.diff(ranked["torsional_minor"].to_numpy()) >= -1e-8 * ranked["torsional_minor"].max())
