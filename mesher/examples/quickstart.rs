//! Quickstart: mesh the paper's spring, solve it, and print its stiffness beside the
//! Castigliano closed form and the paper's Eq. (1).
//!
//! `cargo run --release -p coil-mesher --example quickstart [ELEMENTS_PER_COIL]`

use coil_mesher::closed_form::{simple_stiffness, HelixStiffness};
use coil_mesher::SpringSpec;
use coil_solver::analysis::{run, CaseSolution};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let per_coil: Vec<u32> = match std::env::args().nth(1) {
        Some(arg) => vec![arg.parse()?],
        None => vec![8, 16, 24, 48, 96, 192],
    };
    let e_mpa = 190708.0;
    let base = SpringSpec {
        youngs_modulus_mpa: e_mpa,
        ..SpringSpec::default()
    };
    let geometry = base.geometry();
    let closed = HelixStiffness::new(&geometry, e_mpa, base.poisson);
    println!(
        "paper spring: n = {}, D = {} mm, d = {} mm, h = {} mm, E = {e_mpa} MPa, nu = {}",
        geometry.coils,
        geometry.mean_diameter_mm,
        geometry.wire_diameter_mm,
        geometry.pitch_mm,
        base.poisson
    );
    println!(
        "{:>17} {:>14} {:>16}",
        "elements per coil", "K type 98 N/mm", "vs Castigliano"
    );
    for m in per_coil {
        let spec = SpringSpec {
            elements_per_coil: m,
            ..base.clone()
        };
        let model = spec.build()?;
        let k = match run(&model)?.remove(0).solution {
            CaseSolution::Static(s) => s.stiffness_n_mm.ok_or("no stiffness at the weight")?,
            _ => return Err("expected a static load case".into()),
        };
        let rel = 100.0 * (k / closed.guided(true) - 1.0);
        println!("{m:>17} {k:>14.4} {rel:>+15.2}%");
    }
    println!(
        "Castigliano (torsion + bending + shear + pitch, guided end): {:.4} N/mm",
        closed.guided(true)
    );
    println!(
        "paper's Eq. (1), G d^4 / (8 n D^3):                         {:.4} N/mm",
        simple_stiffness(&geometry, e_mpa / (2.0 * (1.0 + base.poisson)))
    );
    println!("paper's measured K (Table 1 mean):                          3.9275 N/mm");
    Ok(())
}
