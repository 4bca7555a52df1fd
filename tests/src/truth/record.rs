//! A truth case as a lab writes it: the sensor's record (noise, quantisation, band limit,
//! jitter, offset, drift, a hammer blow), the static points, `case.json`, `truth.json` and
//! the CSV files.

use super::model::*;
use serde_json::json;
use std::f64::consts::{PI, TAU};
use std::io;
use std::path::Path;

/// A generated case: both records as written, and what the generation used.
#[derive(Debug, Clone)]
pub struct Generated {
    /// (time_s, value) as measured, the value in the unit of `column`.
    pub decay: Vec<(f64, f64)>,
    /// The decay.csv column (`Sensor::column`).
    pub column: &'static str,
    /// (displacement_mm, force_n) as measured.
    pub static_record: Vec<(f64, f64)>,
    pub trajectory: Trajectory,
    /// Peak of the recorded quantity's free decay before noise (in the column's unit;
    /// m/s^2 for the accelerometer).
    pub peak_m_s2: f64,
    /// The ADC's or the position sensor's step (in the column's unit).
    pub quantisation_m_s2: f64,
    /// Index of the first sample after the hammer blow and its ringing (0 without one).
    pub free_decay_start: usize,
}

/// Gravity used to size the static test when the case has none.
const STATIC_GRAVITY_M_S2: f64 = 9.81;

/// Runs the truth and the measurement model (deterministic in `case.seed`).
pub fn generate(case: &TruthCase) -> Generated {
    let mut rng = Rng::new(case.seed);
    let fs = case.sample_rate_hz;
    let lead_s = 0.2 + rng.uniform();
    let lead_samples = if case.recording.impulse.is_some() {
        1
    } else {
        ((lead_s * fs).round() as usize).max(1)
    };
    let samples = (case.record_s * fs).round() as usize;
    let trajectory = simulate(case, lead_samples, samples);

    let (decay, peak, lsb, free_decay_start) = if case.recording == Recording::default() {
        accelerometer_record(case, &trajectory, &mut rng)
    } else {
        recorded(case, &trajectory, &mut rng)
    };

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
        column: case.recording.sensor.column(),
        static_record,
        trajectory,
        peak_m_s2: peak,
        quantisation_m_s2: lsb,
        free_decay_start,
    }
}

type Record = (Vec<(f64, f64)>, f64, f64, usize);

/// The plain accelerometer (the measurement model of the module docs).
fn accelerometer_record(case: &TruthCase, trajectory: &Trajectory, rng: &mut Rng) -> Record {
    let fs = case.sample_rate_hz;
    let samples = trajectory.accel.len();
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
    (decay, peak, lsb, 0)
}

/// Any other recording (`Recording`), in this order: the sensor's quantity at the
/// (jittered) sample times, AC coupling for the accelerometer and the vibrometer, white
/// noise of `noise_fraction` of the free decay's peak, the recorder's low-pass on signal
/// and noise, offset and drift, quantisation (16 bits over +-1.2 x the largest value,
/// or the position sensor's step).
fn recorded(case: &TruthCase, trajectory: &Trajectory, rng: &mut Rng) -> Record {
    let rec = &case.recording;
    let fs = case.sample_rate_hz;
    let x0 = case.equilibrium_compression_m();
    let clean: Vec<f64> = match rec.sensor {
        Sensor::Accelerometer => trajectory.accel.clone(),
        Sensor::Velocity => trajectory.velocity.clone(),
        Sensor::Position { sign, .. } => trajectory
            .displacement
            .iter()
            .map(|u| sign * 1e3 * (u + x0))
            .collect(),
    };
    let n = clean.len();
    let clean = with_extra_mode(case, clean);
    // Time stamps: uniform plus jitter (all >= 0); values at those times by cubic
    // Lagrange interpolation of the uniformly sampled truth (error about
    // 0.2 (w/fs)^4 / 24 of the amplitude: 1e-4 at 16 samples per cycle).
    let stamps: Vec<f64> = (0..n)
        .map(|i| i as f64 / fs + rec.jitter_s * (2.0 * rng.uniform() - 1.0))
        .collect();
    let mut values: Vec<f64> = if rec.jitter_s > 0.0 {
        stamps.iter().map(|t| lagrange4(&clean, t * fs)).collect()
    } else {
        clean
    };
    let stamps: Vec<f64> = stamps.iter().map(|t| t + rec.jitter_s).collect();
    if !matches!(rec.sensor, Sensor::Position { .. }) {
        let mean = values.iter().sum::<f64>() / n.max(1) as f64;
        values.iter_mut().for_each(|v| *v -= mean);
    }
    let free_decay_start = rec.impulse.map_or(0, |p| {
        (((p.rest_s + p.duration_s + 0.1) * fs).ceil() as usize).min(n.saturating_sub(1))
    });
    let mean_free = {
        let tail = &values[free_decay_start..];
        tail.iter().sum::<f64>() / tail.len().max(1) as f64
    };
    let peak = values[free_decay_start..]
        .iter()
        .fold(0.0f64, |p, v| p.max((v - mean_free).abs()));
    for v in values.iter_mut() {
        *v += case.noise_fraction * peak * rng.normal();
    }
    if let Some(fc) = rec.band_limit_hz {
        values = butterworth_zero_phase(&values, fc, fs);
    }
    if let Some(clip) = rec.clip_fraction {
        let level = clip * peak;
        values.iter_mut().for_each(|v| *v = v.clamp(-level, level));
    }
    let duration = n as f64 / fs;
    for (v, t) in values.iter_mut().zip(&stamps) {
        *v += peak * (rec.offset_fraction + rec.drift_fraction * t / duration);
    }
    if let Sensor::Position { offset_mm, .. } = rec.sensor {
        values.iter_mut().for_each(|v| *v += offset_mm);
    }
    let lsb = match rec.sensor {
        Sensor::Position { step_mm, .. } => step_mm,
        _ => 2.0 * 1.2 * values.iter().fold(0.0f64, |p, v| p.max(v.abs())) / 65536.0,
    };
    let decay = stamps
        .iter()
        .zip(&values)
        .map(|(&t, &v)| (t, (v / lsb).round() * lsb))
        .collect();
    (decay, peak, lsb, free_decay_start)
}

