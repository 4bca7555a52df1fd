//! Two-node 3D beam elements: Marc type 52 (Euler-Bernoulli) and type 98 (Timoshenko).
//!
//! Pure functions: element properties in, local 12x12 stiffness or mass out, written
//! into caller-owned [`Matrix12`] storage. No state, no caches.
//!
//! # DOF order and signs (local axes, see [`super::frame`])
//! Per node `u, v, w, theta_x, theta_y, theta_z`; node 1 then node 2 (indices 0..6,
//! 6..12). Translations in mm along local x, y, z; rotations in rad, right-handed about
//! local x, y, z. Hence in the x-y plane `theta_z = +dv/dx` (Euler-Bernoulli) and in the
//! x-z plane `theta_y = -dw/dx`: the x-z plane matrices are the x-y ones with the
//! translation-rotation coupling terms negated. Units: E, G in MPa, A in mm^2, I, J in
//! mm^4, rho in t/mm^3, so stiffness in N/mm (N mm/rad) and mass in t (t mm^2).
//!
//! # Stiffness
//! - axial `EA/L`, torsion `GJ/L` (uniform St-Venant torsion, J the torsion constant);
//! - bending in each plane by the exact-interpolation beam of Przemieniecki (1968,
//!   *Theory of Matrix Structural Analysis*, sec. 5.6) in the form of Friedman &
//!   Kosmatka (1993, *Computers & Structures* 47(3) 473-481):
//!   `k = EI / ((1 + Phi) L^3) [12, 6L, -12, 6L; 6L, (4+Phi)L^2, -6L, (2-Phi)L^2; ...]`
//!   with `Phi = 12 E I / (kappa G A L^2)` for type 98 and `Phi = 0` for type 52. The
//!   x-y plane (v, theta_z) uses `I_zz`, the x-z plane (w, theta_y) uses `I_yy`. The
//!   interpolation solves the homogeneous Timoshenko equations, so end-loaded
//!   cantilevers are reproduced exactly (including the shear term `PL/(kappa G A)`)
//!   and there is no shear locking.
//!
//! # Consistent mass
//! Obtained with the same interpolation functions (Friedman & Kosmatka 1993, eqs. 21-22;
//! Przemieniecki sec. 11.4 for `Phi = 0`): translational inertia `rho A` plus rotary
//! inertia `rho I` of the section in both bending planes, axial `rho A L/6 [2 1; 1 2]`
//! and torsional `rho I_p L/6 [2 1; 1 2]` with the polar moment `I_p = I_yy + I_zz`
//! (not the torsion constant J, which only equals it for a circle). With `Phi = 0` the
//! bending block is the classical `rho A L/420 [156, 22L, 54, -13L; ...]` plus
//! `rho I/(30 L) [36, 3L, -36, 3L; ...]`. Type 52 includes the rotary inertia too.
//!
//! # Lumped mass
//! The HRZ diagonal (Hinton, Rock & Zienkiewicz 1976, *Earthq. Eng. Struct. Dyn.* 4,
//! 245-249): the diagonal of the consistent matrix, with the translational terms of each
//! direction scaled so that they sum to the element mass `rho A L` and the rotational
//! terms of each bending plane scaled by the factor of that plane's translation; the
//! axial and torsional terms become `rho A L / 2` and `rho I_p L / 2`. A rigid
//! translation keeps its exact kinetic energy. Used only when the model asks for it
//! (`Model::lumped_mass`).

use super::frame::Matrix12;
use crate::model::{ElementType, SectionProperties};

/// Everything the element formulas need, already resolved from the model.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BeamProperties {
    /// Element formulation (type 52 or 98).
    pub kind: ElementType,
    /// Length L (mm).
    pub length: f64,
    /// Young's modulus E (MPa).
    pub youngs_modulus: f64,
    /// Shear modulus G (MPa).
    pub shear_modulus: f64,
    /// Density rho (t/mm^3).
    pub density: f64,
    /// Section properties (mm^2, mm^4).
    pub section: SectionProperties,
}

