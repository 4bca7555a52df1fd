//! Analytic test signals and a seeded random generator for the unit tests.

use std::f64::consts::TAU;

/// `offset + A e^{-zeta omega_n t} cos(omega_d t + phase)`, `omega_n = 2 pi frequency_hz`,
/// `omega_d = omega_n sqrt(1 - zeta^2)`.
#[derive(Debug, Clone, Copy)]
pub struct DampedSine {
    /// Undamped natural frequency, Hz.
    pub frequency_hz: f64,
    pub zeta: f64,
    pub amplitude: f64,
    pub phase: f64,
    pub offset: f64,
}

impl DampedSine {
    pub fn omega_n(&self) -> f64 {
        TAU * self.frequency_hz
    }
    pub fn omega_d(&self) -> f64 {
        self.omega_n() * (1.0 - self.zeta * self.zeta).sqrt()
    }
    pub fn sigma(&self) -> f64 {
        self.zeta * self.omega_n()
    }
    pub fn damped_period_s(&self) -> f64 {
        TAU / self.omega_d()
    }
    pub fn value(&self, t: f64) -> f64 {
        self.offset
            + self.amplitude * (-self.sigma() * t).exp() * (self.omega_d() * t + self.phase).cos()
    }
    /// Times of the true crests in `[0, duration]`: `tan(omega_d t + phase) = -sigma/omega_d`.
    pub fn crest_times(&self, duration_s: f64) -> Vec<f64> {
        let shift = (self.sigma() / self.omega_d()).atan();
        (-2..(duration_s / self.damped_period_s()) as i64 + 3)
            .map(|k| (TAU * k as f64 - shift - self.phase) / self.omega_d())
            .filter(|&t| (0.0..=duration_s).contains(&t))
            .collect()
    }
}

/// Samples `sine` at `rate_hz` over `duration_s`.
pub fn damped_sine(sine: &DampedSine, rate_hz: f64, duration_s: f64) -> (Vec<f64>, Vec<f64>) {
    let n = (duration_s * rate_hz).round() as usize;
    let time: Vec<f64> = (0..n).map(|i| i as f64 / rate_hz).collect();
    let values = time.iter().map(|&t| sine.value(t)).collect();
    (time, values)
}

/// xorshift64* with Box-Muller normals: small, seeded, good enough for test noise.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Rng(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1)
    }
    pub fn uniform(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let bits = self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11;
        (bits as f64 + 0.5) / (1u64 << 53) as f64
    }
    pub fn normal(&mut self) -> f64 {
        let (u, v) = (self.uniform(), self.uniform());
        (-2.0 * u.ln()).sqrt() * (TAU * v).cos()
    }
}
