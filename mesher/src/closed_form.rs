//! Closed-form references for a helical compression spring under an axial load.
//!
//! # Castigliano stiffness of an open-coiled helix
//! The wire centreline is a helix of radius R = D/2, pitch h and pitch angle alpha with
//! tan(alpha) = h / (pi D), over n active coils, so the wire length is
//! L = n pi D / cos(alpha). An axial force F acting on the spring axis produces, in every
//! wire section (Timoshenko & Young; Wahl, *Mechanical Springs*, ch. 2):
//!
//! - torque about the wire axis        T = F R cos(alpha)
//! - bending moment (binormal axis)    M = F R sin(alpha)
//! - transverse (direct) shear force   V = F cos(alpha)
//! - axial wire force                  N = F sin(alpha)
//!
//! Castigliano's theorem on U = int (T^2/2GJ + M^2/2EI + V^2/2 kappa G A + N^2/2EA) ds
//! gives the axial compliance
//!
//! delta / F = L [ R^2 cos^2(alpha)/(G J) + R^2 sin^2(alpha)/(E I)
//!               + cos^2(alpha)/(kappa G A) + sin^2(alpha)/(E A) ]
//!
//! with J = pi d^4/32, I = pi d^4/64, A = pi d^2/4 and the Cowper shear coefficient
//! kappa = 6(1+nu)/(7+6nu) of a solid circle. Dropping the shear term gives the
//! Euler-Bernoulli (Marc type 52) reference.
//!
//! # Guided end
//! The formula above is for ends free to turn about the spring axis. When the loaded end
//! is guided (its rotation about the axis held, as with coil's `--top guided`), the
//! end moment M_z that keeps the rotation zero follows from dU/dM_z = 0; it removes
//! L R^2 sin^2 cos^2 (1/GJ - 1/EI)^2 / (sin^2/GJ + cos^2/EI) from the compliance
//! (about 0.05 % for the paper's spring). [`HelixStiffness::guided`] includes it.
//!
//! # Other references
//! - The paper's Eq. (1), k = G d^4 / (8 n D^3): torsion only, alpha = 0.
//! - Fixed-fixed surge (first axial wave) frequency of a bare spring:
//!   f = (1/2) sqrt(k / m_spring), m_spring = rho A L.
//! - Mass-on-spring with the spring's own mass by Rayleigh's method:
//!   T = 2 pi sqrt((m + m_spring/3) / k).
//!
//! Units: mm, N, MPa, N/mm, as the deck; masses in kg where the name says so.

use std::f64::consts::PI;

/// Geometry of the active part of a helical spring (mm).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HelixGeometry {
    /// Number of active coils n.
    pub coils: f64,
    /// Mean coil diameter D (mm).
    pub mean_diameter_mm: f64,
    /// Wire diameter d (mm).
    pub wire_diameter_mm: f64,
    /// Pitch h (mm per coil).
    pub pitch_mm: f64,
}

impl HelixGeometry {
    /// Pitch angle alpha (rad), tan(alpha) = h / (pi D).
    pub fn pitch_angle(&self) -> f64 {
        (self.pitch_mm / (PI * self.mean_diameter_mm)).atan()
    }

    /// Wire centreline length L = n pi D / cos(alpha) (mm).
    pub fn wire_length_mm(&self) -> f64 {
        self.coils * PI * self.mean_diameter_mm / self.pitch_angle().cos()
    }

    /// Wire cross-section area (mm^2).
    pub fn wire_area_mm2(&self) -> f64 {
        PI * self.wire_diameter_mm.powi(2) / 4.0
    }

    /// Spring (wire) mass in kg for a density in kg/m^3.
    pub fn spring_mass_kg(&self, density_kg_m3: f64) -> f64 {
        density_kg_m3 * self.wire_area_mm2() * self.wire_length_mm() * 1e-9
    }
}

/// The terms of the Castigliano compliance, per unit force (mm/N).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HelixStiffness {
    /// Wire torsion term.
    pub torsion: f64,
    /// Wire bending term (from the pitch angle).
    pub bending: f64,
    /// Direct shear term (Timoshenko only).
    pub shear: f64,
    /// Axial wire extension term.
    pub axial: f64,
    /// Compliance removed by guiding the loaded end against turning (<= 0).
    pub guided_correction: f64,
}

