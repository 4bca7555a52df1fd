//! An independent truth model for the damping-law tests: it writes measured
//! cases (docs/measured-case.md) whose decay records come from a damping law the
//! test knows and `coil-tune damping` must find. It shares no code with coil's solver or
//! tuner (only `truth.rs`'s Jacobi eigensolver).
//!
//! # Model
//! The spring is a chain of `N` equal segments along its axis: the wire's mass
//! `m_s = rho (pi d^2 / 4) n sqrt((pi D)^2 + h^2)` lumped as `m_s / N` at the inner
//! nodes and `m_s / 2N` at the top node, which also carries the weight; each segment has
//! stiffness `N K`, `K = G d^4 / (8 n D^3)` (G = E / 2(1 + nu)), the base node fixed.
//! Damping laws (the weight's mass never takes Rayleigh alpha, as in the paper):
//! - `Rayleigh { alpha, beta }`: `C = alpha M_wire + beta K_chain`;
//! - `Hysteretic { eta }`: `C = M V diag(eta w_i) V^T M` over every chain mode
//!   (`zeta_i = eta / 2`), the modes from the truth model's cyclic Jacobi eigensolver;
//! - `Dashpot { c }`: `c` (N s/m) between the weight and ground.
//!
//! A record at the weight (`mode: axial`) starts from the quasi-static velocity profile
//! `v_i = v0 z_i / L`; a surge record holds the weight (the top node fixed) and starts
//! from the half-sine `u_i = u0 sin(pi z_i / L)`, recorded at mid-coil. The state is
//! integrated by classical Runge-Kutta 4 at a step well inside its stability limit
//! (`|lambda dt| < 1` for every eigenvalue, overdamped chain modes included), in SI units.
//! Noise: seeded Gaussian, standard deviation `noise` times the record's largest value.
//!
//! # Repeat scatter
//! Repeated decay tests of one rig do not give one zeta (mounting, amplitude, temperature;
//! the paper's Table 1 spreads about 3 %). Each record here is a test of its own: its
//! law's parameters are multiplied by `1 + scatter g` (g seeded standard normal), which
//! moves every mode's zeta by that factor. A mass listed twice is a repeated test.
//!
//! # What a design can decide
//! [`DampingTruth::decidability`] says, from the physics and the design alone, whether the
//! records can name the law: a surge record separates every law (zeta of the surge mode
//! over the weight mode's is about 30 under beta, 1 under a loss factor, 0 under a dashpot
//! at the weight); without one, only the hysteretic law is separable (every viscous law
//! gives zeta proportional to `m_eff^-1/2`), by the relative difference
//! `delta = 1 - sqrt(m_lo / m_hi)` (effective masses) between the lightest and heaviest
//! weights. In units of its standard error `z = delta / (s sqrt(1/n_lo + 1/n_hi))`, with
//! `s` the scatter the judge must assume (3 % without repeats, the true one with), it is
//! decidable when `z^2` is at least 4 times the 99.9 % point of the test (chi-square(1),
//! or F(1, nu) with a scatter estimated on nu degrees of freedom: printed tables), not
//! decidable when `z <= 1`, and marginal in between.

// The small dense kernels below index matrices as the textbook formulas do.
#![allow(clippy::needless_range_loop)]

use std::fmt::Write as _;
use std::path::Path;

/// The damping law hidden in a case.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum TruthLaw {
    Rayleigh {
        alpha: f64,
        beta: f64,
    },
    Hysteretic {
        eta: f64,
    },
    /// N s/m.
    Dashpot {
        c: f64,
    },
}

impl TruthLaw {
    /// The law with every parameter multiplied by `factor` (one test's scatter).
    pub fn scaled(self, factor: f64) -> Self {
        match self {
            TruthLaw::Rayleigh { alpha, beta } => TruthLaw::Rayleigh {
                alpha: alpha * factor,
                beta: beta * factor,
            },
            TruthLaw::Hysteretic { eta } => TruthLaw::Hysteretic { eta: eta * factor },
            TruthLaw::Dashpot { c } => TruthLaw::Dashpot { c: c * factor },
        }
    }
}

/// A generated case.
#[derive(Debug, Clone)]
pub struct DampingTruth {
    /// The case's name.
    pub name: String,
    /// The hidden law (each test's parameters scattered about it).
    pub law: TruthLaw,
    /// Attached masses (kg), one axial record each; the first is the case's `mass_kg`.
    /// A mass listed again is a repeated test.
    pub masses_kg: Vec<f64>,
    /// Surge records (weight held), each a test of its own.
    pub surges: usize,
    /// Relative 1-sigma scatter of each test's damping (module docs).
    pub scatter: f64,
    /// Noise standard deviation relative to the record's largest value.
    pub noise: f64,
    /// The generator's seed.
    pub seed: u64,
}

