//! EN 15800:2008 (= DIN 2095), cylindrical helical compression springs made of round
//! wire, tolerances for cold-coiled springs: the permissible deviations of the coil
//! diameter, the free length, the spring force at a given length, and the perpendicularity
//! and parallelism of the ends, for the three quality grades 1 (fine), 2 (medium) and 3
//! (coarse).
//!
//! # Formulation
//! - coil diameter `A_D`: the standard's table by D and spring index w = D/d (below);
//! - the standard's factor `alpha_F = 65.92 d^3.3 / D^1.6 (-0.84 (w/10)^3 + 3.781 (w/10)^2
//!   - 4.244 (w/10) + 2.274)` (N; d, D in mm) and `k_F = 1 / (3 n^2) + 8 / (5 n) + 0.803`;
//! - the grade factor Q: 0.63 (grade 1), 1.0 (grade 2), 1.6 (grade 3);
//! - force at a given length: `A_F = +-(alpha_F k_F + 1.5 F / 100) Q` (N);
//! - free length (when no force is toleranced): `A_L0 = +-alpha_F k_F Q / R` (mm);
//! - perpendicularity `e1` = 0.03, 0.05, 0.08 L0 and parallelism `e2` = 0.015, 0.03,
//!   0.06 De for grades 1, 2, 3 (grade 1 only for w <= 12 and L0 / D <= 5).
//!
//! The formulas are checked against the open implementation springONE's EN 15800 unit
//! (github.com/melchiorrecaruso/springone, `SpringLIB/src/EN15800.pas`), whose
//! coil-diameter table agrees with the one below value for value over 0.63 <= D <= 31.5 mm.
//! The standard's scope: 0.07 <= d <= 16 mm, 0.63 <= D <= 200 mm, L0 <= 630 mm, n >= 2,
//! 4 <= w <= 20; coil tabulates A_D up to D = 31.5 mm.
//!
//! Units: mm, N.

use serde::Serialize;

/// EN 15800 permissible deviation of the coil diameter (+- mm): rows (D from, D to],
/// then grades 1, 2, 3, each for w in (4, 8], (8, 14], (14, 20]. NaN: not read.
const COIL_DIAMETER: [(f64, f64, [[f64; 3]; 3]); 9] = [
    (
        0.63,
        1.0,
        [[0.05, 0.07, 0.10], [0.07, 0.10, 0.15], [0.10, 0.15, 0.20]],
    ),
    (
        1.0,
        1.6,
        [[0.05, 0.07, 0.10], [0.08, 0.10, 0.15], [0.15, 0.20, 0.30]],
    ),
    (
        1.6,
        2.5,
        [[0.07, 0.10, 0.15], [0.10, 0.15, 0.20], [0.20, 0.30, 0.40]],
    ),
    (
        2.5,
        4.0,
        [[0.10, 0.10, 0.15], [0.15, 0.20, 0.25], [0.30, 0.40, 0.50]],
    ),
    (
        4.0,
        6.3,
        [[0.10, 0.15, 0.20], [0.20, 0.25, 0.30], [0.40, 0.50, 0.60]],
    ),
    (
        6.3,
        10.0,
        [[0.15, 0.15, 0.20], [0.25, 0.30, 0.35], [0.50, 0.60, 0.70]],
    ),
    (
        10.0,
        16.0,
        [[0.15, 0.20, 0.25], [0.30, 0.35, 0.40], [0.60, 0.70, 0.80]],
    ),
    (
        16.0,
        25.0,
        [[0.20, 0.25, 0.30], [0.35, 0.45, 0.50], [0.70, 0.90, 1.00]],
    ),
    (
        25.0,
        31.5,
        [
            [0.25, 0.30, 0.35],
            [0.40, 0.50, 0.60],
            [0.80, 1.00, f64::NAN],
        ],
    ),
];

/// EN 15800's permissible deviation of the mean coil diameter (+- mm) of grade `grade`
/// for mean diameter `d_mean` and wire `d_wire`; `None` outside the table.
pub fn coil_diameter(grade: u8, d_mean: f64, d_wire: f64) -> Option<f64> {
    let w = d_mean / d_wire;
    // Columns (4, 8], (8, 14], (14, 20]; w = 4 belongs to the first.
    let column = [8.0, 14.0, 20.0].iter().position(|&upper| w <= upper)?;
    if w < 4.0 {
        return None;
    }
    let grade = usize::from(grade).checked_sub(1).filter(|g| *g < 3)?;
    COIL_DIAMETER
        .iter()
        .find(|(lo, hi, _)| d_mean >= *lo && d_mean <= *hi)
        .map(|(_, _, t)| t[grade][column])
        .filter(|t| t.is_finite())
}

/// The grade factor Q of EN 15800 (grade 1, 2 or 3).
pub fn grade_factor(grade: u8) -> Option<f64> {
    match grade {
        1 => Some(0.63),
        2 => Some(1.0),
        3 => Some(1.6),
        _ => None,
    }
}

/// EN 15800's `alpha_F` (N) of wire `d_wire` and mean diameter `d_mean` (mm).
pub fn alpha_f(d_wire: f64, d_mean: f64) -> f64 {
    let x = d_mean / d_wire / 10.0;
    65.92 * d_wire.powf(3.3) / d_mean.powf(1.6)
        * (-0.84 * x.powi(3) + 3.781 * x * x - 4.244 * x + 2.274)
}