impl BeamProperties {
    /// Shear-flexibility ratios `(Phi_v, Phi_w)` of the x-y plane (bending about z,
    /// `I_zz`) and the x-z plane (bending about y, `I_yy`); zero for type 52.
    #[allow(non_snake_case)]
    pub fn shear_ratios(&self) -> (f64, f64) {
        match self.kind {
            ElementType::Beam52 => (0.0, 0.0),
            ElementType::Beam98 => {
                let s = &self.section;
                let L = self.length;
                let kGA = s.shear_coefficient * self.shear_modulus * s.area;
                (
                    12.0 * self.youngs_modulus * s.izz / (kGA * L * L),
                    12.0 * self.youngs_modulus * s.iyy / (kGA * L * L),
                )
            }
        }
    }
}

/// Local DOF indices of one bending plane, `(v_1, theta_1, v_2, theta_2)`, and the sign
/// that turns its rotation into `+dv/dx`.
const PLANE_XY: ([usize; 4], f64) = ([1, 5, 7, 11], 1.0);
const PLANE_XZ: ([usize; 4], f64) = ([2, 4, 8, 10], -1.0);

/// Adds a 4x4 plane-bending block (written for `theta = +dv/dx`) into `a`.
fn scatter_plane(a: &mut Matrix12, block: &[[f64; 4]; 4], plane: ([usize; 4], f64)) {
    let (idx, sign) = plane;
    // Rotation DOFs (positions 1 and 3) carry the sign.
    let s = [1.0, sign, 1.0, sign];
    for i in 0..4 {
        for j in 0..4 {
            a[(idx[i], idx[j])] += s[i] * s[j] * block[i][j];
        }
    }
}

/// Adds a two-DOF bar block `c [1 -1; -1 1]` or `c [2 1; 1 2]` style 2x2 into `a`.
fn scatter_pair(a: &mut Matrix12, i: usize, j: usize, diag: f64, off: f64) {
    a[(i, i)] += diag;
    a[(j, j)] += diag;
    a[(i, j)] += off;
    a[(j, i)] += off;
}

/// Bending stiffness of one plane, `(v_1, theta_1, v_2, theta_2)`, theta = +dv/dx.
#[allow(non_snake_case)]
fn bending_stiffness(EI: f64, L: f64, phi: f64) -> [[f64; 4]; 4] {
    let c = EI / ((1.0 + phi) * L * L * L);
    let (a, b, d, e) = (
        12.0 * c,
        6.0 * L * c,
        (4.0 + phi) * L * L * c,
        (2.0 - phi) * L * L * c,
    );
    [[a, b, -a, b], [b, d, -b, e], [-a, -b, a, -b], [b, e, -b, d]]
}

/// Consistent bending mass of one plane (translational plus rotary inertia),
/// `(v_1, theta_1, v_2, theta_2)`, theta = +dv/dx. Friedman & Kosmatka (1993).
#[allow(non_snake_case)]
fn bending_mass(rhoA: f64, rhoI: f64, L: f64, phi: f64) -> [[f64; 4]; 4] {
    let p = phi;
    let p2 = phi * phi;
    let ct = rhoA * L / ((1.0 + p) * (1.0 + p));
    let m11 = ct * (13.0 / 35.0 + 7.0 / 10.0 * p + 1.0 / 3.0 * p2);
    let m12 = ct * L * (11.0 / 210.0 + 11.0 / 120.0 * p + 1.0 / 24.0 * p2);
    let m13 = ct * (9.0 / 70.0 + 3.0 / 10.0 * p + 1.0 / 6.0 * p2);
    let m14 = -ct * L * (13.0 / 420.0 + 3.0 / 40.0 * p + 1.0 / 24.0 * p2);
    let m22 = ct * L * L * (1.0 / 105.0 + 1.0 / 60.0 * p + 1.0 / 120.0 * p2);
    let m24 = -ct * L * L * (1.0 / 140.0 + 1.0 / 60.0 * p + 1.0 / 120.0 * p2);
    let translational = [
        [m11, m12, m13, m14],
        [m12, m22, -m14, m24],
        [m13, -m14, m11, -m12],
        [m14, m24, -m12, m22],
    ];
    let cr = rhoI / ((1.0 + p) * (1.0 + p) * L);
    let r11 = cr * 6.0 / 5.0;
    let r12 = cr * L * (1.0 / 10.0 - 1.0 / 2.0 * p);
    let r22 = cr * L * L * (2.0 / 15.0 + 1.0 / 6.0 * p + 1.0 / 3.0 * p2);
    let r24 = cr * L * L * (-1.0 / 30.0 - 1.0 / 6.0 * p + 1.0 / 6.0 * p2);
    let rotary = [
        [r11, r12, -r11, r12],
        [r12, r22, -r12, r24],
        [-r11, -r12, r11, -r12],
        [r12, r24, -r12, r22],
    ];
    let mut m = [[0.0; 4]; 4];
    for i in 0..4 {
        for j in 0..4 {
            m[i][j] = translational[i][j] + rotary[i][j];
        }
    }
    m
}

