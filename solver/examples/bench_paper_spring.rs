//! Speed benchmark (not a test): the paper's spring at 48 elements per coil, type 98,
//! static plus 20 modes, as `coil-solve` runs it after reading the deck.
//!
//! Run: `cargo run --release -p coil-solver --example bench_paper_spring [ELEMENTS_PER_COIL]`
//!
//! The model is built in code (n = 14 coils, D = 24 mm, d = 3 mm, pitch 6.2 mm, helix
//! x = R cos t, y = R sin t, z = h t / 2 pi, E = 190708 MPa, nu = 0.3, 7850 kg/m^3; base
//! wire end clamped, top wire end tied by RBE2 to a reference node on the axis that
//! carries the weight and is guided: only u_z free). The weight is chosen so that
//! 2 pi sqrt(m / K) = 0.23 s. Timings are the best of several repetitions of each stage;
//! the deck reading is not included (the deck reader is timed with the binary).

use coil_solver::analysis::{self, modal, static_analysis, System};
use coil_solver::model::*;

mod common;
use std::time::Instant;

/// The paper's spring with a static and a 20-mode load case.
fn spring(elements_per_coil: usize, weight_t: f64) -> Model {
    let mut model = common::paper_spring_parts(elements_per_coil, weight_t, false);
    model.load_cases.push(LoadCase {
        title: "modal".to_string(),
        analysis: Analysis::Modal { modes: 20 },
        point_loads: Vec::new(),
    });
    model.build().expect("a valid model")
}

/// Best wall time of `reps` runs of `f`, in ms, and the last result.
fn best<T>(reps: usize, mut f: impl FnMut() -> T) -> (f64, T) {
    let mut best = f64::INFINITY;
    let mut out = None;
    for _ in 0..reps {
        let t = Instant::now();
        let r = f();
        best = best.min(t.elapsed().as_secs_f64() * 1e3);
        out = Some(r);
    }
    (best, out.expect("reps > 0"))
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let per_coil: usize = std::env::args()
        .nth(1)
        .map(|s| s.parse())
        .transpose()?
        .unwrap_or(48);
    let reps = 7;
    // K first, then the weight for T = 0.23 s.
    let probe = spring(per_coil, 1e-3);
    let k = {
        let system = System::new(&probe)?;
        let factor = system.factor_stiffness()?;
        static_analysis::solve(&system, &factor, &probe.load_cases()[0], 1.0)?
            .stiffness_n_mm
            .ok_or("no stiffness")?
    };
    let weight = k * (0.23 / std::f64::consts::TAU).powi(2);
    let model = spring(per_coil, weight);

    let (t_system, system) = best(reps, || System::new(&model));
    let system = system?;
    let (t_factor, factor) = best(reps, || system.factor_stiffness());
    let factor = factor?;
    let (t_static, sol) = best(reps, || {
        static_analysis::solve(&system, &factor, &model.load_cases()[0], 1.0)
    });
    let sol = sol?;
    let (t_modal, modes) = best(reps, || modal::solve(&system, &factor, "modal", 20));
    let modes = modes?;
    let dir = std::env::temp_dir().join(format!("coil-bench-{}", std::process::id()));
    let (t_run, cases) = best(reps, || analysis::run(&model));
    let cases = cases?;
    let (t_write, written) = best(reps, || {
        coil_solver::results::write_all(&dir, &model, &cases)
    });
    written?;
    std::fs::remove_dir_all(&dir)?;

    println!(
        "paper spring, {per_coil} elements per coil, type 98: {} free DOFs, {} elements",
        system.dim(),
        model.elements().len()
    );
    println!(
        "  K = {:.6} N/mm, weight {:.4} kg",
        sol.stiffness_n_mm.unwrap_or(f64::NAN),
        weight * 1e3
    );
    println!(
        "  kernel: {}",
        if system.symbolic.is_supernodal() {
            "supernodal"
        } else {
            "simplicial"
        }
    );
    let axial = modes
        .modes
        .iter()
        .enumerate()
        .max_by(|a, b| a.1.effective_mass[2].total_cmp(&b.1.effective_mass[2]))
        .map(|(i, m)| (i + 1, m.period_s))
        .ok_or("no modes")?;
    println!("  axial mode {} period {:.6} s; 20 modes up to {:.2} Hz, max residual {:.1e}, orthonormality {:.1e}",
        axial.0, axial.1,
        modes.modes.last().map_or(f64::NAN, |m| m.frequency_hz),
        modes.modes.iter().map(|m| m.relative_residual).fold(0.0, f64::max),
        modes.orthonormality_error);
    println!("  best of {reps} (ms): system {t_system:.2}, factor {t_factor:.2}, static {t_static:.2}, 20 modes {t_modal:.2}");
    println!("  analysis::run (system + factor + static + modal) {t_run:.2} ms, result files {t_write:.2} ms");
    Ok(())
}
