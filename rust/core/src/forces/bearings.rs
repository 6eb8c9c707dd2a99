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

use multiversion::multiversion;

use crate::error::{check, check_finite, check_length, short, MechanismError, Result};
use crate::mechanism::PhysicalCylinder;
use crate::parallel::{map_indices, Parallelism};

/// Axial positions closer than `SAME_POSITION`·max(1, |z|) (m) are one: units that close
/// are on one throw, and a throw that close to a bearing is at it. A relative tolerance of
/// rounding, not of manufacture.
pub const SAME_POSITION: f64 = 1e-12;

/// The magnitude an axial position (m) may have: beyond it a machine is not a machine.
const MAGNITUDE_LIMIT: f64 = 1e30;

/// Whether two axial positions (m) are one, to [`SAME_POSITION`].
fn same_position(a: f64, b: f64) -> bool {
    (a - b).abs() <= SAME_POSITION * 1.0_f64.max(a.abs()).max(b.abs())
}

/// Where things are along a machine's shaft, the rules of it written once: its **throws**
/// (the units at one axial position, with their crank web and counterweight), which throw
/// each unit sits on, its **main bearings** (given, or interleaving the throws) and each
/// throw's share of its load on the two bearings around it (the lever rule: a throw at z_t
/// between bearings at z_a < z_t < z_b puts (z_b − z_t)/(z_b − z_a) of its load on a).
#[derive(Debug, Clone, PartialEq)]
pub struct BearingLayout {
    throws: Vec<f64>,
    throw_of_unit: Vec<usize>,
    bearing_position: Vec<f64>,
    /// Per throw: (bearing before, its share, bearing after, its share).
    shares: Vec<(usize, f64, usize, f64)>,
}

impl BearingLayout {
    /// The layout of units at `axial_position` (m, one per unit, finite) with the main
    /// bearings `main_bearings` (m: at least two, finite, strictly increasing, every throw
    /// strictly between two), or by default n + 1 bearings interleaving the n throws: the
    /// midpoint between neighbouring throws and, outside, z₁ − d₁/2 and zₙ + dₙ/2
    /// (d₁ = z₂ − z₁, dₙ = zₙ − zₙ₋₁); a lone throw gets z₁ ± `crank_radius` (the lever rule
    /// halves its load whatever the distance, so the distance only places the bearings
    /// plausibly). Units at positions equal to within [`SAME_POSITION`] are one throw, at the
    /// smallest of them.
    pub fn new(
        axial_position: &[f64],
        main_bearings: Option<&[f64]>,
        crank_radius: f64,
    ) -> Result<Self> {
        if axial_position.is_empty() {
            return Err(MechanismError::Empty {
                parameter: "axial_position",
            });
        }
        for &z in axial_position {
            check("axial_position", z, "any finite real (m)", |z| {
                z.abs() <= MAGNITUDE_LIMIT
            })?;
        }
        let (throws, throw_of_unit) = throws_of(axial_position);
        let bearing_position = match main_bearings {
            Some(given) => {
                check_bearings(given, &throws, &throw_of_unit)?;
                given.to_vec()
            }
            None => default_bearings(&throws, crank_radius),
        };
        let shares = throws
            .iter()
            .map(|&z| {
                let after = bearing_position.partition_point(|&b| b <= z);
                let (a, b) = (bearing_position[after - 1], bearing_position[after]);
                let share_b = (z - a) / (b - a);
                (after - 1, 1.0 - share_b, after, share_b)
            })
            .collect();
        Ok(Self {
            throws,
            throw_of_unit,
            bearing_position,
            shares,
        })
    }

    /// The throws' axial positions (m), increasing.
    pub fn throws(&self) -> &[f64] {
        &self.throws
    }

    /// Each unit's throw: its index in [`BearingLayout::throws`].
    pub fn throw_of_unit(&self) -> &[usize] {
        &self.throw_of_unit
    }

    /// The main bearings' axial positions (m), increasing.
    pub fn bearing_position(&self) -> &[f64] {
        &self.bearing_position
    }

    /// The number of bearings.
    pub fn bearings(&self) -> usize {
        self.bearing_position.len()
    }
}

