//! Tests of the conditioning and the checks.

use super::*;
use crate::case::StaticRecord;
use std::path::PathBuf;

fn signal(values: Vec<f64>, dt: f64) -> Signal {
    Signal::uniform(0.0, dt, values)
        .unwrap()
        .named(PathBuf::from("decay.csv"), "accel_m_s2")
}

fn decay(cycles: f64, clip: f64) -> Vec<f64> {
    let n = 4000;
    (0..n)
        .map(|i| {
            let t = i as f64 / n as f64;
            let x = (-t).exp() * (std::f64::consts::TAU * cycles * t + 0.3).sin();
            (x.clamp(-clip, clip) * 3000.0).round() / 3000.0
        })
        .collect()
}

#[test]
fn a_decay_passes() {
    let d = check_decay(signal(decay(40.0, 2.0), 1e-3)).unwrap();
    assert!((39..=41).contains(&d.cycles));
}

#[test]
fn a_coarsely_sampled_noisy_decay_counts_its_cycles() {
    // 14 samples per cycle (a 35 Hz spring at 500 Hz) with 1 % noise: the hysteresis
    // must follow the noise, not the signal's sample-to-sample slope.
    let mut seed = 7_u64;
    let mut noise = || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    let n = 1000;
    let values = (0..n)
        .map(|i| {
            let t = i as f64 / n as f64;
            (-t).exp() * (std::f64::consts::TAU * 71.0 * t).sin() + 0.035 * noise()
        })
        .collect();
    let d = check_decay(signal(values, 2e-3)).unwrap();
    assert!((69..=72).contains(&d.cycles), "{}", d.cycles);
    assert!((d.frequency_hz - 35.5).abs() < 0.5, "{}", d.frequency_hz);
}

/// A 1 000 000-sample record (a 50 kHz logger, 20 s of a 5 Hz decay) is decimated
/// to the band the model needs: 1000 samples per period become 100 (q = 100), the
/// frequency and the cycles are those of the whole record, and the amplitude is kept
/// (the low-pass at 20 times the frequency passes the line with a gain of 1 to
/// 1e-10). A record of more than `MAX_CYCLES` cycles is refused with the length to
/// cut it to.
#[test]
fn a_long_fast_record_is_decimated_and_a_too_long_one_refused() {
    let (fs, f) = (50_000.0, 5.0);
    let n: usize = 1_000_000;
    let mut seed = 11;
    let values: Vec<f64> = (0..n)
        .map(|i| {
            let t = i as f64 / fs;
            (-0.1 * t).exp() * (std::f64::consts::TAU * f * t + 0.3).sin() + 0.001 * lcg(&mut seed)
        })
        .collect();
    let d = check_decay(signal(values, 1.0 / fs)).unwrap();
    assert_eq!(d.signal.len(), n.div_ceil(100));
    assert!((d.signal.step_s() - 100.0 / fs).abs() < 1e-12);
    assert!((d.frequency_hz - f).abs() < 1e-3 * f, "{}", d.frequency_hz);
    assert!((99..=101).contains(&d.cycles), "{}", d.cycles);
    let peak = d
        .signal
        .values()
        .iter()
        .fold(0.0_f64, |m, v| m.max(v.abs()));
    assert!((peak - 1.0).abs() < 0.01, "{peak}");
    assert!(d.warnings.iter().any(|w| w.contains("decimated by 100")));

    let long: Vec<f64> = (0..300_000)
        .map(|i| (std::f64::consts::TAU * 1100.0 * i as f64 / 300_000.0).sin())
        .collect();
    let e = check_decay(signal(long, 1e-3)).unwrap_err().to_string();
    assert!(e.contains("cut the record to its first"), "{e}");
}

#[test]
fn short_flat_and_clipped_records_are_refused() {
    let short = check_decay(signal(decay(5.0, 2.0), 1e-3)).unwrap_err();
    assert!(short.to_string().contains("cycles"), "{short}");
    let flat = check_decay(signal(vec![0.5; 1000], 1e-3)).unwrap_err();
    assert!(flat.to_string().contains("flat"), "{flat}");
    let clipped = check_decay(signal(decay(40.0, 0.5), 1e-3)).unwrap_err();
    assert!(clipped.to_string().contains("clipped"), "{clipped}");
}