/// Local stiffness matrix (N/mm, N mm/rad), overwriting `k`.
#[allow(non_snake_case)]
pub fn local_stiffness(p: &BeamProperties, k: &mut Matrix12) {
    k.fill(0.0);
    let s = &p.section;
    let L = p.length;
    let E = p.youngs_modulus;
    let EA_L = E * s.area / L;
    let GJ_L = p.shear_modulus * s.torsion / L;
    scatter_pair(k, 0, 6, EA_L, -EA_L);
    scatter_pair(k, 3, 9, GJ_L, -GJ_L);
    let (phi_v, phi_w) = p.shear_ratios();
    scatter_plane(k, &bending_stiffness(E * s.izz, L, phi_v), PLANE_XY);
    scatter_plane(k, &bending_stiffness(E * s.iyy, L, phi_w), PLANE_XZ);
}

/// Adds the geometric stiffness of the axial force `force` (N, positive in tension) of
/// an element of length `length` (mm) to the local matrix `k`: in both bending planes
/// `N/(30 L) [36, 3L, -36, 3L; 3L, 4L^2, -3L, -L^2; ...]` (`theta = dw/dx`; Przemieniecki
/// 1968, sec. 15.3, the consistent matrix of the cubic Hermite interpolation). With it a
/// wire of negligible EI is the taut string `rho A w_tt = N w_xx`.
pub fn add_local_geometric_stiffness(length: f64, force: f64, k: &mut Matrix12) {
    let l = length;
    let c = force / (30.0 * l);
    let (a, b, d, e) = (36.0 * c, 3.0 * l * c, 4.0 * l * l * c, -l * l * c);
    let block = [[a, b, -a, b], [b, d, -b, e], [-a, -b, a, -b], [b, e, -b, d]];
    scatter_plane(k, &block, PLANE_XY);
    scatter_plane(k, &block, PLANE_XZ);
}

/// Local consistent mass matrix (t, t mm, t mm^2), overwriting `m`.
#[allow(non_snake_case)]
pub fn local_consistent_mass(p: &BeamProperties, m: &mut Matrix12) {
    m.fill(0.0);
    let s = &p.section;
    let L = p.length;
    let rho = p.density;
    let rhoA = rho * s.area;
    let polar = s.iyy + s.izz;
    scatter_pair(m, 0, 6, rhoA * L / 3.0, rhoA * L / 6.0);
    scatter_pair(m, 3, 9, rho * polar * L / 3.0, rho * polar * L / 6.0);
    let (phi_v, phi_w) = p.shear_ratios();
    scatter_plane(m, &bending_mass(rhoA, rho * s.izz, L, phi_v), PLANE_XY);
    scatter_plane(m, &bending_mass(rhoA, rho * s.iyy, L, phi_w), PLANE_XZ);
}

