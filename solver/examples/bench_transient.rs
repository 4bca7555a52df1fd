//! Speed benchmark (not a test): the issue's peer transient of the paper spring, 20 s at
//! dt = 1 ms, timed as the whole `coil-solve` process (deck reading, assembly, solve,
//! history and result files), by direct integration (Newmark average acceleration) and by
//! modal superposition (`--method modal --modes 20`). Targets: 1 s and 0.05 s.
//!
//! Run (the binary must be built first, in the same profile):
//! ```text
//! cargo build --release -p coil-solver
//! cargo run --release -p coil-solver --example bench_transient [REPEATS]
//! ```
//!
//! The model is built in code with the mesher's layout: n = 14 coils, D = 24 mm,
//! d = 3 mm, pitch 6.2 mm, 24 elements per coil of type 98, E = 190708 MPa, nu = 0.3,
//! 7850 kg/m^3; base clamped, top wire end tied (RBE2) to node 1 on the axis, guided (only
//! u_z free), carrying the weight m = K (0.23 / 2 pi)^2 with K the model's static
//! stiffness; Rayleigh alpha = 0.8, beta = 0.00012 on the wire only;
//! `INITIAL VEL, QUASI STATIC` 0.1 m/s on node 1; node 1's u_z displacement, velocity and
//! acceleration recorded every step (20001 rows).
//!
//! Reported per method: the wall time of each process run (best and median), the CPU
//! time of the child (user + system, from `/proc/self/stat` after `wait`, in clock ticks
//! of 10 ms), and, in-process, `analysis::run` and `results::write_all` separately.

use coil_solver::analysis::{self, System};
use coil_solver::model::*;

mod common;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

use common::WEIGHT;

fn paper_spring(weight_t: f64) -> Model {
    let mut model = common::paper_spring_parts(24, weight_t, false);
    model.title = "paper spring, peer transient".to_string();
    common::damp_wire(&mut model, 0.8, 1.2e-4);
    model.initial_velocities = vec![InitialVelocity {
        dofs: vec![(3, 100.0)],
        nodes: vec![WEIGHT],
        quasi_static: true,
    }];
    model.outputs = vec![OutputRequest {
        nodes: vec![WEIGHT],
        dofs: vec![3],
        quantities: vec![
            Quantity::Displacement,
            Quantity::Velocity,
            Quantity::Acceleration,
        ],
        every: 1,
    }];
    model.load_cases = vec![LoadCase {
        title: "free decay".to_string(),
        analysis: Analysis::Transient {
            dt: 1e-3,
            total_time: 20.0,
            method: TransientMethod::Direct(Integrator::AverageAcceleration),
        },
        point_loads: Vec::new(),
    }];
    model.build().expect("a valid model")
}

/// The static stiffness at the weight (N/mm).
fn stiffness() -> Result<f64, Box<dyn std::error::Error>> {
    let probe = common::paper_spring(24, 1e-3, false);
    let system = System::new(&probe)?;
    let factor = system.factor_stiffness()?;
    Ok(
        analysis::static_analysis::solve(&system, &factor, &probe.load_cases()[0], 1.0)?
            .stiffness_n_mm
            .ok_or("no stiffness at the weight")?,
    )
}

/// User + system CPU seconds of this process's waited-for children (`/proc/self/stat`
/// fields 16 and 17, in ticks of 1/100 s, Linux's USER_HZ).
fn children_cpu_seconds() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    // Fields after the command name (which may hold blanks) start at field 3.
    let rest = &stat[stat.rfind(')')? + 2..];
    let fields: Vec<&str> = rest.split_whitespace().collect();
    let ticks = |i: usize| fields.get(i - 3)?.parse::<f64>().ok();
    Some((ticks(16)? + ticks(17)?) / 100.0)
}

struct Timing {
    wall: Vec<f64>,
    cpu: Vec<f64>,
}

