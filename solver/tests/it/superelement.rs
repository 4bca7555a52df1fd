//! The matrix element (`DMIG`) against what it stands for: a 2x2 element is a spring
//! with two point masses (static and modal, to rounding, and against the two-mass
//! closed forms); a Craig-Bampton reduction of a bar written as a `DMIG` card has, as
//! a deck of its own, the reduction's eigenvalues; direct Newmark transients (with and
//! without the unilateral links of a catenary) swing a matrix oscillator at its
//! closed-form frequency and decay.

use coil_solver::analysis::{run, CaseSolution};
use coil_solver::deck::{dmig_card, read_str};
use coil_solver::model::Model;
use coil_solver::reduce::craig_bampton;

/// Node 1 held; nodes 2 and 3 on the z axis, free in u_z only; a bar 1-2 of 10 N/mm;
/// between 2 and 3 either a massless bar of 100 N/mm (a spring: only u_z is free) and
/// point masses (1 and 2 kg), or one 2x2 `DMIG` with the same stiffness and mass;
/// `history` after END OPTION.
fn two_mass_deck(matrix: bool, history: &str) -> String {
    let (count, spring, coupling) = if matrix {
        (
            1,
            "",
            "DMIG\n1, 2, 0, pair\n2, 3\n3, 3\n100.0, -100.0\n-100.0, 100.0\n\
             1.0e-3, 0\n0, 2.0e-3\n",
        )
    } else {
        (
            2,
            "2, 52, 2, 3\n",
            "POINT MASS\n2, 1.0e-3, 0, 0, 0\n3, 2.0e-3, 0, 0, 0\n",
        )
    };
    format!(
        "TITLE, pair\nELEMENTS, 52\nEND\nCOORDINATES\n3, 3\n1, 0, 0, -1000\n2, 0, 0, 0\n\
         3, 0, 0, 100\nCONNECTIVITY\n{count}\n1, 52, 1, 2\n{spring}ISOTROPIC\n1\n1, bar\n\
         1000.0, 0.3, 0\n1 TO {count}\nGEOMETRY\n1\n1, bar\n10, 1, 1, 1\n1, 0, 0\n1 TO {count}\n\
         {coupling}FIXED DISP\n0, 0, 0, 0, 0, 0\n1, 2, 3, 4, 5, 6\n1\n0, 0, 0, 0, 0\n\
         1, 2, 4, 5, 6\n2, 3\nEND OPTION\n{history}"
    )
}

fn solve(deck: &str) -> (Model, Vec<CaseSolution>) {
    let model = read_str(deck, "t.dat").unwrap_or_else(|e| panic!("{e}\n{deck}"));
    let results = run(&model).unwrap();
    (model, results.into_iter().map(|r| r.solution).collect())
}

fn frequencies(s: &CaseSolution) -> Vec<f64> {
    let CaseSolution::Modal(m) = s else {
        panic!("not modal")
    };
    m.modes.iter().map(|m| m.frequency_hz).collect()
}

#[test]
fn a_two_by_two_matrix_element_is_a_spring_and_two_point_masses() {
    // A pull of 55 N up at node 3 keeps the link taut: u_2 = 55 / 10, u_3 = u_2 + 55 / 100.
    let history = "TITLE, pull\nPOINT LOAD\n0, 0, 55.0\n3\nAUTO LOAD\n1\nTIME STEP\n1.0\n\
                   CONTINUE\nMODAL SHAPE\n2\nCONTINUE\n";
    let mut answers = Vec::new();
    for matrix in [false, true] {
        let (model, sol) = solve(&two_mass_deck(matrix, history));
        let CaseSolution::Static(st) = &sol[0] else {
            panic!("not static")
        };
        let u2 = st.node_displacement(&model, 2).unwrap()[2];
        let u3 = st.node_displacement(&model, 3).unwrap()[2];
        answers.push((u2, u3, frequencies(&sol[1])));
    }
    let close = |a: f64, b: f64, tol: f64| (a - b).abs() <= tol * b.abs();
    let (u2, u3, f) = &answers[1];
    assert!(
        close(*u2, 5.5, 1e-12) && close(*u3, 6.05, 1e-12),
        "{u2} {u3}"
    );
    // Two masses m2 = 1e-3, m3 = 2e-3 t; k1 = 10 (to ground), k2 = 100 N/mm:
    // m2 m3 w^4 - (m2 k2 + m3 (k1 + k2)) w^2 + k1 k2 = 0.
    let (m2, m3, k1, k2): (f64, f64, f64, f64) = (1e-3, 2e-3, 10.0, 100.0);
    let (a, b, c) = (m2 * m3, -(m2 * k2 + m3 * (k1 + k2)), k1 * k2);
    let disc = (b * b - 4.0 * a * c).sqrt();
    let hz = |w2: f64| w2.sqrt() / std::f64::consts::TAU;
    let exact = [hz((-b - disc) / (2.0 * a)), hz((-b + disc) / (2.0 * a))];
    for (got, want) in f.iter().zip(exact) {
        assert!(close(*got, want, 1e-10), "{got} Hz against {want} Hz");
    }
    let (l2, l3, lf) = &answers[0];
    assert!(close(*u2, *l2, 1e-12) && close(*u3, *l3, 1e-12));
    for (got, want) in f.iter().zip(lf) {
        assert!(
            close(*got, *want, 1e-12),
            "{got} Hz against the link's {want} Hz"
        );
    }
}

