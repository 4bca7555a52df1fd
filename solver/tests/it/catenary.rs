//! A tensioned wire (`BEAM TENSION`) against the taut string's closed forms: a force
//! pulse at one point sends velocity pulses `w_t = f(t - |x - x0|/c) / (2 sqrt(N rho))`
//! both ways at `c = sqrt(N / rho)`; the measured speed and height of the pulse at two
//! stations follow them. The wires are those of the EN 50318 reference catenary
//! (contact wire 1.35 kg/m at 20 kN, EI 195 N m^2: c = 121.7 m/s; messenger 1.07 kg/m at
//! 16 kN, EI 131.7 N m^2: c = 122.3 m/s).

use coil_solver::analysis::{run, CaseSolution};
use coil_solver::deck::read_str;

/// A straight wire along x, `length` mm in elements of `h` mm (type 52), ends pinned,
/// only u_z and theta_y free, tension `force` N, `rho_a` t/mm and `ei` N mm^2; a force
/// pulse `peak` N (a triangle of `2 tau` s) at `x0` mm; velocity recorded at `stations`.
#[allow(clippy::too_many_arguments)]
fn pulse_deck(
    length: f64,
    h: f64,
    force: f64,
    rho_a: f64,
    ei: f64,
    x0: f64,
    peak: f64,
    tau: f64,
    stations: &[f64],
    dt: f64,
    total: f64,
) -> (String, Vec<u32>) {
    let n_el = (length / h).round() as u32;
    let node_at = |x: f64| (x / h).round() as u32 + 1;
    // A solid section carrying rho A and EI exactly: A = 100 mm^2, I = 1000 mm^4.
    let (area, inertia) = (100.0, 1000.0);
    let mut d = String::new();
    d.push_str("TITLE, pulse on a taut wire\nELEMENTS, 52\nEND\n");
    d.push_str(&format!("COORDINATES\n3, {}\n", n_el + 1));
    for i in 0..=n_el {
        d.push_str(&format!("{}, {}, 0, 0\n", i + 1, f64::from(i) * h));
    }
    d.push_str(&format!("CONNECTIVITY\n{n_el}\n"));
    for i in 1..=n_el {
        d.push_str(&format!("{i}, 52, {i}, {}\n", i + 1));
    }
    d.push_str(&format!(
        "ISOTROPIC\n1\n1, wire\n{}, 0.3, {}\n1 TO {n_el}\n",
        ei / inertia,
        rho_a / area
    ));
    d.push_str(&format!(
        "GEOMETRY\n1\n1, wire\n{area}, {inertia}, {inertia}, {}\n0, 0, 1\n1 TO {n_el}\n",
        2.0 * inertia
    ));
    d.push_str(&format!("BEAM TENSION\n{force}\n1 TO {n_el}\n"));
    d.push_str(&format!(
        "FIXED DISP\n0, 0, 0, 0\n1, 2, 4, 6\n1 TO {}\n0\n3\n1, {}\n",
        n_el + 1,
        n_el + 1
    ));
    d.push_str(&format!("TABLE, pulse\n0, 0\n{tau}, 1\n{}, 0\n", 2.0 * tau));
    d.push_str(&format!(
        "POINT LOAD, TABLE, pulse\n0, 0, {peak}\n{}\n",
        node_at(x0)
    ));
    let nodes: Vec<u32> = stations.iter().map(|&x| node_at(x)).collect();
    let list = nodes
        .iter()
        .map(u32::to_string)
        .collect::<Vec<_>>()
        .join(", ");
    d.push_str(&format!("HISTORY OUTPUT\n1\nVEL\n3\n{list}\n"));
    d.push_str(&format!(
        "END OPTION\nTITLE, pulse\nDYNAMIC CHANGE\n{dt}, {total}, NEWMARK\nCONTINUE\n"
    ));
    (d, nodes)
}

/// Centroid time and area (rectangle rule) of a pulse in `[t0, t1]`.
fn centroid_and_area(t: &[f64], v: &[f64], t0: f64, t1: f64) -> (f64, f64) {
    let dt = t[1] - t[0];
    let (mut m0, mut m1) = (0.0, 0.0);
    for (&ti, &vi) in t.iter().zip(v) {
        if ti >= t0 && ti <= t1 {
            m0 += vi;
            m1 += ti * vi;
        }
    }
    (m1 / m0, m0 * dt)
}