/// `clean` (the recorded quantity at the sample times) with the recording's
/// [`ExtraMode`] added: `a f e^(-zeta w t) cos(w t + phase)`, `f` the fraction of the
/// clean record's peak, `w` the given ratio of the axial frequency.
fn with_extra_mode(case: &TruthCase, mut clean: Vec<f64>) -> Vec<f64> {
    let Some(mode) = case.recording.extra_mode else {
        return clean;
    };
    let peak = clean.iter().fold(0.0f64, |p, v| p.max(v.abs()));
    let mean = clean.iter().sum::<f64>() / clean.len().max(1) as f64;
    let peak = if matches!(case.recording.sensor, Sensor::Position { .. }) {
        clean.iter().fold(0.0f64, |p, v| p.max((v - mean).abs()))
    } else {
        peak
    };
    let w = TAU * mode.frequency_ratio / rayleigh_period_s(case);
    for (i, v) in clean.iter_mut().enumerate() {
        let t = i as f64 / case.sample_rate_hz;
        *v += mode.amplitude_fraction
            * peak
            * (-mode.damping_ratio * w * t).exp()
            * (w * t + mode.phase_rad).cos();
    }
    clean
}

/// Cubic Lagrange interpolation of uniformly sampled `y` at the fractional index `p`
/// (the four nearest samples; clamped at the ends).
fn lagrange4(y: &[f64], p: f64) -> f64 {
    let n = y.len();
    if n < 4 {
        return y[(p.round().max(0.0) as usize).min(n - 1)];
    }
    let i = (p.floor().max(1.0) as usize).min(n - 3);
    let s = p - i as f64;
    let w = [
        -s * (s - 1.0) * (s - 2.0) / 6.0,
        (s + 1.0) * (s - 1.0) * (s - 2.0) / 2.0,
        -(s + 1.0) * s * (s - 2.0) / 2.0,
        (s + 1.0) * s * (s - 1.0) / 6.0,
    ];
    w[0] * y[i - 1] + w[1] * y[i] + w[2] * y[i + 1] + w[3] * y[i + 2]
}

