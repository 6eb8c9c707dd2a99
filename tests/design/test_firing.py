"""mc.firing_orders: the candidates against brute force over every phase assignment (four
strokes) and every permutation of the throws (two strokes), with an oracle that shares
nothing with the library's way of telling motions apart: each brute-force machine's gas
torque, gravity torque and J sampled over the cycle, compared under every cyclic shift of
the samples (found by FFT cross-correlation, then checked point by point)."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

import multicrank as mc

CYLINDER = mc.Cylinder(
    crank_radius=0.045, rod_length=0.15, piston_mass=0.6, rod_mass=0.55, rod_cg=0.1, bore=0.085,
    crank_mass=1.1, crank_cg_radius=0.025, counterweight_mass=0.8, counterweight_radius=0.04,
    pressure=mc.presets.MACHINES["inline-4"].cylinders[0].pressure,
)  # fmt: skip
TWO_STROKE = CYLINDER.replace(pressure=mc.presets.MACHINES["marine-2t-twin"].cylinders[0].pressure)
SAMPLES = 1440  # half a degree over 4π: every phase and shift here is a whole number of samples
RPM = 2400.0


def signature(machine: mc.Machine) -> np.ndarray:
    """What the motion depends on, over 4π (both cycles): gas torque, gravity torque, J."""
    phi = np.arange(SAMPLES) * 4 * math.pi / SAMPLES
    return np.stack([machine.gas_torque(phi), machine.gravity_torque(phi), machine.reduced_inertia(phi)[0]])


def same_motion(a: np.ndarray, b: np.ndarray) -> bool:
    """Whether b is a shifted by some whole number of samples, every row to 1e-9 of its size
    and 1e-12 in its SI unit (a boxer's gravity cancels to ~1e-17 N·m)."""
    size = np.maximum(np.abs(a).max(axis=1), np.abs(b).max(axis=1))[:, None]
    tolerance = 1e-9 * size + 1e-12
    # Σ_rows Σ_i (a_i − b_{i+s})² / size² for every s at once; its smallest few checked directly.
    a_n, b_n = a / (size + 1e-6), b / (size + 1e-6)
    spectrum = np.conj(np.fft.rfft(a_n, axis=1)) * np.fft.rfft(b_n, axis=1)
    cross = np.fft.irfft(spectrum, n=a.shape[1], axis=1).sum(axis=0)
    distance = (a_n**2).sum() + (b_n**2).sum() - 2 * cross
    return any(np.all(np.abs(np.roll(b, -shift, axis=1) - a) <= tolerance) for shift in np.argsort(distance)[:4])


def classes(machines: list[mc.Machine]) -> list[np.ndarray]:
    """One signature per class of machines that run alike."""
    found: list[np.ndarray] = []
    for machine in machines:
        mark = signature(machine)
        if not any(same_motion(known, mark) for known in found):
            found.append(mark)
    return found


def with_phases(machine: mc.Machine, phases) -> mc.Machine:
    return machine.replace(
        cylinders=[c.replace(phase=float(a)) for c, a in zip(machine.cylinders, phases, strict=True)]
    )


def every_assignment(machine: mc.Machine) -> list[mc.Machine]:
    """Brute force, four strokes: every cylinder at its phase or 2π later, cylinder 0 too."""
    own = np.array([c.phase for c in machine.cylinders])
    return [
        with_phases(machine, np.mod(own + 2 * math.pi * np.array(moved), 4 * math.pi))
        for moved in itertools.product((0, 1), repeat=len(machine))
    ]


def every_arrangement(machine: mc.Machine) -> list[mc.Machine]:
    """Brute force, two strokes: every permutation of the throws' angles over the throws
    (cylinders whose pins coincide, pin = α + γ; each keeps its inclination: α = pin − γ)."""
    pins = np.round(np.degrees([c.phase + c.inclination for c in machine.cylinders]), 6) % 360
    angles = sorted(set(pins.tolist()))
    machines = []
    for order in itertools.permutations(angles):
        moved = dict(zip(angles, order, strict=True))
        machines.append(
            with_phases(
                machine, [math.radians(moved[p]) - c.inclination for p, c in zip(pins, machine.cylinders, strict=True)]
            )
        )
    return machines


def frame_mark(machine: mc.Machine) -> tuple[float, float, float]:
    """The frame's criteria of a machine, each by its own function: the first- and
    second-order free moments (forward + backward) and the largest main-bearing load."""
    orders = mc.shaking_forces(machine, RPM).orders
    moment = orders["moment_forward"] + orders["moment_backward"]
    largest = float(mc.bearing_loads(machine, RPM).magnitude.max())
    return float(moment.get(1.0, 0.0)), float(moment.get(2.0, 0.0)), largest


def same_frame(a, b) -> bool:
    return all(abs(x - y) <= 1e-6 * max(abs(x), abs(y), 1e-3) for x, y in zip(a, b, strict=True))


def check_against(table, oracle_machines) -> None:
    """The rows against brute force: every class of candidates that run alike (by the sampled
    torques) split by what the frame feels (by shaking_forces and bearing_loads of each)."""
    oracle: list[tuple[np.ndarray, tuple[float, float, float]]] = []
    for machine in oracle_machines:
        mark, frame = signature(machine), frame_mark(machine)
        if not any(same_motion(known, mark) and same_frame(loads, frame) for known, loads in oracle):
            oracle.append((mark, frame))
    assert table.attrs["distinct"] == len(table) == len(oracle)
    rows = [(signature(m), frame_mark(m)) for m in table["machine"]]
    for i, j in itertools.combinations(range(len(rows)), 2):
        alike = same_motion(rows[i][0], rows[j][0]) and same_frame(rows[i][1], rows[j][1])
        assert not alike, (table["firing"][i], table["firing"][j])
        if same_motion(rows[i][0], rows[j][0]):  # one class on a rigid shaft: one steady state
            assert table["delta"][i] == table["delta"][j]
    # Complete: every brute-force class has its row (distinct rows as many as classes).
    for mark, frame in oracle:
        assert any(same_motion(row, mark) and same_frame(loads, frame) for row, loads in rows)
    for i, (_, frame) in enumerate(rows):
        expected = [table[name][i] for name in ("free_moment_1", "free_moment_2", "max_bearing_load")]
        np.testing.assert_allclose(expected, frame, rtol=1e-9, atol=1e-9)
    assert table["delta"].is_monotonic_increasing


@pytest.mark.parametrize("layout", ["inline-4-4t", "boxer-4", "v6-60", "inline-5-4t", "inline-6-4t"])
def test_the_four_stroke_candidates_are_complete_and_distinct(layout):
    machine = mc.Machine.from_layout(layout, CYLINDER, shaft_inertia=0.25, strokes=4, rpm=RPM)
    table = mc.firing_orders(machine, max_order=4)
    assert table.attrs["exhaustive"] and table.attrs["candidates"] == 2 ** (len(machine) - 1)
    check_against(table, every_assignment(machine))


@pytest.mark.parametrize("k", [3, 4, 5])
def test_the_two_stroke_candidates_are_complete_and_distinct(k):
    # Unlike cylinders (so that the throws' order matters), then two pairs alike.
    layout = f"inline-{k}-2t"
    unlike = mc.Machine.from_layout(layout, TWO_STROKE, shaft_inertia=0.25, strokes=2, rpm=RPM)
    unlike = unlike.replace(cylinders=[c.replace(piston_mass=0.4 + 0.1 * j) for j, c in enumerate(unlike.cylinders)])
    table = mc.firing_orders(unlike)
    assert table.attrs["candidates"] == math.factorial(k - 1) and table.attrs["exhaustive"]
    check_against(table, every_arrangement(unlike))
    masses = [0.5, 0.7, 0.5, 0.7, 0.9][:k]
    paired = unlike.replace(cylinders=[c.replace(piston_mass=m) for c, m in zip(unlike.cylinders, masses, strict=True)])
    check_against(mc.firing_orders(paired), every_arrangement(paired))


def test_alike_throws_arrange_one_way():
    # Alike cylinders in line, unplaced: every arrangement of the throws is the same machine.
    inline = mc.Machine.from_layout("inline-3-2t", TWO_STROKE, shaft_inertia=0.25, strokes=2, rpm=RPM)
    table = mc.firing_orders(inline)
    assert table.attrs["candidates"] == table.attrs["distinct"] == 1
    # Twelve alike throws taken off their places: one arrangement, found without visiting 11!
    # permutations. Placed along the shaft the frame tells every arrangement apart: 11! of
    # them (the first turned to its angle), the first max_candidates made.
    placed = mc.presets.MACHINES["slow-diesel-12"]
    diesel = placed.replace(cylinders=[c.replace(axial_position=0.0) for c in placed.cylinders])
    assert mc.firing_orders(diesel).attrs["candidates"] == 1
    table = mc.firing_orders(placed, max_candidates=30)
    assert table.attrs["candidates"] == math.factorial(11) and not table.attrs["exhaustive"]
    assert len(table) > 1 and table["as_given"].sum() == 1
    # A cross-plane V8's throws each carry one cylinder of each bank: alike too.
    v8 = mc.Machine.from_layout("v8-cross", TWO_STROKE, shaft_inertia=0.25, strokes=2, rpm=RPM)
    check_against(mc.firing_orders(v8), every_arrangement(v8))


def test_the_standard_in_line_six_order_is_among_them_with_its_delta():
    # A real in-line six crank (throws 0°, 240°, 120°, 120°, 240°, 0° from cylinder 1), firing
    # 1-5-3-6-2-4: cylinder j fires at φ = −α_j mod 720°.
    fires = {1: 0, 5: 120, 3: 240, 6: 360, 2: 480, 4: 600}
    cylinders = [CYLINDER.replace(phase=math.radians((-fires[j]) % 720)) for j in range(1, 7)]
    machine = mc.Machine(cylinders, shaft_inertia=0.4, strokes=4, rpm=2000)
    table = mc.firing_orders(machine, max_order=6)
    row = table[table["firing"] == "1-5-3-6-2-4"]
    assert len(row) == 1
    assert row["delta"].iloc[0] == mc.steady_state(machine).delta
    assert table["firing"].iloc[0] == "1-5-3-6-2-4"  # the even firing shakes least
    assert row["largest_order"].iloc[0] == 3.0  # an even-firing six: its gas's third order


def test_the_cross_plane_v8_fires_evenly_and_is_among_them():
    machine = mc.Machine.from_layout("v8-cross", CYLINDER, shaft_inertia=0.4, strokes=4, rpm=2000)
    fire_times = np.sort(np.mod(-np.array([c.phase for c in machine.cylinders]), 4 * math.pi))
    np.testing.assert_allclose(np.diff(fire_times), math.pi / 2, atol=1e-12)
    table = mc.firing_orders(machine, max_order=4)
    mark = signature(machine)
    matches = [i for i, m in enumerate(table["machine"]) if same_motion(signature(m), mark)]
    # Its class may hold firings that load the frame otherwise (separate rows), the machine
    # as given among them.
    assert table.index[table["as_given"]].tolist() == [0]
    # The same motion, maybe shifted: the same δ to the solver's accuracy.
    for i in matches:
        assert table["delta"].iloc[i] == pytest.approx(mc.steady_state(machine).delta, rel=1e-9)
    assert matches[0] == 0  # even firing is the smoothest


@pytest.mark.parametrize(
    "machine",
    [
        mc.presets.MACHINES["inline-6"],
        mc.Machine.from_layout("boxer-4", CYLINDER, shaft_inertia=0.25, strokes=4, rpm=RPM),
        mc.Machine.from_layout("v8-cross", TWO_STROKE, shaft_inertia=0.25, strokes=2, rpm=RPM),
    ],
)
def test_one_row_is_the_machine_as_given(machine):
    # Each row's own machine made the machine to rank: its row is as_given, and it alone.
    for _, row in mc.firing_orders(machine).iterrows():
        table = mc.firing_orders(row["machine"])
        given = table[table["as_given"]]
        assert len(given) == 1
        assert same_motion(signature(given["machine"].iloc[0]), signature(row["machine"]))
        assert given["delta"].iloc[0] == pytest.approx(row["delta"], rel=1e-9)


def test_each_row_is_its_machine():
    engine = mc.presets.MACHINES["inline-4"]
    table = mc.firing_orders(engine, rpm=3000.0, max_order=6)
    assert table.attrs["rpm"] == 3000.0
    for _, row in table.iterrows():
        state = mc.steady_state(row["machine"], rpm=3000.0)
        # A row's δ is its class's steady state: the same motion, maybe shifted (to rounding).
        assert row["delta"] == pytest.approx(state.delta, rel=1e-12)
        assert row["delta_without_gravity"] == pytest.approx(state.delta_without_gravity, rel=1e-12)
        assert [c.phase for c in row["machine"].cylinders] == list(row["phases"])
        # The largest order, against the whole machine's orders (its own quadrature).
        orders = mc.torque_orders(row["machine"], 3000.0, max_order=6)["total_amplitude"]
        orders = orders[orders.index > 0]
        assert row["largest_order"] == orders.idxmax()
        assert row["largest_order_amplitude"] == pytest.approx(orders.max(), rel=1e-9)


def test_bad_input_is_named():
    machine = mc.presets.MACHINES["inline-4"]
    with pytest.raises(mc.MechanismError, match="max_candidates"):
        mc.firing_orders(machine, max_candidates=0)
    with pytest.raises(mc.MechanismError, match="max_order"):
        mc.firing_orders(machine, max_order=0)
    with pytest.raises(mc.MechanismError, match="rpm"):
        mc.firing_orders(machine, rpm=-5)
    with pytest.raises(mc.MechanismError, match="rpm is required"):
        mc.firing_orders(machine.replace(rpm=None, rpm_range=None))
    with pytest.raises(mc.MechanismError, match="machine"):
        mc.firing_orders("inline-4")
    small = mc.firing_orders(machine, max_candidates=3)
    assert not small.attrs["exhaustive"] and small.attrs["candidates"] == 8


# -- at scale: alike candidates found by signature, not pairwise (issue 26, item 5) -----------


def cycle_samples(machines: list[mc.Machine], points: int = 720) -> np.ndarray:
    """Gas torque, gravity torque and J of each machine over its cycle: (machines, 3, points)."""
    phi = np.arange(points) * machines[0].cycle / points
    return np.array([np.stack([m.gas_torque(phi), m.gravity_torque(phi), m.reduced_inertia(phi)[0]]) for m in machines])


def run_alike(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """(len(a), len(b)) booleans: whether b[j] is a[i] shifted by a whole number of samples,
    every row to 1e-9 of its size and 1e-12 in its SI unit. The shift is the one of least
    squared distance, all of them at once by FFT cross-correlation, then checked point by point."""
    size = np.maximum(np.abs(a).max(axis=(0, 2)), np.abs(b).max(axis=(0, 2)))[:, None]
    tolerance = 1e-9 * size + 1e-12
    a_n, b_n = a / (size + 1e-6), b / (size + 1e-6)
    spectrum_b = np.fft.rfft(b_n, axis=2)
    points = a.shape[2]
    found = np.zeros((len(a), len(b)), dtype=bool)
    for start in range(0, len(a), 16):
        chunk = slice(start, start + 16)
        cross = np.fft.irfft(np.conj(np.fft.rfft(a_n[chunk], axis=2))[:, None] * spectrum_b[None], n=points, axis=3)
        distance = (a_n[chunk] ** 2).sum(axis=(1, 2))[:, None, None] + (b_n**2).sum(axis=(1, 2))[None, :, None]
        best = np.argmin(distance - 2 * cross.sum(axis=2), axis=2)  # (chunk, len(b))
        index = (np.arange(points) + best[:, :, None]) % points
        shifted = np.take_along_axis(np.broadcast_to(b[None], (*best.shape, *b.shape[1:])), index[:, :, None, :], 3)
        found[chunk] = np.all(np.abs(shifted - a[chunk][:, None]) <= tolerance, axis=(2, 3))
    return found


def unlike_two_stroke(k: int) -> mc.Machine:
    """k throws evenly spaced, every cylinder's masses its own and two bores (two gases)."""
    cylinders = [
        TWO_STROKE.replace(
            phase=2 * math.pi * j / k, piston_mass=0.4 + 0.1 * j, rod_mass=0.5 + 0.03 * j, bore=(0.085, 0.09)[j % 2]
        )
        for j in range(k)
    ]
    return mc.Machine(cylinders, shaft_inertia=0.25, strokes=2, rpm=RPM)


def test_an_unlike_six_throw_two_stroke_crank_is_complete_and_distinct():
    """Every one of the 6! arrangements runs as exactly one row, and no two rows run alike."""
    machine = unlike_two_stroke(6)
    table = mc.firing_orders(machine)
    assert table.attrs["exhaustive"] and table.attrs["candidates"] == math.factorial(5)
    rows = cycle_samples(list(table["machine"]))
    brute = cycle_samples(every_arrangement(machine))
    assert len(brute) == math.factorial(6)
    alike = run_alike(brute, rows)
    assert np.all(alike.sum(axis=1) == 1)  # complete, and never two rows for one motion
    assert np.array_equal(run_alike(rows, rows), np.eye(len(rows), dtype=bool))


def test_a_sixteen_throw_unlike_crank_keeps_its_candidates_apart():
    """Sixteen unlike throws (15! arrangements): the first ones made are each their own
    motion (each differs from the others by where the unlike cylinders sit), and the table
    has them all, none twice."""
    machine = unlike_two_stroke(16)
    table = mc.firing_orders(machine, max_candidates=120, max_order=2)
    assert table.attrs["candidates"] == math.factorial(15) and not table.attrs["exhaustive"]
    assert len(table) == table.attrs["distinct"] == 120
    rows = cycle_samples(list(table["machine"]))
    assert np.array_equal(run_alike(rows, rows), np.eye(len(rows), dtype=bool))
    assert len(set(table["phases"])) == 120


def test_telling_candidates_apart_evaluates_each_cylinder_once(monkeypatch):
    """The work of finding alike candidates does not grow with their number: J and gravity
    are evaluated once per cylinder (its Fourier orders moved to each phase), not once per
    pair of candidates and shift as before (100 candidates of sixteen throws took 25 s)."""
    calls = []
    evaluate = mc.Machine.reduced_inertia

    def counted(self, *args, **kwargs):
        calls.append(len(self.cylinders))
        return evaluate(self, *args, **kwargs)

    monkeypatch.setattr(mc.Machine, "reduced_inertia", counted)
    from multicrank.design.firing import _candidates, _groups

    machine = unlike_two_stroke(16)
    counts = []
    for limit in (10, 60):
        phases, _ = _candidates(machine, limit)
        calls.clear()
        assert len(set(_groups(machine, phases).tolist())) == limit
        counts.append(len(calls))
    assert counts[0] == counts[1] <= len(machine)


# -- firing orders as engine people write them (issue 26, item 3) ------------------------------


def fired(order: str, cycle_deg: float = 720.0) -> list[float]:
    """Hand-written: the phases α_j [rad] of a machine that fires ``order`` evenly, cylinder j
    firing at t_j = (its place in the order)·cycle/k, so α_j = −t_j mod the cycle."""
    sequence = [int(c) for c in order.split("-")]
    k = len(sequence)
    return [math.radians(-cycle_deg * sequence.index(j) / k % cycle_deg) for j in range(1, k + 1)]


def test_the_textbook_in_line_cranks_print_their_textbook_orders():
    # Cylinders numbered from the front along the shaft; the layouts are the textbook cranks.
    for layout, order in [
        ("inline-4-4t", "1-3-4-2"),
        ("inline-5-4t", "1-2-4-5-3"),
        ("inline-6-4t", "1-5-3-6-2-4"),
        ("inline-8-4t", "1-6-2-5-8-3-7-4"),
    ]:
        machine = mc.Machine.from_layout(layout, CYLINDER, shaft_inertia=0.25, strokes=4, rpm=RPM)
        np.testing.assert_allclose(np.sort([c.phase for c in machine.cylinders]), np.sort(fired(order)), atol=1e-12)
        table = mc.firing_orders(machine, max_order=2)
        assert table.loc[table["as_given"], "firing"].tolist() == [order]
        assert table["firing"].iloc[0] == order  # even firing runs smoothest
    # The built-in in-line four and six, as the issue found them (1-4-3-2, 1-6-5-4-3-2 before).
    assert mc.firing_orders(mc.presets.MACHINES["inline-4"])["firing"].iloc[0] == "1-3-4-2"
    assert mc.firing_orders(mc.presets.MACHINES["inline-6"], max_order=2)["firing"].iloc[0] == "1-5-3-6-2-4"


@pytest.mark.parametrize(
    ("order", "crank"),
    [
        # (the firing order, the crank's pin angles α mod 360° from cylinder 1, by hand)
        ("1-3-4-2", [0, 180, 180, 0]),
        ("1-2-4-3", [0, 180, 180, 0]),  # the same crank, the other camshaft
        ("1-5-3-6-2-4", [0, 240, 120, 120, 240, 0]),
        ("1-4-2-6-3-5", [0, 120, 240, 240, 120, 0]),  # the mirror-image crank
    ],
)
def test_a_machine_built_to_a_textbook_order_prints_it(order, crank):
    """Read in the direction of rotation from cylinder 1: the machine's own row names its
    own order, and the crank is the one the textbooks draw for it."""
    phases = fired(order)
    np.testing.assert_allclose(np.degrees(np.mod(phases, 2 * math.pi)), crank, atol=1e-9)
    machine = mc.Machine([CYLINDER.replace(phase=a) for a in phases], shaft_inertia=0.4, strokes=4, rpm=2000)
    table = mc.firing_orders(machine, max_order=2)
    assert table.loc[table["as_given"], "firing"].tolist() == [order]
    assert table["firing"].iloc[0] == order


@pytest.mark.parametrize("name", ["genset-v12", "inline-4", "boxer-compressor"])
def test_a_candidate_is_the_machine_its_replace_would_make(name):
    """The candidates skip the machine's checks (only their phases differ): each must be the
    very machine ``Machine.replace`` makes of those cylinders, fields and answers alike."""
    machine = mc.presets.MACHINES[name]
    cylinders = [c.replace(phase=c.phase + 0.25 * j) for j, c in enumerate(machine.cylinders)]
    fast, checked = machine._with_phases(cylinders), machine.replace(cylinders=cylinders)
    assert fast == checked
    assert sorted(fast.__dict__) == sorted(checked.__dict__)
    assert mc.steady_state(fast).delta == mc.steady_state(checked).delta
    assert fast.cylinders == tuple(cylinders)
