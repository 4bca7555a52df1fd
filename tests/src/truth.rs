//! An independent truth model that writes measured-style cases
//! (`docs/measured-case.md`) with a hidden physical effect, so that tests can check
//! that `coil-tune diagnose` finds it. Nothing here uses coil's FE solver, mesher, tuner or
//! post-processor: the stiffness is a closed form and the integrator is written here, so
//! agreement between diagnose and this truth is evidence, not a tautology.
//!
//! # Spring: closed-form compliance of the helix
//! Wahl, *Mechanical Springs* (2nd ed., 1963), ch. 17 ("Helical springs under axial load
//! and twisting moment"); also Timoshenko, *Strength of Materials* II. With R = D/2, the
//! pitch angle `a = atan(h / (pi D))`, the wire length `L = n pi D / cos a`, the wire's
//! `A = pi d^2/4`, `I = pi d^4/64`, `J = 2I` and `G = E / (2 (1 + nu))`, an axial force F
//! and an axial moment M at the end load a wire section with the torque
//! `T = F R cos a + M sin a`, the bending moment `Mb = M cos a - F R sin a`, the shear
//! force `F cos a` and the axial force `F sin a`. Castigliano's theorem on
//! `U = L/2 [T^2/GJ + Mb^2/EI + (F cos a)^2/(kappa G A) + (F sin a)^2/EA]` gives the
//! compliance `(delta, phi) = C (F, M)`:
//! ```text
//! C_zz = L [R^2 cos^2 a / GJ + R^2 sin^2 a / EI + cos^2 a / (kappa G A) + sin^2 a / EA]
//! C_zt = L R sin a cos a (1/GJ - 1/EI)
//! C_tt = L [sin^2 a / GJ + cos^2 a / EI]
//! ```
//! with Cowper's shear coefficient of a solid circle `kappa = 6 (1 + nu) / (7 + 6 nu)`.
//! Signs: delta is the extension along the axis (away from the base), phi the end
//! rotation about that axis, right-handed, for a helix winding right-handed as it rises;
//! the other hand flips C_zt, which no frequency sees (only C_zt^2 enters).
//!
//! # Dynamics: a lumped chain
//! The spring is a chain of N equal segments, node 0 clamped at the base, node N the top
//! end carrying the weight. DOFs per node: (u, theta), u the axial displacement (m,
//! positive away from the base), theta the rotation about the axis (rad). Each segment has
//! the stiffness `K_s = N C^-1` (N m^-1, N, N m). Masses: the wire's mass
//! `m_s = rho A L` is lumped in equal shares m_s/N (half shares at the ends; the base's is
//! lost to the clamp), its rotary inertia as rings, `m_node R^2`. The weight (mass m) sits
//! on node N; its rotation is either held (a guide: theta_N = 0) or free with the rotary
//! inertia J (`axial_torsional_coupling`). Damping: stiffness-proportional `beta K_s` on
//! every segment, `beta = 2 zeta / w_ax`, w_ax the chain's axial mode with the weight's
//! rotation held, so that mode's damping ratio is exactly `zeta` (a Rayleigh family with
//! alpha = 0, which the paper's model can match). Gravity `g` acts on the weight only (the
//! spring's self-weight would add about m_s/(2m) to the preload; the spec's model does
//! not have it either).
//!
//! # Effects at the weight (the spec's table)
//! `coulomb_friction` F opposing the weight's axial velocity, sticking while the other
//! forces stay within F; `quadratic_damping` `-c2 v|v|`; `cubic_stiffness` `k3 x^3` in
//! parallel with the spring, x the compression from the free length (so the gravity
//! preload solves `k x + k3 x^3 = m g`); `axial_torsional_coupling` frees the weight's
//! rotation with rotary inertia J.
//!
//! # Integrator
//! Explicit leapfrog (kick-drift, the central-difference scheme on lumped masses):
//! `v_{n+1/2} = v_{n-1/2} + dt a_n`, `u_{n+1} = u_n + dt v_{n+1/2}`, the velocity-dependent
//! forces evaluated with `v_{n-1/2}` (a half-step lag acts, to first order, as a tiny
//! stiffness change; the dissipation is second-order accurate). Stability of the damped
//! scheme needs `w^2 dt (dt + 2 beta) < 4` for every chain mode; dt is half of that limit
//! for the chain's highest mode (from its eigenvalues) and divides the sample period in
//! an odd number of steps. Friction (a standard explicit stick-slip treatment): a sliding
//! weight whose velocity would reverse within a step sticks (v = 0) if the other forces
//! are within F, else it reverses and slides the rest of the step with the opposite
//! friction; a stuck weight breaks free when the other forces exceed F. The recorded
//! acceleration is the weight's force balance at each step (not a difference).
//!
//! # Measurement model
//! The simulation starts at the static equilibrium (gravity) with an impulse (an initial
//! axial velocity of the weight). A random lead (0.2-1.2 s, a random start phase) is cut
//! off, the fine acceleration is averaged over one sample period centred on each sample
//! time (a simple anti-alias filter: its gain at the axial mode is `1 - (pi f/fs)^2/6`,
//! under 3e-4 here), the record's mean is removed (AC coupling: DC only), Gaussian noise of
//! a given fraction of the peak is added and the result quantised to 16 bits over
//! +-1.2 x peak. The random numbers come from xoshiro256** seeded by splitmix64 (Blackman
//! and Vigna, 2018) with Box-Muller normals, so every case is reproducible bit for bit.
//! The static record is quasi-static: compression from 0 to the compression under
//! 1.5 m g (with g = 9.81 when the case has no gravity) and back, the force
//! `k x + k3 x^3` plus the friction on loading and minus it on unloading, with the same end
//! condition as the dynamics, and noise on both columns.
//!
//! Units: SI inside (m, N, kg, s, rad); the files carry the spec's units (mm, N, MPa).

use serde_json::json;
use std::f64::consts::{PI, TAU};
use std::io;
use std::path::Path;

/// Helix geometry (the spec's `spring`, mm).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Helix {
    pub active_coils: f64,
    pub mean_diameter_mm: f64,
    pub wire_diameter_mm: f64,
    pub pitch_mm: f64,
}

impl Helix {
    /// The paper's spring: n = 14, D = 24 mm, d = 3 mm, h = 6.2 mm.
    pub const PAPER: Helix = Helix {
        active_coils: 14.0,
        mean_diameter_mm: 24.0,
        wire_diameter_mm: 3.0,
        pitch_mm: 6.2,
    };
}

