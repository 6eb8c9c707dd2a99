"""Tests of the public Python API of multicrank when it runs in parallel.

Covered: serial == parallel bit for bit (large φ, many designs), concurrent calls from Python
threads, fork-safety after rayon's pool exists, no threads at import, metadata (version, build
profile, the public names). The helpers and the numpy reference come from
tests/gravity/test_evaluation.py; the fixture ``restore_threshold`` from tests/gravity/conftest.py.
"""

from __future__ import annotations

import concurrent.futures
import math
import multiprocessing
import os
import subprocess
import sys
import threading

import numpy as np
import pytest

import multicrank as mc
from tests.gravity.test_evaluation import (
    DESIGN,
    FAST,
    HUGE_THRESHOLD,
    QUANTITIES,
    assert_bits_equal,
    assert_matches_reference,
)

# ---------------------------------------------------------------------------------------
# 5. serial == parallel, bit for bit
# ---------------------------------------------------------------------------------------


def _serial_and_parallel(call):
    mc.set_parallel_threshold(HUGE_THRESHOLD)
    serial = call()
    mc.set_parallel_threshold(0)
    parallel = call()
    return serial, parallel


def test_threshold_roundtrip(restore_threshold):
    for value in (0, 1, 12345, HUGE_THRESHOLD, np.int64(77)):
        mc.set_parallel_threshold(value)
        assert mc.get_parallel_threshold() == int(value)
    assert isinstance(mc.get_parallel_threshold(), int)


@pytest.mark.parametrize("name", QUANTITIES)
def test_serial_equals_parallel_large_phi(name, restore_threshold):
    phi = np.linspace(-30.0, 30.0, 200_003)
    phases = mc.crank_phases(4, 4)

    def call():
        return FAST[name](phi, phases=phases, **DESIGN)

    serial, parallel = _serial_and_parallel(call)
    assert np.array_equal(serial, parallel)
    assert_matches_reference(name, phi[::97], phases=phases, **DESIGN)
    assert_bits_equal(serial[::97], FAST[name](phi[::97], phases=phases, **DESIGN))


@pytest.mark.parametrize("name", QUANTITIES)
def test_serial_equals_parallel_many_designs(name, restore_threshold):
    rng = np.random.default_rng(5)
    phi = rng.uniform(-10, 10, size=997)
    design = dict(
        crank_ratio=rng.uniform(0, 0.95, size=500),
        inclination=rng.uniform(-3.2, 3.2, size=500),
        u1=rng.uniform(0, 2, size=500),
        u2=rng.uniform(-2, 2, size=500),
    )
    phases = mc.crank_phases(3)

    def call():
        return FAST[name](phi, phases=phases, **design)

    serial, parallel = _serial_and_parallel(call)
    assert serial.shape == (500, 997)
    assert np.array_equal(serial, parallel)
    mc.set_parallel_threshold(0)
    assert_matches_reference(name, phi, phases=phases, **design)
    # rows straddle the parallel chunks: each row equals that design alone
    for row in (0, 8, 9, 250, 499):
        alone = FAST[name](phi, phases=phases, **{k: float(v[row]) for k, v in design.items()})
        assert_bits_equal(parallel[row], alone)


# ---------------------------------------------------------------------------------------
# 6. concurrent calls from Python threads
# ---------------------------------------------------------------------------------------


def _thread_job(i):
    rng = np.random.default_rng(100 + i)
    phi = rng.uniform(-8, 8, size=60_000)
    design = dict(
        crank_ratio=rng.uniform(0, 0.9, size=(12, 1)),
        inclination=rng.uniform(-3, 3, size=4),
        u1=rng.uniform(0, 2),
        u2=rng.uniform(-1, 1, size=4),
    )
    phases = mc.crank_phases(1 + i % 6, 2 if i % 2 else 4)
    return phi, design, phases


@pytest.mark.parametrize("threshold", [0, 50_000, HUGE_THRESHOLD], ids=["parallel", "default-ish", "serial"])
def test_concurrent_threads(threshold, restore_threshold):
    jobs = [_thread_job(i) for i in range(8)]
    mc.set_parallel_threshold(HUGE_THRESHOLD)
    expected = [mc.generalized_force(phi, phases=phases, **design) for phi, design, phases in jobs]
    mc.set_parallel_threshold(threshold)
    barrier = threading.Barrier(8)

    def work(i):
        phi, design, phases = jobs[i]
        barrier.wait(timeout=600)
        results = []
        for _ in range(3):
            results.append(mc.generalized_force(phi, phases=phases, **design))
        return results

    with concurrent.futures.ThreadPoolExecutor(max_workers=8) as pool:
        futures = [pool.submit(work, i) for i in range(8)]
        outcomes = [f.result(timeout=600) for f in futures]
    for i, results in enumerate(outcomes):
        assert expected[i].shape == (12, 4, 60_000)
        for result in results:
            assert np.array_equal(result, expected[i]), f"thread {i} differs"


# ---------------------------------------------------------------------------------------
# 7. fork after rayon's pool exists; no threads at import
# ---------------------------------------------------------------------------------------

FORK_PHI_SIZE = 300_001
FORK_DESIGN = dict(crank_ratio=[0.2, 0.35], inclination=[[1.0], [-0.4]], u1=0.8, u2=-0.3)


