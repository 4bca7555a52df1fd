//! Marc interchange end to end: the paper's spring written in Mentat's extended fixed
//! format (`coil-mesh --format mentat`, i.e. `deck::write_mentat`) reads back to the
//! same model as the free-format deck and solves to the same stiffness, modes and
//! free decay, to 1e-12 relative.

use coil_mesher::{AnalysisKind, SpringSpec};
use coil_solver::analysis::{run, CaseSolution};
use coil_solver::deck;

fn close(a: f64, b: f64, what: &str) {
    let scale = a.abs().max(b.abs()).max(f64::MIN_POSITIVE);
    assert!((a - b).abs() <= 1e-12 * scale, "{what}: {a} vs {b}");
}

#[test]
fn mentat_layout_paper_spring_solves_like_the_free_format_deck() {
    let spec = SpringSpec {
        youngs_modulus_mpa: 190708.0,
        mass_kg: 5.1778,
        alpha: 0.8,
        beta: 1.2e-4,
        analyses: vec![
            AnalysisKind::Static,
            AnalysisKind::Modal,
            AnalysisKind::Transient,
        ],
        modes: 10,
        dt_s: 1e-3,
        duration_s: 1.0,
        initial_velocity_m_s: 0.1,
        ..SpringSpec::default()
    };
    let model = spec.build().unwrap();
    let free = deck::read_str(&deck::write(&model), "free.dat").unwrap();
    let mentat_text = deck::write_mentat(&model);
    assert!(mentat_text.contains("\nEXTENDED\n"));
    let mentat = deck::read_str(&mentat_text, "mentat.dat").unwrap();
    assert_eq!(
        mentat, free,
        "the Mentat-layout deck reads to the same model"
    );
    let (a, b) = (run(&free).unwrap(), run(&mentat).unwrap());
    assert_eq!(a.len(), 3);
    for (x, y) in a.iter().zip(&b) {
        match (&x.solution, &y.solution) {
            (CaseSolution::Static(s), CaseSolution::Static(t)) => close(
                s.stiffness_n_mm.unwrap(),
                t.stiffness_n_mm.unwrap(),
                "K (N/mm)",
            ),
            (CaseSolution::Modal(s), CaseSolution::Modal(t)) => {
                assert_eq!(s.modes.len(), t.modes.len());
                for (m, n) in s.modes.iter().zip(&t.modes) {
                    close(m.frequency_hz, n.frequency_hz, "frequency (Hz)");
                }
            }
            (CaseSolution::Transient(s), CaseSolution::Transient(t)) => {
                assert_eq!(s.history.columns.len(), t.history.columns.len());
                for (c, d) in s.history.columns.iter().zip(&t.history.columns) {
                    let peak = c.values.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
                    for (u, v) in c.values.iter().zip(&d.values) {
                        assert!((u - v).abs() <= 1e-12 * peak, "{}: {u} vs {v}", c.name);
                    }
                }
            }
            _ => panic!("load cases differ"),
        }
    }
}