/// The hidden effect and its magnitude in the spec's unit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Effect {
    None,
    CoulombFriction { friction_force_n: f64 },
    QuadraticDamping { quadratic_damping_n_s2_m2: f64 },
    CubicStiffness { cubic_stiffness_n_m3: f64 },
    AxialTorsionalCoupling { rotary_inertia_kg_m2: f64 },
}

impl Effect {
    /// The spec's effect name.
    pub fn name(&self) -> &'static str {
        match self {
            Effect::None => "none",
            Effect::CoulombFriction { .. } => "coulomb_friction",
            Effect::QuadraticDamping { .. } => "quadratic_damping",
            Effect::CubicStiffness { .. } => "cubic_stiffness",
            Effect::AxialTorsionalCoupling { .. } => "axial_torsional_coupling",
        }
    }

    /// The parameter's name (with its unit, as in the spec) and value; None for `none`.
    pub fn parameter(&self) -> Option<(&'static str, f64)> {
        match *self {
            Effect::None => None,
            Effect::CoulombFriction { friction_force_n } => {
                Some(("friction_force_n", friction_force_n))
            }
            Effect::QuadraticDamping {
                quadratic_damping_n_s2_m2,
            } => Some(("quadratic_damping_n_s2_m2", quadratic_damping_n_s2_m2)),
            Effect::CubicStiffness {
                cubic_stiffness_n_m3,
            } => Some(("cubic_stiffness_n_m3", cubic_stiffness_n_m3)),
            Effect::AxialTorsionalCoupling {
                rotary_inertia_kg_m2,
            } => Some(("rotary_inertia_kg_m2", rotary_inertia_kg_m2)),
        }
    }

    fn friction(&self) -> f64 {
        match *self {
            Effect::CoulombFriction { friction_force_n } => friction_force_n,
            _ => 0.0,
        }
    }

    fn quadratic(&self) -> f64 {
        match *self {
            Effect::QuadraticDamping {
                quadratic_damping_n_s2_m2,
            } => quadratic_damping_n_s2_m2,
            _ => 0.0,
        }
    }

    fn cubic(&self) -> f64 {
        match *self {
            Effect::CubicStiffness {
                cubic_stiffness_n_m3,
            } => cubic_stiffness_n_m3,
            _ => 0.0,
        }
    }

    fn rotary_inertia(&self) -> Option<f64> {
        match *self {
            Effect::AxialTorsionalCoupling {
                rotary_inertia_kg_m2,
            } => Some(rotary_inertia_kg_m2),
            _ => None,
        }
    }
}

/// One generated case: the truth, what the case file claims (nominal values), the test
/// and the measurement settings.
#[derive(Debug, Clone, PartialEq)]
pub struct TruthCase {
    /// Folder name and case name.
    pub name: String,
    pub spring: Helix,
    /// The true Young's modulus (MPa).
    pub youngs_modulus_mpa: f64,
    /// The nominal (handbook) Young's modulus written to case.json (MPa).
    pub nominal_youngs_modulus_mpa: f64,
    pub poisson_ratio: f64,
    pub density_kg_m3: f64,
    /// The true moving mass of the weight (kg).
    pub mass_kg: f64,
    /// The nominal mass written to case.json (kg).
    pub nominal_mass_kg: f64,
    pub gravity_m_s2: f64,
    /// Damping ratio of the axial mode (weight's rotation held).
    pub damping_ratio: f64,
    pub effect: Effect,
    /// Chain segments.
    pub segments: usize,
    /// The impulse: the weight's initial axial velocity (m/s).
    pub impulse_velocity_m_s: f64,
    /// An initial rotation rate of the weight (rad/s; only with a free rotation).
    pub rotation_kick_rad_s: f64,
    pub sample_rate_hz: f64,
    pub record_s: f64,
    /// Decay noise: standard deviation over the record's peak.
    pub noise_fraction: f64,
    /// Static noise: standard deviation over each column's full scale.
    pub static_noise_fraction: f64,
    /// Points of the loading branch (the unloading branch has one fewer).
    pub static_points: usize,
    pub seed: u64,
}

/// The 2x2 compliance of the whole spring (SI: m/N, rad/N = m/(N m), rad/(N m)).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Compliance {
    pub c_zz: f64,
    pub c_zt: f64,
    pub c_tt: f64,
}

impl Compliance {
    /// The closed form of the module docs.
    pub fn of(spring: &Helix, youngs_modulus_mpa: f64, poisson_ratio: f64) -> Compliance {
        let r = 0.5e-3 * spring.mean_diameter_mm;
        let d = 1e-3 * spring.wire_diameter_mm;
        let a = (spring.pitch_mm / (PI * spring.mean_diameter_mm)).atan();
        let (s, c) = a.sin_cos();
        let e = youngs_modulus_mpa * 1e6;
        let g = e / (2.0 * (1.0 + poisson_ratio));
        let area = PI * d * d / 4.0;
        let i = PI * d.powi(4) / 64.0;
        let (gj, ei) = (g * 2.0 * i, e * i);
        let kappa = 6.0 * (1.0 + poisson_ratio) / (7.0 + 6.0 * poisson_ratio);
        let l = wire_length_m(spring);
        Compliance {
            c_zz: l
                * (r * r * c * c / gj
                    + r * r * s * s / ei
                    + c * c / (kappa * g * area)
                    + s * s / (e * area)),
            c_zt: l * r * s * c * (1.0 / gj - 1.0 / ei),
            c_tt: l * (s * s / gj + c * c / ei),
        }
    }

    /// The stiffness matrix `C^-1` as (k_zz, k_zt, k_tt).
    pub fn stiffness(&self) -> (f64, f64, f64) {
        let det = self.c_zz * self.c_tt - self.c_zt * self.c_zt;
        (self.c_tt / det, -self.c_zt / det, self.c_zz / det)
    }

    /// Axial stiffness (N/m) with the end's rotation free (M = 0) or held (phi = 0).
    pub fn axial_stiffness(&self, rotation_free: bool) -> f64 {
        if rotation_free {
            1.0 / self.c_zz
        } else {
            1.0 / (self.c_zz - self.c_zt * self.c_zt / self.c_tt)
        }
    }
}

/// Wire length `n pi D / cos a` (m).
pub fn wire_length_m(spring: &Helix) -> f64 {
    let a = (spring.pitch_mm / (PI * spring.mean_diameter_mm)).atan();
    spring.active_coils * PI * spring.mean_diameter_mm * 1e-3 / a.cos()
}

