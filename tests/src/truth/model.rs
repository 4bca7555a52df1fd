//! The truth model: the helix's closed-form compliance, the hidden effects and the
//! lumped chain integrated here (no coil solver), with its seeded random numbers.

use std::f64::consts::{PI, TAU};

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

/// A law at the weight that the diagnosis catalogue does not hold (out-of-catalogue
/// truth): the diagnosis must call its misfit unexplained, or name a cause and report
/// the misfit it leaves, never a confident wrong cause. `y` is the weight's axial
/// displacement from its static equilibrium (m), `k` the spring's linear stiffness.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Anomaly {
    None,
    /// A stop of stiffness `stiffness_ratio k` that engages beyond `+-gap_m`: the force
    /// `-stiffness_ratio k (y - gap_m sign y)` for `|y| > gap_m` (a backlash gap
    /// between the weight and a stiff guide).
    Backlash {
        gap_m: f64,
        stiffness_ratio: f64,
    },
    /// A spring stiffer on one side of the equilibrium: `-stiffness_ratio k y` for
    /// `y > 0` only (a bilinear spring, a stop that closes on extension).
    Bilinear {
        stiffness_ratio: f64,
    },
    /// Hysteretic friction of the Bouc-Wen form (Wen, J. Eng. Mech. 102, 1976):
    /// force `-force_n z`, `dz/dt = (v / yield_m) (1 - (0.5 sign(v z) + 0.5) |z|)`
    /// (n = 1, beta = gamma = 0.5): a smooth stick-slip whose loss per cycle is
    /// neither constant nor a power of the amplitude.
    BoucWen {
        force_n: f64,
        yield_m: f64,
    },
}

impl Anomaly {
    /// The spec-style name of the anomaly (`none` for none).
    pub fn name(&self) -> &'static str {
        match self {
            Anomaly::None => "none",
            Anomaly::Backlash { .. } => "backlash",
            Anomaly::Bilinear { .. } => "bilinear_spring",
            Anomaly::BoucWen { .. } => "bouc_wen_friction",
        }
    }

    /// The force on the weight (N) at displacement `y` from equilibrium and velocity
    /// `v`, with the Bouc-Wen state `z` advanced over `dt` (explicit Euler, clamped to
    /// `|z| <= 1`, its bound).
    fn force(&self, k: f64, y: f64, v: f64, z: &mut f64, dt: f64) -> f64 {
        match *self {
            Anomaly::None => 0.0,
            Anomaly::Backlash {
                gap_m,
                stiffness_ratio,
            } => {
                if y.abs() > gap_m {
                    -stiffness_ratio * k * (y - gap_m * y.signum())
                } else {
                    0.0
                }
            }
            Anomaly::Bilinear { stiffness_ratio } => {
                if y > 0.0 {
                    -stiffness_ratio * k * y
                } else {
                    0.0
                }
            }
            Anomaly::BoucWen { force_n, yield_m } => {
                let f = -force_n * *z;
                let shape = 0.5 * (v * *z).signum() + 0.5;
                *z += dt * v / yield_m * (1.0 - shape * z.abs());
                *z = z.clamp(-1.0, 1.0);
                f
            }
        }
    }
}

/// A second decaying oscillation added to the recorded quantity: a slow mode of the
/// rig (a frame, a pendulum sway) or a second mode close to the axial one. Its
/// amplitude is `amplitude_fraction` of the free decay's peak (in the recorded
/// quantity), its frequency `frequency_ratio` times the axial one, its damping ratio
/// `damping_ratio`, its phase `phase_rad`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ExtraMode {
    pub frequency_ratio: f64,
    pub amplitude_fraction: f64,
    pub damping_ratio: f64,
    pub phase_rad: f64,
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
    /// Further hidden effects acting together with `effect` (each kind at most once).
    pub also: Vec<Effect>,
    /// How the decay is recorded (sensor and imperfections); the default is the
    /// accelerometer of the measurement model above.
    pub recording: Recording,
    /// A law outside the catalogue acting at the weight ([`Anomaly`]).
    pub anomaly: Anomaly,
}

