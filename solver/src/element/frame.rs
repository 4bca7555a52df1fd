//! The local frame of a two-node beam and the local-to-global rotation.
//!
//! # Convention
//! - Local x runs from node 1 to node 2: `e_x = (x_2 - x_1) / L`.
//! - Local y is the part of the orientation vector `o` normal to the axis:
//!   `e_y = (o - (o . e_x) e_x) / |o - (o . e_x) e_x|`.
//! - Local z completes a right-handed triad: `e_z = e_x x e_y`.
//!
//! This is the convention of Marc's beam `GEOMETRY` orientation vector and of most
//! frame codes (e.g. Przemieniecki, *Theory of Matrix Structural Analysis*, 1968,
//! ch. 5, with the "third point" replaced by a direction).
//!
//! The rotation matrix `R` holds the local axes as its rows (global components), so a
//! vector transforms as `v_local = R v_global` and a 12x12 element matrix as
//! `K_global = T^T K_local T` with `T = diag(R, R, R, R)` acting on
//! `(u_1, theta_1, u_2, theta_2)` of the two nodes.
//!
//! # Why this is the delicate part for a helix
//! On a helix every element has its own axis, so the frame is recomputed per element.
//! The orientation vector of a spring's `GEOMETRY` is usually the spring axis; the helix
//! tangent makes the pitch angle (about 4.7 degrees for the paper's spring) with the
//! plane normal to that axis, so it is never close to parallel and `e_y` is the axial
//! direction with the tangent's component removed. For a solid circular wire the
//! section is axisymmetric and the stiffness does not depend on which normal is `e_y`,
//! but a general section does, so the construction is exact and documented.
//!
//! A nearly parallel orientation vector is an error, never a silent fallback axis.

use nalgebra::{Matrix3, SMatrix, Vector3};

/// A 12x12 element matrix (two nodes, six DOFs each).
pub type Matrix12 = SMatrix<f64, 12, 12>;

/// Smallest admissible sine of the angle between the element axis and the orientation
/// vector. Below it the local y axis is fixed by the orientation vector's components at
/// the 1e-6 level, i.e. by the last printed digits of a deck: the frame is then not
/// what the user specified, so it is rejected.
pub const MIN_ORIENTATION_SINE: f64 = 1e-6;

/// Why a local frame cannot be built.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum FrameError {
    /// Both nodes coincide (length at the rounding level of the coordinates), or a
    /// coordinate is not finite.
    #[error("zero or non-finite length ({length:e} mm): the two nodes coincide or a coordinate is not finite")]
    ZeroLength {
        /// The length (mm).
        length: f64,
    },
    /// The orientation vector is zero or not finite.
    #[error("orientation vector is zero or not finite")]
    BadOrientation,
    /// The orientation vector is (nearly) parallel to the element axis.
    #[error(
        "orientation vector is parallel to the element axis (sine of the angle {sine:e} < {min:e}); \
         choose a GEOMETRY orientation vector normal to the beam"
    )]
    ParallelOrientation {
        /// Sine of the angle between them.
        sine: f64,
        /// The smallest sine accepted.
        min: f64,
    },
}

/// Length and rotation of one element.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frame {
    /// Element length (mm).
    pub length: f64,
    /// Rows are the local axes e_x, e_y, e_z in global components: `v_local = R v_global`.
    pub rotation: Matrix3<f64>,
}

/// Builds the local frame from the node coordinates (mm) and the orientation vector.
pub fn local_frame(x1: [f64; 3], x2: [f64; 3], orientation: [f64; 3]) -> Result<Frame, FrameError> {
    let p1 = Vector3::from(x1);
    let p2 = Vector3::from(x2);
    let axis = p2 - p1;
    let length = axis.norm();
    // Coordinates carry about 16 significant digits; a length within a few hundred ulps
    // of the coordinate magnitude is rounding noise, not an element.
    let scale = p1.amax().max(p2.amax()).max(1.0);
    if length.is_nan() || length <= 1e3 * f64::EPSILON * scale {
        return Err(FrameError::ZeroLength { length });
    }
    let e_x = axis / length;
    let o = Vector3::from(orientation);
    let o_norm = o.norm();
    if !o_norm.is_finite() || o_norm <= 0.0 {
        return Err(FrameError::BadOrientation);
    }
    let o = o / o_norm;
    let normal = o - e_x * o.dot(&e_x);
    let sine = normal.norm();
    if sine.is_nan() || sine < MIN_ORIENTATION_SINE {
        return Err(FrameError::ParallelOrientation {
            sine,
            min: MIN_ORIENTATION_SINE,
        });
    }
    let e_y = normal / sine;
    let e_z = e_x.cross(&e_y);
    let rotation = Matrix3::from_rows(&[e_x.transpose(), e_y.transpose(), e_z.transpose()]);
    Ok(Frame { length, rotation })
}