/// The wire's mass `rho A L` (kg).
pub fn wire_mass_kg(spring: &Helix, density_kg_m3: f64) -> f64 {
    let d = 1e-3 * spring.wire_diameter_mm;
    density_kg_m3 * PI * d * d / 4.0 * wire_length_m(spring)
}

impl TruthCase {
    pub fn compliance(&self) -> Compliance {
        Compliance::of(&self.spring, self.youngs_modulus_mpa, self.poisson_ratio)
    }

    /// The weight's rotation is free (coupling case) or held by a guide.
    pub fn rotation_free(&self) -> bool {
        self.effect.rotary_inertia().is_some()
    }

    /// Linear axial stiffness of the spring with this case's end condition (N/m).
    pub fn linear_stiffness_n_m(&self) -> f64 {
        self.compliance().axial_stiffness(self.rotation_free())
    }

    /// The wire's mass (kg).
    pub fn spring_mass_kg(&self) -> f64 {
        wire_mass_kg(&self.spring, self.density_kg_m3)
    }

    /// Static compression (m) under the axial force `force_n`: the root of
    /// `k x + k3 x^3 = force` (Newton from the linear root; the left side is monotonic
    /// for k3 >= 0, as in every case here).
    pub fn compression_under(&self, force_n: f64) -> f64 {
        let k = self.linear_stiffness_n_m();
        let k3 = self.effect.cubic();
        let mut x = force_n / k;
        for _ in 0..60 {
            let step = (k * x + k3 * x.powi(3) - force_n) / (k + 3.0 * k3 * x * x);
            x -= step;
            if step.abs() <= 1e-15 * x.abs().max(1e-12) {
                break;
            }
        }
        x
    }

    /// Static compression of the gravity preload (m).
    pub fn equilibrium_compression_m(&self) -> f64 {
        self.compression_under(self.mass_kg * self.gravity_m_s2)
    }

    /// The chain of this case.
    pub fn chain(&self) -> Chain {
        Chain::new(self, self.rotation_free())
    }
}

/// The lumped chain of the module docs, assembled.
#[derive(Debug, Clone)]
pub struct Chain {
    pub segments: usize,
    /// Segment stiffness `N C^-1`: (k_zz, k_zt, k_tt).
    pub segment_stiffness: (f64, f64, f64),
    /// Axial mass of nodes 1..=N (node N includes the weight), kg.
    pub mass: Vec<f64>,
    /// Rotary inertia of nodes 1..=N (node N includes J when free), kg m^2.
    pub inertia: Vec<f64>,
    pub rotation_free: bool,
    /// Stiffness-proportional damping coefficient (s).
    pub beta: f64,
}

/// One eigenmode of the undamped chain.
#[derive(Debug, Clone)]
pub struct ChainMode {
    /// Circular frequency (rad/s).
    pub omega: f64,
    /// Mass-normalised axial displacement of the weight: its square is the share of an
    /// axial impulse on the weight that goes into this mode.
    pub weight_axial: f64,
    /// Mass-normalised rotation of the weight (0 when held).
    pub weight_rotation: f64,
}

impl Chain {
    fn new(case: &TruthCase, rotation_free: bool) -> Chain {
        let n = case.segments.max(1);
        let (kzz, kzt, ktt) = case.compliance().stiffness();
        let scale = n as f64;
        let share = case.spring_mass_kg() / scale;
        let r = 0.5e-3 * case.spring.mean_diameter_mm;
        let mut mass = vec![share; n];
        mass[n - 1] = 0.5 * share + case.mass_kg;
        let mut inertia = vec![share * r * r; n];
        inertia[n - 1] = 0.5 * share * r * r + case.effect.rotary_inertia().unwrap_or(0.0);
        let mut chain = Chain {
            segments: n,
            segment_stiffness: (scale * kzz, scale * kzt, scale * ktt),
            mass,
            inertia,
            rotation_free,
            beta: 0.0,
        };
        let held = if rotation_free {
            Chain {
                rotation_free: false,
                ..chain.clone()
            }
        } else {
            chain.clone()
        };
        let axial = held
            .modes()
            .into_iter()
            .max_by(|a, b| a.weight_axial.abs().total_cmp(&b.weight_axial.abs()));
        if let Some(mode) = axial {
            chain.beta = 2.0 * case.damping_ratio / mode.omega;
        }
        chain
    }

    /// Number of free DOFs: u_1..u_N, theta_1..theta_{N-1}, and theta_N when free.
    fn dofs(&self) -> usize {
        2 * self.segments - usize::from(!self.rotation_free)
    }

    /// Index of u_i and theta_i (node i = 1..=N) among the free DOFs.
    fn u_index(i: usize) -> usize {
        i - 1
    }

    fn theta_index(&self, i: usize) -> Option<usize> {
        (i < self.segments || self.rotation_free).then(|| self.segments + i - 1)
    }

    /// Dense stiffness matrix and diagonal mass of the free DOFs.
    fn matrices(&self) -> (Vec<Vec<f64>>, Vec<f64>) {
        let dofs = self.dofs();
        let (kzz, kzt, ktt) = self.segment_stiffness;
        let block = [[kzz, kzt], [kzt, ktt]];
        let mut k = vec![vec![0.0; dofs]; dofs];
        let mut m = vec![0.0; dofs];
        for i in 1..=self.segments {
            m[Self::u_index(i)] = self.mass[i - 1];
            if let Some(t) = self.theta_index(i) {
                m[t] = self.inertia[i - 1];
            }
        }
        for i in 1..=self.segments {
            // Segment i joins node i - 1 (the clamp when i = 1) and node i.
            let lower = (i > 1).then(|| [Some(Self::u_index(i - 1)), self.theta_index(i - 1)]);
            let upper = [Some(Self::u_index(i)), self.theta_index(i)];
            for a in 0..2 {
                for b in 0..2 {
                    if let (Some(p), Some(q)) = (upper[a], upper[b]) {
                        k[p][q] += block[a][b];
                    }
                    if let Some(lower) = lower {
                        if let (Some(p), Some(q)) = (lower[a], lower[b]) {
                            k[p][q] += block[a][b];
                        }
                        if let (Some(p), Some(q)) = (upper[a], lower[b]) {
                            k[p][q] -= block[a][b];
                            k[q][p] -= block[a][b];
                        }
                    }
                }
            }
        }
        (k, m)
    }