impl HelixStiffness {
    /// Compliance terms for a solid round wire of the given material.
    pub fn new(geometry: &HelixGeometry, youngs_modulus_mpa: f64, poisson: f64) -> Self {
        let e = youngs_modulus_mpa;
        let g = e / (2.0 * (1.0 + poisson));
        let d = geometry.wire_diameter_mm;
        let r = 0.5 * geometry.mean_diameter_mm;
        let area = PI * d * d / 4.0;
        let i = PI * d.powi(4) / 64.0;
        let j = 2.0 * i;
        let kappa = 6.0 * (1.0 + poisson) / (7.0 + 6.0 * poisson);
        let alpha = geometry.pitch_angle();
        let (s2, c2) = (alpha.sin().powi(2), alpha.cos().powi(2));
        let l = geometry.wire_length_mm();
        let coupling = r * r * s2 * c2 * (1.0 / (g * j) - 1.0 / (e * i)).powi(2)
            / (s2 / (g * j) + c2 / (e * i));
        HelixStiffness {
            torsion: l * r * r * c2 / (g * j),
            bending: l * r * r * s2 / (e * i),
            shear: l * c2 / (kappa * g * area),
            axial: l * s2 / (e * area),
            guided_correction: -l * coupling,
        }
    }

    /// Stiffness (N/mm) with the end free to turn, with or without direct shear.
    pub fn free(&self, with_shear: bool) -> f64 {
        1.0 / self.compliance(with_shear, false)
    }

    /// Stiffness (N/mm) with the loaded end guided against turning about the axis.
    pub fn guided(&self, with_shear: bool) -> f64 {
        1.0 / self.compliance(with_shear, true)
    }

    fn compliance(&self, with_shear: bool, guided: bool) -> f64 {
        let shear = if with_shear { self.shear } else { 0.0 };
        let correction = if guided { self.guided_correction } else { 0.0 };
        self.torsion + self.bending + shear + self.axial + correction
    }
}

/// The paper's Eq. (1): k = G d^4 / (8 n D^3) in N/mm.
pub fn simple_stiffness(geometry: &HelixGeometry, shear_modulus_mpa: f64) -> f64 {
    shear_modulus_mpa * geometry.wire_diameter_mm.powi(4)
        / (8.0 * geometry.coils * geometry.mean_diameter_mm.powi(3))
}

/// First surge frequency (Hz) of a spring held at both ends: f = (1/2) sqrt(k / m_s),
/// k in N/mm, m_s in kg.
pub fn surge_frequency_hz(stiffness_n_mm: f64, spring_mass_kg: f64) -> f64 {
    0.5 * (stiffness_n_mm * 1000.0 / spring_mass_kg).sqrt()
}

/// Period (s) of a mass on a spring with a third of the spring's mass added (Rayleigh).
pub fn rayleigh_period_s(stiffness_n_mm: f64, mass_kg: f64, spring_mass_kg: f64) -> f64 {
    2.0 * PI * ((mass_kg + spring_mass_kg / 3.0) / (stiffness_n_mm * 1000.0)).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn paper() -> HelixGeometry {
        HelixGeometry {
            coils: 14.0,
            mean_diameter_mm: 24.0,
            wire_diameter_mm: 3.0,
            pitch_mm: 6.2,
        }
    }

    #[test]
    fn paper_spring_castigliano_is_about_3_80() {
        let k = HelixStiffness::new(&paper(), 190708.0, 0.3);
        // Hand evaluation of the four terms (see the module doc) gives 3.797 N/mm.
        assert!((k.free(true) - 3.797).abs() < 0.002, "{}", k.free(true));
        // Shear softens, so Euler-Bernoulli is stiffer, by about shear/total = 0.87 %.
        let ratio = k.free(false) / k.free(true) - 1.0;
        assert!((ratio - k.shear / (1.0 / k.free(true) - k.shear)).abs() < 1e-12);
        assert!(ratio > 0.0085 && ratio < 0.0090, "{ratio}");
        // The guided end is stiffer, but only by about 0.05 %.
        let g = k.guided(true) / k.free(true) - 1.0;
        assert!(g > 0.0 && g < 1e-3, "{g}");
    }

    #[test]
    fn zero_pitch_torsion_only_matches_eq1() {
        let flat = HelixGeometry {
            pitch_mm: 0.0,
            ..paper()
        };
        let k = HelixStiffness::new(&flat, 190708.0, 0.3);
        let g = 190708.0 / 2.6;
        let torsion_only = 1.0 / k.torsion;
        assert!((torsion_only / simple_stiffness(&flat, g) - 1.0).abs() < 1e-12);
        assert_eq!(k.bending, 0.0);
        assert_eq!(k.guided_correction, 0.0);
    }

    #[test]
    fn spring_mass_of_paper_spring() {
        // rho A L = 7850 kg/m^3 * 7.0686 mm^2 * 1059.15 mm = 58.8 g.
        let m = paper().spring_mass_kg(7850.0);
        assert!((m - 0.05877).abs() < 2e-4, "{m}");
    }
}
