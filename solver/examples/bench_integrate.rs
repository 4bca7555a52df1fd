//! Throughput of the time integrators on the paper's spring, assembled by coil.
//!
//! The model is the one `coil-mesh` writes for the paper (n = 14 coils, D = 24 mm,
//! d = 3 mm, pitch 6.2 mm, E = 190708 MPa, nu = 0.3, 7850 kg/m^3, type 98 beams; base
//! wire end clamped, top wire end tied by RBE2 to the weight's reference node on the
//! axis, which is guided: only u_z free; Rayleigh alpha = 0.8, beta = 1.2e-4 on the
//! wire only). The weight's DOF is equation 0 and couples to the last free wire node:
//! the "arrow" of the tie. It is assembled by `analysis::System` with consistent mass
//! (coil's default) and with lumped mass (`LUMP`), at 24 elements per coil (the
//! paper's mesh, 2011 DOFs) and 48 (4027 DOFs). The weight is set for a period of
//! 0.23 s from the model's static stiffness.
//!
//! Each scheme runs the peer's test, 20000 steps of 1 ms from 0.1 m/s on the weight,
//! through `Stepper::step`, timing thread CPU time and counting heap allocations in
//! the step loop (a counting global allocator). Modal superposition runs 20000 steps
//! of 20 exact modes with one output DOF.
//!
//! Run: `cargo run --release -p coil-solver --example bench_integrate [ELEMENTS_PER_COIL...]`

use std::time::Instant;

use coil_solver::analysis::System;
use coil_solver::integrate::modal_superposition::{integrate_modal, ModalBasis, ModalState};
use coil_solver::integrate::{Operators, Scheme, Stepper};
use coil_solver::linalg::upper_to_full;
use coil_solver::model::*;

mod common;
mod counting;

#[global_allocator]
static GLOBAL: counting::CountingAllocator = counting::CountingAllocator;

/// The paper's spring (see the module docs) with `weight_t` on the guided reference.
fn spring(elements_per_coil: usize, weight_t: f64, lumped_mass: bool) -> Model {
    let mut model = common::paper_spring_parts(elements_per_coil, weight_t, lumped_mass);
    common::damp_wire(&mut model, 0.8, 1.2e-4);
    model.build().expect("a valid model")
}

