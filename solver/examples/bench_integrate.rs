//! Throughput of the time integrators on a system the size of the paper spring.
//!
//! A chain of 667 six-DOF nodes (4002 DOFs) with a full 12x12 SPD block per
//! two-node element, the sparsity of a helical beam model; M, K and Rayleigh C on
//! that pattern. Direct integration runs 20000 steps of each scheme through
//! `Stepper::step`, counting heap allocations inside the step loop (a counting
//! global allocator); modal superposition runs 20000 steps of 20 exact modes with
//! one output DOF.
//!
//! Run: `cargo run --release -p coil-solver --example bench_integrate`

// The 12x12 element kernels below read as the textbook index formulas.
#![allow(clippy::needless_range_loop)]

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

use coil_solver::integrate::modal::{integrate_modal, ModalBasis, ModalState};
use coil_solver::integrate::{Operators, Scheme, Stepper};
use faer::sparse::{SparseColMat, Triplet};

struct CountingAllocator;

static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for CountingAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: CountingAllocator = CountingAllocator;

/// The benchmark system: operators over the free DOFs and the weight's axial DOF.
struct Spring {
    m: SparseColMat<usize, f64>,
    k: SparseColMat<usize, f64>,
    c: SparseColMat<usize, f64>,
    weight_dof: usize,
}