    /// Undamped modes, lowest first (Jacobi on `M^-1/2 K M^-1/2`).
    pub fn modes(&self) -> Vec<ChainMode> {
        let (k, m) = self.matrices();
        let dofs = m.len();
        let scale: Vec<f64> = m.iter().map(|x| 1.0 / x.sqrt()).collect();
        let a: Vec<Vec<f64>> = (0..dofs)
            .map(|p| (0..dofs).map(|q| scale[p] * k[p][q] * scale[q]).collect())
            .collect();
        let (values, vectors) = jacobi_eigen(a);
        let tip_u = Self::u_index(self.segments);
        let tip_t = self.theta_index(self.segments);
        let mut modes: Vec<ChainMode> = (0..dofs)
            .map(|j| ChainMode {
                omega: values[j].max(0.0).sqrt(),
                weight_axial: vectors[tip_u][j] * scale[tip_u],
                weight_rotation: tip_t.map_or(0.0, |t| vectors[t][j] * scale[t]),
            })
            .collect();
        modes.sort_by(|a, b| a.omega.total_cmp(&b.omega));
        modes
    }

    /// The stable step: half of the damped leapfrog's limit `w^2 dt (dt + 2 beta) < 4`
    /// for the highest mode.
    pub fn stable_step(&self) -> f64 {
        let w_max = self
            .modes()
            .last()
            .map_or(1.0, |mode| mode.omega.max(1e-12));
        let b = self.beta;
        let limit = -b + (b * b + 4.0 / (w_max * w_max)).sqrt();
        0.5 * limit
    }
}

/// Cyclic Jacobi eigen-decomposition of a symmetric matrix: eigenvalues and the matrix
/// whose columns are the orthonormal eigenvectors (Golub and Van Loan, section 8.5).
fn jacobi_eigen(mut a: Vec<Vec<f64>>) -> (Vec<f64>, Vec<Vec<f64>>) {
    let n = a.len();
    let mut v: Vec<Vec<f64>> = (0..n)
        .map(|i| (0..n).map(|j| f64::from(u8::from(i == j))).collect())
        .collect();
    let norm: f64 = a.iter().flatten().map(|x| x * x).sum::<f64>().sqrt();
    for _sweep in 0..100 {
        let off: f64 = (0..n)
            .flat_map(|p| (0..n).filter(move |&q| q != p).map(move |q| (p, q)))
            .map(|(p, q)| a[p][q] * a[p][q])
            .sum::<f64>()
            .sqrt();
        if off <= 1e-15 * norm {
            break;
        }
        for p in 0..n {
            for q in p + 1..n {
                if a[p][q] == 0.0 {
                    continue;
                }
                let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
                let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
                let t = if theta == 0.0 { 1.0 } else { t };
                let c = 1.0 / (t * t + 1.0).sqrt();
                let s = t * c;
                for row in a.iter_mut() {
                    let (x, y) = (row[p], row[q]);
                    row[p] = c * x - s * y;
                    row[q] = s * x + c * y;
                }
                let (upper, lower) = a.split_at_mut(q);
                for (x, y) in upper[p].iter_mut().zip(lower[0].iter_mut()) {
                    let (xp, yq) = (*x, *y);
                    *x = c * xp - s * yq;
                    *y = s * xp + c * yq;
                }
                for row in v.iter_mut() {
                    let (x, y) = (row[p], row[q]);
                    row[p] = c * x - s * y;
                    row[q] = s * x + c * y;
                }
            }
        }
    }
    ((0..n).map(|i| a[i][i]).collect(), v)
}

/// The weight's motion at the sample times (before the measurement model).
#[derive(Debug, Clone)]
pub struct Trajectory {
    /// Integration step (s).
    pub dt: f64,
    /// Steps per sample period (odd).
    pub steps_per_sample: usize,
    /// Time cut off before the first sample (s).
    pub lead_s: f64,
    /// The weight's axial acceleration averaged over one sample period (m/s^2).
    pub accel: Vec<f64>,
    /// The weight's axial displacement from the free length at the sample times (m,
    /// positive away from the base).
    pub displacement: Vec<f64>,
    /// The weight's rotation at the sample times (rad).
    pub rotation: Vec<f64>,
}

/// Integrates the case from its gravity equilibrium with the impulse and keeps `samples`
/// samples after `lead_samples` (at least 1, so that the first sample's averaging window
/// lies inside the run).
pub fn simulate(case: &TruthCase, lead_samples: usize, samples: usize) -> Trajectory {
    simulate_chain(case, &case.chain(), lead_samples, samples)
}