/// The 12x12 transformation `T = diag(R, R, R, R)` (local = T global).
pub fn transformation(rotation: &Matrix3<f64>) -> Matrix12 {
    let mut t = Matrix12::zeros();
    for block in 0..4 {
        t.fixed_view_mut::<3, 3>(3 * block, 3 * block)
            .copy_from(rotation);
    }
    t
}

/// Rotates a local element matrix to global axes in place: `A <- T^T A T`.
pub fn to_global(rotation: &Matrix3<f64>, a: &mut Matrix12) {
    let t = transformation(rotation);
    *a = t.transpose() * *a * t;
}

#[cfg(test)]
mod tests {
    use super::*;

    fn assert_orthonormal(r: &Matrix3<f64>) {
        let err = (r * r.transpose() - Matrix3::identity()).amax();
        assert!(err < 1e-14, "R R^T - I = {err:e}");
        // Right-handed: det = +1.
        assert!((r.determinant() - 1.0).abs() < 1e-14);
    }

    #[test]
    fn frame_of_an_axis_aligned_beam() {
        let f = local_frame([0.0; 3], [2.0, 0.0, 0.0], [0.0, 1.0, 0.0]).unwrap();
        assert_eq!(f.length, 2.0);
        assert_orthonormal(&f.rotation);
        assert_eq!(f.rotation, Matrix3::identity());
    }

    #[test]
    fn frame_is_orthonormal_on_a_helix() {
        // Chords of the paper's helix (R = 12 mm, pitch 6.2 mm, 48 elements per coil)
        // with the spring axis as orientation vector: e_y must be the axis direction with
        // the tangent part removed, hence normal to e_x and with a positive z component.
        let (r, h, n) = (12.0, 6.2, 48.0);
        let point = |t: f64| [r * t.cos(), r * t.sin(), h * t / std::f64::consts::TAU];
        for i in 0..96 {
            let t0 = std::f64::consts::TAU * i as f64 / n;
            let t1 = std::f64::consts::TAU * (i + 1) as f64 / n;
            let f = local_frame(point(t0), point(t1), [0.0, 0.0, 1.0]).unwrap();
            assert_orthonormal(&f.rotation);
            let e_x = f.rotation.row(0).transpose();
            let e_y = f.rotation.row(1).transpose();
            let chord = Vector3::from(point(t1)) - Vector3::from(point(t0));
            assert!((e_x - chord / chord.norm()).amax() < 1e-15);
            assert!(e_y.z > 0.99, "e_y is nearly the spring axis");
            assert!(e_x.dot(&e_y).abs() < 1e-15);
        }
    }

    #[test]
    fn parallel_orientation_is_an_error() {
        let err = local_frame([0.0; 3], [0.0, 0.0, 5.0], [0.0, 1e-9, 1.0]).unwrap_err();
        assert!(matches!(err, FrameError::ParallelOrientation { .. }));
        // Just above the threshold it is accepted.
        assert!(local_frame([0.0; 3], [0.0, 0.0, 5.0], [0.0, 1e-5, 1.0]).is_ok());
    }

    #[test]
    fn zero_length_and_zero_orientation_are_errors() {
        let p = [100.0, 3.0, -7.0];
        assert!(matches!(
            local_frame(p, p, [0.0, 0.0, 1.0]),
            Err(FrameError::ZeroLength { .. })
        ));
        assert!(matches!(
            local_frame([0.0; 3], [1.0, 0.0, 0.0], [0.0; 3]),
            Err(FrameError::BadOrientation)
        ));
        assert!(matches!(
            local_frame([0.0; 3], [1.0, 0.0, 0.0], [f64::NAN, 0.0, 1.0]),
            Err(FrameError::BadOrientation)
        ));
    }
}