/// A steel bar along z (1000 mm, 20 elements, 100 mm^2), held at z = 0, free in u_z
/// only: the "spring" to reduce, its top node 21 the boundary.
fn bar_deck() -> String {
    let n = 20;
    let mut d = String::from("TITLE, bar\nELEMENTS, 52\nEND\n");
    d.push_str(&format!("COORDINATES\n3, {}\n", n + 1));
    for i in 0..=n {
        d.push_str(&format!("{}, 0, 0, {}\n", i + 1, f64::from(i) * 50.0));
    }
    d.push_str(&format!("CONNECTIVITY\n{n}\n"));
    for i in 1..=n {
        d.push_str(&format!("{i}, 52, {i}, {}\n", i + 1));
    }
    d.push_str(&format!(
        "ISOTROPIC\n1\n1, steel\n2.0e5, 0.3, 7.85e-9\n1 TO {n}\n\
         GEOMETRY\n1\n1, bar\n100, 800, 800, 1600\n1, 0, 0\n1 TO {n}\n\
         FIXED DISP\n0, 0, 0, 0, 0, 0\n1, 2, 3, 4, 5, 6\n1\n0, 0, 0, 0, 0\n1, 2, 4, 5, 6\n2 TO {}\n\
         END OPTION\nMODAL SHAPE\n3\nCONTINUE\n",
        n + 1
    ));
    d
}

#[test]
fn a_reduced_bar_as_a_dmig_deck_has_the_reductions_eigenvalues() {
    let bar = read_str(&bar_deck(), "bar.dat").unwrap();
    let red = craig_bampton(&bar, &[(21, 3)], 4).unwrap();
    // The DMIG's own deck: the boundary on node 1's u_z, modes on nodes 11..14's u_x,
    // a 2 kg mass on the boundary.
    let element = red
        .matrix_element("bar", &[(1, 3)], &[11, 12, 13, 14], 1.0, 0.0, 0.0)
        .unwrap();
    let deck = format!(
        "TITLE, reduced bar\nELEMENTS, 52\nEND\nCOORDINATES\n3, 5\n1, 0, 0, 0\n11, 0, 0, 1\n\
         12, 0, 0, 2\n13, 0, 0, 3\n14, 0, 0, 4\n{}POINT MASS\n1, 2.0e-3, 0, 0, 0\n\
         FIXED DISP\n0, 0, 0, 0, 0\n1, 2, 4, 5, 6\n1\n0, 0, 0, 0, 0\n2, 3, 4, 5, 6\n11 TO 14\n\
         END OPTION\nMODAL SHAPE\n5\nCONTINUE\n",
        dmig_card(&[element])
    );
    let (_, sol) = solve(&deck);
    let f = frequencies(&sol[0]);
    let own = red.frequencies_hz(1.0, &[2.0e-3]).unwrap();
    println!("deck {f:?}\nreduction {own:?}");
    assert_eq!(f.len(), own.len());
    for (got, want) in f.iter().zip(&own) {
        assert!(
            (got - want).abs() <= 1e-9 * want,
            "{got} Hz against {want} Hz"
        );
    }
    // Held boundary: the deck's modes are the reduction's fixed-interface modes.
    let held = deck.replace("1, 2, 4, 5, 6\n1\n", "1, 2, 3, 4, 5, 6\n1\n");
    let held = held.replace("0, 0, 0, 0, 0\n1, 2, 3", "0, 0, 0, 0, 0, 0\n1, 2, 3");
    let held = held.replace("MODAL SHAPE\n5", "MODAL SHAPE\n4");
    let (_, sol) = solve(&held);
    for (got, want) in frequencies(&sol[0]).iter().zip(&red.fixed_interface_hz) {
        assert!(
            (got - want).abs() <= 1e-9 * want,
            "{got} Hz against {want} Hz"
        );
    }
}

