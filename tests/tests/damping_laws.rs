//! The damping laws of issue 10 as solver features, each checked against its closed form
//! on a single degree of freedom: a massless axial bar (k = EA/L) with a point mass m at
//! its free end, every other DOF held, given v0 at t = 0. The exact free decay is
//! `u(t) = v0 / w_d exp(-zeta w t) sin(w_d t)`, `w = sqrt(k/m)`, `w_d = w sqrt(1 - zeta^2)`,
//! with, per law (deck card):
//!
//! | card | zeta |
//! |---|---|
//! | `DAMPING` beta on the bar, alpha on the mass | `beta w / 2 + alpha / (2 w)` |
//! | `LOSS FACTOR eta` | `eta / 2` |
//! | `MODAL DAMPING 1, z` | `z` |
//! | `DASHPOT c` | `c / (2 m w)` |
//!
//! Each deck runs by direct integration (average acceleration, the modal term as the
//! low-rank correction) and by modal superposition. Tolerance: average acceleration's
//! period error `(w dt)^2 / 12` (w dt = 4e-3 here: 1.3e-6 per period) accumulates to a
//! phase error below 1e-4 rad over the 2 s record, and the amplitude of the damped
//! scheme is exact to the same order, so the record must match the closed form to 2e-4
//! of v0 / w; a 1 % error in zeta moves the record by about 3e-3 of it (checked below).
//! Modal superposition integrates the single mode exactly (1e-9).

use coil_solver::analysis::{run, CaseSolution};
use coil_solver::deck::read_str;

const K_N_MM: f64 = 200_000.0 * 1.0 * std::f64::consts::PI / 4.0 / 100.0;
const MASS_T: f64 = 1.0;
const V0_MM_S: f64 = 100.0;
const DT: f64 = 1e-4;
const TOTAL: f64 = 2.0;

fn omega() -> f64 {
    (K_N_MM / MASS_T).sqrt()
}

/// The single-DOF deck with `extra` model cards and a transient `method` line.
fn deck(extra: &str, method: &str) -> String {
    format!(
        "TITLE, single dof\nELEMENTS, 52\nEND\n\
         COORDINATES\n3, 2\n1, 0, 0, 0\n2, 0, 0, 100\n\
         CONNECTIVITY\n1\n1, 52, 1, 2\n\
         ISOTROPIC\n1\n1, bar\n200000, 0.3, 0\n1\n\
         GEOMETRY\n1\n1.0\n1, 0, 0\n1\n\
         POINT MASS\n2, {MASS_T}, 0, 0, 0\n\
         FIXED DISP\n0, 0, 0, 0, 0, 0\n1, 2, 3, 4, 5, 6\n1\n0, 0, 0, 0, 0\n1, 2, 4, 5, 6\n2\n\
         INITIAL VEL\n{V0_MM_S}\n3\n2\n\
         HISTORY OUTPUT\n1\nDISP\n3\n2\n\
         {extra}\
         END OPTION\nTITLE, decay\nDYNAMIC CHANGE\n{DT}, {TOTAL}{method}\nCONTINUE\n"
    )
}

/// Largest |u - u_exact| over the record, relative to v0 / w (m).
fn misfit(extra: &str, method: &str, zeta: f64) -> f64 {
    let model = read_str(&deck(extra, method), "sdof.dat").unwrap_or_else(|e| panic!("{e}"));
    let cases = run(&model).unwrap_or_else(|e| panic!("{e}"));
    let CaseSolution::Transient(t) = &cases[0].solution else {
        panic!("expected a transient");
    };
    let u = t.history.column("node2_uz_disp_m").expect("the weight's record");
    let w = omega();
    let wd = w * (1.0 - zeta * zeta).sqrt();
    let scale = V0_MM_S / w * 1e-3;
    t.history
        .time_s
        .iter()
        .zip(u)
        .map(|(&s, &x)| {
            let exact = V0_MM_S / wd * 1e-3 * (-zeta * w * s).exp() * (wd * s).sin();
            (x - exact).abs() / scale
        })
        .fold(0.0, f64::max)
}

fn laws() -> Vec<(&'static str, String, f64)> {
    let w = omega();
    let (alpha, beta) = (0.3, 4.0e-4);
    let eta = 0.012;
    let z1 = 0.0075;
    let c = 0.9; // N s/mm
    vec![
        (
            "rayleigh",
            format!("DAMPING\n{alpha}, {beta}, 1\n1\n2\n"),
            beta * w / 2.0 + alpha / (2.0 * w),
        ),
        ("loss factor", format!("LOSS FACTOR\n{eta}, 1\n"), eta / 2.0),
        ("modal damping", format!("MODAL DAMPING\n1, {z1}\n"), z1),
        (
            "dashpot",
            format!("DASHPOT\n2, 3, {c}\n"),
            c / (2.0 * MASS_T * w),
        ),
    ]
}

#[test]
fn single_dof_decay_matches_the_closed_form_for_every_law() {
    for (name, cards, zeta) in laws() {
        let direct = misfit(&cards, "", zeta);
        let modal = misfit(&cards, ", MODAL, 1", zeta);
        let wrong = misfit(&cards, ", MODAL, 1", zeta * 1.01);
        println!(
            "{name:14} zeta {zeta:.6}: direct misfit {direct:.2e}, modal {modal:.2e}, \
             modal against zeta + 1% {wrong:.2e}"
        );
        assert!(direct < 2e-4, "{name}: direct misfit {direct}");
        assert!(modal < 1e-9, "{name}: modal misfit {modal}");
        assert!(wrong > 2e-3, "{name}: a 1% error in zeta must show ({wrong})");
    }
}

#[test]
fn modal_damping_in_direct_integration_refuses_other_schemes() {
    let text = deck("LOSS FACTOR\n0.01, 1\n", ", HHT, -0.05");
    let model = read_str(&text, "sdof.dat").unwrap();
    let err = run(&model).unwrap_err().to_string();
    assert!(err.contains("NEWMARK"), "{err}");
}
