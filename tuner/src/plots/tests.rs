//! Every figure is written, and a bad extension leaves nothing.

use super::*;
use crate::decay::DecayMeasure;
use crate::grid::{Axis, GridPoint, GridSpec};
use crate::loops::Iteration;

#[test]
fn figures_are_written_and_bad_extensions_leave_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let report = LoopReport {
        parameter: "youngs_modulus_mpa".into(),
        quantity: "stiffness_n_mm".into(),
        target: 3.9275,
        tolerance: 1e-5,
        iterations: vec![
            Iteration {
                iteration: 1,
                parameter: 206000.0,
                result: 4.2,
                relative_error: 0.07,
                deck: None,
            },
            Iteration {
                iteration: 2,
                parameter: 193000.0,
                result: 3.9275,
                relative_error: 0.0,
                deck: None,
            },
        ],
        value: 193000.0,
        result: 3.9275,
        relative_error: 0.0,
    };
    loops_figure(&[&report, &report], &dir.path().join("fig7.png")).unwrap();
    let spec = GridSpec {
        name: "g".into(),
        alpha: Axis::parse("0:1:2").unwrap(),
        beta: Axis::parse("0:1:1").unwrap(),
    };
    let points = (0..3)
        .flat_map(|i| (0..2).map(move |j| (i, j)))
        .map(|(i, j)| GridPoint {
            i,
            j,
            alpha: i as f64,
            beta: j as f64,
            measure: (i + j > 0).then_some(DecayMeasure {
                zeta_mean: 0.1 * i as f64 + j as f64,
                zeta_fit: 0.0,
                period_s: 0.23,
                crests: 20,
            }),
            error: (i + j == 0).then(|| "x".to_string()),
        })
        .collect();
    let grid = GridResult {
        spec,
        points,
        computed: 6,
        resumed: 0,
        elapsed_s: 0.0,
    };
    let marks = HeatMapMarks {
        target_zeta: 0.5,
        paper: Some((1.0, 0.5)),
        valley: Some((0.0, 0.1, 1.0)),
    };
    heat_map(&grid, &marks, &dir.path().join("fig8.png")).unwrap();
    heat_map(&grid, &marks, &dir.path().join("fig8.svg")).unwrap();
    let valley = ValleyPlot {
        target_zeta: 0.5,
        plane: (0.0, 0.1, 1.0),
        points: &[(0.0, 0.5, 0.5), (2.0, 0.3, 0.5)],
        alpha_max: 5.0,
    };
    valley_figure(&valley, &dir.path().join("valley.png")).unwrap();
    assert!(heat_map(&grid, &marks, &dir.path().join("fig8.txt")).is_err());
    let mut names: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|f| f.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(names, ["fig7.png", "fig8.png", "fig8.svg", "valley.png"]);
}

#[test]
fn a_shifted_scaled_record_is_aligned_and_leaves_no_residual() {
    // Model: a decaying cosine sampled at 1 ms; reference: the same read 0.05 s later
    // at half the amplitude, on a 2 ms grid (a measured record cut after the impulse).
    let period = 0.23;
    let w = std::f64::consts::TAU / period;
    let wave = |t: f64| (-0.05 * t).exp() * (w * t).cos();
    let model_t: Vec<f64> = (0..6000).map(|k| k as f64 * 1e-3).collect();
    let model_a: Vec<f64> = model_t.iter().map(|&t| wave(t)).collect();
    let ref_t: Vec<f64> = (0..2000).map(|k| k as f64 * 2e-3).collect();
    let ref_a: Vec<f64> = ref_t.iter().map(|&t| 0.5 * wave(t + 0.05)).collect();
    let reference = DecayTrace {
        label: "measured",
        time_s: &ref_t,
        accel_m_s2: &ref_a,
    };
    let model = DecayTrace {
        label: "coil",
        time_s: &model_t,
        accel_m_s2: &model_a,
    };
    let (a, residual) = align(&reference, &model, period);
    assert!((a.shift_s - 0.05).abs() < 1e-9, "{a:?}");
    assert!((a.gain - 0.5).abs() < 1e-4, "{a:?}");
    // Linear interpolation of a 1 ms model: error ~ (w dt)^2 / 8 = 9e-5 relative.
    assert!(a.relative_rms < 3e-4, "{a:?}");
    assert_eq!(residual.len(), ref_t.len());
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("fig10.png");
    decay_figure(&reference, &model, period, &path).unwrap();
    assert!(path.is_file());
}