/// Second-order Butterworth low-pass (bilinear transform with pre-warping,
/// `K = tan(pi fc / fs)`), run forward then backward: zero phase, gain
/// `1 / (1 + (f/fc)^4)` (of the analogue prototype, squared by the two passes).
/// Each pass starts in the steady state of its first input value.
pub fn butterworth_zero_phase(x: &[f64], cutoff_hz: f64, sample_rate_hz: f64) -> Vec<f64> {
    let k = (PI * cutoff_hz / sample_rate_hz).tan();
    let norm = 1.0 / (1.0 + 2f64.sqrt() * k + k * k);
    let b0 = k * k * norm;
    let (b1, b2) = (2.0 * b0, b0);
    let a1 = 2.0 * (k * k - 1.0) * norm;
    let a2 = (1.0 - 2f64.sqrt() * k + k * k) * norm;
    let pass = |input: &mut dyn Iterator<Item = f64>| -> Vec<f64> {
        let mut out = Vec::with_capacity(x.len());
        let (mut x1, mut x2, mut y1, mut y2) = (f64::NAN, 0.0, 0.0, 0.0);
        for v in input {
            if x1.is_nan() {
                (x1, x2, y1, y2) = (v, v, v, v);
            }
            let y = b0 * v + b1 * x1 + b2 * x2 - a1 * y1 - a2 * y2;
            (x2, x1, y2, y1) = (x1, v, y1, y);
            out.push(y);
        }
        out
    };
    let forward = pass(&mut x.iter().copied());
    let mut backward = pass(&mut forward.iter().rev().copied());
    backward.reverse();
    backward
}

/// The noise-free static record: (compression mm, force N, compression full scale mm,
/// force full scale N) per point, loading then unloading.
pub fn static_points(case: &TruthCase) -> Vec<(f64, f64, f64, f64)> {
    let g = if case.gravity_m_s2 > 0.0 {
        case.gravity_m_s2
    } else {
        STATIC_GRAVITY_M_S2
    };
    // A softening spring is loaded to at most 90 % of the force where it gives way.
    let limit = case.softening_limit_m();
    let give_way = case.linear_stiffness_n_m() * limit + case.cubic() * limit.powi(3);
    let max_force = (1.5 * case.mass_kg * g).min(0.9 * give_way);
    let x_max = case.compression_under(max_force);
    let k = case.linear_stiffness_n_m();
    let k3 = case.cubic();
    let friction = case.friction();
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
    for (_, name, value) in case.causes() {
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
    let tangent = case.linear_stiffness_n_m() + 3.0 * case.cubic() * x0 * x0;
    let t = &generated.trajectory;
    let period_samples = ((TAU / axial_omega.max(1e-9)) * case.sample_rate_hz).ceil() as usize;
    let start_amplitude = half_range(&t.displacement[..period_samples.min(t.displacement.len())]);
    let end_amplitude =
        half_range(&t.displacement[t.displacement.len().saturating_sub(period_samples)..]);
    let mut truth = json!({
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
    });
    // Only the extended cases carry these (the shipped files stay as they were).
    if !case.also.is_empty() || case.recording != Recording::default() {
        let causes: Vec<serde_json::Value> = case
            .causes()
            .iter()
            .map(|(effect, name, value)| json!({"effect": effect, "parameters": {*name: value}}))
            .collect();
        let rec = &case.recording;
        let sensor = match rec.sensor {
            Sensor::Position {
                step_mm,
                offset_mm,
                sign,
            } => json!({"column": "displacement_mm", "step_mm": step_mm,
                        "offset_mm": offset_mm, "sign": sign}),
            other => json!({"column": other.column(), "adc_bits": 16}),
        };
        truth["causes"] = json!(causes);
        truth["cubic_backbone_shift"] = json!(backbone_shift(case));
        truth["recording"] = json!({
            "sensor": sensor,
            "band_limit_hz": rec.band_limit_hz,
            "jitter_s": rec.jitter_s,
            "offset_fraction_of_peak": rec.offset_fraction,
            "drift_fraction_of_peak": rec.drift_fraction,
            "impulse": rec.impulse.map(|p| json!({"rest_s": p.rest_s, "duration_s": p.duration_s})),
            "free_decay_start_s": generated.free_decay_start as f64 / case.sample_rate_hz,
            "peak": generated.peak_m_s2,
            "quantisation": generated.quantisation_m_s2,
        });
    }
    truth
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
    record_csv("accel_m_s2", decay)
}

/// The text of a decay record with the given value column (`displacement_mm` written
/// in plain decimals to 0.1 um, the others as `{:.6e}`).
pub fn record_csv(column: &str, decay: &[(f64, f64)]) -> String {
    let mut text = String::with_capacity(24 * decay.len() + 32);
    text.push_str(&format!("time_s,{column}\n"));
    for (t, a) in decay {
        if column == "displacement_mm" {
            text.push_str(&format!("{t:.6},{a:.4}\n"));
        } else {
            text.push_str(&format!("{t:.6},{a:.6e}\n"));
        }
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
    write_atomic(
        &dir.join("decay.csv"),
        &record_csv(generated.column, &generated.decay),
    )?;
    write_atomic(
        &dir.join("truth.json"),
        &pretty(&truth_json(case, &generated))?,
    )?;
    write_atomic(&dir.join("case.json"), &pretty(&case_json(case))?)
}