#[allow(non_snake_case)]
fn simulate_chain(
    case: &TruthCase,
    chain: &Chain,
    lead_samples: usize,
    samples: usize,
) -> Trajectory {
    let n = chain.segments;
    let period = 1.0 / case.sample_rate_hz;
    let sub = {
        let raw = (period / chain.stable_step()).ceil().max(1.0) as usize;
        raw + 1 - raw % 2
    };
    let dt = period / sub as f64;
    let half = (sub - 1) / 2;
    let (kzz, kzt, ktt) = chain.segment_stiffness;
    let beta = chain.beta;
    let F = case.effect.friction();
    let c2 = case.effect.quadratic();
    let k3 = case.effect.cubic();
    let weight_force = -case.mass_kg * case.gravity_m_s2;

    // Static equilibrium: every segment carries the tip load; with the rotation held the
    // reaction moment cancels each segment's twist, with it free each twists C_zt F / N.
    let x0 = case.equilibrium_compression_m();
    let tip_u = -x0;
    let tip_theta_per_segment = if chain.rotation_free {
        let c = case.compliance();
        c.c_zt * (-(case.mass_kg * case.gravity_m_s2) + k3 * x0.powi(3)) / n as f64
    } else {
        0.0
    };
    let mut u: Vec<f64> = (0..=n).map(|i| tip_u * i as f64 / n as f64).collect();
    let mut th: Vec<f64> = (0..=n).map(|i| tip_theta_per_segment * i as f64).collect();
    let mut vu = vec![0.0; n + 1];
    let mut vt = vec![0.0; n + 1];
    vu[n] = case.impulse_velocity_m_s;
    if chain.rotation_free {
        vt[n] = case.rotation_kick_rad_s;
    } else {
        th[n] = 0.0;
    }
    let mut fu = vec![0.0; n + 1];
    let mut ft = vec![0.0; n + 1];

    // Sample s averages steps s sub - half ..= s sub + half; the lead keeps the first
    // window inside the run.
    let lead_samples = lead_samples.max(1);
    let total = (lead_samples + samples).saturating_sub(1) * sub + half;
    let mut accel = vec![0.0; samples];
    let mut displacement = vec![0.0; samples];
    let mut rotation = vec![0.0; samples];
    let m_tip = chain.mass[n - 1];
    for step in 0..=total {
        // Sample bookkeeping at step `step` (time step * dt), before the kick.
        fu.iter_mut().for_each(|f| *f = 0.0);
        ft.iter_mut().for_each(|f| *f = 0.0);
        for i in 1..=n {
            let du = u[i] - u[i - 1] + beta * (vu[i] - vu[i - 1]);
            let dth = th[i] - th[i - 1] + beta * (vt[i] - vt[i - 1]);
            let f = kzz * du + kzt * dth;
            let m = kzt * du + ktt * dth;
            fu[i] -= f;
            ft[i] -= m;
            fu[i - 1] += f;
            ft[i - 1] += m;
        }
        let v = vu[n];
        let other = fu[n] + weight_force - k3 * u[n].powi(3) - c2 * v * v.abs();
        // The weight's kick with friction (explicit stick-slip).
        let (v_new, a_tip) = if F == 0.0 {
            (v + dt * other / m_tip, other / m_tip)
        } else if v == 0.0 {
            if other.abs() > F {
                let a = (other - F * other.signum()) / m_tip;
                (dt * a, a)
            } else {
                (0.0, 0.0)
            }
        } else {
            let a = (other - F * v.signum()) / m_tip;
            let trial = v + dt * a;
            if trial.signum() == v.signum() {
                (trial, a)
            } else if other.abs() <= F {
                (0.0, a)
            } else {
                let rest = dt + v / a;
                (rest * (other - F * other.signum()) / m_tip, a)
            }
        };

        let slot = (step + half) / sub;
        if slot >= lead_samples && slot < lead_samples + samples {
            accel[slot - lead_samples] += a_tip / sub as f64;
            if step % sub == 0 {
                displacement[slot - lead_samples] = u[n];
                rotation[slot - lead_samples] = th[n];
            }
        }
        if step == total {
            break;
        }

        vu[n] = v_new;
        for i in 1..n {
            vu[i] += dt * fu[i] / chain.mass[i - 1];
        }
        let rotating = if chain.rotation_free { n } else { n - 1 };
        for i in 1..=rotating {
            vt[i] += dt * ft[i] / chain.inertia[i - 1];
        }
        for i in 1..=n {
            u[i] += dt * vu[i];
            th[i] += dt * vt[i];
        }
    }
    Trajectory {
        dt,
        steps_per_sample: sub,
        lead_s: lead_samples as f64 * period,
        accel,
        displacement,
        rotation,
    }
}

/// xoshiro256** seeded through splitmix64 (Blackman and Vigna, "Scrambled linear
/// pseudorandom number generators", 2018), with Box-Muller normals.
#[derive(Debug, Clone)]
pub struct Rng {
    state: [u64; 4],
}

impl Rng {
    pub fn new(seed: u64) -> Rng {
        let mut x = seed;
        let mut next = || {
            x = x.wrapping_add(0x9e37_79b9_7f4a_7c15);
            let mut z = x;
            z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
            z ^ (z >> 31)
        };
        Rng {
            state: [next(), next(), next(), next()],
        }
    }

    pub fn next_u64(&mut self) -> u64 {
        let s = &mut self.state;
        let result = s[1].wrapping_mul(5).rotate_left(7).wrapping_mul(9);
        let t = s[1] << 17;
        s[2] ^= s[0];
        s[3] ^= s[1];
        s[1] ^= s[2];
        s[0] ^= s[3];
        s[2] ^= t;
        s[3] = s[3].rotate_left(45);
        result
    }

    /// Uniform in [0, 1) with 53 random bits.
    pub fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// Standard normal (Box-Muller; one of the pair is used, for simplicity of the
    /// stream's bookkeeping).
    pub fn normal(&mut self) -> f64 {
        let u1 = 1.0 - self.uniform();
        let u2 = self.uniform();
        (-2.0 * u1.ln()).sqrt() * (TAU * u2).cos()
    }
}

/// A generated case: both records as written, and what the generation used.
#[derive(Debug, Clone)]
pub struct Generated {
    /// (time_s, accel_m_s2) as measured.
    pub decay: Vec<(f64, f64)>,
    /// (displacement_mm, force_n) as measured.
    pub static_record: Vec<(f64, f64)>,
    pub trajectory: Trajectory,
    /// Peak of the AC-coupled acceleration before noise (m/s^2).
    pub peak_m_s2: f64,
    /// The ADC's step (m/s^2).
    pub quantisation_m_s2: f64,
}

/// Gravity used to size the static test when the case has none.
const STATIC_GRAVITY_M_S2: f64 = 9.81;

/// Runs the truth and the measurement model (deterministic in `case.seed`).
pub fn generate(case: &TruthCase) -> Generated {
    let mut rng = Rng::new(case.seed);
    let fs = case.sample_rate_hz;
    let lead_s = 0.2 + rng.uniform();
    let lead_samples = ((lead_s * fs).round() as usize).max(1);
    let samples = (case.record_s * fs).round() as usize;
    let trajectory = simulate(case, lead_samples, samples);

    let mean = trajectory.accel.iter().sum::<f64>() / samples.max(1) as f64;
    let ac: Vec<f64> = trajectory.accel.iter().map(|a| a - mean).collect();
    let peak = ac.iter().fold(0.0f64, |p, a| p.max(a.abs()));
    let full_scale = 1.2 * peak;
    let lsb = 2.0 * full_scale / 65536.0;
    let decay = ac
        .iter()
        .enumerate()
        .map(|(i, a)| {
            let noisy = a + case.noise_fraction * peak * rng.normal();
            let code = (noisy / lsb).round().clamp(-32768.0, 32767.0);
            (i as f64 / fs, code * lsb)
        })
        .collect();

    let static_record = static_points(case)
        .into_iter()
        .map(|(x_mm, f_n, x_full, f_full)| {
            let dx = case.static_noise_fraction * x_full * rng.normal();
            let df = case.static_noise_fraction * f_full * rng.normal();
            (x_mm + dx, f_n + df)
        })
        .collect();
    Generated {
        decay,
        static_record,
        trajectory,
        peak_m_s2: peak,
        quantisation_m_s2: lsb,
    }
}