/// The distinct positions (increasing; a chain of neighbours within [`SAME_POSITION`] is one,
/// at the smallest) and each unit's index among them.
fn throws_of(axial_position: &[f64]) -> (Vec<f64>, Vec<usize>) {
    let mut order: Vec<usize> = (0..axial_position.len()).collect();
    order.sort_by(|&a, &b| axial_position[a].total_cmp(&axial_position[b]));
    let mut throws: Vec<f64> = Vec::new();
    let mut index = vec![0; axial_position.len()];
    for j in order {
        let z = axial_position[j];
        if throws.last().is_none_or(|&last| !same_position(z, last)) {
            throws.push(z);
        }
        index[j] = throws.len() - 1;
    }
    (throws, index)
}

fn default_bearings(throws: &[f64], crank_radius: f64) -> Vec<f64> {
    if let [z] = throws {
        return vec![z - crank_radius, z + crank_radius];
    }
    let n = throws.len();
    let mut bearings = Vec::with_capacity(n + 1);
    bearings.push(throws[0] - (throws[1] - throws[0]) / 2.0);
    bearings.extend(throws.windows(2).map(|w| w[0] + (w[1] - w[0]) / 2.0));
    bearings.push(throws[n - 1] + (throws[n - 1] - throws[n - 2]) / 2.0);
    bearings
}

/// The rules of given main bearings, each refusal naming `main_bearings`, the bearing and the
/// throw (with its units, as `cylinders[j]`).
fn check_bearings(bearings: &[f64], throws: &[f64], throw_of_unit: &[usize]) -> Result<()> {
    const ALLOWED: &str = "allowed: at least two finite axial positions [m], strictly \
                           increasing, every throw strictly between two";
    let refused = |message: String| MechanismError::Refused {
        parameter: "main_bearings",
        message,
    };
    if bearings.len() < 2 {
        return Err(refused(format!(
            "main_bearings must hold at least two axial positions [m], got {}; {ALLOWED}",
            bearings.len()
        )));
    }
    for (i, &z) in bearings.iter().enumerate() {
        if !(z.is_finite() && z.abs() <= MAGNITUDE_LIMIT) {
            return Err(refused(format!(
                "main_bearings[{i}] = {} is out of range; {ALLOWED}, |z| <= {}",
                short(z),
                short(MAGNITUDE_LIMIT)
            )));
        }
    }
    for i in 1..bearings.len() {
        if bearings[i] <= bearings[i - 1] {
            return Err(refused(format!(
                "main_bearings[{i}] = {} m is not beyond main_bearings[{}] = {} m; {ALLOWED}",
                short(bearings[i]),
                i - 1,
                short(bearings[i - 1])
            )));
        }
    }
    for (t, &z) in throws.iter().enumerate() {
        let units: Vec<String> = (0..throw_of_unit.len())
            .filter(|&j| throw_of_unit[j] == t)
            .map(|j| format!("cylinders[{j}]"))
            .collect();
        let throw = format!("the throw at z = {} m ({})", short(z), units.join(", "));
        if let Some(i) = bearings.iter().position(|&b| same_position(z, b)) {
            return Err(refused(format!(
                "main_bearings[{i}] = {} m is at {throw}: a throw lies between two bearings, \
                 not on one; {ALLOWED}",
                short(bearings[i])
            )));
        }
        if z < bearings[0] {
            return Err(refused(format!(
                "main_bearings: {throw} is overhung, before the first bearing at {} m; {ALLOWED}",
                short(bearings[0])
            )));
        }
        if z > bearings[bearings.len() - 1] {
            return Err(refused(format!(
                "main_bearings: {throw} is overhung, beyond the last bearing at {} m; {ALLOWED}",
                short(bearings[bearings.len() - 1])
            )));
        }
    }
    Ok(())
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
    let trig = (phi + unit.phase).sin_cos();
    unit_forces_at(
        unit,
        trig,
        unit.inclination.sin_cos(),
        omega,
        epsilon,
        gas,
        g,
    )
}