/// CPU time of this thread (Linux scheduler statistics), immune to other processes
/// sharing the cores; `None` elsewhere.
fn thread_cpu_seconds() -> Option<f64> {
    let text = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    Some(text.split_whitespace().next()?.parse::<f64>().ok()? * 1e-9)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let sizes: Vec<usize> = std::env::args()
        .skip(1)
        .map(|s| s.parse())
        .collect::<Result<_, _>>()?;
    let sizes = if sizes.is_empty() {
        vec![24, 48]
    } else {
        sizes
    };
    let (n_steps, dt) = (20_000, 1e-3);
    for per_coil in sizes {
        for lumped in [false, true] {
            let weight = common::weight_for_period(&spring(per_coil, 1e-3, lumped), 0.23)?;
            let model = spring(per_coil, weight, lumped);
            let system = System::new(&model)?;
            let weight_dof = system
                .dofs
                .full_index(1, 3)
                .and_then(|full| match system.dofs.status(full) {
                    coil_solver::dof::DofStatus::Free(eq) => Some(eq),
                    _ => None,
                })
                .ok_or("weight DOF not free")?;
            let m = upper_to_full(system.mass.as_ref())?;
            let c = upper_to_full(system.damping.as_ref())?;
            let k = upper_to_full(system.stiffness.as_ref())?;
            let n = k.nrows();
            println!(
                "{per_coil} elements per coil, {} mass: {n} DOFs (weight = equation {weight_dof}), nnz(K) = {}, nnz(M) = {}, {n_steps} steps of {dt} s",
                if lumped { "lumped" } else { "consistent" },
                k.val().len(),
                m.val().len()
            );
            let ops = Operators {
                m: m.as_ref(),
                c: Some(c.as_ref()),
                k: k.as_ref(),
            };
            for scheme in [
                Scheme::AverageAcceleration,
                Scheme::Hht { alpha: -0.05 },
                Scheme::GeneralizedAlpha { rho_inf: 0.8 },
            ] {
                let setup = Instant::now();
                let mut stepper = Stepper::new(ops, scheme, dt)?;
                // The peer's test: 0.1 m/s on the weight, the spring at rest.
                let mut v0 = vec![0.0; n];
                v0[weight_dof] = 100.0;
                let zero = vec![0.0; n];
                let mut state = stepper.initial_state(0.0, &zero, &v0, &zero)?;
                let setup_s = setup.elapsed().as_secs_f64();
                let mut f_n = vec![0.0; n];
                let mut f_next = vec![0.0; n];
                let mut history = vec![0.0; n_steps + 1];
                history[0] = state.u[weight_dof];
                let cpu_start = thread_cpu_seconds();
                let before = counting::allocations();
                let start = Instant::now();
                for (step, h) in history.iter_mut().enumerate().skip(1) {
                    stepper.step(&mut state, &f_n, &f_next, step)?;
                    *h = state.u[weight_dof];
                    std::mem::swap(&mut f_n, &mut f_next);
                }
                let elapsed = start.elapsed().as_secs_f64();
                let allocations = counting::allocations() - before;
                let cpu = thread_cpu_seconds()
                    .zip(cpu_start)
                    .map(|(end, start)| end - start);
                // Weight period from upward zero crossings (a check of the model).
                let crossings: Vec<f64> = history
                    .windows(2)
                    .enumerate()
                    .filter(|(_, w)| w[0] < 0.0 && w[1] >= 0.0)
                    .map(|(k, w)| (k as f64 + w[0] / (w[0] - w[1])) * dt)
                    .collect();
                let period =
                    (crossings[crossings.len() - 1] - crossings[0]) / (crossings.len() - 1) as f64;
                let cpu_text = cpu.map_or(String::from("n/a"), |c| {
                    format!("{c:.3} s ({:.1} us/step)", c / n_steps as f64 * 1e6)
                });
                println!(
                    "  {scheme:?}: setup {:.1} ms; steps: thread CPU {cpu_text}, wall {elapsed:.3} s; allocations in the loop: {allocations}; weight period {period:.5} s",
                    setup_s * 1e3,
                );
            }
        }
    }

    // Modal superposition: 20 modes, shapes of unit size (only the cost matters here).
    let (n, n_modes, weight_dof) = (2011, 20, 1000);
    let shapes = faer::Mat::<f64>::from_fn(n, n_modes, |i, j| ((i * (j + 1)) as f64 * 1e-3).sin());
    let omega: Vec<f64> = (0..n_modes).map(|j| 27.3 * (j + 1) as f64).collect();
    let zeta: Vec<f64> = omega.iter().map(|w| 0.5 * (0.8 / w + 1.2e-4 * w)).collect();
    let basis = ModalBasis {
        shapes: shapes.as_ref(),
        omega: &omega,
        zeta: &zeta,
    };
    let initial = ModalState {
        t: 0.0,
        q: vec![0.0; n_modes],
        qd: vec![1.0; n_modes],
    };
    let mut last = 0.0;
    let start = Instant::now();
    integrate_modal(
        basis,
        dt,
        n_steps,
        &initial,
        &[weight_dof],
        &mut |_, _| {},
        &mut |_, _, r| last = r.a[0],
    )?;
    let elapsed = start.elapsed().as_secs_f64();
    println!(
        "modal: {n_modes} modes, {n_steps} steps in {:.4} s = {:.0} steps/s (last a = {last:.3e})",
        elapsed,
        n_steps as f64 / elapsed
    );
    Ok(())
}
