"""mc.Shaft.from_opentorsion: an openTorsion model read as a chain, its modes against
openTorsion's own modal analysis (its eigen solver on its assembled matrices), the lumped
element inertias against the lumped matrices written out here, the section and node damping
through the round trip against openTorsion's damping matrix written out here, and what a
chain cannot hold refused by name."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import multicrank as mc

ot = pytest.importorskip("opentorsion")


def chain(inertia, stiffness, *, damping=None, node_damping=None, order=None):
    """An openTorsion chain of disks and massless shaft elements: element i joins nodes i and
    i + 1, listed in ``order``; disk i has the damping to ground ``node_damping[i]``."""
    damping = damping or [0.0] * len(stiffness)
    node_damping = node_damping or [0.0] * len(inertia)
    order = range(len(stiffness)) if order is None else order
    elements = [ot.Shaft(i, i + 1, k=stiffness[i], c=damping[i]) for i in order]
    disks = [ot.Disk(i, I=value, c=c) for i, (value, c) in enumerate(zip(inertia, node_damping, strict=True))]
    return ot.Assembly(elements, disk_elements=disks)


def opentorsion_modes(assembly):
    """openTorsion's undamped modes: its eigenvalues ω² [rad²/s²] of (K, M) sorted, the rigid
    one (ω = 0) dropped, as f [Hz]; the eigenvectors in the same order."""
    values, vectors = assembly.undamped_modal_analysis()
    order = np.argsort(values.real)[1:]
    return np.sqrt(np.maximum(values.real[order], 0.0)) / (2 * math.pi), vectors[:, order].real


@settings(max_examples=40, deadline=None)
@given(
    inertia=st.lists(st.floats(0.01, 5.0), min_size=2, max_size=10),
    data=st.data(),
)
def test_any_chain_has_opentorsions_natural_frequencies_and_mode_shapes(inertia, data):
    sections = len(inertia) - 1
    stiffness = data.draw(st.lists(st.floats(1e4, 1e7), min_size=sections, max_size=sections))
    order = data.draw(st.permutations(range(sections)))
    assembly = chain(inertia, stiffness, order=order)
    shaft = mc.Shaft.from_opentorsion(assembly, cylinder_nodes=[0])
    assert shaft.inertia == pytest.approx(inertia, rel=1e-15) and shaft.stiffness == pytest.approx(stiffness)
    assert shaft.damping is None and shaft.node_damping is None
    modes = shaft.modes()
    expected, vectors = opentorsion_modes(assembly)
    # openTorsion's general solver (scipy's eig on K, M) is good to ~1e-12 of the largest ω².
    np.testing.assert_allclose(modes.natural_frequency, expected, rtol=1e-7, atol=1e-6 * expected.max())
    gaps = np.diff(np.concatenate([[0.0], expected]))
    for m in range(sections):
        if gaps[m] < 1e-3 * expected.max() or (m + 1 < sections and gaps[m + 1] < 1e-3 * expected.max()):
            continue  # a (nearly) repeated frequency has no one shape
        vector = vectors[:, m] / np.abs(vectors[:, m]).max()
        sign = 1.0 if np.dot(vector, modes.shapes[:, m]) > 0 else -1.0
        np.testing.assert_allclose(modes.shapes[:, m], sign * vector, atol=1e-5)


def test_the_damped_modal_analysis_gives_the_same_natural_frequencies():
    inertia, stiffness = [0.02, 0.02, 0.02, 0.02, 0.5], [2e5, 2.5e5, 3e5, 4e5]
    assembly = chain(inertia, stiffness, damping=[2.0, 1.0, 3.0, 2.0])
    shaft = mc.Shaft.from_opentorsion(assembly, cylinder_nodes=[0, 1, 2, 3])
    assert shaft.damping == (2.0, 1.0, 3.0, 2.0)
    # openTorsion's wn = |λ| of the state matrix, undamped (C = 0, as Shaft.modes is): each
    # mode twice (±iω), the rigid mode (0, twice) first.
    wn, _, _ = assembly.modal_analysis(C=np.zeros_like(assembly.M))
    expected = np.sort(wn)[2::2] / (2 * math.pi)
    np.testing.assert_allclose(shaft.modes().natural_frequency, expected, rtol=1e-6)


def test_element_inertias_are_lumped_half_at_each_end():
    # Steel shaft elements by geometry (openTorsion's millimetres): each has its own inertia
    # ρ (π d⁴/32) L and stiffness G (π d⁴/32)/L.
    rho, G = 7800.0, 80e9
    pieces = [(120.0, 60.0), (100.0, 50.0), (150.0, 55.0)]  # (L, d) [mm]
    disks = [0.05, 0.02, 0.03, 0.4]
    elements = [ot.Shaft(i, i + 1, L=L, odl=d, rho=rho, G=G) for i, (L, d) in enumerate(pieces)]
    assembly = ot.Assembly(elements, disk_elements=[ot.Disk(i, I=value) for i, value in enumerate(disks)])
    polar = [math.pi * (d * 1e-3) ** 4 / 32 for _, d in pieces]
    own = [rho * p * L * 1e-3 for p, (L, _) in zip(polar, pieces, strict=True)]
    k = [G * p / (L * 1e-3) for p, (L, _) in zip(polar, pieces, strict=True)]
    # The lumped matrices: each element's inertia half at each of its ends.
    lumped = np.array(disks, dtype=float)
    for i, value in enumerate(own):
        lumped[i : i + 2] += value / 2
    K = np.zeros((4, 4))
    for i, value in enumerate(k):
        K[i : i + 2, i : i + 2] += value * np.array([[1.0, -1.0], [-1.0, 1.0]])
    shaft = mc.Shaft.from_opentorsion(assembly, cylinder_nodes=[1, 2])
    np.testing.assert_allclose(shaft.inertia, lumped, rtol=1e-12)
    np.testing.assert_allclose(shaft.stiffness, k, rtol=1e-12)
    # The rigid body's inertia is openTorsion's: the sum of its consistent mass matrix.
    assert sum(shaft.inertia) == pytest.approx(assembly.M.sum(), rel=1e-12)
    values = np.sort(np.linalg.eigvals(np.linalg.solve(np.diag(lumped), K)).real)[1:]
    expected = np.sqrt(values) / (2 * math.pi)
    found = shaft.modes().natural_frequency
    np.testing.assert_allclose(found, expected, rtol=1e-9)
    # Slightly off openTorsion's consistent-mass frequencies, as documented.
    consistent, _ = opentorsion_modes(assembly)
    assert 1e-6 < np.max(np.abs(found / consistent - 1)) < 0.05


def test_an_element_given_k_and_i_lumps_what_opentorsions_matrix_holds():
    # openTorsion's element of given k and I has the mass matrix I·[[2, 1], [1, 2]]: 6 I in all.
    assembly = ot.Assembly(
        [ot.Shaft(0, 1, k=1e5, I=0.01), ot.Shaft(1, 2, k=2e5)],
        disk_elements=[ot.Disk(0, I=0.1), ot.Disk(1, I=0.05), ot.Disk(2, I=0.2)],
    )
    shaft = mc.Shaft.from_opentorsion(assembly, cylinder_nodes=[0])
    assert shaft.inertia == pytest.approx((0.1 + 0.03, 0.05 + 0.03, 0.2), rel=1e-14)
    assert sum(shaft.inertia) == pytest.approx(assembly.M.sum(), rel=1e-14)


def test_a_machines_model_reads_back_as_its_shaft():
    shaft = mc.Shaft([0.02, 0.03, 0.02, 0.6], [3e5, 2e5, 5e5], cylinder_nodes=[0, 1, 2, 2], damping=[1.0, 0.0, 2.5])
    model = mc.to_opentorsion(mc.presets.MACHINES["inline-4"], shaft=shaft, max_order=2)
    assert mc.Shaft.from_opentorsion(model.assembly, cylinder_nodes=shaft.cylinder_nodes) == shaft
    # With node damping (a damper at the front, a brake at the back) and without section damping.
    damped = mc.Shaft(shaft.inertia, shaft.stiffness, cylinder_nodes=[0, 1, 2, 2], node_damping=[4.0, 0.0, 0.0, 1.5])
    model = mc.to_opentorsion(mc.presets.MACHINES["inline-4"], shaft=damped, max_order=2)
    again = mc.Shaft.from_opentorsion(model.assembly, cylinder_nodes=damped.cylinder_nodes)
    assert again == damped and again.node_damping == (4.0, 0.0, 0.0, 1.5) and again.damping is None


@settings(max_examples=30, deadline=None)
@given(
    inertia=st.lists(st.floats(0.01, 5.0), min_size=2, max_size=8),
    data=st.data(),
)
def test_any_damped_chain_round_trips_through_opentorsion(inertia, data):
    """Shaft → openTorsion → Shaft gives the same shaft, section and node damping included,
    and openTorsion's damping matrix is the one written out here: each section's c_i between
    its two nodes, each node's c_i on the diagonal."""
    n = len(inertia)
    stiffness = data.draw(st.lists(st.floats(1e4, 1e7), min_size=n - 1, max_size=n - 1))
    damping = data.draw(st.none() | st.lists(st.floats(0.0, 50.0), min_size=n - 1, max_size=n - 1))
    node_damping = data.draw(st.none() | st.lists(st.floats(0.0, 50.0), min_size=n, max_size=n))
    shaft = mc.Shaft(inertia, stiffness, cylinder_nodes=[0], damping=damping, node_damping=node_damping)
    model = mc.to_opentorsion(mc.presets.MACHINES["slow-compressor"], shaft=shaft, max_order=1)
    C = np.diag(np.zeros(n) if node_damping is None else np.asarray(node_damping))
    for i, c in enumerate(damping or [0.0] * (n - 1)):
        C[i : i + 2, i : i + 2] += c * np.array([[1.0, -1.0], [-1.0, 1.0]])
    np.testing.assert_allclose(model.assembly.C, C, rtol=1e-15, atol=0)  # summed in another order
    again = mc.Shaft.from_opentorsion(model.assembly, cylinder_nodes=[0])
    # All zeros read back as None (0 everywhere), as the shaft without them is.
    expected = mc.Shaft(
        inertia,
        stiffness,
        cylinder_nodes=[0],
        damping=damping if damping and any(damping) else None,
        node_damping=node_damping if node_damping and any(node_damping) else None,
    )
    assert again == expected