/// Measures the wave speed (m/s) and the pulse's area (its displacement step) at both
/// stations against its closed form, for a
/// wire of `rho_kg_m` at `tension_n` with `ei_n_m2`.
fn measured_wave(rho_kg_m: f64, tension_n: f64, ei_n_m2: f64) -> (f64, f64, f64) {
    let rho_a = rho_kg_m * 1e-6; // t/mm
    let c = (tension_n / rho_a).sqrt(); // mm/s
    let (length, h, x0, tau) = (160_000.0, 250.0, 40_000.0, 0.05);
    let stations = [80_000.0, 120_000.0];
    let peak = 100.0;
    let (deck, nodes) = pulse_deck(
        length,
        h,
        tension_n,
        rho_a,
        ei_n_m2 * 1e6,
        x0,
        peak,
        tau,
        &stations,
        5e-4,
        1.1,
    );
    let model = read_str(&deck, "pulse.dat").unwrap();
    let results = run(&model).unwrap();
    let CaseSolution::Transient(sol) = &results[0].solution else {
        panic!("not a transient case");
    };
    let t = &sol.history.time_s;
    let arrive = |x: f64| (x - x0) / c;
    let mut centroids = Vec::new();
    let mut heights = Vec::new();
    for (&node, &x) in nodes.iter().zip(&stations) {
        let v = sol
            .history
            .column(&format!("node{node}_uz_vel_m_s"))
            .unwrap();
        // The pulse passes between arrive(x) and arrive(x) + 2 tau; a window 0.1 s
        // wider each side (reflections arrive far later).
        let (tc, p) = centroid_and_area(t, v, arrive(x) - 0.1, arrive(x) + 2.0 * tau + 0.1);
        centroids.push(tc);
        heights.push(p);
    }
    let speed = (stations[1] - stations[0]) * 1e-3 / (centroids[1] - centroids[0]);
    // Closed-form area: the impulse peak tau over the impedance 2 sqrt(N rho) (mm) -> m.
    let height = peak * tau / (2.0 * (tension_n * rho_a).sqrt()) * 1e-3;
    (speed, heights[0] / height, heights[1] / height)
}

#[test]
fn a_pulse_travels_along_each_wire_at_sqrt_tension_over_mass() {
    for (name, rho, tension, ei, expected) in [
        ("contact wire", 1.35_f64, 20_000.0_f64, 195.0, 121.716),
        ("messenger", 1.07, 16_000.0, 131.7, 122.284),
    ] {
        let closed = (tension / rho).sqrt();
        assert!((closed - expected).abs() < 1e-3, "{name}: {closed}");
        let (speed, h1, h2) = measured_wave(rho, tension, ei);
        println!(
            "{name}: c = {speed:.4} m/s against sqrt(T/rho) = {closed:.4} m/s ({:+.2e}); \
             pulse area / closed form {h1:.5}, {h2:.5}",
            speed / closed - 1.0
        );
        // Bounds: the pulse's wavelength (c 2 tau = 12 m) sees the wire's EI as a
        // dispersion of group speed 1 + 3 EI k^2 / (2 N) ~ 1e-3 at k = 2 pi / 12 m, and
        // the 0.25 m elements and 0.5 ms steps add (k h)^2 / 720 and (w dt)^2 / 12,
        // both below 1e-4: 0.3 % on the speed. Dispersion lowers the triangle's peak
        // (by 6-7 % here) but keeps its area, the k = 0 content: 1 % (rectangle rule).
        assert!((speed / closed - 1.0).abs() < 3e-3, "{name}: {speed} m/s");
        assert!(
            (h1 - 1.0).abs() < 1e-2 && (h2 - 1.0).abs() < 1e-2,
            "{name}: {h1} {h2}"
        );
    }
}