/// The noise-free static record: (compression mm, force N, compression full scale mm,
/// force full scale N) per point, loading then unloading.
pub fn static_points(case: &TruthCase) -> Vec<(f64, f64, f64, f64)> {
    let g = if case.gravity_m_s2 > 0.0 {
        case.gravity_m_s2
    } else {
        STATIC_GRAVITY_M_S2
    };
    let max_force = 1.5 * case.mass_kg * g;
    let x_max = case.compression_under(max_force);
    let k = case.linear_stiffness_n_m();
    let k3 = case.effect.cubic();
    let friction = case.effect.friction();
    let n = case.static_points.max(2) - 1;
    let loading = (0..=n).map(|j| (j, 1.0));
    let unloading = (0..n).rev().map(|j| (j, -1.0));
    loading
        .chain(unloading)
        .map(|(j, sense)| {
            let x = x_max * j as f64 / n as f64;
            let force = k * x + k3 * x.powi(3) + sense * friction;
            (1e3 * x, force, 1e3 * x_max, max_force + friction)
        })
        .collect()
}

/// Linear axial period (s) from Rayleigh's estimate `2 pi sqrt((m + m_s/3) / k)`.
pub fn rayleigh_period_s(case: &TruthCase) -> f64 {
    TAU * ((case.mass_kg + case.spring_mass_kg() / 3.0) / case.linear_stiffness_n_m()).sqrt()
}

/// The chain's axial mode with the weight's rotation held (the one `zeta` refers to).
pub fn axial_mode(case: &TruthCase) -> Option<ChainMode> {
    Chain::new(case, false)
        .modes()
        .into_iter()
        .max_by(|a, b| a.weight_axial.abs().total_cmp(&b.weight_axial.abs()))
}

/// The case's `case.json` (nominal values, as a rig would give them).
pub fn case_json(case: &TruthCase) -> serde_json::Value {
    json!({
        "name": case.name,
        "spring": {
            "active_coils": case.spring.active_coils,
            "mean_diameter_mm": case.spring.mean_diameter_mm,
            "wire_diameter_mm": case.spring.wire_diameter_mm,
            "pitch_mm": case.spring.pitch_mm,
        },
        "material": {
            "youngs_modulus_mpa": case.nominal_youngs_modulus_mpa,
            "poisson_ratio": case.poisson_ratio,
            "density_kg_m3": case.density_kg_m3,
        },
        "mass_kg": case.nominal_mass_kg,
        "gravity_m_s2": case.gravity_m_s2,
        "records": { "static": ["static.csv"], "decay": ["decay.csv"] },
    })
}

/// The hidden truth (`truth.json`).
pub fn truth_json(case: &TruthCase, generated: &Generated) -> serde_json::Value {
    let mut parameters = serde_json::Map::new();
    if let Some((name, value)) = case.effect.parameter() {
        parameters.insert(name.to_string(), json!(value));
    }
    let axial = axial_mode(case);
    let axial_omega = axial.as_ref().map_or(0.0, |m| m.omega);
    let modes: Vec<serde_json::Value> = case
        .chain()
        .modes()
        .iter()
        .take(2)
        .map(|m| {
            json!({
                "frequency_hz": m.omega / TAU,
                "weight_axial_share": m.weight_axial * m.weight_axial * case.mass_kg,
            })
        })
        .collect();
    let x0 = case.equilibrium_compression_m();
    let tangent = case.linear_stiffness_n_m() + 3.0 * case.effect.cubic() * x0 * x0;
    let t = &generated.trajectory;
    let period_samples = ((TAU / axial_omega.max(1e-9)) * case.sample_rate_hz).ceil() as usize;
    let start_amplitude = half_range(&t.displacement[..period_samples.min(t.displacement.len())]);
    let end_amplitude =
        half_range(&t.displacement[t.displacement.len().saturating_sub(period_samples)..]);
    json!({
        "case": case.name,
        "effect": case.effect.name(),
        "parameters": parameters,
        "youngs_modulus_mpa": case.youngs_modulus_mpa,
        "mass_kg": case.mass_kg,
        "damping_ratio": case.damping_ratio,
        "rayleigh_beta_s": case.chain().beta,
        "stiffness_n_mm": case.linear_stiffness_n_m() * 1e-3,
        "tangent_stiffness_n_mm": tangent * 1e-3,
        "period_s": TAU / axial_omega,
        "spring_mass_kg": case.spring_mass_kg(),
        "equilibrium_compression_mm": x0 * 1e3,
        "weight_rotation": if case.rotation_free() { "free" } else { "held" },
        "lowest_modes": modes,
        "record_start_amplitude_mm": start_amplitude * 1e3,
        "record_end_amplitude_mm": end_amplitude * 1e3,
        "nominal": {
            "youngs_modulus_mpa": case.nominal_youngs_modulus_mpa,
            "mass_kg": case.nominal_mass_kg,
        },
        "generation": {
            "seed": case.seed,
            "sample_rate_hz": case.sample_rate_hz,
            "record_s": case.record_s,
            "lead_s": t.lead_s,
            "noise_fraction_of_peak": case.noise_fraction,
            "static_noise_fraction_of_full_scale": case.static_noise_fraction,
            "adc_bits": 16,
            "adc_full_scale_m_s2": 1.2 * generated.peak_m_s2,
            "peak_accel_m_s2": generated.peak_m_s2,
            "segments": case.segments,
            "dt_s": t.dt,
            "steps_per_sample": t.steps_per_sample,
            "impulse_velocity_m_s": case.impulse_velocity_m_s,
            "rotation_kick_rad_s": case.rotation_kick_rad_s,
        },
    })
}

fn half_range(values: &[f64]) -> f64 {
    let (lo, hi) = values
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
            (lo.min(v), hi.max(v))
        });
    if values.is_empty() {
        0.0
    } else {
        0.5 * (hi - lo)
    }
}

/// Writes `text` to `path` through a temporary file in the same folder and a rename.
fn write_atomic(path: &Path, text: &str) -> io::Result<()> {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let temp = path.with_file_name(format!(".{name}.tmp"));
    std::fs::write(&temp, text)?;
    std::fs::rename(&temp, path)
}

/// The text of decay.csv.
pub fn decay_csv(decay: &[(f64, f64)]) -> String {
    let mut text = String::with_capacity(24 * decay.len() + 32);
    text.push_str("time_s,accel_m_s2\n");
    for (t, a) in decay {
        text.push_str(&format!("{t:.6},{a:.6e}\n"));
    }
    text
}

/// The text of static.csv.
pub fn static_csv(points: &[(f64, f64)]) -> String {
    let mut text = String::from("displacement_mm,force_n\n");
    for (x, f) in points {
        text.push_str(&format!("{x:.5},{f:.5}\n"));
    }
    text
}