def test_the_disks_damping_is_the_nodes_summed_where_disks_share_one():
    assembly = ot.Assembly(
        [ot.Shaft(0, 1, k=1e5), ot.Shaft(1, 2, k=2e5)],
        disk_elements=[ot.Disk(0, I=0.1, c=1.5), ot.Disk(2, I=0.2, c=0.25), ot.Disk(1, I=0.05), ot.Disk(2, I=0.1, c=2)],
    )
    shaft = mc.Shaft.from_opentorsion(assembly, cylinder_nodes=[0])
    assert shaft.node_damping == (1.5, 0.0, 2.25) and shaft.inertia == pytest.approx((0.1, 0.05, 0.3))
    np.testing.assert_array_equal(np.diag(assembly.C), shaft.node_damping)


def _gears():
    parent = ot.Gear(1, I=0.01, R=50)
    return {"gear_elements": [parent, ot.Gear(2, I=0.02, R=100, parent=parent)]}


def _elastic_gears():
    parent = ot.ElasticGear(1, I=0.01, R=50)
    return {"elastic_gear_elements": [parent, ot.ElasticGear(2, I=0.02, R=100, k=1e6, c=0.0, parent=parent)]}


@pytest.mark.parametrize(
    ("build", "named"),
    [
        (lambda: ot.Assembly([ot.Shaft(0, 1, k=1e5), ot.Shaft(2, 3, k=1e5)], **_gears()), r"gear_elements"),
        (
            lambda: ot.Assembly(
                [ot.Shaft(0, 1, k=1e5), ot.Shaft(2, 3, k=1e5)],
                disk_elements=[ot.Disk(i, I=0.1) for i in range(4)],
                **_elastic_gears(),
            ),
            r"elastic_gear_elements",
        ),
        (
            lambda: ot.Assembly([ot.Shaft(0, 1, k=1e5)], disk_elements=[ot.Disk(0, I=0.1, k=5e3), ot.Disk(1, I=0.1)]),
            r"disk_elements\[0\]\.k = 5000\.0: a stiffness to ground at node 0",
        ),
        (
            lambda: ot.Assembly([ot.Shaft(0, 1, k=1e5)], disk_elements=[ot.Disk(0, I=0.1), ot.Disk(1, I=0.1, c=-2.0)]),
            r"^assembly: node_damping must hold 2 values 0 <= c",
        ),
        (
            lambda: ot.Assembly(
                [ot.Shaft(0, 1, k=1e5)], disk_elements=[ot.Disk(0, I=0.1), ot.Disk(1, I=0.1, c=math.inf)]
            ),
            r"disk_elements\[1\]\.c = inf is not a finite real number",
        ),
        (
            lambda: ot.Assembly([ot.Shaft(0, 2, k=1e5)], disk_elements=[ot.Disk(i, I=0.1) for i in range(3)]),
            r"shaft_elements\[0\] joins nodes 0 and 2",
        ),
        (
            lambda: ot.Assembly(
                [ot.Shaft(0, 1, k=1e5), ot.Shaft(1, 2, k=1e5), ot.Shaft(1, 3, k=1e5)],
                disk_elements=[ot.Disk(i, I=0.1) for i in range(4)],
            ),
            r"shaft_elements\[2\] joins nodes 1 and 3: .*branched",
        ),
        (
            lambda: ot.Assembly([ot.Shaft(0, 1, k=1e5), ot.Shaft(0, 1, k=2e5)], disk_elements=[ot.Disk(0, I=0.1)]),
            r"shaft_elements\[1\] is a second element between nodes 0 and 1",
        ),
        (
            lambda: ot.Assembly(
                [ot.Shaft(0, 1, k=1e5), ot.Shaft(2, 3, k=1e5)], disk_elements=[ot.Disk(i, I=0.1) for i in range(4)]
            ),
            r"no shaft element between nodes 1 and 2: the chain is broken",
        ),
        (
            lambda: ot.Assembly([ot.Shaft(0, 1, k=1e5), ot.Shaft(1, 2, k=1e5)], disk_elements=[ot.Disk(0, I=0.1)]),
            r"node 1 has no inertia",
        ),
        (lambda: chain([0.1, 0.1], [-1e5]), r"^assembly: stiffness\[0\] = -100000\.0 is out of range"),
        (lambda: chain([0.1, -0.1], [1e5]), r"^assembly: inertia\[1\] = -0\.1 is out of range"),
        (lambda: chain([0.1, 0.1], [math.nan]), r"shaft_elements\[0\]\.k = nan is not a finite real number"),
        (lambda: chain([0.1, 0.1], [1e5], damping=[-1.0]), r"^assembly: damping must hold 1 values"),
        (lambda: "a model", r"^assembly must be an opentorsion\.Assembly, got str"),
    ],
)
def test_what_a_chain_cannot_hold_is_refused_by_name(build, named):
    with pytest.raises(mc.MechanismError, match=named):
        mc.Shaft.from_opentorsion(build(), cylinder_nodes=[0])


def test_bad_cylinder_nodes_are_named_as_such():
    assembly = chain([0.1, 0.1, 0.2], [1e5, 1e5])
    for nodes in ([3], [], [0.5]):
        with pytest.raises(mc.MechanismError, match=r"^cylinder_nodes"):
            mc.Shaft.from_opentorsion(assembly, cylinder_nodes=nodes)