/// HRZ lumped mass from a local consistent mass matrix (see the module docs), overwriting
/// `lumped` with a diagonal matrix.
pub fn hrz_lump(consistent: &Matrix12, lumped: &mut Matrix12) {
    lumped.fill(0.0);
    // Axial and torsional terms: the diagonal sums to the total of the 2x2 block.
    for (i, j) in [(0, 6), (3, 9)] {
        let total = consistent[(i, i)] + consistent[(j, j)] + 2.0 * consistent[(i, j)];
        lumped[(i, i)] = 0.5 * total;
        lumped[(j, j)] = 0.5 * total;
    }
    // Bending planes: the translational diagonal is scaled to the rigid-translation
    // mass of the plane, the rotational diagonal by the same factor.
    for (idx, _) in [PLANE_XY, PLANE_XZ] {
        let (a, b) = (idx[0], idx[2]);
        let total = consistent[(a, a)] + consistent[(b, b)] + 2.0 * consistent[(a, b)];
        let diagonal = consistent[(a, a)] + consistent[(b, b)];
        let scale = if diagonal > 0.0 {
            total / diagonal
        } else {
            0.0
        };
        for &i in &idx {
            lumped[(i, i)] = scale * consistent[(i, i)];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::element::frame::{local_frame, to_global};
    use nalgebra::{SMatrix, SVector, Vector3};

    type Vector12 = SVector<f64, 12>;

    /// A stocky general section (unequal I, Phi of order 0.1-1) so that every term of the
    /// Timoshenko matrices matters.
    fn props(kind: ElementType) -> BeamProperties {
        BeamProperties {
            kind,
            length: 7.0,
            youngs_modulus: 2.1e5,
            shear_modulus: 8.0e4,
            density: 7.85e-9,
            section: SectionProperties {
                area: 12.0,
                iyy: 40.0,
                izz: 9.0,
                torsion: 25.0,
                shear_coefficient: 0.85,
            },
        }
    }

    /// The geometric stiffness does work `N/2 int w'^2 dx` on a deflection: exact for a
    /// cubic, and a rigid rotation of the string costs `N L theta^2 / 2` per plane while
    /// a rigid translation costs nothing.
    #[test]
    fn geometric_stiffness_is_the_strings_stretch_energy() {
        let (l, n) = (7.0, 2.0e4);
        let mut k = Matrix12::zeros();
        add_local_geometric_stiffness(l, n, &mut k);
        assert!((k - k.transpose()).amax() == 0.0);
        // Rigid translation in z: no energy.
        let mut u = Vector12::zeros();
        u[2] = 1.0;
        u[8] = 1.0;
        assert!((k * u).amax() < 1e-9 * n);
        // Rigid rotation about y (w = -theta x, theta_y = theta): N L theta^2 / 2 per
        // plane, and nothing axial.
        let theta = 1e-3;
        let mut u = Vector12::zeros();
        u[4] = theta;
        u[10] = theta;
        u[8] = -theta * l;
        let energy = 0.5 * u.dot(&(k * u));
        assert!((energy - 0.5 * n * l * theta * theta).abs() < 1e-12 * n * l);
        // w = x^2 (w' = 2x): N/2 int_0^L 4 x^2 dx = 2 N L^3 / 3, in the x-y plane too.
        let mut u = Vector12::zeros();
        u[7] = l * l;
        u[11] = 2.0 * l;
        let energy = 0.5 * u.dot(&(k * u));
        assert!((energy / (2.0 * n * l.powi(3) / 3.0) - 1.0).abs() < 1e-12);
        assert_eq!(k[(0, 0)], 0.0);
        assert_eq!(k[(3, 3)], 0.0);
    }

    fn both() -> [BeamProperties; 2] {
        [props(ElementType::Beam52), props(ElementType::Beam98)]
    }

    /// Global matrices of the element lying along a skew direction with a skew
    /// orientation vector, plus the node coordinates.
    fn skew_global(p: &BeamProperties) -> (Matrix12, Matrix12, Vector3<f64>, Vector3<f64>) {
        let x1 = Vector3::new(1.3, -0.4, 2.2);
        let dir = Vector3::new(0.3, -0.7, 0.5).normalize();
        let x2 = x1 + dir * p.length;
        let frame = local_frame(x1.into(), x2.into(), [0.2, 0.9, -0.4]).unwrap();
        assert!((frame.length - p.length).abs() < 1e-12);
        let mut k = Matrix12::zeros();
        let mut m = Matrix12::zeros();
        local_stiffness(p, &mut k);
        local_consistent_mass(p, &mut m);
        to_global(&frame.rotation, &mut k);
        to_global(&frame.rotation, &mut m);
        (k, m, x1, x2)
    }

    /// The six rigid-body motions (3 translations, 3 rotations about the origin).
    fn rigid_modes(x1: Vector3<f64>, x2: Vector3<f64>) -> [Vector12; 6] {
        let mut modes = [Vector12::zeros(); 6];
        for (a, mode) in modes.iter_mut().enumerate() {
            let mut e = Vector3::zeros();
            e[a % 3] = 1.0;
            for (node, x) in [(0, x1), (1, x2)] {
                let (u, theta) = if a < 3 {
                    (e, Vector3::zeros())
                } else {
                    (e.cross(&x), e)
                };
                for c in 0..3 {
                    mode[6 * node + c] = u[c];
                    mode[6 * node + 3 + c] = theta[c];
                }
            }
        }
        modes
    }

    #[test]
    fn matrices_are_symmetric() {
        for p in both() {
            let (k, m, _, _) = skew_global(&p);
            // Relative to the largest entry: symmetric to rounding of the T^T A T product.
            assert!((k - k.transpose()).amax() <= 1e-14 * k.amax());
            assert!((m - m.transpose()).amax() <= 1e-14 * m.amax());
        }
    }

    #[test]
    fn six_rigid_body_modes_are_in_the_null_space_of_k() {
        for p in both() {
            let (k, _, x1, x2) = skew_global(&p);
            for (i, r) in rigid_modes(x1, x2).iter().enumerate() {
                // |K r| against |K| |r|: zero up to rounding (the bound allows for the
                // cancellation between terms of size |K| |r|).
                let residual = (k * r).amax();
                assert!(
                    residual <= 1e-12 * k.amax() * r.amax(),
                    "{:?} mode {i}: |K r| = {residual:e}",
                    p.kind
                );
            }
        }
    }

    #[test]
    fn rank_is_six_and_k_is_positive_semidefinite() {
        for p in both() {
            let (k, _, _, _) = skew_global(&p);
            let eig = k.symmetric_eigen().eigenvalues;
            let max = eig.amax();
            let mut sorted: Vec<f64> = eig.iter().copied().collect();
            sorted.sort_by(f64::total_cmp);
            for (i, l) in sorted.iter().enumerate() {
                if i < 6 {
                    assert!(l.abs() <= 1e-12 * max, "rigid eigenvalue {l:e}");
                } else {
                    assert!(*l > 1e-8 * max, "deformation eigenvalue {l:e} must be > 0");
                }
            }
        }
    }

    #[test]
    fn rigid_translation_kinetic_energy_is_the_element_mass() {
        for p in both() {
            let (_, m, x1, x2) = skew_global(&p);
            let mut lumped_local = Matrix12::zeros();
            let mut consistent_local = Matrix12::zeros();
            local_consistent_mass(&p, &mut consistent_local);
            hrz_lump(&consistent_local, &mut lumped_local);
            let frame = local_frame(x1.into(), x2.into(), [0.2, 0.9, -0.4]).unwrap();
            let mut lumped = lumped_local;
            to_global(&frame.rotation, &mut lumped);
            let mass = p.density * p.section.area * p.length;
            for r in &rigid_modes(x1, x2)[..3] {
                for mm in [&m, &lumped] {
                    let e = (r.transpose() * mm * r)[0];
                    assert!(
                        (e - mass).abs() <= 1e-13 * mass,
                        "{:?}: {e:e} vs {mass:e}",
                        p.kind
                    );
                }
            }
        }
    }

    #[test]
    fn mass_matrices_are_positive_definite() {
        for p in both() {
            let (_, m, _, _) = skew_global(&p);
            let min = m.symmetric_eigen().eigenvalues.min();
            assert!(min > 0.0, "{:?}: smallest mass eigenvalue {min:e}", p.kind);
            let mut consistent = Matrix12::zeros();
            let mut lumped = Matrix12::zeros();
            local_consistent_mass(&p, &mut consistent);
            hrz_lump(&consistent, &mut lumped);
            assert!((0..12).all(|i| lumped[(i, i)] > 0.0));
            assert_eq!(
                (lumped - Matrix12::from_diagonal(&lumped.diagonal())).amax(),
                0.0
            );
        }
    }

    /// Exact Timoshenko interpolation (Friedman & Kosmatka 1993, eq. 14) of one bending
    /// plane at xi = x/L: rows (v, theta) against (v_1, theta_1, v_2, theta_2).
    #[allow(non_snake_case)]
    fn shape(xi: f64, L: f64, p: f64) -> ([f64; 4], [f64; 4], [f64; 4], [f64; 4]) {
        let c = 1.0 / (1.0 + p);
        let (x2, x3) = (xi * xi, xi * xi * xi);
        let nv = [
            c * (2.0 * x3 - 3.0 * x2 - p * xi + 1.0 + p),
            c * L * (x3 - (2.0 + p / 2.0) * x2 + (1.0 + p / 2.0) * xi),
            -c * (2.0 * x3 - 3.0 * x2 - p * xi),
            c * L * (x3 - (1.0 - p / 2.0) * x2 - p / 2.0 * xi),
        ];
        let nt = [
            6.0 * c / L * (x2 - xi),
            c * (3.0 * x2 - (4.0 + p) * xi + 1.0 + p),
            -6.0 * c / L * (x2 - xi),
            c * (3.0 * x2 - (2.0 - p) * xi),
        ];
        // d/dx of both rows.
        let dnv = [
            c / L * (6.0 * x2 - 6.0 * xi - p),
            c * (3.0 * x2 - 2.0 * (2.0 + p / 2.0) * xi + 1.0 + p / 2.0),
            -c / L * (6.0 * x2 - 6.0 * xi - p),
            c * (3.0 * x2 - 2.0 * (1.0 - p / 2.0) * xi - p / 2.0),
        ];
        let dnt = [
            6.0 * c / (L * L) * (2.0 * xi - 1.0),
            c / L * (6.0 * xi - (4.0 + p)),
            -6.0 * c / (L * L) * (2.0 * xi - 1.0),
            c / L * (6.0 * xi - (2.0 - p)),
        ];
        (nv, nt, dnv, dnt)
    }

    /// The closed-form bending blocks equal the energy integrals of the exact
    /// interpolation (5-point Gauss is exact for these degree <= 6 polynomials):
    /// k = int EI N_t'^T N_t' + kGA (N_v' - N_t)^T (N_v' - N_t) dx and
    /// m = int rhoA N_v^T N_v + rhoI N_t^T N_t dx.
    #[test]
    #[allow(non_snake_case)]
    fn bending_blocks_match_the_interpolation_integrals() {
        let gauss = [
            (0.0, 128.0 / 225.0),
            (-0.538_469_310_105_683_1, 0.478_628_670_499_366_5),
            (0.538_469_310_105_683_1, 0.478_628_670_499_366_5),
            (-0.906_179_845_938_664, 0.236_926_885_056_189_1),
            (0.906_179_845_938_664, 0.236_926_885_056_189_1),
        ];
        let (L, EI, rhoA, rhoI) = (3.0, 5.0e4, 2.0, 0.7);
        for phi in [0.0, 0.37, 2.5] {
            let kGA = if phi > 0.0 {
                12.0 * EI / (phi * L * L)
            } else {
                f64::INFINITY
            };
            let mut k = SMatrix::<f64, 4, 4>::zeros();
            let mut m = SMatrix::<f64, 4, 4>::zeros();
            for (g, w) in gauss {
                let xi = 0.5 * (g + 1.0);
                let dx = 0.5 * w * L;
                let (nv, nt, dnv, dnt) = shape(xi, L, phi);
                for i in 0..4 {
                    for j in 0..4 {
                        let shear = if kGA.is_finite() {
                            kGA * (dnv[i] - nt[i]) * (dnv[j] - nt[j])
                        } else {
                            0.0
                        };
                        k[(i, j)] += dx * (EI * dnt[i] * dnt[j] + shear);
                        m[(i, j)] += dx * (rhoA * nv[i] * nv[j] + rhoI * nt[i] * nt[j]);
                    }
                }
            }
            let kc = bending_stiffness(EI, L, phi);
            let mc = bending_mass(rhoA, rhoI, L, phi);
            for i in 0..4 {
                for j in 0..4 {
                    assert!(
                        (k[(i, j)] - kc[i][j]).abs() <= 1e-10 * k.amax(),
                        "k {phi} {i}{j}"
                    );
                    assert!(
                        (m[(i, j)] - mc[i][j]).abs() <= 1e-12 * m.amax(),
                        "m {phi} {i}{j}"
                    );
                }
            }
        }
    }

    #[test]
    fn euler_bernoulli_blocks_are_the_classical_ones() {
        let p = props(ElementType::Beam52);
        let mut k = Matrix12::zeros();
        local_stiffness(&p, &mut k);
        let l = p.length;
        let ei = p.youngs_modulus * p.section.izz;
        assert!((k[(1, 1)] - 12.0 * ei / l.powi(3)).abs() < 1e-9 * k[(1, 1)]);
        assert!((k[(5, 11)] - 2.0 * ei / l).abs() < 1e-9 * k[(5, 11)]);
        // x-z plane: theta_y = -dw/dx flips the coupling sign.
        let eiy = p.youngs_modulus * p.section.iyy;
        assert!((k[(2, 4)] + 6.0 * eiy / (l * l)).abs() < 1e-9 * k[(2, 4)].abs());
        assert!((k[(1, 5)] - 6.0 * ei / (l * l)).abs() < 1e-9 * k[(1, 5)]);
    }
}
