//! coil's springs in the pantograph's head stage, reduced: the Craig-Bampton stage of
//! [`reduced`] (four calibrated springs in parallel, their surge
//! modes kept, Rayleigh damping on the wire with the paper's law) as the head stage's
//! `matrix` in the catenary spec ([`crate::model::StageMatrix`], one `DMIG` in
//! the deck; docs/catenary.md, "A stage as matrices").
//!
//! # Formulation
//! The reduced stage's coordinates `[frame u_z, head u_z, eta_1..eta_r]` are the spec's
//! `[lower end u, upper end u, eta..]` of stage 1 (the head's mass above, the frame's
//! below), its matrices already in deck units (N/mm, t, N s/mm; a modal coordinate in
//! sqrt(t) mm), so they are copied row-major as they are. The stage's `stiffness_n_m` is
//! the reduced stage's static stiffness (`K = 4 k` to rounding), its `damping_n_s_m` 0
//! (the wire's Rayleigh damping is the matrix's), its `mass_kg` the head's as before:
//! the springs' own mass comes in through the matrix, a third of it on the head in the
//! static shape (Rayleigh), so the reduced run carries the springs' mass, their damping
//! law and their surge modes, where the lumped stage has `(K, c)` alone.

mod design;
pub mod from_spring;
pub mod reduced;
pub mod response;
mod source;
pub mod springs;

use crate::model::PantographSpec;
use crate::Result;
use coil_tuner::case::VariantsFile;
use coil_tuner::fe::FeSettings;
pub use reduced::reduced_stage_spec;
use reduced::{reduced_stage, ReducedStage};
use springs::HeadStages;

/// `pantograph` with its head stage (the first) replaced by `stage`, the head's mass
/// kept.
pub fn with_reduced_head(pantograph: &PantographSpec, stage: &ReducedStage) -> PantographSpec {
    let mut p = pantograph.clone();
    if let Some(head) = p.stages.first_mut() {
        *head = reduced_stage_spec(stage, head.mass_kg);
    }
    p
}

/// The reduced stage of every spring of `stages` (the case's own spring first, then
/// `variants` in file order: `stages.stages`' order), with the calibrated material and
/// the paper's Rayleigh law on the wire (`stages.rayleigh_mid`).
pub fn reduced_head_stages(
    stages: &HeadStages,
    variants: &VariantsFile,
    fe: &FeSettings,
) -> Result<Vec<ReducedStage>> {
    let [alpha, beta] = stages.rayleigh_mid;
    std::iter::once(stages.material.spring)
        .chain(variants.variants.iter().map(|v| v.spring))
        .map(|spring| reduced_stage(&stages.material.with_spring(spring), fe, alpha, beta))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::springs::{head_stages_of_files, HeadStageSettings};
    use super::*;
    use crate::model::{CatenaryDeckSpec, CONTACT_FORCE_COLUMN, PANTOGRAPH_BASE};
    use coil_solver::analysis::{run, CaseSolution};
    use coil_tuner::case::read_variants;
    use std::path::Path;

    /// The static pantograph displacements (mm) and the contact force (N) of a run.
    fn static_and_force(spec: &CatenaryDeckSpec) -> (Vec<f64>, Vec<f64>) {
        let built = crate::model::build(spec).unwrap();
        let results = run(&built.model).unwrap();
        let (CaseSolution::Static(rest), CaseSolution::Transient(moving)) =
            (&results[0].solution, &results[1].solution)
        else {
            panic!("expected a static case and a transient")
        };
        let u = (0..2)
            .map(|i| {
                rest.node_displacement(&built.model, PANTOGRAPH_BASE + i)
                    .unwrap()[2]
            })
            .collect();
        let f = moving
            .history
            .column(CONTACT_FORCE_COLUMN)
            .unwrap()
            .to_vec();
        (u, f)
    }

    #[test]
    fn the_reduced_160ect_head_stage_runs_in_the_catenary() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../cases/160ect");
        let settings = HeadStageSettings::default();
        let table4 = root.join("table4.json");
        let stages = head_stages_of_files(&root, &table4, 7.2, &settings).unwrap();
        let mut variants = read_variants(&table4).unwrap();
        variants.variants.clear();
        let reduced = reduced_head_stages(&stages, &variants, &settings.fe).unwrap();
        assert_eq!(reduced.len(), 1);
        let stage = &reduced[0];
        let lumped_k = stages.stages[0].stiffness_n_m;
        // 2 spans, the first 15 m at 250 km/h (216 steps of 1 ms).
        let mut lumped = CatenaryDeckSpec::en50318_reference(2, 1.0);
        lumped.run.end_m = Some(15.0);
        lumped.pantograph.stages[0].stiffness_n_m = lumped_k;
        lumped.pantograph.stages[0].damping_n_s_m = stages.stages[0].damping_mid_n_s_m;
        let mut spec = lumped.clone();
        spec.pantograph = with_reduced_head(&lumped.pantograph, stage);
        let head = &spec.pantograph.stages[0];
        assert_eq!(head.mass_kg, 7.2);
        assert!((head.stiffness_n_m - lumped_k).abs() <= 1e-9 * lumped_k);
        let (u0, f0) = static_and_force(&lumped);
        let (u1, f1) = static_and_force(&spec);
        let mean = |f: &[f64]| f.iter().sum::<f64>() / f.len() as f64;
        let worst = f0
            .iter()
            .zip(&f1)
            .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()));
        println!(
            "{} modes; static u lumped {u0:?}, reduced {u1:?} mm; contact force mean {:.3} / \
             {:.3} N, largest difference {worst:.3} N",
            stage.dim() - 2,
            mean(&f0),
            mean(&f1)
        );
        // Statics: the same stiffness, no gravity on the pantograph: the same state.
        for (a, b) in u0.iter().zip(&u1) {
            assert!((a - b).abs() <= 1e-6 * a.abs(), "{a} {b}");
        }
        assert!((f0[0] - f1[0]).abs() <= 1e-6 * f0[0], "{} {}", f0[0], f1[0]);
        // Moving: the springs' mass and damping law change the force a little, not its
        // level (the mean is the uplift less the frame spring's force in both).
        assert!(f1.iter().all(|f| f.is_finite()));
        assert!((mean(&f0) - mean(&f1)).abs() <= 0.02 * mean(&f0));
    }
}
