//! The head stage alone, lumped against reduced: for each of the paper's springs (the
//! 160ECT and Table 4's #1-#6), the 7.2 kg collector head (EN 50318's m1) on four
//! springs in parallel, either the lumped stage of `coil_catenary::head_stage::springs` (K = 4 k,
//! the dashpot of the paper's damping law carried over to the head, `zeta_mid`) or
//! the Craig-Bampton stage of `coil_catenary::head_stage::reduced` (the same calibrated
//! springs, their surge modes kept, Rayleigh damping on the wire with the same law).
//!
//! Two frequency responses, 0-100 Hz, computed exactly from the dense matrices
//! (`Z(w) = K - w^2 M + i w C`, the frame's row and column taken out):
//! - the receptance `H = u_head / F` of a force on the head with the frame held (what a
//!   contact force does), mm/N;
//! - the transmissibility `T = u_head / u_frame` with the frame moving.
//!
//! Printed: per spring, the head's resonance (lumped `sqrt(K / m)`, Rayleigh's
//! `sqrt(K / (m + m_s / 3))`, reduced), the first surge, and the largest relative
//! difference `|H_r - H_l| / |H_l|` inside the 20 Hz band that EN 50318 keeps (and
//! outside the resonance's half-power band), then the 160ECT's responses at a few
//! frequencies. Run: `cargo run --release -p coil-catenary --example head_stage_reduced`
//! (about 1 s).

use coil_catenary::head_stage::reduced::{reduced_stage, ReducedStage, FRAME, HEAD};
use coil_catenary::head_stage::springs::{head_stages_of_files, HeadStageSettings};
use coil_tuner::case::read_variants;
use nalgebra::{Complex, DMatrix};
use std::f64::consts::TAU;
use std::path::Path;

/// The head (t), EN 50318's m1 = 7.2 kg.
const HEAD_MASS_T: f64 = 7.2e-3;
/// The band the standard's statistics keep (Hz).
const BAND_HZ: f64 = 20.0;
/// The frequency step of the scan (Hz).
const STEP_HZ: f64 = 0.005;

/// `(H, T)` of a lumped stage at `f` Hz: `K` N/mm, `c` N s/mm, the mass `m` t.
fn lumped(k: f64, c: f64, m: f64, f: f64) -> (Complex<f64>, Complex<f64>) {
    let w = TAU * f;
    let z = Complex::new(k - w * w * m, w * c);
    let support = Complex::new(k, w * c);
    (z.inv(), support / z)
}