/// Whether a design's records can name the law (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Decidability {
    /// The law must be named.
    Decidable,
    /// The verdict must be "not identifiable".
    Undecidable,
    /// Either the true law or "not identifiable"; never another law.
    Marginal,
}

/// The 99.9 % points of F(1, nu), nu = 1..=12 (printed tables), then chi-square(1).
const F1_999: [f64; 12] = [
    405_284.0, 998.5, 167.0, 74.14, 47.18, 35.51, 29.25, 25.41, 22.86, 21.04, 19.69, 18.64,
];
const CHI2_1_999: f64 = 10.828;
/// The scatter a judge assumes without repeated tests (the paper's Table 1).
pub const DEFAULT_SCATTER: f64 = 0.03;

impl DampingTruth {
    /// What the design can decide (module docs).
    pub fn decidability(&self) -> Decidability {
        if self.surges > 0 {
            return Decidability::Decidable;
        }
        let TruthLaw::Hysteretic { .. } = self.law else {
            return Decidability::Undecidable;
        };
        let (m_s, _) = spring_mass_and_stiffness();
        let lo = self.masses_kg.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = self.masses_kg.iter().copied().fold(0.0, f64::max);
        let count = |m: f64| self.masses_kg.iter().filter(|&&x| x == m).count() as f64;
        // Degrees of freedom of the repeats: records minus distinct masses.
        let mut distinct = self.masses_kg.clone();
        distinct.sort_by(f64::total_cmp);
        distinct.dedup();
        let nu = self.masses_kg.len() - distinct.len();
        let (s, critical) = match nu {
            0 => (DEFAULT_SCATTER, CHI2_1_999),
            n => (
                self.scatter,
                F1_999.get(n - 1).copied().unwrap_or(F1_999[11]),
            ),
        };
        let delta = 1.0 - ((lo + m_s / 3.0) / (hi + m_s / 3.0)).sqrt();
        let z = delta / (s * (1.0 / count(lo) + 1.0 / count(hi)).sqrt());
        if z * z >= 4.0 * critical {
            Decidability::Decidable
        } else if z <= 1.0 {
            Decidability::Undecidable
        } else {
            Decidability::Marginal
        }
    }
}

/// The paper's spring (Table 1 geometry) and a steel at the paper's calibrated E.
pub const COILS: f64 = 14.0;
pub const MEAN_DIAMETER_MM: f64 = 24.0;
pub const WIRE_DIAMETER_MM: f64 = 3.0;
pub const PITCH_MM: f64 = 6.2;
pub const YOUNGS_MPA: f64 = 193_837.8;
pub const POISSON: f64 = 0.3;
pub const DENSITY: f64 = 7850.0;
const SEGMENTS: usize = 16;

/// Wire mass (kg) and axial stiffness (N/m) of the truth spring.
pub fn spring_mass_and_stiffness() -> (f64, f64) {
    let d = WIRE_DIAMETER_MM * 1e-3;
    let big_d = MEAN_DIAMETER_MM * 1e-3;
    let h = PITCH_MM * 1e-3;
    let length = COILS * ((std::f64::consts::PI * big_d).powi(2) + h * h).sqrt();
    let m_s = DENSITY * std::f64::consts::PI * d * d / 4.0 * length;
    let g = YOUNGS_MPA * 1e6 / (2.0 * (1.0 + POISSON));
    (m_s, g * d.powi(4) / (8.0 * COILS * big_d.powi(3)))
}

/// Seeded generator: SplitMix64 with Box-Muller normals.
struct Normal(u64);