/// A helical spring of 3D Euler-Bernoulli beams (steel wire), clamped at its first
/// node, with a point mass ("the weight") on its last node: the shape and size of
/// the paper's model. Returns (M, K, C) over the free DOFs (node-major, 6 per node)
/// and the index of the weight's axial DOF. C is Rayleigh on the wire only.
fn helical_spring(n_nodes: usize) -> Spring {
    let (radius, pitch, per_coil) = (20.0, 6.0, 24.0); // mm
    let (e, nu, rho, d) = (190_708.0, 0.3, 7.85e-9, 3.0); // MPa, -, t/mm^3, mm
    let g = e / (2.0 * (1.0 + nu));
    let area = std::f64::consts::PI * d * d / 4.0;
    let i = std::f64::consts::PI * d.powi(4) / 64.0;
    let j = 2.0 * i;
    let node = |n: usize| {
        let phi = 2.0 * std::f64::consts::PI * n as f64 / per_coil;
        [
            radius * phi.cos(),
            radius * phi.sin(),
            pitch * n as f64 / per_coil,
        ]
    };
    let n_free = 6 * (n_nodes - 1);
    let (mut k_t, mut m_t, mut c_t) = (Vec::new(), Vec::new(), Vec::new());
    let (alpha, beta) = (0.8, 1.2e-4);
    let push = |t: &mut Vec<Triplet<usize, usize, f64>>, gi: usize, gj: usize, v: f64| {
        // Node 0 is clamped: its DOFs are eliminated.
        if gi >= 6 && gj >= 6 && v != 0.0 {
            t.push(Triplet::new(gi - 6, gj - 6, v));
        }
    };
    for el in 0..n_nodes - 1 {
        let (a, b) = (node(el), node(el + 1));
        let dx = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
        let l = (dx[0] * dx[0] + dx[1] * dx[1] + dx[2] * dx[2]).sqrt();
        let e1 = [dx[0] / l, dx[1] / l, dx[2] / l];
        // e2 towards the helix axis (perpendicular to e1), e3 = e1 x e2.
        let mid = [(a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0, 0.0];
        let inward = [-mid[0], -mid[1], 0.0];
        let dot = inward[0] * e1[0] + inward[1] * e1[1];
        let mut e2 = [
            inward[0] - dot * e1[0],
            inward[1] - dot * e1[1],
            -dot * e1[2],
        ];
        let n2 = (e2[0] * e2[0] + e2[1] * e2[1] + e2[2] * e2[2]).sqrt();
        e2 = [e2[0] / n2, e2[1] / n2, e2[2] / n2];
        let e3 = [
            e1[1] * e2[2] - e1[2] * e2[1],
            e1[2] * e2[0] - e1[0] * e2[2],
            e1[0] * e2[1] - e1[1] * e2[0],
        ];
        let r = [e1, e2, e3];
        // Local stiffness (u, v, w, rx, ry, rz per node; bending about e3 in v, about e2 in w).
        let mut kl = [[0.0; 12]; 12];
        let mut set = |p: usize, q: usize, v: f64| {
            kl[p][q] += v;
            if p != q {
                kl[q][p] += v;
            }
        };
        let (ea, gj, ei) = (e * area / l, g * j / l, e * i);
        for (p, q, v) in [
            (0, 0, ea),
            (6, 6, ea),
            (0, 6, -ea),
            (3, 3, gj),
            (9, 9, gj),
            (3, 9, -gj),
        ] {
            set(p, q, v);
        }
        // Bending in the (v, rz) and (w, ry) planes.
        for (v1, r1, sign) in [(1usize, 5usize, 1.0), (2, 4, -1.0)] {
            let (v2, r2) = (v1 + 6, r1 + 6);
            let (k12, k6, k4, k2) = (
                12.0 * ei / l.powi(3),
                6.0 * ei / (l * l),
                4.0 * ei / l,
                2.0 * ei / l,
            );
            set(v1, v1, k12);
            set(v2, v2, k12);
            set(v1, v2, -k12);
            set(v1, r1, sign * k6);
            set(v1, r2, sign * k6);
            set(v2, r1, -sign * k6);
            set(v2, r2, -sign * k6);
            set(r1, r1, k4);
            set(r2, r2, k4);
            set(r1, r2, k2);
        }
        // Global = T^T kl T with T = diag(R, R, R, R).
        let t = |p: usize, q: usize| if p / 3 == q / 3 { r[p % 3][q % 3] } else { 0.0 };
        let mut kg = [[0.0; 12]; 12];
        for p in 0..12 {
            for q in 0..12 {
                let mut s = 0.0;
                for a in 0..12 {
                    let ta = t(a, p);
                    if ta == 0.0 {
                        continue;
                    }
                    for b in 0..12 {
                        s += ta * kl[a][b] * t(b, q);
                    }
                }
                kg[p][q] = s;
            }
        }
        // Lumped mass: half the wire to each node, rotary inertia rho J L / 2.
        let (m_node, m_rot) = (rho * area * l / 2.0, rho * j * l / 2.0);
        for p in 0..12 {
            let gp = 6 * el + p;
            for q in 0..12 {
                let gq = 6 * el + q;
                push(&mut k_t, gp, gq, kg[p][q]);
                push(&mut c_t, gp, gq, beta * kg[p][q]);
            }
            let m = if p % 6 < 3 { m_node } else { m_rot };
            push(&mut m_t, gp, gp, m);
            push(&mut c_t, gp, gp, alpha * m);
        }
    }
    // The weight: mass such that its axial period is about 0.23 s
    // (K from Castigliano, G d^4 / (8 D^3 n)).
    let coils = (n_nodes - 1) as f64 / per_coil;
    let k_axial = g * d.powi(4) / (8.0 * (2.0 * radius).powi(3) * coils);
    let weight = k_axial * (0.23 / (2.0 * std::f64::consts::PI)).powi(2);
    let last = 6 * (n_nodes - 1);
    for dof in 0..3 {
        push(&mut m_t, last + dof, last + dof, weight);
    }
    let build = |t: &[Triplet<usize, usize, f64>]| {
        SparseColMat::try_new_from_triplets(n_free, n_free, t).expect("valid triplets")
    };
    Spring {
        m: build(&m_t),
        k: build(&k_t),
        c: build(&c_t),
        weight_dof: last + 2 - 6,
    }
}

/// CPU time of this thread (Linux scheduler statistics), immune to other processes
/// sharing the cores; `None` elsewhere.
fn thread_cpu_seconds() -> Option<f64> {
    let text = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    Some(text.split_whitespace().next()?.parse::<f64>().ok()? * 1e-9)
}

fn main() {
    let n_nodes = 667;
    let n_steps = 20_000;
    let dt = 1e-3;
    let Spring {
        m,
        k,
        c,
        weight_dof,
    } = helical_spring(n_nodes);
    let n = k.nrows();
    println!(
        "system: helical spring, {n} free DOFs, nnz(K) = {}, {n_steps} steps of dt = {dt}",
        k.val().len()
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
        let mut stepper = Stepper::new(ops, scheme, dt).expect("SPD operators");
        // The peer's test: 0.1 m/s on the weight, the spring at rest.
        let mut v0 = vec![0.0; n];
        v0[weight_dof] = 100.0;
        let zero = vec![0.0; n];
        let mut state = stepper
            .initial_state(0.0, &zero, &v0, &zero)
            .expect("initial state");
        let setup_s = setup.elapsed().as_secs_f64();
        let mut f_n = vec![0.0; n];
        let mut f_next = vec![0.0; n];
        let mut history = vec![0.0; n_steps + 1];
        history[0] = state.u[weight_dof];
        let cpu_start = thread_cpu_seconds();
        let before = ALLOCATIONS.load(Ordering::Relaxed);
        let start = Instant::now();
        for step in 1..=n_steps {
            stepper
                .step(&mut state, &f_n, &f_next, step)
                .expect("finite state");
            history[step] = state.u[weight_dof];
            std::mem::swap(&mut f_n, &mut f_next);
        }
        let elapsed = start.elapsed().as_secs_f64();
        let allocations = ALLOCATIONS.load(Ordering::Relaxed) - before;
        let cpu = thread_cpu_seconds()
            .zip(cpu_start)
            .map(|(end, start)| end - start);
        // Weight period from upward zero crossings (a sanity check of the model).
        let crossings: Vec<f64> = history
            .windows(2)
            .enumerate()
            .filter(|(_, w)| w[0] < 0.0 && w[1] >= 0.0)
            .map(|(k, w)| (k as f64 + w[0] / (w[0] - w[1])) * dt)
            .collect();
        let period = (crossings[crossings.len() - 1] - crossings[0]) / (crossings.len() - 1) as f64;

        let cpu_text = cpu.map_or(String::from("n/a"), |c| {
            format!(
                "{c:.3} s = {:.0} steps/s ({:.1} us/step)",
                n_steps as f64 / c,
                c / n_steps as f64 * 1e6
            )
        });
        println!(
            "direct {scheme:?}: setup (merge, analyse, factor, a0) {:.1} ms; {n_steps} steps: wall {elapsed:.3} s = {:.0} steps/s, thread CPU {cpu_text}; allocations in the loop: {allocations}; weight period {period:.5} s",
            setup_s * 1e3,
            n_steps as f64 / elapsed,
        );
    }

    // Modal superposition: 20 modes, shapes of unit size (only the cost matters here).
    let n_modes = 20;
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
    )
    .expect("valid modes");
    let elapsed = start.elapsed().as_secs_f64();
    println!(
        "modal: {n_modes} modes, {n_steps} steps in {:.4} s = {:.0} steps/s (last a = {last:.3e})",
        elapsed,
        n_steps as f64 / elapsed
    );
}
