//! Forces on the frame (docs/theory.md, "Forces on the frame"): the shaking forces and
//! moments by order, from the gravity kernels, and the main-bearing loads (`bearings`). For a rigid mechanism of mass M whose centre
//! of mass is r_G(φ), the potential of a uniform field of unit strength along a unit vector
//! e is S_e(φ) = M e·r_G(φ) + const (kg·m), so the frame's inertial reaction along e is
//!
//!   F_e = −M a_G·e = −(S_e″(φ) ω² + S_e′(φ) ε),
//!
//! and at constant speed its order-n amplitude is n² ω² |S_e,n|. S_e is the paper's U with
//! g = 1 and U1, U2 the first moments (kg·m): with e vertical S_e′ is the paper's Q, with e
//! horizontal the same kernel with every inclination turned by +90°, and each unit's S_e
//! weighted by its lever z − z_ref gives the moments about the engine centre z_ref, the
//! midpoint of the outermost units (`engine_centre`). The two-mass rod keeps
//! the rod's mass and centre of gravity, so this is exact with the kernels and their exact
//! series; no new kinematics.

mod bearings;
mod shaking;

pub use bearings::{bearing_loads, frame_torque, BearingLayout, BearingParts, SAME_POSITION};
pub(crate) use bearings::{
    crank_trig, largest_bearing_load, max_bearing_load, throw_loads, LoadScratch,
};
pub use shaking::{engine_centre, ShakingForces, ShakingOrders, ORDER_COLUMNS};
pub(crate) use shaking::{FORCE_FORWARD, MOMENT_FORWARD};