/// Generates `case` and writes its folder: case.json, static.csv, decay.csv, truth.json
/// (each through a temporary file and a rename).
pub fn write_case(dir: &Path, case: &TruthCase) -> io::Result<()> {
    std::fs::create_dir_all(dir)?;
    let generated = generate(case);
    let pretty = |value: &serde_json::Value| {
        serde_json::to_string_pretty(value)
            .map(|s| s + "\n")
            .map_err(io::Error::other)
    };
    write_atomic(
        &dir.join("static.csv"),
        &static_csv(&generated.static_record),
    )?;
    write_atomic(&dir.join("decay.csv"), &decay_csv(&generated.decay))?;
    write_atomic(
        &dir.join("truth.json"),
        &pretty(&truth_json(case, &generated))?,
    )?;
    write_atomic(&dir.join("case.json"), &pretty(&case_json(case))?)
}

/// The handbook modulus every case.json gives (the truths are 3-7 % below it).
pub const NOMINAL_YOUNGS_MODULUS_MPA: f64 = 206_000.0;

/// A spring with its true modulus and weight (the catalogue's building block).
#[derive(Debug, Clone, Copy)]
struct Rig {
    spring: Helix,
    youngs_modulus_mpa: f64,
    mass_kg: f64,
}

const PAPER_RIG: Rig = Rig {
    spring: Helix::PAPER,
    youngs_modulus_mpa: 194_000.0,
    mass_kg: 5.24,
};
const RIG_G1: Rig = Rig {
    spring: Helix {
        active_coils: 12.0,
        mean_diameter_mm: 26.0,
        wire_diameter_mm: 3.2,
        pitch_mm: 6.8,
    },
    youngs_modulus_mpa: 196_000.0,
    mass_kg: 5.75,
};
const RIG_G2: Rig = Rig {
    spring: Helix {
        active_coils: 9.0,
        mean_diameter_mm: 18.0,
        wire_diameter_mm: 2.2,
        pitch_mm: 4.6,
    },
    youngs_modulus_mpa: 200_000.0,
    mass_kg: 2.8,
};
const RIG_G3: Rig = Rig {
    spring: Helix {
        active_coils: 8.0,
        mean_diameter_mm: 30.0,
        wire_diameter_mm: 4.0,
        pitch_mm: 8.5,
    },
    youngs_modulus_mpa: 192_000.0,
    mass_kg: 5.4,
};
const RIG_G4: Rig = Rig {
    spring: Helix {
        active_coils: 16.0,
        mean_diameter_mm: 22.0,
        wire_diameter_mm: 2.8,
        pitch_mm: 5.6,
    },
    youngs_modulus_mpa: 198_000.0,
    mass_kg: 6.8,
};
/// A steeper helix (pitch angle 8 degrees): a stronger axial-torsional coupling.
const RIG_G5: Rig = Rig {
    spring: Helix {
        active_coils: 10.0,
        mean_diameter_mm: 20.0,
        wire_diameter_mm: 2.5,
        pitch_mm: 9.0,
    },
    youngs_modulus_mpa: 197_000.0,
    mass_kg: 4.0,
};

/// Measurement settings of one catalogue entry.
#[derive(Debug, Clone, Copy)]
struct Test {
    sample_rate_hz: f64,
    record_s: f64,
    noise_fraction: f64,
    damping_ratio: f64,
    /// Initial amplitude of the axial motion (m).
    amplitude_m: f64,
    /// Nominal mass over the true one (0.9 or 1.1).
    nominal_mass_ratio: f64,
    seed: u64,
}

/// A linear case (no effect yet) of `rig` under `test`.
fn linear_case(name: &str, rig: Rig, test: Test) -> TruthCase {
    let mut case = TruthCase {
        name: name.to_string(),
        spring: rig.spring,
        youngs_modulus_mpa: rig.youngs_modulus_mpa,
        nominal_youngs_modulus_mpa: NOMINAL_YOUNGS_MODULUS_MPA,
        poisson_ratio: 0.3,
        density_kg_m3: 7850.0,
        mass_kg: rig.mass_kg,
        nominal_mass_kg: (rig.mass_kg * test.nominal_mass_ratio * 1e3).round() / 1e3,
        gravity_m_s2: 9.81,
        damping_ratio: test.damping_ratio,
        effect: Effect::None,
        segments: 16,
        impulse_velocity_m_s: 0.0,
        rotation_kick_rad_s: 0.0,
        sample_rate_hz: test.sample_rate_hz,
        record_s: test.record_s,
        noise_fraction: test.noise_fraction,
        static_noise_fraction: 0.003,
        static_points: 41,
        seed: test.seed,
    };
    case.impulse_velocity_m_s = test.amplitude_m * TAU / rayleigh_period_s(&case);
    case
}

/// Friction that makes the amplitude at the record's end `fraction` smaller than the
/// linear decay alone. Per cycle `dA/dn = -delta A - 4F/k` (delta = 2 pi zeta) gives
/// `A(n) = (A0 + c) e^(-delta n) - c`, `c = 4F / (k delta)`, so the loss against the
/// linear decay after n cycles is `c (e^(delta n) - 1) / A0`.
fn friction_case(name: &str, rig: Rig, test: Test, fraction: f64) -> TruthCase {
    let mut case = linear_case(name, rig, test);
    let cycles = test.record_s / rayleigh_period_s(&case);
    let delta = TAU * test.damping_ratio;
    let growth = (delta * cycles).exp_m1() / delta;
    let force = fraction * test.amplitude_m * case.linear_stiffness_n_m() / (4.0 * growth);
    case.effect = Effect::CoulombFriction {
        friction_force_n: round_to(force, 4),
    };
    case
}

/// Velocity-squared drag whose equivalent viscous coefficient at the initial amplitude,
/// `8 c2 w A / (3 pi)`, is `ratio` times the linear one `2 zeta m w`.
fn quadratic_case(name: &str, rig: Rig, test: Test, ratio: f64) -> TruthCase {
    let mut case = linear_case(name, rig, test);
    let c2 = ratio * 3.0 * PI * test.damping_ratio * case.mass_kg / (4.0 * test.amplitude_m);
    case.effect = Effect::QuadraticDamping {
        quadratic_damping_n_s2_m2: round_to(c2, 4),
    };
    case
}