/// A constant force `P` moving at `v < c` along a taut string of length `L` (both ends
/// pinned) has the exact solution `w = P G(x, vt) / (N (1 - v^2/c^2))`, `G(x, s)` the
/// string's static Green's function (`x (L - s) / L` for `x < s`), once the string starts
/// with its velocity `P v (L - x) / (L N (1 - v^2/c^2))`: `G` is a Green's function in `s`
/// too, so `N w_xx - rho v^2 w_ss = -P (1 - v^2/c^2) delta`. Under the load the string
/// sits at `P s (L - s) / (N L (1 - v^2/c^2))`. Here the force is a `MOVING CONTACT`: a
/// head of mass `m` pushed up by `P` on a penalty spring, whose constant head
/// acceleration `-2 lambda v^2 / (N L (1 - v^2/c^2))` makes the contact force
/// `lambda = P / (1 - 2 m v^2 / (N L (1 - v^2/c^2)))`.
#[test]
fn a_force_moving_on_a_taut_string_deflects_it_by_the_closed_form() {
    let (length, h, tension, rho_a): (f64, f64, f64, f64) = (40_000.0, 250.0, 20_000.0, 1.35e-6);
    let (p, m_head, k_contact): (f64, f64, f64) = (100.0, 1.0e-3, 1000.0);
    let c = (tension / rho_a).sqrt();
    let v = 0.5 * c;
    let amp = 1.0 / (1.0 - (v / c).powi(2));
    let lambda = p / (1.0 - 2.0 * m_head * v * v * amp / (tension * length));
    let n_el = (length / h).round() as u32;
    let head = 9999;
    let mut d = String::from("TITLE, moving force\nELEMENTS, 52\nEND\n");
    // The head hangs on a vertical bar of 1e-6 N/mm to a fixed node (the DOF map wants
    // every free DOF on an element; its force stays below 1e-4 N).
    d.push_str(&format!("COORDINATES\n3, {}\n", n_el + 3));
    for i in 0..=n_el {
        d.push_str(&format!("{}, {}, 0, 0\n", i + 1, f64::from(i) * h));
    }
    d.push_str(&format!("{}, 0, 0, -1000\n{head}, 0, 0, 0\n", head - 1));
    d.push_str(&format!("CONNECTIVITY\n{}\n", n_el + 1));
    for i in 1..=n_el {
        d.push_str(&format!("{i}, 52, {i}, {}\n", i + 1));
    }
    d.push_str(&format!("{}, 52, {}, {head}\n", n_el + 1, head - 1));
    d.push_str(&format!(
        "ISOTROPIC\n2\n1, wire\n{}, 0.3, {}\n1 TO {n_el}\n2, bar\n1.0e-3, 0.3, 0\n{}\n",
        195.0e6 / 1000.0,
        rho_a / 100.0,
        n_el + 1
    ));
    d.push_str(&format!(
        "GEOMETRY\n2\n1, wire\n100, 1000, 1000, 2000\n0, 0, 1\n1 TO {n_el}\n\
         2, bar\n1, 1, 1, 1\n1, 0, 0\n{}\n",
        n_el + 1
    ));
    d.push_str(&format!("BEAM TENSION\n{tension}\n1 TO {n_el}\n"));
    d.push_str(&format!("POINT MASS\n{head}, {m_head}, 0, 0, 0\n"));
    d.push_str(&format!(
        "MOVING CONTACT\n{head}, 3, {k_contact}, {v}, 0.0\n1 TO {}\n",
        n_el + 1
    ));
    d.push_str(&format!(
        "FIXED DISP\n0, 0, 0, 0\n1, 2, 4, 6\n1 TO {}\n0\n3\n1, {}\n0, 0, 0, 0, 0\n1, 2, 4, 5, 6\n{head}\n0, 0, 0, 0, 0, 0\n1, 2, 3, 4, 5, 6\n{}\n",
        n_el + 1,
        n_el + 1,
        head - 1
    ));
    d.push_str(&format!("POINT LOAD\n0, 0, {p}\n{head}\n"));
    // The particular solution's velocity: the string's, its slope's, the head's.
    let speed = lambda * v * amp / tension;
    d.push_str("INITIAL VEL\n");
    d.push_str(&format!("{}\n5\n1 TO {}\n", speed / length, n_el + 1));
    for i in 1..n_el {
        let x = f64::from(i) * h;
        d.push_str(&format!(
            "{}\n3\n{}\n",
            speed * (length - x) / length,
            i + 1
        ));
    }
    d.push_str(&format!("{speed}\n3\n{head}\n"));
    d.push_str(&format!("HISTORY OUTPUT\n1\nDISP\n3\n{head}\n"));
    let total = 0.95 * length / v;
    d.push_str(&format!(
        "END OPTION\nTITLE, rest\nAUTO LOAD\n1\nTIME STEP\n1.0\nCONTINUE\n\
         TITLE, move\nDYNAMIC CHANGE\n1.0e-4, {total}, NEWMARK\nCONTINUE\n"
    ));
    let model = read_str(&d, "moving.dat").unwrap();
    let results = run(&model).unwrap();
    let CaseSolution::Transient(sol) = &results[1].solution else {
        panic!("not a transient case");
    };
    let t = &sol.history.time_s;
    let u_head = sol
        .history
        .column(&format!("node{head}_uz_disp_m"))
        .unwrap();
    let force = sol.history.column("contact1_force_n").unwrap();
    let (mut worst, mut ripple, mut peak) = (0.0_f64, 0.0_f64, 0.0_f64);
    let (mut sum, mut count) = (0.0, 0.0);
    for ((&ti, &uh), &f) in t.iter().zip(u_head).zip(force) {
        let s = v * ti;
        if s < 0.1 * length || s > 0.9 * length {
            continue;
        }
        // The string under the point: the head less the penetration (mm).
        let w = uh * 1e3 - f / k_contact;
        let exact = lambda * s * (length - s) / (tension * length) * amp;
        worst = worst.max((w - exact).abs());
        peak = peak.max(exact);
        ripple = ripple.max((f / lambda - 1.0).abs());
        sum += f;
        count += 1.0;
    }
    let mean = sum / count;
    println!(
        "moving force at v = c/2: deflection under the load within {:.3e} of the closed-form \
         peak {peak:.3} mm (static would be {:.3} mm); mean contact force {mean:.4} N against \
         lambda = {lambda:.4} N ({:+.2e}), ripple up to {ripple:.2e} of it",
        worst / peak,
        peak / amp,
        mean / lambda - 1.0
    );
    // Bounds: the start's velocity kink (a jump at the support, spread over one
    // element h = L/160) and the head on its penalty spring (1000 rad/s, undamped),
    // excited by the point passing the nodes (v/h = 1530 rad/s) and by its start from
    // the static penetration P/k instead of lambda/k: 2 % of the peak deflection, 1 % on
    // the mean force. The force itself ripples (measured up to 74 %) at these
    // frequencies, far above the string's; the dynamic amplification is 33 %.
    assert!(worst / peak < 2e-2, "{worst} of {peak}");
    assert!(
        (mean / lambda - 1.0).abs() < 1e-2,
        "{mean} against {lambda}"
    );
}

