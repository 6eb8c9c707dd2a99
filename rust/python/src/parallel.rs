//! When the kernels go parallel: the module-wide default threshold, a call's own, and
//! serial for good in a forked child (rayon's threads do not survive fork).

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

use multicrank_core as core;
use pyo3::prelude::*;

/// Work (points × cranks) from which kernels run on rayon's pool, unless a call says.
pub(crate) static PARALLEL_THRESHOLD: AtomicUsize =
    AtomicUsize::new(core::Parallelism::DEFAULT_THRESHOLD);
/// Set in a forked child: rayon's pool threads do not survive fork, so stay serial there.
pub(crate) static FORKED_CHILD: AtomicBool = AtomicBool::new(false);

pub(crate) fn parallelism(threshold: Option<usize>) -> core::Parallelism {
    if FORKED_CHILD.load(Ordering::Relaxed) {
        core::Parallelism::SERIAL
    } else {
        core::Parallelism {
            threshold: threshold.unwrap_or_else(|| PARALLEL_THRESHOLD.load(Ordering::Relaxed)),
        }
    }
}

/// The work size (points × cranks) from which kernels run in parallel by default.
#[pyfunction]
pub(crate) fn get_parallel_threshold() -> usize {
    PARALLEL_THRESHOLD.load(Ordering::Relaxed)
}

/// Set the default work size (points × cranks) from which kernels run in parallel;
/// 0 = always parallel, a huge value = always serial. Results do not depend on it.
#[pyfunction]
pub(crate) fn set_parallel_threshold(threshold: usize) {
    PARALLEL_THRESHOLD.store(threshold, Ordering::Relaxed);
}

/// Called in a forked child (os.register_at_fork): rayon's threads did not survive
/// the fork, so every later call in this process runs serially.
#[pyfunction]
pub(crate) fn _after_fork_in_child() {
    FORKED_CHILD.store(true, Ordering::Relaxed);
}
