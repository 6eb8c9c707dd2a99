//! The loads on the main bearings: each unit's piston and rod as rigid bodies (Newton–Euler
//! in the plane, the rod with its real mass, centre of gravity and moment of inertia), the
//! gas force carried through the rod to the crank pin, the crank web and counterweight
//! turning with the throw, and the weights; each throw's load shared between the two
//! bearings on either side of it by the lever rule (the shaft statically determinate,
//! cut at every bearing). Docs: docs/theory.md, "Main-bearing loads".
//!
//! In a unit's own frame — e along the cylinder axis away from the shaft, n = e turned by
//! +90° — the crank pin is P = r(cos ψ e + sin ψ n), the piston pin B = x_B e with
//! x_B = r cos ψ + l cos β, sin β = λ sin ψ, and the rod's unit vector from P to B is
//! u = cos β e − sin β n (its angle −β); its centre of gravity G = B − z_k u. With R the
//! rod's force on the piston, N n the wall's, F the gas force (along −e) and Q the pin's
//! force on the rod:
//!
//!   piston  m_t a_B = R + N n − F e + m_t g,
//!   rod     m_k a_G = Q − R + m_k g,
//!           I_k α   = (B − G) × (−R) + (P − G) × Q,   α = −β̈,
//!
//! which give u × R = −[I_k α + (l − z_k) m_k u × (a_G − g)]/l, then N from the piston's
//! n-component, R and Q. The throw receives −Q from each of its rods and loads its bearings
//! with L = Σ(−Q) + (m_s + m_p) g − (m_s r_s − m_p r_p)/r · a_P.

use crate::dynamics::PhysicalCylinder;
use crate::error::{check, check_length, MechanismError, Result};
use crate::parallel::{map_indices, Parallelism};

/// Which throw each unit sits on, and for each throw the two bearings it lies between with
/// their shares of its load.
#[derive(Debug, Clone, PartialEq)]
pub struct BearingLayout {
    throw_of_unit: Vec<usize>,
    /// Per throw: (bearing before, its share, bearing after, its share).
    shares: Vec<(usize, f64, usize, f64)>,
    bearings: usize,
}

impl BearingLayout {
    /// Units on the throws `throw_of_unit` (an index into `throw_position`, m) and the main
    /// bearings at `bearing_position` (m, increasing); every throw strictly between two
    /// bearings. A throw at z_t between bearings at z_a < z_t < z_b puts
    /// (z_b − z_t)/(z_b − z_a) of its load on a and the rest on b.
    pub fn new(
        throw_of_unit: &[usize],
        throw_position: &[f64],
        bearing_position: &[f64],
    ) -> Result<Self> {
        if bearing_position.len() < 2 {
            return Err(MechanismError::InvalidChoice {
                parameter: "main_bearings",
                value: bearing_position.len().to_string(),
                allowed: "at least two bearings",
            });
        }
        for window in bearing_position.windows(2) {
            check("main_bearings", window[1], "finite and increasing", |z| {
                window[0].is_finite() && z > window[0]
            })?;
        }
        let mut shares = Vec::with_capacity(throw_position.len());
        for &z in throw_position {
            let after = bearing_position.partition_point(|&b| b <= z);
            if after == 0 || after == bearing_position.len() || bearing_position[after - 1] == z {
                return Err(MechanismError::OutOfRange {
                    parameter: "main_bearings",
                    value: z,
                    allowed: "every throw strictly between two bearings",
                });
            }
            let (a, b) = (bearing_position[after - 1], bearing_position[after]);
            let share_b = (z - a) / (b - a);
            shares.push((after - 1, 1.0 - share_b, after, share_b));
        }
        for &t in throw_of_unit {
            if t >= throw_position.len() {
                return Err(MechanismError::InvalidChoice {
                    parameter: "throw_of_unit",
                    value: t.to_string(),
                    allowed: "the index of one of the throws",
                });
            }
        }
        Ok(Self {
            throw_of_unit: throw_of_unit.to_vec(),
            shares,
            bearings: bearing_position.len(),
        })
    }

    /// The number of bearings.
    pub fn bearings(&self) -> usize {
        self.bearings
    }
}

/// What one unit does at crank angle φ, speed ω (rad/s), acceleration ε (rad/s²), gas force
/// `gas` (N, toward the shaft) and gravity g (m/s²).
struct UnitForces {
    /// Its load on its throw (horizontal, vertical; N).
    throw_load: [f64; 2],
    /// The moment about the shaft axis (N·m, positive with the crank's rotation) of the force
    /// the piston pushes the cylinder wall with: −N·x_B.
    wall_moment: f64,
}