/// [`unit_forces`] with its sines and cosines given: (sin ψ, cos ψ) of the crank angle
/// ψ = φ + α and (sin γ, cos γ) of the inclination (the same doubles, for callers that keep
/// them).
#[inline(always)]
fn unit_forces_at(
    unit: &PhysicalCylinder,
    (s, c): (f64, f64),
    (sin_g, cos_g): (f64, f64),
    omega: f64,
    epsilon: f64,
    gas: f64,
    g: f64,
) -> UnitForces {
    let (r, l, z) = (unit.crank_radius, unit.rod_length, unit.rod_cg);
    let lambda = r / l;
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
    check_length("horizontal", layout.bearings() * points, horizontal.len())?;
    check_length("vertical", layout.bearings() * points, vertical.len())?;
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
        check_finite(name, values, "finite")?;
    }
    horizontal.fill(0.0);
    vertical.fill(0.0);
    // Each unit's load on its throw at every angle (a few dozen flops and one sin_cos each),
    // summed into the bearings unit by unit: the same doubles on one thread or many.
    let work = units.len().saturating_mul(points).saturating_mul(64);
    let load = |j: usize, i: usize| {
        unit_forces(
            &units[j],
            phi[i],
            omega[i],
            acceleration[i],
            gas[j * points + i],
            g,
        )
        .throw_load
    };
    let mut add = |j: usize, i: usize, [h, v]: [f64; 2]| {
        let (a, share_a, b, share_b) = layout.shares[layout.throw_of_unit[j]];
        horizontal[a * points + i] += share_a * h;
        vertical[a * points + i] += share_a * v;
        horizontal[b * points + i] += share_b * h;
        vertical[b * points + i] += share_b * v;
    };
    if parallelism.runs_parallel(work) {
        let per_unit = map_indices(units.len(), work, parallelism, |j| {
            (0..points).map(|i| load(j, i)).collect::<Vec<[f64; 2]>>()
        });
        for (j, loads) in per_unit.iter().enumerate() {
            for (i, &hv) in loads.iter().enumerate() {
                add(j, i, hv);
            }
        }
    } else {
        for j in 0..units.len() {
            for i in 0..points {
                add(j, i, load(j, i));
            }
        }
    }
    Ok(())
}

/// What [`max_bearing_load`] reuses from one call to the next: each bearing's load at one
/// angle, each unit's (sin γ, cos γ) and its (sin ψ, cos ψ) at every angle.
#[derive(Debug, Default)]
pub(crate) struct LoadScratch {
    bearings: Vec<[f64; 2]>,
    frames: Vec<(f64, f64)>,
    trig: Vec<(f64, f64)>,
    /// Every unit's throw loads, unit-major.
    throws: Vec<[f64; 2]>,
}

impl LoadScratch {
    /// The scratch of the bearings' sums alone ([`largest_bearing_load`]).
    pub(crate) fn bearings(&mut self) -> &mut Vec<[f64; 2]> {
        &mut self.bearings
    }
}

/// (sin ψ, cos ψ) of every unit at every angle, ψ = φ + α (unit-major, units × phi), into
/// `out`.
pub(crate) fn crank_trig(units: &[PhysicalCylinder], phi: &[f64], out: &mut Vec<(f64, f64)>) {
    out.clear();
    for unit in units {
        out.extend(phi.iter().map(|p| (p + unit.phase).sin_cos()));
    }
}

/// The largest magnitude of any main bearing's load (N) at the crank angles `phi` (rad) at
/// the constant speed `omega` (rad/s) with the gas forces `gas` (N, unit-major) times
/// `gas_scale` and g (m/s²): the loads of [`bearing_loads`], the same doubles (with
/// `gas_scale` 1), taken angle by angle, nothing kept. The units' (sin ψ, cos ψ) are
/// `trig` ([`crank_trig`] of these units and angles) where given, else made in `scratch`.
/// The units and values checked by the caller.
#[allow(clippy::too_many_arguments)]
pub(crate) fn max_bearing_load(
    units: &[PhysicalCylinder],
    layout: &BearingLayout,
    phi: &[f64],
    omega: f64,
    gas: &[f64],
    gas_scale: f64,
    g: f64,
    trig: Option<&[(f64, f64)]>,
    scratch: &mut LoadScratch,
) -> f64 {
    let points = phi.len();
    let LoadScratch {
        bearings,
        frames,
        trig: own,
        throws,
    } = scratch;
    let trig = match trig {
        Some(trig) => trig,
        None => {
            crank_trig(units, phi, own);
            own
        }
    };
    frames.clear();
    frames.extend(units.iter().map(|u| u.inclination.sin_cos()));
    throws.clear();
    for (j, unit) in units.iter().enumerate() {
        let unit_points = j * points..(j + 1) * points;
        let forces = (omega, gas_scale, g);
        unit_throw_loads(
            unit,
            &trig[unit_points.clone()],
            frames[j],
            &gas[unit_points],
            forces,
            throws,
        );
    }
    let per_unit: Vec<&[[f64; 2]]> = throws.chunks_exact(points.max(1)).collect();
    largest_bearing_load(layout, &per_unit, points, bearings)
}