/// One mass on a `DMIG` spring to ground with its own damping, launched at 100 mm/s:
/// `u = v0 / w_d exp(-zeta w t) sin(w_d t)`; first peak at `t = atan(w_d / (zeta w)) /
/// w_d`. With a permanently slack tension link beside it the run takes the unilateral
/// (active-set) path of a catenary and must give the same swing.
#[test]
fn newmark_transients_see_the_matrix_element() {
    let (k, m, c): (f64, f64, f64) = (100.0, 1.0e-3, 0.02);
    let swing = |link: &str| {
        let deck = format!(
            "TITLE, swing\nELEMENTS, 52\nEND\nCOORDINATES\n3, 2\n1, 0, 0, 0\n2, 0, 0, 100\n\
             DMIG\n1, 2, 1\n1, 3\n2, 3\n{k}, -{k}\n-{k}, {k}\n0, 0\n0, {m}\n{c}, -{c}\n-{c}, {c}\n\
             {link}FIXED DISP\n0, 0, 0, 0, 0, 0\n1, 2, 3, 4, 5, 6\n1\n0, 0, 0, 0, 0\n1, 2, 4, 5, 6\n2\n\
             INITIAL VEL\n100.0\n3\n2\nHISTORY OUTPUT\n1\nDISP\n3\n2\n\
             END OPTION\nTITLE, swing\nDYNAMIC CHANGE\n1.0e-5, 0.01, NEWMARK\nCONTINUE\n"
        );
        let (_, sol) = solve(&deck);
        let CaseSolution::Transient(t) = &sol[0] else {
            panic!("not a transient")
        };
        let u = t.history.column("node2_uz_disp_m").unwrap();
        let (i, peak) = u
            .iter()
            .enumerate()
            .fold((0, f64::MIN), |b, (i, &x)| if x > b.1 { (i, x) } else { b });
        (i as f64 * 1.0e-5, peak * 1e3)
    };
    let w = (k / m).sqrt();
    let zeta = c / (2.0 * (k * m).sqrt());
    let wd = w * (1.0 - zeta * zeta).sqrt();
    let t_peak = (wd / (zeta * w)).atan() / wd;
    let u_peak = 100.0 / wd * (-zeta * w * t_peak).exp() * (wd * t_peak).sin();
    let (t, u) = swing("");
    println!("matrix oscillator: peak {u:.6} mm at {t:.5} s ({u_peak:.6} at {t_peak:.5})");
    // Average acceleration at w dt = 3.2e-3: period error (w dt)^2 / 12, far below
    // the sampled time's 1e-5 s; the peak's height holds to 1e-5 relative.
    assert!((t - t_peak).abs() <= 1.5e-5, "{t} {t_peak}");
    assert!((u - u_peak).abs() <= 1e-5 * u_peak, "{u} {u_peak}");
    // The link (50 N/mm) needs 1 mm of stretch to pull; node 2 never moves that far.
    // The active-set path removes the taut link's force k (u_2 - 1 mm) every step; the
    // swing then differs by 3e-6 relative, a difference that grows with k times the
    // slack (4e-3 at 1000 mm), the link path's own, not the matrix element's.
    let (tl, ul) = swing("TENSION LINK\n1, 2, 3, 50.0, 1.0\n");
    println!("with a slack link: peak {ul:.6} mm at {tl:.5} s");
    assert!(
        (tl - t).abs() <= 1.5e-5 && (ul - u).abs() <= 2e-5 * u,
        "{ul} {u}"
    );
}