fn unit_forces(
    unit: &PhysicalCylinder,
    phi: f64,
    omega: f64,
    epsilon: f64,
    gas: f64,
    g: f64,
) -> UnitForces {
    let (r, l, z) = (unit.crank_radius, unit.rod_length, unit.rod_cg);
    let lambda = r / l;
    let psi = phi + unit.phase;
    let (s, c) = psi.sin_cos();
    let sin_beta = lambda * s;
    let cos_beta = (1.0 - sin_beta * sin_beta).sqrt();
    // β and the piston pin's position x_B along e as functions of φ, and their derivatives.
    let beta_1 = lambda * c / cos_beta;
    let beta_2 = (beta_1 * beta_1 * sin_beta - lambda * s) / cos_beta;
    let x_2 = -r * c - l * (beta_2 * sin_beta + beta_1 * beta_1 * cos_beta);
    let x_1 = -r * s - l * beta_1 * sin_beta;
    let (beta_dot, beta_ddot) = (beta_1 * omega, beta_2 * omega * omega + beta_1 * epsilon);
    let a_b = [x_2 * omega * omega + x_1 * epsilon, 0.0];
    let u = [cos_beta, -sin_beta];
    // ü of u = (cos β, −sin β): β̈(−sin β, −cos β) − β̇²(cos β, −sin β).
    let u_ddot = [
        -beta_ddot * sin_beta - beta_dot * beta_dot * cos_beta,
        -beta_ddot * cos_beta + beta_dot * beta_dot * sin_beta,
    ];
    let a_g = [a_b[0] - z * u_ddot[0], a_b[1] - z * u_ddot[1]];
    let a_p = [
        r * (-omega * omega * c - epsilon * s),
        r * (-omega * omega * s + epsilon * c),
    ];
    // Gravity in the unit's frame: −g (sin γ e + cos γ n).
    let (sin_g, cos_g) = unit.inclination.sin_cos();
    let weight = [-g * sin_g, -g * cos_g];
    let cross = |a: [f64; 2], b: [f64; 2]| a[0] * b[1] - a[1] * b[0];
    let rod_rest = [a_g[0] - weight[0], a_g[1] - weight[1]];
    let alpha = -beta_ddot;
    let u_cross_r = -(unit.rod_inertia * alpha + (l - z) * unit.rod_mass * cross(u, rod_rest)) / l;
    let v = [
        unit.piston_mass * (a_b[0] - weight[0]) + gas,
        unit.piston_mass * (a_b[1] - weight[1]),
    ];
    let wall = (cross(u, v) - u_cross_r) / cos_beta;
    let rod_on_piston = [v[0], v[1] - wall];
    let pin_on_rod = [
        unit.rod_mass * rod_rest[0] + rod_on_piston[0],
        unit.rod_mass * rod_rest[1] + rod_on_piston[1],
    ];
    let turning = (unit.crank_mass * unit.crank_cg_radius
        - unit.counterweight_mass * unit.counterweight_radius)
        / r;
    let crank_weight = unit.crank_mass + unit.counterweight_mass;
    let load = [
        -pin_on_rod[0] + crank_weight * weight[0] - turning * a_p[0],
        -pin_on_rod[1] + crank_weight * weight[1] - turning * a_p[1],
    ];
    // Back to (horizontal, vertical): e = (cos γ, sin γ), n = (−sin γ, cos γ).
    UnitForces {
        throw_load: [
            load[0] * cos_g - load[1] * sin_g,
            load[0] * sin_g + load[1] * cos_g,
        ],
        // The wall takes −N n at B = x_B e: moment x_B e × (−N n) = −N x_B.
        wall_moment: -wall * (r * c + l * cos_beta),
    }
}