/// A tension link pulls only: node 2 on a bar of k_b = 10 N/mm to the fixed node 1
/// below it, and a link of k = 100 N/mm to the fixed node 3 above it. Pulled away from
/// node 3 the two springs act in parallel (u = F / (k_b + k)); pushed towards it the link
/// goes slack (u = F / k_b); a pretensioned link holds until the push exceeds it.
#[test]
fn a_tension_link_pulls_and_goes_slack() {
    let deck = |slack: f64, force: f64| {
        format!(
            "TITLE, link\nELEMENTS, 52\nEND\nCOORDINATES\n3, 3\n1, 0, 0, -1000\n2, 0, 0, 0\n\
             3, 0, 0, 500\nCONNECTIVITY\n1\n1, 52, 1, 2\nISOTROPIC\n1\n1, bar\n1000.0, 0.3, 0\n1\n\
             GEOMETRY\n1\n1, bar\n10, 1, 1, 1\n1, 0, 0\n1\n\
             TENSION LINK\n2, 3, 3, 100.0, {slack}\n\
             FIXED DISP\n0, 0, 0, 0, 0, 0\n1, 2, 3, 4, 5, 6\n1, 3\n0, 0, 0, 0, 0\n1, 2, 4, 5, 6\n2\n\
             POINT LOAD\n0, 0, {force}\n2\n\
             END OPTION\nAUTO LOAD\n1\nTIME STEP\n1.0\nCONTINUE\n"
        )
    };
    let u = |slack: f64, force: f64| {
        let model = read_str(&deck(slack, force), "link.dat").unwrap();
        let results = run(&model).unwrap();
        let CaseSolution::Static(sol) = &results[0].solution else {
            panic!("not static");
        };
        assert!(
            sol.relative_residual < 1e-12,
            "{} {:?}",
            sol.relative_residual,
            sol.node_displacement(&model, 2)
        );
        sol.node_displacement(&model, 2).unwrap()[2]
    };
    // The link from node 2 (a) to node 3 (b, above it along +z): e = u_3 - u_2 - slack,
    // stretched when node 2 moves down.
    let close = |a: f64, b: f64| (a - b).abs() < 1e-12 * b.abs().max(1.0);
    assert!(close(u(0.0, -55.0), -55.0 / 110.0));
    assert!(close(u(0.0, 55.0), 55.0 / 10.0));
    // Pretensioned (slack -1 mm, 100 N at the reference): it lifts node 2 by 100 / 110;
    // a pull of 200 N down keeps it taut; a push of 200 N up slackens it (the taut
    // guess 300 / 110 would shorten it by 1.7 mm).
    assert!(close(u(-1.0, 0.0), 100.0 / 110.0));
    assert!(close(u(-1.0, -200.0), -100.0 / 110.0));
    assert!(close(u(-1.0, 200.0), 200.0 / 10.0));
}