/// Seeded uniform numbers in [-0.5, 0.5) (a 64-bit LCG).
fn lcg(seed: &mut u64) -> f64 {
    *seed = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    (*seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
}

/// A 4.35 Hz position decay (mm in the file, m here), amplitude 4 mm, zeta 0.002.
fn position_m(t: f64) -> f64 {
    let w = std::f64::consts::TAU * 4.35;
    4e-3 * (-0.002 * w * t).exp() * (w * t + 0.7).sin()
}

fn record(quantity: Quantity, time_s: Vec<f64>, values: Vec<f64>) -> MeasuredDecay {
    MeasuredDecay {
        file: PathBuf::from("decay.csv"),
        quantity,
        lines: (2..time_s.len() as u64 + 2).collect(),
        time_s,
        values,
        time_resolution_s: 1e-6,
    }
}

/// 100 Hz +- 1 ms stamps, the values taken at the jittered times: resampled with a
/// warning, and the acceleration derived from the quantised (0.01 mm) position
/// matches the closed form to the differentiation's predicted noise (3 sigma) plus
/// the interpolation error.
#[test]
fn jittered_position_is_resampled_and_differentiated() {
    let mut seed = 5;
    let n = 4000;
    let time_s: Vec<f64> = (0..n)
        .map(|i| i as f64 * 0.01 + 0.001 + 0.002 * lcg(&mut seed))
        .collect();
    let q = 1e-5;
    let values: Vec<f64> = time_s
        .iter()
        .map(|&t| (position_m(t) / q).round() * q)
        .collect();
    let d = condition_decay(record(Quantity::Displacement, time_s, values)).unwrap();
    let r = d.resampled.as_ref().expect("resampled");
    assert!(r.max_step_deviation_s > 1e-3 && r.max_step_deviation_s <= 2e-3);
    assert!(d.warnings.iter().any(|w| w.contains("resampled")));
    assert!(d.cut.is_none(), "{:?}", d.cut);
    assert_eq!(d.signal.values().len(), n - 6);
    assert_eq!(d.measured.len(), n - 6);
    let w = std::f64::consts::TAU * 4.35;
    let peak = 4e-3 * w * w;
    let errors: Vec<f64> = d
        .signal
        .time_s()
        .iter()
        .zip(d.signal.values())
        .skip(100)
        .take(n - 206)
        .map(|(&t, &a)| {
            // The exact second derivative of the damped sinusoid.
            let h = 1e-4;
            let exact = (position_m(t + h) - 2.0 * position_m(t) + position_m(t - h)) / (h * h);
            a - exact
        })
        .collect();
    let worst = errors.iter().fold(0.0_f64, |m, e| m.max(e.abs()));
    let rms = (errors.iter().map(|e| e * e).sum::<f64>() / errors.len() as f64).sqrt();
    println!(
        "accel error rms {rms:.3e}, worst {worst:.3e} of peak {peak:.3}; noise floor {:.3e}",
        d.noise.rms
    );
    assert!(rms < 0.005 * peak, "{rms}");
    assert!(
        (d.noise.rms / rms - 1.0).abs() < 0.5,
        "{} vs {rms}",
        d.noise.rms
    );
}

/// A gap (one dropped sample, a step of 2 h) is an error naming its line and the
/// limit.
#[test]
fn a_gap_is_an_error_naming_the_line() {
    let time_s: Vec<f64> = (0..3000)
        .filter(|&i| i != 1200)
        .map(|i| i as f64 * 0.01)
        .collect();
    let values = time_s.iter().map(|&t| position_m(t)).collect();
    let e = condition_decay(record(Quantity::Displacement, time_s, values)).unwrap_err();
    let e = e.to_string();
    assert!(
        e.contains("decay.csv:1202:") && e.contains("gap") && e.contains("50 %"),
        "{e}"
    );
}

/// A record whose ADC sits before the blow: a rest, a half-sine blow 10 times the
/// decay's peak, ringing at 9 f0: the cut lands within a few half-cycles after the
/// blow; the same decay without the blow, started at any phase, is not cut.
#[test]
fn the_impulse_is_cut_and_a_plain_decay_is_not() {
    let fs = 500.0;
    let w = std::f64::consts::TAU * 4.35;
    let (rest, blow) = (0.3, 0.004);
    let n = 10_000;
    let mut seed = 9;
    let time_s: Vec<f64> = (0..n).map(|i| i as f64 / fs).collect();
    let accel: Vec<f64> = time_s
        .iter()
        .map(|&t| {
            let noise = 0.01 * lcg(&mut seed);
            if t < rest {
                return noise;
            }
            let s = t - rest;
            let spike = if s < blow {
                10.0 * (std::f64::consts::PI * s / blow).sin()
            } else {
                0.0
            };
            let ring = 0.8 * (-30.0 * s).exp() * (9.0 * w * s).sin();
            spike + ring - (-0.002 * w * s).exp() * (w * s).sin() + noise
        })
        .collect();
    let d = condition_decay(record(Quantity::Acceleration, time_s.clone(), accel)).unwrap();
    let cut = d.cut.as_ref().expect("a cut");
    println!("{cut:?}");
    assert!(
        cut.time_s > rest + blow && cut.time_s < rest + 0.5,
        "{cut:?}"
    );
    assert!(d.warnings.iter().any(|w| w.contains("impulse")));
    for phase in [0.0, 0.8, 1.6, 2.4, 3.2, 4.0, 4.8, 5.6] {
        let plain: Vec<f64> = time_s
            .iter()
            .map(|&t| (-0.004 * w * t).exp() * (w * t + phase).sin() + 0.01 * lcg(&mut seed))
            .collect();
        let d = condition_decay(record(Quantity::Acceleration, time_s.clone(), plain)).unwrap();
        assert!(d.cut.is_none(), "phase {phase}: {:?}", d.cut);
    }
    // A position at rest, then the decay: cut at the first crossing after the rest.
    let position: Vec<f64> = time_s
        .iter()
        .map(|&t| if t < rest { 0.0 } else { position_m(t - rest) } + 1e-6 * lcg(&mut seed))
        .collect();
    let d = condition_decay(record(Quantity::Displacement, time_s.clone(), position)).unwrap();
    let cut = d.cut.as_ref().expect("a cut");
    assert!(cut.time_s > rest && cut.time_s < rest + 0.2, "{cut:?}");
}

/// Glitches of a position record (one sample 40 mm off, two successive ones 25 and
/// 15 mm off, on a 4 mm decay quantised to 0.01 mm) are replaced to within 0.05 mm
/// of the truth; the same record without them, and the accelerometer's, are not
/// touched.
#[test]
fn position_glitches_are_replaced() {
    let fs = 100.0;
    let q = 1e-5;
    let clean: Vec<f64> = (0..4000)
        .map(|i| (position_m(i as f64 / fs) / q).round() * q)
        .collect();
    let mut x = clean.clone();
    assert!(despike(&mut x).is_empty());
    assert_eq!(x, clean);
    x[500] += 0.04;
    x[1700] += 0.025;
    x[1701] += 0.015;
    let replaced = despike(&mut x);
    println!("{replaced:?}");
    for i in [500, 1700, 1701] {
        assert!(replaced.contains(&i), "{replaced:?}");
    }
    assert!(replaced.len() <= 5, "{replaced:?}");
    for &i in &replaced {
        assert!(
            (x[i] - clean[i]).abs() < 5e-5,
            "{i}: {} vs {}",
            x[i],
            clean[i]
        );
    }
    let time_s: Vec<f64> = (0..4000).map(|i| i as f64 / fs).collect();
    let mut glitchy = clean.clone();
    glitchy[500] += 0.04;
    let d = condition_decay(record(Quantity::Displacement, time_s, glitchy)).unwrap();
    assert!(d.warnings.iter().any(|w| w.contains("1 isolated outliers")));
}

/// A record that is all impulse (a blow and 10 cycles of ringing down) is refused as
/// such.
#[test]
fn a_record_that_is_all_impulse_is_refused() {
    let fs = 500.0;
    let w = std::f64::consts::TAU * 4.35;
    let mut seed = 3;
    let time_s: Vec<f64> = (0..3000).map(|i| i as f64 / fs).collect();
    let accel: Vec<f64> = time_s
        .iter()
        .map(|&t| {
            let s = t - 0.3;
            let v = if s < 0.0 {
                0.0
            } else if s < 0.004 {
                10.0 * (std::f64::consts::PI * s / 0.004).sin()
            } else {
                (-0.25 * w * s).exp() * (w * s).sin()
            };
            v + 0.002 * lcg(&mut seed)
        })
        .collect();
    let e = condition_decay(record(Quantity::Acceleration, time_s, accel)).unwrap_err();
    assert!(e.to_string().contains("all impulse"), "{e}");
}

/// Band-limited noise (the record low-passed at 3 f0 after the noise was added): the
/// noise floor is the filtered noise's, where the fourth differences read nearly 0.
#[test]
fn noise_floor_on_a_band_limited_record() {
    let fs = 500.0;
    let n = 12_500;
    let mut seed = 21;
    let noise: Vec<f64> = (0..n)
        .map(|_| 0.02 * lcg(&mut seed) * 12f64.sqrt())
        .collect();
    let filtered = coil_postproc::filter::lowpass_zero_phase(&noise, 1.0 / fs, 13.0, 2).unwrap();
    let w = std::f64::consts::TAU * 4.35;
    let time_s: Vec<f64> = (0..n).map(|i| i as f64 / fs).collect();
    let accel: Vec<f64> = time_s
        .iter()
        .zip(&filtered)
        .map(|(&t, e)| (-0.002 * w * t).exp() * (w * t).sin() + e)
        .collect();
    let d = condition_decay(record(Quantity::Acceleration, time_s, accel)).unwrap();
    let truth = (filtered.iter().map(|e| e * e).sum::<f64>() / n as f64).sqrt();
    println!(
        "noise floor {:.4e}, fourth differences {:.4e}, truth {truth:.4e}",
        d.noise.rms, d.noise.white_rms
    );
    assert!((d.noise.rms / truth - 1.0).abs() < 0.1);
    assert!(d.noise.white_rms < 0.2 * truth);
}

/// The shared real recordings (position at 100 Hz, 0.1 mm), when the folder exists:
/// what the conditioning does to them (no impulse to cut: they start after the
/// release; uniform stamps; the derived acceleration's and the position's noise).
/// `cargo test -p coil-ident --lib real_recordings -- --ignored --nocapture` (the
/// folder is `../shared/real` beside the repository, or `$COIL_SHARED_REAL`).
#[test]
#[ignore = "reads the shared real recordings (../shared/real), which CI does not have: cargo test --release -p coil-ident --lib real_recordings -- --ignored --nocapture"]
fn real_recordings_are_conditioned() {
    let root = std::env::var_os("COIL_SHARED_REAL")
        .map(PathBuf::from)
        .unwrap_or_else(|| {
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/real")
        });
    let Ok(entries) = std::fs::read_dir(&root) else {
        println!("no {}: skipped", root.display());
        return;
    };
    let mut files: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path().join("position.csv")))
        .filter(|p| p.is_file())
        .collect();
    files.sort();
    for file in files {
        let r = crate::case::read_decay_record(&file).unwrap();
        let d = condition_decay(r).unwrap();
        println!(
            "{}: {} samples, {} cycles at {:.4} Hz, cut {:?}, resampled {:?}, \
             cut-off {:?} Hz, position noise {:.3e} m (fourth differences {:.3e}), \
             acceleration noise {:.3e} m/s^2 of rms {:.3e}",
            file.display(),
            d.signal.values().len(),
            d.cycles,
            d.frequency_hz,
            d.cut,
            d.resampled,
            d.differentiation_cutoff_hz,
            d.measured_noise.rms,
            d.measured_noise.white_rms,
            d.noise.rms,
            (d.signal.values().iter().map(|a| a * a).sum::<f64>() / d.signal.values().len() as f64)
                .sqrt()
        );
        for w in &d.warnings {
            println!("  {w}");
        }
        assert!(d.cut.is_none());
    }
}

#[test]
fn static_record_needs_a_loading_branch() {
    let record = |x: Vec<f64>| StaticRecord {
        file: PathBuf::from("static.csv"),
        force_n: x.clone(),
        displacement_mm: x,
    };
    let r = record(vec![0.0, 1.0, 2.0, 3.0, 4.0, 3.0, 2.0]);
    assert_eq!(check_static(&r).unwrap(), 0..5);
    let e = check_static(&record(vec![4.0, 3.0, 2.0, 1.0, 0.0])).unwrap_err();
    assert!(e.to_string().contains("no loading branch"), "{e}");
}