/// The force every main bearing receives from the shaft (N), into `horizontal` and
/// `vertical` (bearings × points, bearing-major): at the crank angles `phi` (rad) with the
/// speed `omega` (rad/s), acceleration `acceleration` (rad/s²) and each unit's gas force
/// `gas` (N, toward the shaft; unit-major, units × points) there, under gravity `g` (m/s²,
/// downward; 0: none). Horizontal is positive toward a cylinder at γ = 0, vertical upward.
/// The units are solved in parallel when the work reaches `parallelism`'s threshold, and
/// summed into the bearings in their order: the same doubles for any thread count.
#[allow(clippy::too_many_arguments)]
pub fn bearing_loads(
    units: &[PhysicalCylinder],
    layout: &BearingLayout,
    phi: &[f64],
    omega: &[f64],
    acceleration: &[f64],
    gas: &[f64],
    g: f64,
    horizontal: &mut [f64],
    vertical: &mut [f64],
    parallelism: Parallelism,
) -> Result<()> {
    let points = phi.len();
    check_length("throw_of_unit", units.len(), layout.throw_of_unit.len())?;
    check_length("omega", points, omega.len())?;
    check_length("acceleration", points, acceleration.len())?;
    check_length("gas", units.len() * points, gas.len())?;
    check_length("horizontal", layout.bearings * points, horizontal.len())?;
    check_length("vertical", layout.bearings * points, vertical.len())?;
    check("g", g, "any finite real", |_| true)?;
    for unit in units {
        unit.validate()?;
    }
    for (name, values) in [
        ("phi", phi),
        ("omega", omega),
        ("acceleration", acceleration),
        ("gas", gas),
    ] {
        for &value in values {
            check(name, value, "finite", |_| true)?;
        }
    }
    // Each unit's load on its throw at every angle (a few dozen flops and one sin_cos each).
    let work = units.len().saturating_mul(points).saturating_mul(64);
    let per_unit = map_indices(units.len(), work, parallelism, |j| {
        let unit = &units[j];
        (0..points)
            .map(|i| {
                unit_forces(
                    unit,
                    phi[i],
                    omega[i],
                    acceleration[i],
                    gas[j * points + i],
                    g,
                )
                .throw_load
            })
            .collect::<Vec<[f64; 2]>>()
    });
    horizontal.fill(0.0);
    vertical.fill(0.0);
    for (j, loads) in per_unit.iter().enumerate() {
        let (a, share_a, b, share_b) = layout.shares[layout.throw_of_unit[j]];
        for (i, [h, v]) in loads.iter().enumerate() {
            horizontal[a * points + i] += share_a * h;
            vertical[a * points + i] += share_a * v;
            horizontal[b * points + i] += share_b * h;
            vertical[b * points + i] += share_b * v;
        }
    }
    Ok(())
}

/// The torque about the shaft axis that the frame receives from the moving parts (N·m,
/// positive in the crank's sense of rotation), at the crank angles `phi` (rad) with the speed
/// `omega` (rad/s), acceleration `acceleration` (rad/s²) and gas forces `gas` (N, unit-major,
/// units × points) there, under gravity `g` (m/s²), into `out`: the moments of the pistons'
/// side forces on the cylinder walls, −Σ_j N_j·x_B,j (the main bearings' forces pass through
/// the axis, the gas force on each cylinder head along its axis). The mounts take it; over a
/// steady cycle without gravity it averages −(the mean gas torque): the block rolls against
/// the crank.
#[allow(clippy::too_many_arguments)]
pub fn frame_torque(
    units: &[PhysicalCylinder],
    phi: &[f64],
    omega: &[f64],
    acceleration: &[f64],
    gas: &[f64],
    g: f64,
    out: &mut [f64],
) -> Result<()> {
    let points = phi.len();
    check_length("omega", points, omega.len())?;
    check_length("acceleration", points, acceleration.len())?;
    check_length("gas", units.len() * points, gas.len())?;
    check_length("out", points, out.len())?;
    check("g", g, "any finite real", |_| true)?;
    for unit in units {
        unit.validate()?;
    }
    out.fill(0.0);
    for (j, unit) in units.iter().enumerate() {
        for i in 0..points {
            let forces = unit_forces(
                unit,
                phi[i],
                omega[i],
                acceleration[i],
                gas[j * points + i],
                g,
            );
            out[i] += forces.wall_moment;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_lever_rule_shares_a_throw_between_its_neighbours() {
        // Throws at 0.1 and 0.5 between bearings at 0, 0.4 and 1.0: 3/4 and 1/4, then 5/6
        // and 1/6.
        let layout = BearingLayout::new(&[0, 1, 1], &[0.1, 0.5], &[0.0, 0.4, 1.0]).unwrap();
        assert_eq!(layout.bearings(), 3);
        let close = |a: f64, b: f64| (a - b).abs() < 1e-15;
        let (a, share_a, b, share_b) = layout.shares[0];
        assert!((a, b) == (0, 1) && close(share_a, 0.75) && close(share_b, 0.25));
        let (a, share_a, b, share_b) = layout.shares[1];
        assert!((a, b) == (1, 2) && close(share_a, 5.0 / 6.0) && close(share_b, 1.0 / 6.0));
    }

    #[test]
    fn an_overhung_throw_or_one_at_a_bearing_is_refused() {
        for throws in [[-0.1], [0.0], [0.4], [1.2]] {
            assert!(
                BearingLayout::new(&[0], &throws, &[0.0, 0.4, 1.0]).is_err(),
                "{throws:?}"
            );
        }
        assert!(BearingLayout::new(&[0], &[0.5], &[0.0]).is_err());
        assert!(BearingLayout::new(&[0], &[0.5], &[1.0, 0.0]).is_err());
        assert!(BearingLayout::new(&[1], &[0.5], &[0.0, 1.0]).is_err());
    }
}