/// EN 15800's `k_F` of `n` active coils.
pub fn k_f(n: f64) -> f64 {
    1.0 / (3.0 * n * n) + 8.0 / (5.0 * n) + 0.803
}

/// Every EN 15800 tolerance of one spring at one quality grade.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Tolerances {
    /// The quality grade (1, 2 or 3).
    pub grade: u8,
    /// +- deviation of the coil diameter (mm), `None` outside coil's table.
    pub coil_diameter_mm: Option<f64>,
    /// +- deviation of the free length (mm), when the forces are not toleranced.
    pub free_length_mm: f64,
    /// +- deviation of F1 at L1 (N).
    pub force_1_n: f64,
    /// +- deviation of F2 at L2 (N).
    pub force_2_n: f64,
    /// Perpendicularity e1 (mm).
    pub perpendicularity_mm: f64,
    /// Parallelism e2 (mm).
    pub parallelism_mm: f64,
}

/// EN 15800's tolerances of a spring (d, D, n, L0 in mm, rate R in N/mm, F1 and F2 in
/// N) at `grade`; `None` for a grade other than 1, 2, 3.
#[allow(clippy::too_many_arguments)]
pub fn tolerances(
    grade: u8,
    d_wire: f64,
    d_mean: f64,
    n: f64,
    free_length: f64,
    rate: f64,
    force_1: f64,
    force_2: f64,
) -> Option<Tolerances> {
    let q = grade_factor(grade)?;
    let base = alpha_f(d_wire, d_mean) * k_f(n);
    let (e1, e2) = match grade {
        1 => (0.03, 0.015),
        2 => (0.05, 0.03),
        _ => (0.08, 0.06),
    };
    Some(Tolerances {
        grade,
        coil_diameter_mm: coil_diameter(grade, d_mean, d_wire),
        free_length_mm: base * q / rate,
        force_1_n: (base + 1.5 * force_1 / 100.0) * q,
        force_2_n: (base + 1.5 * force_2 / 100.0) * q,
        perpendicularity_mm: e1 * free_length,
        parallelism_mm: e2 * (d_mean + d_wire),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The coil-diameter table at points of springONE's independent transcription of
    /// the standard's table (SpringLIB/src/EN15800.pas, AD_TABLE): D in (16, 25] mm,
    /// grade 2, w in (4, 8] 0.35 and (8, 14] 0.45; grade 1, w in (4, 8] 0.20; D in
    /// (25, 31.5], grade 2, w in (8, 14] 0.50; D in (2.5, 4], grade 3, w in (14, 20] 0.50.
    #[test]
    fn coil_diameter_table_matches_an_independent_transcription() {
        assert_eq!(coil_diameter(2, 24.0, 3.0), Some(0.35));
        assert_eq!(coil_diameter(2, 24.0, 2.5), Some(0.45));
        assert_eq!(coil_diameter(1, 20.0, 3.0), Some(0.20));
        assert_eq!(coil_diameter(2, 28.0, 3.0), Some(0.50));
        assert_eq!(coil_diameter(3, 3.0, 0.2), Some(0.50));
        assert_eq!(coil_diameter(3, 30.0, 2.0), None);
        assert_eq!(coil_diameter(2, 40.0, 3.0), None);
        assert_eq!(coil_diameter(4, 24.0, 3.0), None);
        assert_eq!(coil_diameter(2, 24.0, 1.0), None);
    }

    /// By hand for the 160ECT spring (d 3, D 24, n 14, R 3.9275 N/mm, L0 95.8 mm, F2
    /// 77 N): w/10 = 0.8, the polynomial 0.86856, alpha_F = 65.92 3^3.3 / 24^1.6 0.86856
    /// = 13.30 N, k_F = 0.91899; grade 2: A_L0 = 3.113 mm, A_F2 = 13.38 N; grades scale
    /// by Q.
    #[test]
    fn force_and_length_tolerances_by_hand() {
        let a = alpha_f(3.0, 24.0);
        let expected = 65.92 * 3f64.powf(3.3) / 24f64.powf(1.6) * 0.86856;
        assert!((a / expected - 1.0).abs() < 1e-9, "{a} {expected}");
        assert!((k_f(14.0) - 0.918_986).abs() < 1e-5, "{}", k_f(14.0));
        let t2 = tolerances(2, 3.0, 24.0, 14.0, 95.8, 3.9275, 51.4, 77.0).unwrap();
        let t1 = tolerances(1, 3.0, 24.0, 14.0, 95.8, 3.9275, 51.4, 77.0).unwrap();
        assert!((t2.free_length_mm - a * k_f(14.0) / 3.9275).abs() < 1e-12);
        assert!((t1.free_length_mm / t2.free_length_mm - 0.63).abs() < 1e-12);
        assert!((t2.force_2_n - (a * k_f(14.0) + 1.155)).abs() < 1e-12);
        assert!(
            (t2.free_length_mm - 3.113).abs() < 5e-4,
            "{}",
            t2.free_length_mm
        );
        assert!((t2.force_2_n - 13.38).abs() < 5e-3, "{}", t2.force_2_n);
        assert!((t2.perpendicularity_mm - 0.05 * 95.8).abs() < 1e-12);
        assert!((t2.parallelism_mm - 0.03 * 27.0).abs() < 1e-12);
        assert!(tolerances(4, 3.0, 24.0, 14.0, 95.8, 3.9275, 51.4, 77.0).is_none());
    }
}