fn time_process(
    binary: &Path,
    deck: &Path,
    out: &Path,
    extra: &[&str],
    repeats: usize,
) -> Result<Timing, Box<dyn std::error::Error>> {
    let mut timing = Timing {
        wall: Vec::new(),
        cpu: Vec::new(),
    };
    for _ in 0..repeats {
        let cpu0 = children_cpu_seconds();
        let start = Instant::now();
        let status = Command::new(binary)
            .arg(deck)
            .arg("--out")
            .arg(out)
            .arg("--quiet")
            .args(extra)
            .status()?;
        timing.wall.push(start.elapsed().as_secs_f64());
        if !status.success() {
            return Err(format!("coil-solve failed: {status}").into());
        }
        if let (Some(a), Some(b)) = (cpu0, children_cpu_seconds()) {
            timing.cpu.push(b - a);
        }
    }
    let history = std::fs::read_to_string(out.join("history.csv"))?;
    let rows = history.lines().count() - 1;
    if rows != 20_001 {
        return Err(format!("history.csv has {rows} rows, expected 20001").into());
    }
    Ok(timing)
}

fn best_median(x: &[f64]) -> (f64, f64) {
    let mut v = x.to_vec();
    v.sort_by(f64::total_cmp);
    (
        v.first().copied().unwrap_or(f64::NAN),
        v.get(v.len() / 2).copied().unwrap_or(f64::NAN),
    )
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let repeats: usize = std::env::args()
        .nth(1)
        .map(|s| s.parse())
        .transpose()?
        .unwrap_or(5);
    let exe = std::env::current_exe()?;
    // target/<profile>/examples/bench_transient -> target/<profile>/coil-solve
    let binary: PathBuf = exe
        .parent()
        .and_then(Path::parent)
        .map(|p| p.join(format!("coil-solve{}", std::env::consts::EXE_SUFFIX)))
        .ok_or("no target directory")?;
    if !binary.is_file() {
        return Err(format!(
            "{} not found: build it first (cargo build --release -p coil-solver)",
            binary.display()
        )
        .into());
    }
    let k = stiffness()?;
    let weight = k * (0.23 / std::f64::consts::TAU).powi(2);
    let model = paper_spring(weight);
    let dir = tempfile::tempdir()?;
    let deck = dir.path().join("peer.dat");
    std::fs::write(&deck, coil_solver::deck::write(&model))?;
    let system = System::new(&model)?;
    println!(
        "paper spring, 24 elements per coil, type 98: {} free DOFs; K = {k:.6} N/mm, weight \
         {:.4} kg; 20000 steps of 1 ms, 3 columns every step",
        system.dim(),
        units::mass_to_si(weight)
    );
    println!(
        "machine: {} CPUs, load average {}",
        std::thread::available_parallelism().map_or(0, |n| n.get()),
        std::fs::read_to_string("/proc/loadavg")
            .map(|s| s.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
            .unwrap_or_default()
    );

    for (label, extra, target) in [
        ("direct (Newmark average acceleration)", &[][..], 1.0),
        (
            "modal superposition, 20 modes",
            &["--method", "modal", "--modes", "20"][..],
            0.05,
        ),
    ] {
        let out = dir.path().join("out");
        let timing = time_process(&binary, &deck, &out, extra, repeats)?;
        let (wall_best, wall_median) = best_median(&timing.wall);
        let (cpu_best, cpu_median) = best_median(&timing.cpu);
        println!(
            "{label}: whole coil-solve process, {repeats} runs: wall best {wall_best:.3} s, \
             median {wall_median:.3} s; CPU best {cpu_best:.2} s, median {cpu_median:.2} s \
             (target {target} s)"
        );
    }

    // In-process breakdown (best of the repeats).
    for (label, choice) in [
        ("direct", None),
        (
            "modal",
            Some(analysis::transient::MethodOverride::Modal { modes: Some(20) }),
        ),
    ] {
        let mut m = model.clone();
        if let Some(choice) = choice {
            analysis::transient::override_method(&mut m, choice);
        }
        let (mut t_run, mut t_write) = (f64::INFINITY, f64::INFINITY);
        for _ in 0..repeats {
            let start = Instant::now();
            let cases = analysis::run(&m)?;
            t_run = t_run.min(start.elapsed().as_secs_f64());
            let start = Instant::now();
            coil_solver::results::write_all(&dir.path().join("in-process"), &m, &cases)?;
            t_write = t_write.min(start.elapsed().as_secs_f64());
        }
        println!(
            "  in process, {label}: analysis::run {:.1} ms, results::write_all {:.1} ms",
            t_run * 1e3,
            t_write * 1e3
        );
    }
    Ok(())
}
