//! The head stage alone, lumped against reduced, in the frequency domain
//! (`coil_catenary::head_stage::response`: the formulation and what each column is):
//! prints the table docs/catenary.md shows (its test holds the numbers), then the
//! 160ECT's responses at a few frequencies. Run: `cargo run --release -p coil-catenary
//! --example head_stage_reduced` (about 1 s).

use coil_catenary::head_stage::response::{compare, lumped, reduced};
use coil_catenary::head_stage::springs::{head_stages_of_files, HeadStageSettings};
use coil_tuner::case::read_variants;
use std::path::Path;

/// The head, EN 50318's m1 (kg).
const HEAD_MASS_KG: f64 = 7.2;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let start = std::time::Instant::now();
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../cases/160ect");
    let settings = HeadStageSettings::default();
    let variants = read_variants(&root.join("table4.json"))?;
    let stages = head_stages_of_files(&root, &root.join("table4.json"), HEAD_MASS_KG, &settings)?;
    let [alpha, beta] = stages.rayleigh_mid;
    println!("Rayleigh on the wire: alpha {alpha} 1/s, beta {beta:e} s (the paper's law)\n");
    println!(
        "| spring | modes | surge (Hz) | f lumped | f Rayleigh | f reduced (Hz) | \
         peak H r/l | max dH 0-20 | off +-0.5 Hz | int H^2 r/l | corrected: max dH 0-20 | \
         max dH 20-100 | max dT 20-100 |"
    );
    println!("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
    let rows = compare(&stages, &variants, HEAD_MASS_KG, &settings)?;
    for (r, _) in &rows {
        println!(
            "| {} | {} | {:.1} | {:.4} | {:.4} | {:.4} | {:.3} | {:.2} | {:.3} | {:.3} | {:.4} | {:.3} | {:.2} |",
            r.name,
            r.modes,
            r.surge_hz,
            r.f_lumped_hz,
            r.f_rayleigh_hz,
            r.f_reduced_hz,
            r.peak_ratio,
            r.max_dh_band,
            r.max_dh_off_resonance,
            r.energy_ratio,
            r.corrected_dh_band,
            r.max_dh_above,
            r.max_dt_above
        );
    }
    if let (Some((_, stage)), Some(first)) = (rows.first(), stages.stages.first()) {
        let (k, c, m) = (
            first.stiffness_n_m / 1e3,
            first.damping_mid_n_s_m / 1e3,
            HEAD_MASS_KG * 1e-3,
        );
        println!("\n160ECT: |H| (mm/N) and |T| (-), lumped and reduced");
        println!("| f (Hz) | H lumped | H reduced | T lumped | T reduced |");
        println!("|---:|---:|---:|---:|---:|");
        for f in [
            0.0, 2.0, 5.0, 7.0, 7.394, 7.434, 8.0, 10.0, 15.0, 20.0, 50.0, 100.0, 109.6, 129.8,
        ] {
            let (hl, tl) = lumped(k, c, m, f);
            let (hr, tr) = reduced(stage, m, f);
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
