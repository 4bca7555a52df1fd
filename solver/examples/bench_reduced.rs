//! Cost of the reduced model that `coil-tune diagnose` fits: one Craig-Bampton
//! reduction of the paper's spring, then whole 40 s decay simulations with the dense
//! average-acceleration stepper and point laws at the weight.
//!
//! The model is the paper's spring of `examples/common` (24 elements per coil, type 98,
//! E = 190708 MPa, weight for a 0.23 s period, guided; or with the weight's rotation
//! about the axis freed and a rotary inertia), reduced to the weight's u_z (and
//! theta_z) plus 4 fixed-interface modes: r = 5 (6). Rayleigh alpha = 0.8,
//! beta = 1.2e-4 on the wire. A record is 40 s sampled at 1 kHz; the stepper runs at
//! dt = 1 ms / substeps with the fewest substeps giving omega dt <= 0.01 for the axial
//! mode (~4.3 Hz), and returns the weight's samples (`simulate_into`, no allocation in
//! the loop). Each variant is timed over 15 runs: the median wall time of one run and
//! the mean thread CPU time (scheduler ticks, so only their mean is meaningful); heap
//! allocations inside `step` are counted by a counting allocator.
//!
//! Run: `cargo run --release -p coil-solver --example bench_reduced [N_MODES]` (default 4)

use std::time::Instant;

use coil_solver::integrate::dense::Sample;
use coil_solver::integrate::{DenseStepper, PointLaw};
use coil_solver::reduce::craig_bampton;

mod common;
mod counting;

#[global_allocator]
static GLOBAL: counting::CountingAllocator = counting::CountingAllocator;

/// CPU time of this thread (Linux scheduler statistics); wall time elsewhere.
fn cpu_seconds(start: &Instant) -> f64 {
    std::fs::read_to_string("/proc/thread-self/schedstat")
        .ok()
        .and_then(|t| t.split_whitespace().next()?.parse::<f64>().ok())
        .map_or_else(|| start.elapsed().as_secs_f64(), |ns| ns * 1e-9)
}

fn median(mut x: Vec<f64>) -> f64 {
    x.sort_by(f64::total_cmp);
    x[x.len() / 2]
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let clock = Instant::now();
    let per_coil = 24;
    let weight = common::weight_for_period(&common::paper_spring(per_coil, 1e-3, false), 0.23)?;
    let n_modes: usize = match std::env::args().nth(1) {
        Some(arg) => arg.parse()?,
        None => 4,
    };
    let (record_s, sample_hz) = (40.0, 1000.0);
    let n_samples = (record_s * sample_hz) as usize + 1;
    let (alpha, beta) = (0.8, 1.2e-4);

    for free_rotation in [false, true] {
        let mut model = common::paper_spring_parts(per_coil, weight, false);
        let mut boundary = vec![(common::WEIGHT, 3u8)];
        if free_rotation {
            model.fixed_disp[1].dofs.retain(|&(d, _)| d != 6);
            // 1e-3 kg m^2 = 1 t mm^2: the torsional mode near the axial one.
            model.point_masses[0].inertia[2] = 1.0;
            boundary.push((common::WEIGHT, 6));
        }
        let model = model.build()?;
        let t0 = cpu_seconds(&clock);
        let red = craig_bampton(&model, &boundary, n_modes)?;
        let reduce_ms = (cpu_seconds(&clock) - t0) * 1e3;
        let extra = vec![0.0; boundary.len()];
        let ops = red.operators(1.0, &extra, alpha, beta)?;
        let f = red.frequencies_hz(1.0, &extra)?;
        let omega = std::f64::consts::TAU * f[0];
        let substeps = (omega / sample_hz / 0.01).ceil() as usize;
        let dt = 1.0 / (sample_hz * substeps as f64);
        println!(
            "{}: r = {} ({} boundary + {n_modes} modes), reduction {reduce_ms:.1} ms, f = {:.4?} Hz, {substeps} substeps (omega dt = {:.4}), {} steps per simulation",
            if free_rotation { "free rotation" } else { "guided" },
            red.dim(),
            boundary.len(),
            &f[..3],
            omega * dt,
            (n_samples - 1) * substeps
        );
        let law = |cubic, quadratic, friction| PointLaw {
            cubic,
            quadratic,
            friction,
        };
        let variants = [
            ("linear", vec![]),
            ("cubic k3 = 1e-3 N/mm^3", vec![(0, law(1e-3, 0.0, 0.0))]),
            (
                "velocity-squared c2 = 1e-4 N s^2/mm^2",
                vec![(0, law(0.0, 1e-4, 0.0))],
            ),
            ("Coulomb F = 0.01 N", vec![(0, law(0.0, 0.0, 0.01))]),
            ("all three", vec![(0, law(1e-3, 1e-4, 0.01))]),
        ];
        let mut u0 = vec![0.0; red.dim()];
        u0[0] = -2.0;
        let v0 = vec![0.0; red.dim()];
        let mut samples: Vec<Sample> = Vec::with_capacity(n_samples);
        for (name, laws) in variants {
            let t0 = Instant::now();
            let mut stepper = DenseStepper::new(&ops.m, &ops.c, &ops.k, dt, &laws)?;
            let setup_us = t0.elapsed().as_secs_f64() * 1e6;
            let mut times = Vec::new();
            let repetitions = 15;
            let cpu0 = cpu_seconds(&clock);
            for _ in 0..repetitions {
                let t0 = Instant::now();
                stepper.simulate_into(&u0, &v0, n_samples, substeps, 0, &mut samples)?;
                times.push(t0.elapsed().as_secs_f64() * 1e3);
            }
            let cpu_ms = (cpu_seconds(&clock) - cpu0) * 1e3 / repetitions as f64;
            stepper.set_state(&u0, &v0)?;
            let before = counting::allocations();
            for _ in 0..10_000 {
                stepper.step()?;
            }
            let allocations = counting::allocations() - before;
            let ms = median(times);
            let last = samples.last().map_or(0.0, |s| s.u);
            println!(
                "  {name:40} setup {setup_us:6.1} us, {ms:6.2} ms per 40 s simulation (wall median; CPU mean {cpu_ms:6.2} ms; {:5.1} ns per step), {allocations} allocations in 10000 steps, u(40 s) = {last:+.3e} mm",
                ms * 1e6 / ((n_samples - 1) * substeps) as f64
            );
        }
    }
    Ok(())
}
