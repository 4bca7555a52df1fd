//! End-to-end tests of the `coil-post` binary: each writes CSV files into a temporary folder,
//! runs the real binary on them and checks its JSON, its pictures or its error messages.

use std::f64::consts::TAU;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use serde_json::Value;

const BIN: &str = env!("CARGO_BIN_EXE_coil-post");

/// xorshift64*: a seeded generator for phases and noise (no external crate).
struct Rng(u64);

impl Rng {
    fn new(seed: u64) -> Self {
        Rng(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1)
    }
    fn uniform(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let bits = self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11;
        (bits as f64 + 0.5) / (1u64 << 53) as f64
    }
    fn normal(&mut self) -> f64 {
        let (u, v) = (self.uniform(), self.uniform());
        (-2.0 * u.ln()).sqrt() * (TAU * v).cos()
    }
}

/// `A e^{-zeta omega_n t} cos(omega_d t + phase)` with `omega_n = 2 pi f_n`.
struct Decay {
    natural_hz: f64,
    zeta: f64,
    phase: f64,
}

impl Decay {
    fn omega_d(&self) -> f64 {
        TAU * self.natural_hz * (1.0 - self.zeta * self.zeta).sqrt()
    }
    fn period_s(&self) -> f64 {
        TAU / self.omega_d()
    }
    fn value(&self, t: f64) -> f64 {
        (-self.zeta * TAU * self.natural_hz * t).exp() * (self.omega_d() * t + self.phase).cos()
    }
}

/// Writes `time_s` and one column; values printed with Rust's shortest round-trip format.
fn write_csv(path: &Path, column: &str, rate_hz: f64, values: &[f64]) {
    let mut text = format!("time_s,{column}\n");
    for (i, v) in values.iter().enumerate() {
        text.push_str(&format!("{},{}\n", i as f64 / rate_hz, v));
    }
    std::fs::write(path, text).unwrap();
}

fn sample(decay: &Decay, rate_hz: f64, seconds: f64) -> Vec<f64> {
    (0..(rate_hz * seconds).round() as usize)
        .map(|i| decay.value(i as f64 / rate_hz))
        .collect()
}

fn run(args: &[&str]) -> Output {
    Command::new(BIN).args(args).output().unwrap()
}