/// `(H, T)` of the reduced stage at `f` Hz.
fn reduced(s: &ReducedStage, f: f64) -> (Complex<f64>, Complex<f64>) {
    let w = TAU * f;
    let n = s.dim();
    let free: Vec<usize> = (0..n).filter(|&i| i != FRAME).collect();
    let z = |r: usize, c: usize| {
        let mut m = s.m[(r, c)];
        if r == HEAD && c == HEAD {
            m += HEAD_MASS_T;
        }
        Complex::new(s.k[(r, c)] - w * w * m, w * s.c[(r, c)])
    };
    let zff = DMatrix::from_fn(free.len(), free.len(), |r, c| z(free[r], free[c]));
    let lu = zff.lu();
    let head = free.iter().position(|&i| i == HEAD).unwrap_or(0);
    let mut unit = DMatrix::<Complex<f64>>::zeros(free.len(), 1);
    unit[(head, 0)] = Complex::new(1.0, 0.0);
    let h = lu
        .solve(&unit)
        .map_or(Complex::new(f64::NAN, 0.0), |x| x[(head, 0)]);
    let drive = DMatrix::from_fn(free.len(), 1, |r, _| -z(free[r], FRAME));
    let t = lu
        .solve(&drive)
        .map_or(Complex::new(f64::NAN, 0.0), |x| x[(head, 0)]);
    (h, t)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let start = std::time::Instant::now();
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../cases/160ect");
    let settings = HeadStageSettings::default();
    let variants = read_variants(&root.join("table4.json"))?;
    let stages = head_stages_of_files(&root, &root.join("table4.json"), 7.2, &settings)?;
    let [alpha, beta] = stages.rayleigh_mid;
    println!("Rayleigh on the wire: alpha {alpha} 1/s, beta {beta:e} s (the paper's law)\n");
    println!(
        "| spring | modes | surge (Hz) | f lumped | f Rayleigh | f reduced (Hz) | \
         peak H r/l | max dH 0-20 | off +-0.5 Hz | int H^2 r/l | corrected: max dH 0-20 | \
         max dH 20-100 | max dT 20-100 |"
    );
    println!("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
    let springs =
        std::iter::once(stages.material.spring).chain(variants.variants.iter().map(|v| v.spring));
    let mut first = None;
    for (lumped_stage, spring) in stages.stages.iter().zip(springs) {
        let state = stages.material.with_spring(spring);
        let stage = reduced_stage(&state, &settings.fe, alpha, beta)?;
        let k = lumped_stage.stiffness_n_m / 1e3;
        let c = lumped_stage.damping_mid_n_s_m / 1e3;
        let m_s = 4.0 * stage.spring_mass_t;
        // The lumped stage corrected: a third of the springs' mass on the head, and the
        // wire's Rayleigh damping on the static shape, alpha m_s / 3 + beta K.
        let (m_corr, c_corr) = (HEAD_MASS_T + m_s / 3.0, alpha * m_s / 3.0 + beta * k);
        let f_lumped = (k / HEAD_MASS_T).sqrt() / TAU;
        let f_rayleigh = (k / m_corr).sqrt() / TAU;
        let f_reduced = stage
            .frequencies_on_head_hz(HEAD_MASS_T)
            .and_then(|f| f.first().copied())
            .unwrap_or(f64::NAN);
        let mut peak = [0.0_f64; 2];
        let mut energy = [0.0_f64; 2];
        let mut worst = [0.0_f64; 6];
        let steps = (100.0 / STEP_HZ).round() as usize;
        for i in 0..=steps {
            let f = i as f64 * STEP_HZ;
            let (hl, tl) = lumped(k, c, HEAD_MASS_T, f);
            let (hc, _) = lumped(k, c_corr, m_corr, f);
            let (hr, tr) = reduced(&stage, f);
            peak[0] = peak[0].max(hl.norm());
            peak[1] = peak[1].max(hr.norm());
            let rel = |a: Complex<f64>, b: Complex<f64>| (a - b).norm() / b.norm();
            let values = if f <= BAND_HZ {
                energy[0] += hl.norm_sqr() * STEP_HZ;
                energy[1] += hr.norm_sqr() * STEP_HZ;
                let off = (f - f_reduced).abs() > 0.5;
                [
                    rel(hr, hl),
                    if off { rel(hr, hl) } else { 0.0 },
                    rel(hr, hc),
                    0.0,
                    0.0,
                    0.0,
                ]
            } else {
                [0.0, 0.0, 0.0, rel(hr, hl), rel(tr, tl), 0.0]
            };
            for (w, v) in worst.iter_mut().zip(values) {
                *w = w.max(v);
            }
        }
        println!(
            "| {} | {} | {:.1} | {:.4} | {:.4} | {:.4} | {:.3} | {:.2} | {:.3} | {:.3} | {:.4} | {:.3} | {:.2} |",
            lumped_stage.name,
            stage.dim() - 2,
            stage.surge_hz,
            f_lumped,
            f_rayleigh,
            f_reduced,
            peak[1] / peak[0],
            worst[0],
            worst[1],
            energy[1] / energy[0],
            worst[2],
            worst[3],
            worst[4]
        );
        if first.is_none() {
            first = Some((k, c, stage));
        }
    }
    if let Some((k, c, stage)) = first {
        println!("\n160ECT: |H| (mm/N) and |T| (-), lumped and reduced");
        println!("| f (Hz) | H lumped | H reduced | T lumped | T reduced |");
        println!("|---:|---:|---:|---:|---:|");
        for f in [
            0.0, 2.0, 5.0, 7.0, 7.394, 7.434, 8.0, 10.0, 15.0, 20.0, 50.0, 100.0, 109.6, 129.8,
        ] {
            let (hl, tl) = lumped(k, c, HEAD_MASS_T, f);
            let (hr, tr) = reduced(&stage, f);
            println!(
                "| {f} | {:.4e} | {:.4e} | {:.4e} | {:.4e} |",
                hl.norm(),
                hr.norm(),
                tl.norm(),
                tr.norm()
            );
        }
    }
    println!("\n{:.1} s", start.elapsed().as_secs_f64());
    Ok(())
}