/// What measures the weight's axial motion.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Sensor {
    /// AC-coupled acceleration (m/s^2), 16-bit over +-1.2 x peak (`accel_m_s2`).
    Accelerometer,
    /// Velocity (m/s, a vibrometer), 16-bit over +-1.2 x peak (`velocity_m_s`).
    Velocity,
    /// Position (mm: laser, LVDT, video), quantised in steps of `step_mm`, read as
    /// `offset_mm + sign * (u - u_eq)` (`displacement_mm`).
    Position {
        step_mm: f64,
        offset_mm: f64,
        sign: f64,
    },
}

impl Sensor {
    /// The decay.csv column the sensor writes.
    pub fn column(&self) -> &'static str {
        match self {
            Sensor::Accelerometer => "accel_m_s2",
            Sensor::Velocity => "velocity_m_s",
            Sensor::Position { .. } => "displacement_mm",
        }
    }
}

/// A hammer blow left at the start of the record: the weight rests for `rest_s`, then a
/// half-sine force of `duration_s` gives it the case's impulse velocity
/// (`integral F dt = m_tip v0`, peak `pi m_tip v0 / (2 duration)`), which also rings the
/// chain's higher modes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Impulse {
    pub rest_s: f64,
    pub duration_s: f64,
}

/// The decay record's sensor and imperfections, as real rigs write them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Recording {
    pub sensor: Sensor,
    /// The record (signal and noise) passed forward and backward through a
    /// second-order Butterworth low-pass at this cut-off (Hz), as a recorder's filter
    /// would: the noise is no longer white.
    pub band_limit_hz: Option<f64>,
    /// Time stamps jitter uniformly within +-`jitter_s` about the uniform step; the
    /// values are taken at the jittered times.
    pub jitter_s: f64,
    /// A DC offset and a linear drift over the record, each a fraction of the record's
    /// peak (of the free decay).
    pub offset_fraction: f64,
    pub drift_fraction: f64,
    pub impulse: Option<Impulse>,
    /// A second oscillation in the record ([`ExtraMode`]).
    pub extra_mode: Option<ExtraMode>,
    /// A sensor that saturates at this fraction of the free decay's peak.
    pub clip_fraction: Option<f64>,
}

impl Default for Recording {
    fn default() -> Recording {
        Recording {
            sensor: Sensor::Accelerometer,
            band_limit_hz: None,
            jitter_s: 0.0,
            offset_fraction: 0.0,
            drift_fraction: 0.0,
            impulse: None,
            extra_mode: None,
            clip_fraction: None,
        }
    }
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
    /// Every hidden effect (`effect`, then `also`), `none` left out.
    pub fn effects(&self) -> Vec<Effect> {
        std::iter::once(self.effect)
            .chain(self.also.iter().copied())
            .filter(|e| *e != Effect::None)
            .collect()
    }

    /// Every hidden effect as (spec's effect name, parameter name, value): the causes a
    /// diagnosis should name (empty for a null case).
    pub fn causes(&self) -> Vec<(&'static str, &'static str, f64)> {
        self.effects()
            .iter()
            .filter_map(|e| e.parameter().map(|(p, v)| (e.name(), p, v)))
            .collect()
    }

    /// Friction force (N) of all effects.
    pub fn friction(&self) -> f64 {
        self.effects().iter().map(Effect::friction).sum()
    }

    /// Drag coefficient (N s^2/m^2) of all effects.
    pub fn quadratic(&self) -> f64 {
        self.effects().iter().map(Effect::quadratic).sum()
    }

    /// Cubic stiffness (N/m^3) of all effects (negative: softening).
    pub fn cubic(&self) -> f64 {
        self.effects().iter().map(Effect::cubic).sum()
    }

    /// The weight's rotary inertia when it turns freely.
    pub fn rotary_inertia(&self) -> Option<f64> {
        self.effects().iter().find_map(Effect::rotary_inertia)
    }

    pub fn compliance(&self) -> Compliance {
        Compliance::of(&self.spring, self.youngs_modulus_mpa, self.poisson_ratio)
    }