impl Normal {
    fn uniform(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        ((z >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }

    fn sample(&mut self) -> f64 {
        let (u, v) = (self.uniform(), self.uniform());
        (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
    }
}

/// The chain's M (diagonal), K and C (dense) on its free nodes, SI units.
struct Chain {
    m: Vec<f64>,
    k: Vec<Vec<f64>>,
    c: Vec<Vec<f64>>,
    /// Axial position of each free node over the length (0..1].
    z: Vec<f64>,
}

fn chain(law: TruthLaw, mass_kg: f64, held: bool) -> Chain {
    let (m_s, k_total) = spring_mass_and_stiffness();
    let n = if held { SEGMENTS - 1 } else { SEGMENTS };
    let ks = SEGMENTS as f64 * k_total;
    let mut wire = vec![m_s / SEGMENTS as f64; n];
    if !held {
        wire[n - 1] = m_s / (2.0 * SEGMENTS as f64);
    }
    let mut m = wire.clone();
    if !held {
        m[n - 1] += mass_kg;
    }
    let mut k = vec![vec![0.0; n]; n];
    for i in 0..n {
        // Segment below node i, and above it unless it is the free top.
        k[i][i] += ks;
        if i > 0 {
            k[i][i - 1] -= ks;
            k[i - 1][i] -= ks;
            k[i - 1][i - 1] += ks;
        }
    }
    if held {
        // The segment from the last free node to the held weight.
        k[n - 1][n - 1] += ks;
    }
    let mut c = vec![vec![0.0; n]; n];
    match law {
        TruthLaw::Rayleigh { alpha, beta } => {
            for i in 0..n {
                c[i][i] += alpha * wire[i];
                for j in 0..n {
                    c[i][j] += beta * k[i][j];
                }
            }
        }
        TruthLaw::Hysteretic { eta } => {
            let a: Vec<Vec<f64>> = (0..n)
                .map(|i| (0..n).map(|j| k[i][j] / (m[i] * m[j]).sqrt()).collect())
                .collect();
            let (w2, v) = crate::truth::jacobi_eigen(a);
            for (mode, &lambda) in w2.iter().enumerate() {
                let d = eta * lambda.max(0.0).sqrt();
                for i in 0..n {
                    for j in 0..n {
                        c[i][j] += m[i].sqrt() * v[i][mode] * d * v[j][mode] * m[j].sqrt();
                    }
                }
            }
        }
        TruthLaw::Dashpot { c: dashpot } => {
            if !held {
                c[n - 1][n - 1] += dashpot;
            }
        }
    }
    let z = (1..=n).map(|i| i as f64 / SEGMENTS as f64).collect();
    Chain { m, k, c, z }
}

/// `a = M^-1 (-K u - C v)`.
fn accel(ch: &Chain, u: &[f64], v: &[f64], out: &mut [f64]) {
    for i in 0..u.len() {
        let f: f64 = (0..u.len())
            .map(|j| ch.k[i][j] * u[j] + ch.c[i][j] * v[j])
            .sum();
        out[i] = -f / ch.m[i];
    }
}

/// Acceleration at node `probe` every `sample_s` for `duration_s`.
fn simulate(
    ch: &Chain,
    u0: Vec<f64>,
    v0: Vec<f64>,
    probe: usize,
    sample_s: f64,
    duration_s: f64,
) -> Vec<f64> {
    let n = u0.len();
    // Step: below 1 / |lambda| for the stiffest undamped and the fastest overdamped modes.
    let k_max = (0..n).map(|i| ch.k[i][i] / ch.m[i]).fold(0.0, f64::max);
    let c_max = (0..n)
        .map(|i| ch.c[i][i].abs() / ch.m[i])
        .fold(0.0, f64::max);
    let limit = 0.5 / (2.0 * k_max.sqrt()).max(2.0 * c_max);
    let sub = (sample_s / limit).ceil().max(1.0) as usize;
    let dt = sample_s / sub as f64;
    let samples = (duration_s / sample_s).round() as usize;
    let (mut u, mut v) = (u0, v0);
    let mut a = vec![0.0; n];
    let mut out = Vec::with_capacity(samples);
    let (mut k1u, mut k1v, mut k2u, mut k2v) =
        (vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let (mut k3u, mut k3v, mut k4u, mut k4v) =
        (vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let (mut tu, mut tv) = (vec![0.0; n], vec![0.0; n]);
    for _ in 0..samples {
        accel(ch, &u, &v, &mut a);
        out.push(a[probe]);
        for _ in 0..sub {
            k1u.copy_from_slice(&v);
            accel(ch, &u, &v, &mut k1v);
            for i in 0..n {
                tu[i] = u[i] + 0.5 * dt * k1u[i];
                tv[i] = v[i] + 0.5 * dt * k1v[i];
            }
            k2u.copy_from_slice(&tv);
            accel(ch, &tu, &tv, &mut k2v);
            for i in 0..n {
                tu[i] = u[i] + 0.5 * dt * k2u[i];
                tv[i] = v[i] + 0.5 * dt * k2v[i];
            }
            k3u.copy_from_slice(&tv);
            accel(ch, &tu, &tv, &mut k3v);
            for i in 0..n {
                tu[i] = u[i] + dt * k3u[i];
                tv[i] = v[i] + dt * k3v[i];
            }
            k4u.copy_from_slice(&tv);
            accel(ch, &tu, &tv, &mut k4v);
            for i in 0..n {
                u[i] += dt / 6.0 * (k1u[i] + 2.0 * k2u[i] + 2.0 * k3u[i] + k4u[i]);
                v[i] += dt / 6.0 * (k1v[i] + 2.0 * k2v[i] + 2.0 * k3v[i] + k4v[i]);
            }
        }
    }
    out
}

fn csv(values: &[f64], sample_s: f64, noise: f64, rng: &mut Normal) -> String {
    let peak = values.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let mut s = String::from("time_s,accel_m_s2\n");
    for (i, x) in values.iter().enumerate() {
        let y = x + noise * peak * rng.sample();
        let _ = writeln!(s, "{:.7},{y:.9e}", i as f64 * sample_s);
    }
    s
}

impl DampingTruth {
    /// Writes `case.json` and the records into `dir`.
    pub fn write(&self, dir: &Path) -> std::io::Result<()> {
        std::fs::create_dir_all(dir)?;
        let mut rng = Normal(self.seed);
        let mut entries = Vec::new();
        let test_law = |rng: &mut Normal| self.law.scaled(1.0 + self.scatter * rng.sample());
        for (i, &mass) in self.masses_kg.iter().enumerate() {
            let ch = chain(test_law(&mut rng), mass, false);
            let v0: Vec<f64> = ch.z.iter().map(|z| 0.1 * z).collect();
            let u0 = vec![0.0; v0.len()];
            let probe = v0.len() - 1;
            let record = simulate(&ch, u0, v0, probe, 1e-3, 12.0);
            let file = format!("decay_{i}.csv");
            std::fs::write(dir.join(&file), csv(&record, 1e-3, self.noise, &mut rng))?;
            entries.push(format!("{{\"file\": \"{file}\", \"mass_kg\": {mass}}}"));
        }
        for j in 0..self.surges {
            let ch = chain(test_law(&mut rng), self.masses_kg[0], true);
            let u0: Vec<f64> =
                ch.z.iter()
                    .map(|z| 1e-4 * (std::f64::consts::PI * z).sin())
                    .collect();
            let v0 = vec![0.0; u0.len()];
            let probe = u0.len() / 2;
            let record = simulate(&ch, u0, v0, probe, 1e-4, 1.2);
            let file = format!("surge_{j}.csv");
            std::fs::write(dir.join(&file), csv(&record, 1e-4, self.noise, &mut rng))?;
            entries.push(format!(
                "{{\"file\": \"{file}\", \"mode\": \"surge\", \"location\": \"mid-coil\"}}"
            ));
        }
        let case = format!(
            "{{\n  \"name\": \"{}\",\n  \"spring\": {{\"active_coils\": {COILS}, \"mean_diameter_mm\": {MEAN_DIAMETER_MM}, \
             \"wire_diameter_mm\": {WIRE_DIAMETER_MM}, \"pitch_mm\": {PITCH_MM}}},\n  \
             \"material\": {{\"youngs_modulus_mpa\": 206000.0, \"poisson_ratio\": {POISSON}, \"density_kg_m3\": {DENSITY}}},\n  \
             \"mass_kg\": {},\n  \"gravity_m_s2\": 0.0,\n  \"records\": {{\"decay\": [{}]}}\n}}\n",
            self.name,
            self.masses_kg[0],
            entries.join(", ")
        );
        std::fs::write(dir.join("case.json"), case)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The chain's weight mode against `K / (m + m_s / 3)` (Rayleigh, 0.1 %), and the
    /// hysteretic chain's modal damping equal to eta / 2 in every mode.
    #[test]
    fn the_chain_is_the_spring() {
        let (m_s, k) = spring_mass_and_stiffness();
        let ch = chain(TruthLaw::Hysteretic { eta: 0.004 }, 5.0, false);
        let n = ch.m.len();
        let a: Vec<Vec<f64>> = (0..n)
            .map(|i| {
                (0..n)
                    .map(|j| ch.k[i][j] / (ch.m[i] * ch.m[j]).sqrt())
                    .collect()
            })
            .collect();
        let (w2, v) = crate::truth::jacobi_eigen(a);
        let w_min = w2.iter().copied().fold(f64::INFINITY, f64::min).sqrt();
        let rayleigh = (k / (5.0 + m_s / 3.0)).sqrt();
        assert!((w_min / rayleigh - 1.0).abs() < 1e-3, "{w_min} {rayleigh}");
        for (mode, &l) in w2.iter().enumerate() {
            // phi = M^-1/2 v: zeta = phi^T C phi / 2 w.
            let phi: Vec<f64> = (0..n).map(|i| v[i][mode] / ch.m[i].sqrt()).collect();
            let c: f64 = (0..n)
                .flat_map(|i| (0..n).map(move |j| (i, j)))
                .map(|(i, j)| phi[i] * ch.c[i][j] * phi[j])
                .sum();
            assert!((c / (2.0 * l.sqrt()) / 0.002 - 1.0).abs() < 1e-9);
        }
    }
}