/// One unit's throw loads at the angles of (sin ψ, cos ψ) `trig`, at the constant speed ω with
/// its gas forces `gas` times the scale and g (`(omega, gas_scale, g)`), appended to `out`:
/// [`unit_forces_at`] of each angle in the widest vectors the machine has (their square roots
/// and divisions side by side), no operation fused, so the same doubles.
#[multiversion(targets("x86_64+avx512f+avx512vl+avx512dq", "x86_64+avx2"))]
fn unit_throw_loads(
    unit: &PhysicalCylinder,
    trig: &[(f64, f64)],
    frame: (f64, f64),
    gas: &[f64],
    (omega, gas_scale, g): (f64, f64, f64),
    out: &mut Vec<[f64; 2]>,
) {
    // A loop, not a closure: a closure is compiled apart, without the target's features.
    let first = out.len();
    out.resize(first + trig.len(), [0.0; 2]);
    for ((load, &trig), &gas) in out[first..].iter_mut().zip(trig).zip(gas) {
        *load = unit_forces_at(unit, trig, frame, omega, 0.0, gas_scale * gas, g).throw_load;
    }
}

/// Each unit's load on its throw (N; horizontal, vertical) at the crank angles `phi` (rad) at
/// the constant speed `omega` (rad/s) with its gas forces `gas` (N) and g (m/s²), into `out`:
/// what [`max_bearing_load`] takes of it, the same doubles, for a caller that keeps a unit's
/// loads for several machines (a firing order's candidates, a unit at a phase made once).
pub(crate) fn throw_loads(
    unit: &PhysicalCylinder,
    phi: &[f64],
    omega: f64,
    gas: &[f64],
    g: f64,
    out: &mut Vec<[f64; 2]>,
) {
    let frame = unit.inclination.sin_cos();
    out.clear();
    out.extend(phi.iter().zip(gas).map(|(p, &gas)| {
        unit_forces_at(unit, (p + unit.phase).sin_cos(), frame, omega, 0.0, gas, g).throw_load
    }));
}

/// The largest magnitude (N) of any bearing's load over `points` angles, the units' throw
/// loads `per_unit` (each `points` long, in unit order) shared by the lever rule and summed
/// unit by unit: the one sum and maximum of [`max_bearing_load`] (`bearings` its scratch).
pub(crate) fn largest_bearing_load(
    layout: &BearingLayout,
    per_unit: &[&[[f64; 2]]],
    points: usize,
    bearings: &mut Vec<[f64; 2]>,
) -> f64 {
    let (mut largest, mut cut) = (0.0_f64, 0.0_f64);
    for i in 0..points {
        bearings.clear();
        bearings.resize(layout.bearings(), [0.0; 2]);
        for (j, loads) in per_unit.iter().enumerate() {
            let [h, v] = loads[i];
            let (a, share_a, b, share_b) = layout.shares[layout.throw_of_unit[j]];
            bearings[a][0] += share_a * h;
            bearings[a][1] += share_a * v;
            bearings[b][0] += share_b * h;
            bearings[b][1] += share_b * v;
        }
        for [h, v] in bearings.iter() {
            // hypot only where it may be the largest: h² + v² within rounding of the largest
            // so far (the same doubles as the largest hypot of all).
            if h * h + v * v >= cut {
                largest = largest.max(h.hypot(*v));
                cut = largest * largest * (1.0 - 1e-12);
            }
        }
    }
    largest
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

mod parts;
#[cfg(test)]
mod tests;

pub use parts::BearingParts;