    /// The weight's rotation is free (coupling case) or held by a guide.
    pub fn rotation_free(&self) -> bool {
        self.rotary_inertia().is_some()
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
    /// `k x + k3 x^3 = force` (Newton from the linear root). The left side is monotonic
    /// for k3 >= 0; for a softening spring (k3 < 0) it rises up to
    /// [`TruthCase::softening_limit_m`], and Newton from the linear root (left of the
    /// root of a concave function) climbs to the root without overshooting it.
    pub fn compression_under(&self, force_n: f64) -> f64 {
        let k = self.linear_stiffness_n_m();
        let k3 = self.cubic();
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

    /// The compression where a softening spring's force `k x + k3 x^3` peaks,
    /// `sqrt(k / (3 |k3|))` (m): beyond it the spring has no stiffness left (infinite for
    /// k3 >= 0).
    pub fn softening_limit_m(&self) -> f64 {
        let k3 = self.cubic();
        if k3 >= 0.0 {
            f64::INFINITY
        } else {
            (self.linear_stiffness_n_m() / (3.0 * -k3)).sqrt()
        }
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
        inertia[n - 1] = 0.5 * share * r * r + case.rotary_inertia().unwrap_or(0.0);
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
pub(crate) fn jacobi_eigen(mut a: Vec<Vec<f64>>) -> (Vec<f64>, Vec<Vec<f64>>) {
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
    /// The weight's axial velocity at the sample times (m/s; the mean of the leapfrog's
    /// half-step velocities either side).
    pub velocity: Vec<f64>,
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
    let F = case.friction();
    let c2 = case.quadratic();
    let k3 = case.cubic();
    let weight_force = -case.mass_kg * case.gravity_m_s2;
    let k_linear = case.linear_stiffness_n_m();
    let mut bouc_wen = 0.0;

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
    // A hammer blow (Recording::impulse) starts from rest; else the impulse is the
    // initial velocity.
    let pulse = case.recording.impulse.map(|p| {
        let peak = PI * chain.mass[n - 1] * case.impulse_velocity_m_s / (2.0 * p.duration_s);
        (p.rest_s, p.duration_s, peak)
    });
    if pulse.is_none() {
        vu[n] = case.impulse_velocity_m_s;
    }
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
    let mut velocity = vec![0.0; samples];
    let m_tip = chain.mass[n - 1];
    let t0 = lead_samples.max(1) as f64 * period;
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
        let hammer = pulse.map_or(0.0, |(rest, duration, peak)| {
            let t = step as f64 * dt - t0 - rest;
            if (0.0..duration).contains(&t) {
                peak * (PI * t / duration).sin()
            } else {
                0.0
            }
        });
        let anomaly = case
            .anomaly
            .force(k_linear, u[n] - tip_u, v, &mut bouc_wen, dt);
        let other = fu[n] + weight_force - k3 * u[n].powi(3) - c2 * v * v.abs() + hammer + anomaly;
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
                velocity[slot - lead_samples] = 0.5 * (v + v_new);
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
        velocity,
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

/// Relative change of the axial frequency at the record's initial amplitude
/// `A = v0 / w` due to the cubic spring, from the backbone (Nayfeh and Mook, 4.1): about
/// the preload `x0`, `dw/w = (A/x0)^2 (3 eps/8 - 15 eps^2/4)` with
/// `eps = k3 x0^2 / k_t`, `k_t = k + 3 k3 x0^2`; without gravity `3 k3 A^2 / (8 k)`.
/// Negative: softening (the frequency rises as the amplitude falls).
pub fn backbone_shift(case: &TruthCase) -> f64 {
    let k3 = case.cubic();
    let k = case.linear_stiffness_n_m();
    let x0 = case.equilibrium_compression_m();
    let k_t = k + 3.0 * k3 * x0 * x0;
    let w = (k_t / (case.mass_kg + case.spring_mass_kg() / 3.0)).sqrt();
    let a = case.impulse_velocity_m_s / w;
    if x0 > 0.0 {
        let eps = k3 * x0 * x0 / k_t;
        (a / x0).powi(2) * (3.0 * eps / 8.0 - 15.0 * eps * eps / 4.0)
    } else {
        3.0 * k3 * a * a / (8.0 * k)
    }
}
