//! Conversions between the model's units (mm, N, t, s) and SI.

/// mm per m.
pub const MM_PER_M: f64 = 1000.0;
/// kg per tonne.
pub const KG_PER_T: f64 = 1000.0;

/// kg/m^3 -> t/mm^3.
pub fn density_from_si(kg_m3: f64) -> f64 {
    kg_m3 / 1e12
}
/// t/mm^3 -> kg/m^3.
pub fn density_to_si(t_mm3: f64) -> f64 {
    t_mm3 * 1e12
}
/// kg -> t.
pub fn mass_from_si(kg: f64) -> f64 {
    kg / KG_PER_T
}
/// t -> kg.
pub fn mass_to_si(t: f64) -> f64 {
    t * KG_PER_T
}
/// kg m^2 -> t mm^2.
pub fn inertia_from_si(kg_m2: f64) -> f64 {
    kg_m2 * 1e3
}
/// t mm^2 -> kg m^2.
pub fn inertia_to_si(t_mm2: f64) -> f64 {
    t_mm2 / 1e3
}
/// m (or m/s, m/s^2) -> mm (mm/s, mm/s^2).
pub fn length_from_si(m: f64) -> f64 {
    m * MM_PER_M
}
/// mm (mm/s, mm/s^2) -> m (m/s, m/s^2).
pub fn length_to_si(mm: f64) -> f64 {
    mm / MM_PER_M
}
/// Cubic stiffness N/m^3 -> N/mm^3: `k3 u^3` with `u` in m is `k3 (u_mm/1e3)^3`,
/// so 1 N/m^3 = 1e-9 N/mm^3.
pub fn cubic_stiffness_from_si(n_m3: f64) -> f64 {
    n_m3 * 1e-9
}
/// Cubic stiffness N/mm^3 -> N/m^3 (1 N/mm^3 = 1e9 N/m^3).
pub fn cubic_stiffness_to_si(n_mm3: f64) -> f64 {
    n_mm3 * 1e9
}
/// Velocity-squared damping N s^2/m^2 -> N s^2/mm^2: `c2 v^2` with `v` in m/s is
/// `c2 (v_mm/1e3)^2`, so 1 N s^2/m^2 = 1e-6 N s^2/mm^2.
pub fn quadratic_damping_from_si(n_s2_m2: f64) -> f64 {
    n_s2_m2 * 1e-6
}
/// Velocity-squared damping N s^2/mm^2 -> N s^2/m^2 (1 N s^2/mm^2 = 1e6 N s^2/m^2).
pub fn quadratic_damping_to_si(n_s2_mm2: f64) -> f64 {
    n_s2_mm2 * 1e6
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trips_are_identities() {
        for x in [1.0, 7850.0, 5.3, 1e-4] {
            assert!((density_to_si(density_from_si(x)) - x).abs() <= 1e-12 * x);
            assert!((mass_to_si(mass_from_si(x)) - x).abs() <= 1e-12 * x);
            assert!((inertia_to_si(inertia_from_si(x)) - x).abs() <= 1e-12 * x);
            assert!((length_to_si(length_from_si(x)) - x).abs() <= 1e-12 * x);
            let k3 = cubic_stiffness_to_si(cubic_stiffness_from_si(x));
            assert!((k3 - x).abs() <= 1e-12 * x);
            let c2 = quadratic_damping_to_si(quadratic_damping_from_si(x));
            assert!((c2 - x).abs() <= 1e-12 * x);
        }
        // 7850 kg/m^3 is 7.85e-9 t/mm^3, 1 kg m^2 is 1e3 t mm^2 (1e-3 t * 1e6 mm^2).
        assert!((density_from_si(7850.0) - 7.85e-9).abs() < 1e-20);
        assert!((inertia_from_si(1.0) - 1e3).abs() < 1e-12);
        // 1 mm of a 1e9 N/m^3 cubic spring: 1e9 * (1e-3)^3 = 1 N = k3_mm * 1^3.
        assert!((cubic_stiffness_from_si(1e9) - 1.0).abs() < 1e-15);
        // 1 m/s (1000 mm/s) through 1 N s^2/m^2: 1 N = c2_mm * 1000^2.
        assert!((quadratic_damping_from_si(1.0) * 1e6 - 1.0).abs() < 1e-15);
    }
}