def _fork_child_compute(size):
    phi = np.linspace(-12.0, 12.0, size)
    mc.set_parallel_threshold(0)  # ask for parallel; must not hang in the child
    result = mc.generalized_force(phi, phases=mc.crank_phases(3), **FORK_DESIGN)
    energy = mc.potential_energy(phi, phases=mc.crank_phases(3), **FORK_DESIGN)
    return result, float(np.sum(energy))


@pytest.mark.filterwarnings("ignore::DeprecationWarning")
def test_fork_after_parallel_run(restore_threshold):
    phi = np.linspace(-12.0, 12.0, FORK_PHI_SIZE)
    mc.set_parallel_threshold(0)
    # run a parallel computation in the parent first, so that rayon's pool exists
    parent = mc.generalized_force(phi, phases=mc.crank_phases(3), **FORK_DESIGN)
    parent_energy = float(np.sum(mc.potential_energy(phi, phases=mc.crank_phases(3), **FORK_DESIGN)))
    assert parent.shape == (2, 2, FORK_PHI_SIZE)
    context = multiprocessing.get_context("fork")
    pool = context.Pool(processes=1)
    try:
        child, child_energy = pool.apply_async(_fork_child_compute, (FORK_PHI_SIZE,)).get(timeout=600)
        # a second task in the same child still works
        again, _ = pool.apply_async(_fork_child_compute, (1001,)).get(timeout=600)
    finally:
        pool.terminate()
        pool.join()
    assert np.array_equal(child, parent)
    assert child_energy == parent_energy
    mc.set_parallel_threshold(0)
    assert_bits_equal(
        again, mc.generalized_force(np.linspace(-12.0, 12.0, 1001), phases=mc.crank_phases(3), **FORK_DESIGN)
    )
    # the parent's pool still works after the fork
    assert np.array_equal(mc.generalized_force(phi, phases=mc.crank_phases(3), **FORK_DESIGN), parent)


def _fork_queue_child(queue):
    phi = np.linspace(-12.0, 12.0, FORK_PHI_SIZE)
    result = mc.generalized_force(phi, phases=mc.crank_phases(3), **FORK_DESIGN)
    queue.put(float(np.sum(result * np.arange(result.size).reshape(result.shape))))


@pytest.mark.filterwarnings("ignore::DeprecationWarning")
def test_fork_process_queue_checksum(restore_threshold):
    phi = np.linspace(-12.0, 12.0, FORK_PHI_SIZE)
    mc.set_parallel_threshold(0)
    parent = mc.generalized_force(phi, phases=mc.crank_phases(3), **FORK_DESIGN)
    checksum = float(np.sum(parent * np.arange(parent.size).reshape(parent.shape)))
    context = multiprocessing.get_context("fork")
    queue = context.Queue()
    process = context.Process(target=_fork_queue_child, args=(queue,))
    process.start()
    try:
        child_checksum = queue.get(timeout=600)
    finally:
        process.join(timeout=600)
        if process.is_alive():
            process.kill()
            process.join()
    assert process.exitcode == 0
    assert child_checksum == checksum


_THREAD_PROBE = """
import threading
import multicrank
threads = [l for l in open('/proc/self/status') if l.startswith('Threads:')][0].split()[1]
print(threading.active_count(), threads)
"""


@pytest.mark.skipif(not os.path.exists("/proc/self/status"), reason="needs /proc")
def test_import_spawns_no_threads():
    # OpenBLAS (loaded by numpy) starts its own pool unless told not to: isolate multicrank.
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1", MKL_NUM_THREADS="1")
    completed = subprocess.run(
        [sys.executable, "-c", _THREAD_PROBE], capture_output=True, text=True, timeout=600, env=env
    )
    assert completed.returncode == 0, completed.stderr
    python_threads, os_threads = completed.stdout.split()
    assert python_threads == "1"
    assert os_threads == "1"


@pytest.mark.skipif(not os.path.exists("/proc/self/status"), reason="needs /proc")
def test_import_adds_no_threads_over_numpy():
    probe = """
import numpy
def count():
    return int([l for l in open('/proc/self/status') if l.startswith('Threads:')][0].split()[1])
before = count()
import multicrank
multicrank.crank_phases(3)
print(before, count())
"""
    completed = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, timeout=600)
    assert completed.returncode == 0, completed.stderr
    before, after = completed.stdout.split()
    assert before == after


# ---------------------------------------------------------------------------------------
# 8. metadata
# ---------------------------------------------------------------------------------------


def test_metadata():
    assert isinstance(mc.__version__, str) and mc.__version__
    assert mc._native.build_profile == mc.build_profile
    assert "MechanismError" in mc.__all__
    assert issubclass(mc.MechanismError, ValueError)
    assert mc.MechanismError is mc._native.MechanismError
    for name in (
        "crank_phases",
        "dimensionless_moments",
        "potential_energy",
        "generalized_force",
        "force_derivative",
        "set_parallel_threshold",
        "get_parallel_threshold",
    ):
        assert callable(getattr(mc, name))
    assert math.isclose(float(mc.crank_phases(2)[1]), math.pi)


@pytest.mark.skipif(
    "MULTICRANK_EXPECT_BUILD_PROFILE" not in os.environ, reason="only where the build's profile is known (scripts/test)"
)
def test_build_profile_is_the_one_built():
    # scripts/test builds the wheel with pyproject's profile = "release" and says so here; a
    # debug extension would pass every other test, 10-50x slower.
    assert mc.build_profile == os.environ["MULTICRANK_EXPECT_BUILD_PROFILE"]