/// The displacement history (m) of the mass in the bilinear oscillator of the test
/// below, stepped at `dt` (s); without the link when `link` is false.
fn bilinear_swing(dt: f64, link: bool) -> Vec<f64> {
    let link = if link {
        "TENSION LINK\n2, 3, 3, 100.0, 0.0\n"
    } else {
        ""
    };
    let deck = format!(
        "TITLE, link\nELEMENTS, 52\nEND\nCOORDINATES\n3, 3\n1, 0, 0, -1000\n2, 0, 0, 0\n\
        3, 0, 0, 500\nCONNECTIVITY\n1\n1, 52, 1, 2\nISOTROPIC\n1\n1, bar\n1000.0, 0.3, 0\n1\n\
        GEOMETRY\n1\n1, bar\n10, 1, 1, 1\n1, 0, 0\n1\n\
        {link}POINT MASS\n2, 1.0e-3, 0, 0, 0\n\
        FIXED DISP\n0, 0, 0, 0, 0, 0\n1, 2, 3, 4, 5, 6\n1, 3\n0, 0, 0, 0, 0\n1, 2, 4, 5, 6\n2\n\
        INITIAL VEL\n100.0\n3\n2\nHISTORY OUTPUT\n1\nDISP\n3\n2\n\
        END OPTION\nTITLE, swing\nDYNAMIC CHANGE\n{dt:e}, 0.2, NEWMARK\nCONTINUE\n"
    );
    let model = read_str(&deck, "swing.dat").unwrap();
    let results = run(&model).unwrap();
    let CaseSolution::Transient(sol) = &results[0].solution else {
        panic!("not a transient case");
    };
    sol.history.column("node2_uz_disp_m").unwrap().to_vec()
}

/// The same link in a transient: a 1 kg mass on the 10 N/mm bar, the link (100 N/mm)
/// above it, launched upwards at 100 mm/s. Going up the link is slack (w = 100 rad/s,
/// peak v0 / w = 1 mm); coming down it is taut (w = sqrt(110 / 1e-3) = 331.7 rad/s, peak
/// -v0 / w = -0.3015 mm); the period is pi/100 + pi/331.7 s. Average acceleration keeps
/// the energy of each linear piece, so the peaks hold to the step's resolution.
#[test]
fn a_mass_on_a_tension_link_swings_as_a_bilinear_oscillator() {
    let u = bilinear_swing(1e-5, true);
    let up = u.iter().fold(f64::MIN, |m, &x| m.max(x)) * 1e3;
    let down = u.iter().fold(f64::MAX, |m, &x| m.min(x)) * 1e3;
    let w_taut = (110.0_f64 / 1e-3).sqrt();
    println!(
        "bilinear swing: up {up:.6} mm (1), down {down:.6} mm ({:.6})",
        -100.0 / w_taut
    );
    // A step of 1e-5 s moves the peak by at most (w dt)^2 / 8 relative: 1.4e-5.
    assert!((up - 1.0).abs() < 1e-4, "{up}");
    assert!((down + 100.0 / w_taut).abs() < 1e-4 * 0.3, "{down}");
}

/// A slack link carries no force at any step size: while the mass of the swing above
/// rises (the link slack from the first step), its history at a coarse step (w dt = 0.2
/// on the bar, 0.66 on bar and link) is the bar's alone at that step, to 1e-9 relative. The
/// step's effective stiffness (k_b + k + 4 m / dt^2 = 1110 N/mm) is not far above the
/// link's, so a slack correction that read the link's response with the wrong sign
/// would leave about a fifth of the link's force in the step.
#[test]
fn a_slack_link_carries_no_force_at_a_coarse_step() {
    let dt = 2e-3;
    let with = bilinear_swing(dt, true);
    let without = bilinear_swing(dt, false);
    let rising: Vec<(f64, f64)> = with
        .iter()
        .zip(&without)
        .skip(1)
        .take_while(|(a, b)| **a > 0.0 && **b > 0.0)
        .map(|(a, b)| (*a, *b))
        .collect();
    // Half a period of the bar alone: pi / (100 rad/s) / dt = 15.7 steps.
    assert!(rising.len() >= 14, "{} rising steps", rising.len());
    for (step, (a, b)) in rising.iter().enumerate() {
        assert!(
            (a - b).abs() <= 1e-9 * b.abs(),
            "step {}: {a} m with the slack link, {b} m without",
            step + 1
        );
    }
}