/// A cubic spring with `k3 x0^2 = eps k_t` at the preload x0, `k_t = k + 3 k3 x0^2` the
/// tangent stiffness there. About the preload the restoring force is
/// `k_t y + 3 k3 x0 y^2 + k3 y^3`, whose backbone (Nayfeh and Mook, Nonlinear
/// Oscillations, 4.1) is `dw/w = (A/x0)^2 (3 eps/8 - 15 eps^2/4)`: hardening up to
/// eps = 0.1, softening beyond. Without gravity, eps is `k3 A^2 / k` at the initial
/// amplitude A and the backbone `dw/w = 3 k3 A^2 / (8 k)`.
fn cubic_case(name: &str, rig: Rig, test: Test, gravity_m_s2: f64, epsilon: f64) -> TruthCase {
    let mut case = linear_case(name, rig, test);
    case.gravity_m_s2 = gravity_m_s2;
    let k = case.linear_stiffness_n_m();
    let k3 = if case.gravity_m_s2 > 0.0 {
        // k3 x0^2 = b k with b = eps / (1 - 3 eps), and k x0 (1 + b) = m g.
        let b = epsilon / (1.0 - 3.0 * epsilon);
        let x0 = case.mass_kg * case.gravity_m_s2 / (k * (1.0 + b));
        b * k / (x0 * x0)
    } else {
        epsilon * k / test.amplitude_m.powi(2)
    };
    case.effect = Effect::CubicStiffness {
        cubic_stiffness_n_m3: round_to(k3, 4),
    };
    case
}

/// A free-turning weight whose uncoupled torsional frequency `sqrt(K_tt / (J + J_s/3))` is
/// `1 + detuning` times the axial one `sqrt(K_zz / (m + m_s/3))`, K = C^-1.
fn coupling_case(name: &str, rig: Rig, test: Test, detuning: f64) -> TruthCase {
    let mut case = linear_case(name, rig, test);
    let (kzz, _, ktt) = case.compliance().stiffness();
    let m_s = case.spring_mass_kg();
    let r = 0.5e-3 * case.spring.mean_diameter_mm;
    let w_axial_sq = kzz / (case.mass_kg + m_s / 3.0);
    let j = ktt / (w_axial_sq * (1.0 + detuning).powi(2)) - m_s * r * r / 3.0;
    case.effect = Effect::AxialTorsionalCoupling {
        rotary_inertia_kg_m2: round_to(j, 4),
    };
    case
}

/// `x` to `digits` significant digits (parameters read well in truth.json).
fn round_to(x: f64, digits: i32) -> f64 {
    if x == 0.0 {
        return 0.0;
    }
    let scale = 10f64.powi(digits - 1 - x.abs().log10().floor() as i32);
    (x * scale).round() / scale
}

/// The catalogue: every effect at two or more magnitudes, and null cases, on springs other
/// than the paper's (and the paper's), with varied noise, sampling and length.
pub fn standard_cases() -> Vec<TruthCase> {
    let test = |sample_rate_hz, record_s, noise_fraction, damping_ratio, amplitude_mm, seed| Test {
        sample_rate_hz,
        record_s,
        noise_fraction,
        damping_ratio,
        amplitude_m: amplitude_mm * 1e-3,
        nominal_mass_ratio: if seed % 2 == 0 { 1.1 } else { 0.9 },
        seed,
    };
    vec![
        linear_case("null_g4", RIG_G4, test(500.0, 20.0, 0.01, 0.002, 4.0, 101)),
        linear_case(
            "null_paper",
            PAPER_RIG,
            test(1000.0, 25.0, 0.005, 0.00175, 3.0, 102),
        ),
        linear_case(
            "null_g2",
            RIG_G2,
            test(2000.0, 30.0, 0.02, 0.0025, 2.0, 103),
        ),
        linear_case(
            "null_g3",
            RIG_G3,
            test(500.0, 40.0, 0.002, 0.0015, 2.5, 104),
        ),
        friction_case(
            "friction_g1",
            RIG_G1,
            test(1000.0, 20.0, 0.005, 0.001, 3.0, 201),
            0.4,
        ),
        friction_case(
            "friction_g4_strong",
            RIG_G4,
            test(800.0, 30.0, 0.01, 0.0008, 4.0, 202),
            0.6,
        ),
        // Friction that stops the weight within the record (it sticks for the last
        // third): the decay ends in a dead band, not in noise.
        friction_case(
            "friction_paper_sticks",
            PAPER_RIG,
            test(1000.0, 30.0, 0.005, 0.00175, 3.0, 204),
            1.6,
        ),
        friction_case(
            "friction_g2_weak",
            RIG_G2,
            test(1250.0, 25.0, 0.003, 0.0012, 2.0, 203),
            0.25,
        ),
        quadratic_case(
            "quadratic_g3",
            RIG_G3,
            test(500.0, 25.0, 0.005, 0.0015, 3.0, 301),
            1.0,
        ),
        quadratic_case(
            "quadratic_g1_weak",
            RIG_G1,
            test(2000.0, 35.0, 0.002, 0.002, 4.0, 302),
            0.5,
        ),
        quadratic_case(
            "quadratic_paper_strong",
            PAPER_RIG,
            test(800.0, 30.0, 0.01, 0.00175, 3.0, 303),
            2.0,
        ),
        cubic_case(
            "cubic_g2",
            RIG_G2,
            test(1000.0, 20.0, 0.003, 0.0015, 5.0, 401),
            9.81,
            0.05,
        ),
        cubic_case(
            "cubic_g3_strong",
            RIG_G3,
            test(800.0, 30.0, 0.01, 0.0015, 2.5, 402),
            9.81,
            0.16,
        ),
        // A horizontal rig (no preload): the plain backbone 3 k3 A^2 / (8 k).
        cubic_case(
            "cubic_g1_horizontal",
            RIG_G1,
            test(1000.0, 25.0, 0.005, 0.0015, 3.0, 403),
            0.0,
            0.016,
        ),
        coupling_case(
            "coupling_g5",
            RIG_G5,
            test(1000.0, 25.0, 0.005, 0.002, 3.0, 501),
            0.03,
        ),
        coupling_case(
            "coupling_g5_far",
            RIG_G5,
            test(2000.0, 30.0, 0.01, 0.002, 3.0, 502),
            0.09,
        ),
        coupling_case(
            "coupling_paper",
            PAPER_RIG,
            test(500.0, 40.0, 0.002, 0.00175, 3.0, 503),
            0.04,
        ),
    ]
}

/// The cases shipped under `cases/measured/` (one per effect and one null).
pub const SHIPPED: [&str; 5] = [
    "null_g4",
    "friction_g1",
    "quadratic_g3",
    "cubic_g2",
    "coupling_g5",
];