fn run_json(args: &[&str]) -> Value {
    let output = run(args);
    assert!(
        output.status.success(),
        "coil-post {args:?} failed: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    serde_json::from_slice(&output.stdout).unwrap()
}

fn number(value: &Value, key: &str) -> f64 {
    value[key]
        .as_f64()
        .unwrap_or_else(|| panic!("no number `{key}` in {value}"))
}

fn path_str(path: &Path) -> &str {
    path.to_str().unwrap()
}

/// The paper's signal: 4.35 Hz, zeta 0.00175, 20 s at 1 kHz, random phase.
fn paper_record(folder: &Path, seed: u64) -> (PathBuf, Decay) {
    let decay = Decay {
        natural_hz: 4.35,
        zeta: 0.00175,
        phase: Rng::new(seed).uniform() * TAU,
    };
    let path = folder.join("decay.csv");
    write_csv(&path, "accel_m_s2", 1000.0, &sample(&decay, 1000.0, 20.0));
    (path, decay)
}

/// ACCEPTANCE ("Estimator"): on a 1 kHz analytic damped sine the decrement recovers
/// zeta within 0.3%, both ways. Measured: 9e-8 (zeta_mean) and 2e-8 (zeta_fit) relative, the
/// period within 3e-11. Raw sample crests (no interpolation) are 50 to 600 times worse.
#[test]
fn acceptance_decrement_recovers_zeta_of_an_analytic_decay() {
    let folder = tempfile::tempdir().unwrap();
    for seed in [1, 2, 3] {
        let (path, decay) = paper_record(folder.path(), seed);
        let file = path_str(&path);
        let report = run_json(&[
            "decrement",
            file,
            "--column",
            "accel_m_s2",
            "--every",
            "10",
            "--json",
        ]);
        let zeta_mean = number(&report, "zeta_mean");
        let zeta_fit = number(&report, "zeta_fit");
        let period = number(&report, "period_s");
        let mean_error = (zeta_mean / decay.zeta - 1.0).abs();
        let fit_error = (zeta_fit / decay.zeta - 1.0).abs();
        assert!(
            mean_error < 3e-3 && fit_error < 3e-3,
            "seed {seed}: {zeta_mean} {zeta_fit}"
        );
        // Far tighter in fact: the crest fit's varying error is 1e-7 of the amplitude.
        assert!(
            mean_error < 1e-6 && fit_error < 1e-6,
            "seed {seed}: {mean_error:e} {fit_error:e}"
        );
        assert!(
            (period / decay.period_s() - 1.0).abs() < 1e-8,
            "period {period}"
        );

        let peaks = report["peaks"].as_array().unwrap();
        assert!(peaks.len() >= 85, "{} crests", peaks.len());
        for peak in peaks {
            let (t, a) = (number(peak, "time_s"), number(peak, "amplitude"));
            assert!((a / decay.value(t) - 1.0).abs() < 2e-5, "crest {t} s: {a}");
        }
        let spans = report["spans"].as_array().unwrap();
        assert_eq!(spans.len(), (peaks.len() - 1) / 10);
        assert_eq!(report["every"], 10);

        let raw = run_json(&[
            "decrement",
            file,
            "--column",
            "accel_m_s2",
            "--json",
            "--peak-fit",
            "raw",
        ]);
        let raw_error = (number(&raw, "zeta_mean") / decay.zeta - 1.0).abs();
        assert!(
            raw_error > 20.0 * mean_error,
            "raw {raw_error:e} vs {mean_error:e}"
        );
    }
}

#[test]
fn decrement_table_and_json_file() {
    let folder = tempfile::tempdir().unwrap();
    let (path, _) = paper_record(folder.path(), 4);
    // The only signal column is picked without --column.
    let output = run(&["decrement", path_str(&path)]);
    assert!(output.status.success());
    let table = String::from_utf8(output.stdout).unwrap();
    for needle in [
        "zeta_mean",
        "zeta_fit",
        "period_s",
        "span",
        "decay.csv: accel_m_s2",
    ] {
        assert!(table.contains(needle), "{needle} missing from\n{table}");
    }

    let out = folder.path().join("report.json");
    let output = run(&[
        "decrement",
        path_str(&path),
        "--out",
        path_str(&out),
        "--troughs",
    ]);
    assert!(output.status.success());
    let report: Value = serde_json::from_slice(&std::fs::read(&out).unwrap()).unwrap();
    assert!((number(&report, "zeta_fit") / 0.00175 - 1.0).abs() < 1e-5);
    assert!((number(&report["troughs"], "zeta_fit") / 0.00175 - 1.0).abs() < 1e-5);
    // Nothing left over from the temporary file.
    let names: Vec<String> = std::fs::read_dir(folder.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names.len(), 2, "{names:?}");
}

/// An FE-like history: gravity offset on displacement, a 60 Hz second mode and a ripple that
/// alternates every step on the acceleration. `--lowpass` and `--detrend midline` handle them.
#[test]
fn fe_history_with_ripple_offset_and_second_mode() {
    let folder = tempfile::tempdir().unwrap();
    let decay = Decay {
        natural_hz: 4.35,
        zeta: 0.00175,
        phase: 0.4,
    };
    let rate = 1000.0;
    let n = 20_000;
    let mut text = String::from("time_s,node12_uz_accel_m_s2,node12_uz_disp_mm\n");
    for i in 0..n {
        let t = i as f64 / rate;
        let ripple = if i % 2 == 0 { 4e-3 } else { -4e-3 };
        let second = 0.2 * (-0.3 * t).exp() * (TAU * 61.3 * t).cos();
        let accel = 3.0 * decay.value(t) + ripple + second;
        let disp = -12.5 + 1.2 * decay.value(t);
        text.push_str(&format!("{},{},{}\n", t, accel, disp));
    }
    let path = folder.path().join("history.csv");
    std::fs::write(&path, text).unwrap();
    let file = path_str(&path);
    let column = "node12_uz_accel_m_s2";

    let raw = run_json(&[
        "decrement",
        file,
        "--column",
        column,
        "--json",
        "--peak-fit",
        "raw",
    ]);
    let filtered = run_json(&[
        "decrement",
        file,
        "--column",
        column,
        "--json",
        "--lowpass",
        "30",
    ]);
    let raw_error = number(&raw, "zeta_mean") / decay.zeta - 1.0;
    let filtered_error = number(&filtered, "zeta_mean") / decay.zeta - 1.0;
    let filtered_fit_error = number(&filtered, "zeta_fit") / decay.zeta - 1.0;
    // Measured: raw crests +6.4%; after the 30 Hz zero-phase low-pass, 1e-7.
    assert!(raw_error > 0.02, "raw {raw_error:e}");
    assert!(filtered_error.abs() < 1e-5 && filtered_fit_error.abs() < 1e-5);
    assert!((number(&filtered, "period_s") / decay.period_s() - 1.0).abs() < 1e-7);

    let displacement = run_json(&[
        "decrement",
        file,
        "--column",
        "node12_uz_disp_mm",
        "--json",
        "--detrend",
        "midline",
    ]);
    assert!((number(&displacement, "offset_removed") + 12.5).abs() < 1e-6);
    assert!((number(&displacement, "zeta_mean") / decay.zeta - 1.0).abs() < 1e-5);
}

/// A measured-style record (`time_s,accel_m_s2`, noise and ADC quantisation).
#[test]
fn measured_record_with_noise_and_quantisation() {
    let folder = tempfile::tempdir().unwrap();
    let decay = Decay {
        natural_hz: 4.33,
        zeta: 0.0019,
        phase: 1.0,
    };
    let mut rng = Rng::new(17);
    let rate = 900.0;
    let values: Vec<f64> = sample(&decay, rate, 20.0)
        .iter()
        .map(|v| ((2.5 * v + 0.01 * rng.normal()) / 0.002).round() * 0.002)
        .collect();
    let mut text = String::from("time_s,accel_m_s2\n");
    for (i, v) in values.iter().enumerate() {
        text.push_str(&format!("{:.6},{:.3}\n", i as f64 / rate, v));
    }
    let path = folder.path().join("decay.csv");
    std::fs::write(&path, text).unwrap();
    let report = run_json(&["decrement", path_str(&path), "--json"]);
    // Noise of 0.4% of the first amplitude: the fit's standard error is ~5e-7 (0.03%).
    let se = number(&report, "zeta_fit_std_error");
    let fit_error = (number(&report, "zeta_fit") - decay.zeta).abs();
    assert!(fit_error < 5.0 * se && se < 2e-6, "{fit_error:e} vs {se:e}");
    assert!((number(&report, "zeta_mean") / decay.zeta - 1.0).abs() < 0.01);
}

#[test]
fn spectrum_lists_both_tones() {
    let folder = tempfile::tempdir().unwrap();
    let rate = 1000.0;
    let values: Vec<f64> = (0..10_000)
        .map(|i| {
            let t = i as f64 / rate;
            (TAU * 4.35 * t).sin() + 0.3 * (TAU * 17.123 * t).cos()
        })
        .collect();
    let path = folder.path().join("tones.csv");
    write_csv(&path, "accel_m_s2", rate, &values);
    let report = run_json(&["spectrum", path_str(&path), "--json"]);
    let peaks = report["peaks"].as_array().unwrap();
    assert_eq!(peaks.len(), 2);
    let bin = number(&report, "native_bin_hz");
    assert!((number(&peaks[0], "frequency_hz") - 4.35).abs() < 0.01 * bin);
    assert!((number(&peaks[1], "frequency_hz") - 17.123).abs() < 0.01 * bin);
}

#[test]
fn envelope_gives_the_damping_of_a_decay() {
    let folder = tempfile::tempdir().unwrap();
    let decay = Decay {
        natural_hz: 4.35,
        zeta: 0.01,
        phase: 0.5,
    };
    let path = folder.path().join("decay.csv");
    write_csv(&path, "accel_m_s2", 1000.0, &sample(&decay, 1000.0, 15.0));
    let report = run_json(&["envelope", path_str(&path), "--json"]);
    assert!((number(&report, "zeta_fit") / 0.01 - 1.0).abs() < 1e-3);
    let points = report["points"].as_array().unwrap();
    assert!(points.len() > 10);
    for point in points {
        assert!((number(point, "zeta") / 0.01 - 1.0).abs() < 5e-3);
    }
    let banded = run_json(&["envelope", path_str(&path), "--json", "--bandpass", "0.5"]);
    assert!(
        (number(&banded, "zeta_fit") / 0.01 - 1.0).abs() < 2e-3,
        "{banded}"
    );
}

fn assert_picture(path: &Path) {
    let bytes = std::fs::read(path).unwrap();
    match path.extension().and_then(|e| e.to_str()) {
        Some("png") => assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n"),
        _ => assert!(String::from_utf8_lossy(&bytes).contains("<svg")),
    }
    assert!(
        bytes.len() > 10_000,
        "{} is only {} bytes",
        path.display(),
        bytes.len()
    );
}

#[test]
fn plots_of_every_kind() {
    let folder = tempfile::tempdir().unwrap();
    let (measured, _) = paper_record(folder.path(), 5);
    let simulated = folder.path().join("history.csv");
    let decay = Decay {
        natural_hz: 4.3,
        zeta: 0.002,
        phase: 0.0,
    };
    write_csv(
        &simulated,
        "node12_uz_accel_m_s2",
        1000.0,
        &sample(&decay, 1000.0, 20.0),
    );
    let (measured, simulated) = (path_str(&measured), path_str(&simulated));
    for (kind, name) in [
        ("time", "time.png"),
        ("time", "time.svg"),
        ("spectrum", "spectrum.png"),
        ("envelope", "envelope.png"),
        ("envelope", "envelope.svg"),
    ] {
        let out = folder.path().join(name);
        let output = run(&[
            "plot",
            measured,
            "--compare",
            simulated,
            "--kind",
            kind,
            "-o",
            path_str(&out),
        ]);
        assert!(
            output.status.success(),
            "{}",
            String::from_utf8_lossy(&output.stderr)
        );
        assert_picture(&out);
    }
    let single = folder.path().join("single.png");
    let output = run(&["plot", measured, "-o", path_str(&single)]);
    assert!(output.status.success());
    assert_picture(&single);
}

/// Runs a failing command: exit code 1, a message containing every `needles`, no panic.
fn assert_fails(args: &[&str], needles: &[&str]) {
    let output = run(args);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{args:?}: {stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    for needle in needles {
        assert!(stderr.contains(needle), "`{needle}` missing from: {stderr}");
    }
}

#[test]
fn bad_inputs_give_located_messages_and_no_output() {
    let folder = tempfile::tempdir().unwrap();
    let dir = folder.path();
    let write = |name: &str, text: &str| {
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        path.to_str().unwrap().to_string()
    };
    let good: String = (0..100)
        .map(|i| format!("{},{}\n", i as f64 * 0.01, (i as f64 * 0.3).sin()))
        .collect();
    let ok = write("ok.csv", &format!("time_s,accel_m_s2\n{good}"));

    assert_fails(
        &["decrement", &ok, "--column", "accel"],
        &[
            "ok.csv:1:",
            "no column named `accel`",
            "available columns: time_s, accel_m_s2",
        ],
    );
    // A header without `time_s` is read as a CSV dialect, as `diagnose` reads it (`t` or
    // `time` would be the time in s there): a header with no time column at all.
    let no_time = write("no_time.csv", "x,accel_m_s2\n0,1\n1,2\n2,3\n");
    assert_fails(
        &["decrement", &no_time],
        &["no_time.csv:1:", "`time_s`", "x, accel_m_s2"],
    );
    let nan = write(
        "nan.csv",
        "time_s,accel_m_s2\n0,1\n0.01,2\n0.02,NaN\n0.03,1\n",
    );
    assert_fails(
        &["decrement", &nan],
        &["nan.csv:4:", "`NaN` is not a finite number"],
    );
    // Blank and comment lines count: the line is the one an editor shows.
    let blank = write("blank.csv", "# rig B\ntime_s,accel_m_s2\n0,1\n\n0.01,inf\n");
    assert_fails(
        &["decrement", &blank],
        &["blank.csv:5:", "`inf` is not a finite number"],
    );
    let text = write("text.csv", "time_s,accel_m_s2\n0,1\n0.01,abc\n0.02,1\n");
    assert_fails(
        &["decrement", &text],
        &["text.csv:3:", "expected a number, found `abc`"],
    );
    let gap = write(
        "gap.csv",
        "time_s,accel_m_s2\n0,1\n0.01,2\n0.02,3\n0.04,1\n0.05,0\n",
    );
    assert_fails(
        &["decrement", &gap],
        &["gap.csv:5:", "time step", "uniformly sampled"],
    );
    let back = write("back.csv", "time_s,accel_m_s2\n0,1\n0.01,2\n0.01,3\n");
    assert_fails(&["decrement", &back], &["back.csv:4:", "does not increase"]);
    let ragged = write("ragged.csv", "time_s,accel_m_s2\n0,1\n0.01\n");
    assert_fails(
        &["decrement", &ragged],
        &["ragged.csv:3:", "expected 2 fields"],
    );
    let short = write("short.csv", "time_s,accel_m_s2\n0,1\n");
    assert_fails(
        &["decrement", &short],
        &["short.csv", "1 data rows; need at least 3"],
    );
    let empty = write("empty.csv", "");
    assert_fails(&["decrement", &empty], &["empty.csv", "empty"]);
    assert_fails(
        &["decrement", &dir.join("absent.csv").to_string_lossy()],
        &["absent.csv", "cannot read"],
    );
    // 100 samples of a 0.48 Hz sine: one crest, not the 11 of one span.
    assert_fails(
        &["decrement", &ok],
        &[
            "ok.csv",
            "column `accel_m_s2`",
            "need at least 11",
            "--every",
        ],
    );
    let two = write(
        "two.csv",
        "time_s,a_m_s2,b_m_s2\n0,1,1\n0.01,2,2\n0.02,3,3\n",
    );
    assert_fails(
        &["decrement", &two],
        &["two.csv:1:", "a_m_s2, b_m_s2", "--column"],
    );
    assert_fails(
        &["decrement", &ok, "--lowpass", "80"],
        &["cutoff 80 Hz", "Nyquist"],
    );

    // A failed run leaves no picture and no JSON, not even a temporary file.
    let picture = dir.join("out.png");
    assert_fails(
        &["plot", &ok, "--column", "nope", "-o", path_str(&picture)],
        &["ok.csv:1:", "nope"],
    );
    let json = dir.join("out.json");
    assert_fails(
        &["decrement", &ok, "--out", path_str(&json)],
        &["need at least 11"],
    );
    let unknown = dir.join("out.jpg");
    assert_fails(&["plot", &ok, "-o", path_str(&unknown)], &[".png or .svg"]);
    let leftovers: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|name| !name.ends_with(".csv"))
        .collect();
    assert!(leftovers.is_empty(), "{leftovers:?}");
}

/// `coil-post signature`: the paper's 4.35 Hz record (zeta 0.00175, 20 s) gives the
/// viscous loss `a1 = 2 pi zeta` and an exponential envelope; the table prints every part.
#[test]
fn signature_reads_a_viscous_decay() {
    let folder = tempfile::tempdir().unwrap();
    let (path, decay) = paper_record(folder.path(), 4);
    let file = path_str(&path);
    let value = run_json(&["signature", file, "--json"]);
    let delta = TAU * decay.zeta / (1.0 - decay.zeta * decay.zeta).sqrt();
    let a1 = number(
        &value["loss"]["single"]["viscous_a1"]["coefficient"],
        "value",
    );
    // Clean record: the windowed slopes are exact to ~1e-4 relative.
    assert!((a1 - delta).abs() < 0.01 * delta, "a1 {a1} vs {delta}");
    assert_eq!(value["envelope_shape"]["kind"], "exponential", "{value}");
    let f0 = number(&value["backbone"]["f0_hz"], "value");
    assert!((f0 - 1.0 / decay.period_s()).abs() < 1e-3, "f0 {f0}");
    assert!(value["spectral_peaks"]["side"].is_null(), "{value}");
    assert!(value["cycles"]["cycles"].as_array().unwrap().len() > 60);

    let output = run(&["signature", file]);
    assert!(output.status.success());
    let text = String::from_utf8_lossy(&output.stdout);
    for part in [
        "loss per cycle",
        "backbone",
        "envelope shape",
        "spectral peaks",
    ] {
        assert!(text.contains(part), "no `{part}` in\n{text}");
    }
}

/// `coil-post static`: a loading-unloading loop with friction 0.8 N gives k, k3 and Ff; a
/// record that only unloads is an error naming the missing branch.
#[test]
fn static_fits_a_loop_and_refuses_a_record_without_loading() {
    let folder = tempfile::tempdir().unwrap();
    let (k, k3, friction) = (3.93, 1e-4, 0.8);
    let mut text = String::from("displacement_mm,force_n\n");
    let mut unloading_only = String::from("displacement_mm,force_n\n");
    for i in 0..300 {
        let (x, s) = if i < 150 {
            (40.0 * i as f64 / 149.0, 1.0)
        } else {
            (40.0 * (299 - i) as f64 / 149.0, -1.0)
        };
        let line = format!("{x},{}\n", k * x + k3 * x.powi(3) + s * friction);
        text.push_str(&line);
        if s < 0.0 {
            unloading_only.push_str(&line);
        }
    }
    let path = folder.path().join("static.csv");
    std::fs::write(&path, text).unwrap();
    let value = run_json(&["static", path_str(&path), "--json"]);
    // Exact data: the fit is exact to round-off.
    assert!((number(&value["stiffness_n_mm"], "value") - k).abs() < 1e-9);
    assert!((number(&value["cubic_n_m3"], "value") - k3 * 1e9).abs() < 1e-3);
    assert!((number(&value["friction_n"], "value") - friction).abs() < 1e-9);

    let bad = folder.path().join("unloading.csv");
    std::fs::write(&bad, unloading_only).unwrap();
    let output = run(&["static", path_str(&bad)]);
    assert_eq!(output.status.code(), Some(1));
    let message = String::from_utf8_lossy(&output.stderr);
    assert!(message.contains("no loading branch"), "{message}");
}

/// The decay of the sample records shipped under `cases/records/` (the examples of
/// docs/postproc.md): the paper's 4.35 Hz at zeta 0.00175, 2 m/s^2, 12 s at 200 Hz.
fn sample_decay() -> (Decay, Vec<f64>) {
    let decay = Decay {
        natural_hz: 4.35,
        zeta: 0.00175,
        phase: 0.3,
    };
    let values = sample(&decay, SAMPLE_RATE_HZ, 12.0)
        .into_iter()
        .map(|a| 2.0 * a)
        .collect();
    (decay, values)
}

const SAMPLE_RATE_HZ: f64 = 200.0;

/// The sample as coil's UFF writer writes it: one ASCII dataset 58, acceleration of
/// node 1 in z, m/s^2.
fn sample_uff(values: &[f64]) -> Vec<u8> {
    let (ordinate_type, length_exponent) = coil_io::uff::Uff58::ordinate_kind("accel");
    let dataset = coil_io::uff::Uff58 {
        description: "sample free decay: 4.35 Hz, zeta 0.00175".into(),
        name: "accel_m_s2".into(),
        node: 1,
        direction: 3,
        ordinate_type,
        length_exponent,
        ordinate_label: "acceleration".into(),
        ordinate_unit: "m/s^2".into(),
        start_s: 0.0,
        step_s: 1.0 / SAMPLE_RATE_HZ,
        values: values.to_vec(),
    };
    coil_io::uff::uff58_bytes(&[dataset], false)
}

/// The sample as a MATLAB level 5 MAT-file (uncompressed, little-endian, as `save -v6`
/// writes it): column vectors `t` (s) and `acc` (the acceleration in g, a unit the file
/// cannot state).
fn sample_mat(values: &[f64]) -> Vec<u8> {
    const G_N: f64 = 9.80665;
    let mut out =
        b"MATLAB 5.0 MAT-file, Platform: coil, Created on: sample decay for coil-post's examples"
            .to_vec();
    out.resize(116, b' ');
    out.extend([0u8; 8]);
    out.extend(0x0100u16.to_le_bytes());
    out.extend(b"IM");
    let time: Vec<f64> = (0..values.len())
        .map(|i| i as f64 / SAMPLE_RATE_HZ)
        .collect();
    let acc: Vec<f64> = values.iter().map(|a| a / G_N).collect();
    for (name, data) in [("t", &time), ("acc", &acc)] {
        let element = |kind: u32, bytes: &[u8]| {
            let mut e = Vec::new();
            e.extend(kind.to_le_bytes());
            e.extend((bytes.len() as u32).to_le_bytes());
            e.extend(bytes);
            e.resize(e.len().div_ceil(8) * 8, 0);
            e
        };
        let mut body = element(6, &[6u32.to_le_bytes(), 0u32.to_le_bytes()].concat());
        body.extend(element(
            5,
            &[(data.len() as i32).to_le_bytes(), 1i32.to_le_bytes()].concat(),
        ));
        body.extend(element(1, name.as_bytes()));
        let reals: Vec<u8> = data.iter().flat_map(|x| x.to_le_bytes()).collect();
        body.extend(element(9, &reals));
        out.extend(element(14, &body));
    }
    out
}

/// `cases/records/decay.uff` and `decay.mat` are what [`sample_uff`] and [`sample_mat`]
/// write (regenerate them with `COIL_BLESS_DOCS=1 cargo test --release -p coil-postproc
/// --test cli shipped`).
#[test]
fn shipped_sample_records_are_what_their_generator_writes() {
    let folder = Path::new(env!("CARGO_MANIFEST_DIR")).join("../cases/records");
    let (_, values) = sample_decay();
    for (name, bytes) in [
        ("decay.uff", sample_uff(&values)),
        ("decay.mat", sample_mat(&values)),
    ] {
        let path = folder.join(name);
        if std::env::var_os("COIL_BLESS_DOCS").is_some() {
            std::fs::create_dir_all(&folder).unwrap();
            std::fs::write(&path, &bytes).unwrap();
        }
        let shipped = std::fs::read(&path).unwrap_or_default();
        assert!(
            shipped == bytes,
            "{} differs from its generator; rerun with COIL_BLESS_DOCS=1",
            path.display()
        );
    }
}

/// `coil-post` reads a UFF 58 file, a MAT-file and a CSV dialect through the record
/// readers `diagnose` uses, with the record entry's keys as flags: each gives the
/// decay's zeta and period (the shipped samples: 46 samples a period, 52 crests, so the
/// estimator's error is far below 1e-4), the same as coil's CSV of the same numbers.
#[test]
fn uff_mat_and_csv_dialects_give_the_decay_they_hold() {
    let records = Path::new(env!("CARGO_MANIFEST_DIR")).join("../cases/records");
    let (decay, values) = sample_decay();
    let folder = tempfile::tempdir().unwrap();
    let csv = folder.path().join("decay.csv");
    write_csv(&csv, "accel_m_s2", SAMPLE_RATE_HZ, &values);
    let reference = run_json(&["decrement", path_str(&csv), "--json"]);
    let zeta = number(&reference, "zeta_mean");
    assert!((zeta / decay.zeta - 1.0).abs() < 1e-4, "csv: zeta {zeta}");
    let uff = records.join("decay.uff");
    let mat = records.join("decay.mat");
    let dialect = folder.path().join("logger.csv");
    let mut text = String::from("% logger export\nZeit [s];Beschl. (g)\n");
    for (i, a) in values.iter().enumerate() {
        let row = format!("{:.3};{:.9}\n", i as f64 / SAMPLE_RATE_HZ, a / 9.80665);
        text.push_str(&row.replace('.', ","));
    }
    std::fs::write(&dialect, text).unwrap();
    let runs: [&[&str]; 4] = [
        &[path_str(&uff)],
        &[path_str(&uff), "--channel", "1:3", "--unit", "m/s^2"],
        &[
            path_str(&mat),
            "--channel",
            "acc",
            "--time",
            "t",
            "--unit",
            "g",
        ],
        &[path_str(&dialect)],
    ];
    for args in runs {
        let report = run_json(&[&["decrement"], args, &["--json"]].concat());
        let (z, period) = (number(&report, "zeta_mean"), number(&report, "period_s"));
        assert!(
            (z / zeta - 1.0).abs() < 1e-6,
            "{args:?}: zeta {z} vs {zeta}"
        );
        assert!(
            (period / decay.period_s() - 1.0).abs() < 1e-6,
            "{args:?}: period {period}"
        );
    }
    assert_fails(
        &["decrement", path_str(&mat), "--channel", "acc"],
        &["decay.mat", "states no unit", "`unit`"],
    );
    assert_fails(
        &["decrement", path_str(&uff), "--unit", "g"],
        &["decay.uff", "mismatched units"],
    );
    assert_fails(
        &[
            "spectrum",
            path_str(&mat),
            "--channel",
            "nope",
            "--unit",
            "g",
        ],
        &["decay.mat", "nope"],
    );
}
