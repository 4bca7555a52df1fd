//! Section forces and wire stresses of the beam elements, and the spring summary of a
//! helical wire (index, solid length, the load at which adjacent coils touch).
//!
//! # Section forces
//! For each beam the local end forces are `f = k_e T u_e` (local stiffness, rotation to
//! local axes, the element's global DOFs), in the element's local axes (x from node 1 to
//! node 2, y and z as in [`crate::element::frame`]). The section resultant at an end is
//! the force the part on the node-2 side exerts on the part on the node-1 side:
//! `S(end 2) = f[6..12]`, `S(end 1) = -f[0..6]`, in the order axial force N (tension
//! positive), shear forces V_y, V_z (N), torque T, bending moments M_y, M_z (N mm).
//! Without loads along an element, N, V and T are the same at both ends and M is linear.
//!
//! # Wire stresses (solid circular wire of diameter d)
//! - torsion shear `tau_t = 16 |T| / (pi d^3)` at the surface;
//! - direct shear `tau_v = |V| / A`, `A = pi d^2 / 4` (the mean shear, the convention
//!   of the spring handbooks' direct-shear factor `K_s = 1 + 0.5 / C`);
//! - `shear_stress_mpa = tau_t + tau_v`: the two add at the coil's inner fibre;
//! - bending `sigma_b = 32 |M| / (pi d^3)` and axial `sigma_n = N / A` (small in a
//!   close-coiled spring; they grow with the pitch angle).
//!
//! Each element reports the larger of its two ends. A straight beam model has no
//! curvature of the wire, so the stress concentration at the coil's inner fibre (Wahl,
//! Bergsträsser) is not in `shear_stress_mpa`; the spring summary applies the handbook
//! factors on top and reports both (see below).
//!
//! # Spring summary (a single helical wire about global z)
//! When the beams with a solid circular section form one chain whose nodes all lie
//! within 2 % of one radius from the global z axis and turn through at least one coil,
//! the chain is read as the spring's wire:
//! - mean diameter D (twice the mean node radius), wire diameter d, spring index
//!   `C = D / d`, coils n (the wire's turning angle / 2 pi), pitch (axial rise / n);
//! - solid length `(n + 1) d`: the modelled helix closed coil on coil (its centreline
//!   spans n d, plus half a wire at each end; ground or closed end coils are not part of
//!   the model);
//! - the nominal torsion stress of the handbooks `tau = 8 F D / (pi d^3)`, F the axial
//!   force the wire carries (the sum of the z reactions), and the corrected stresses
//!   `K tau` with Wahl's factor `K_W = (4C - 1)/(4C - 4) + 0.615/C` and Bergsträsser's
//!   `K_B = (4C + 2)/(4C - 3)` (Wahl 1963, *Mechanical Springs*, ch. 3; EN 13906-1 eq. 5);
//! - the load at which adjacent coils touch: for every node at wire angle t, the wire
//!   point one coil further (t + 2 pi, interpolated along the chain) is `g` above it
//!   (axially) and closes by `dg` under the load case. The response is linear, so the
//!   two touch at the load factor `(g - d) / -dg`; the smallest over the wire, times F,
//!   is `coil_contact_load_n`. For a uniform spring it is `(pitch - d) n k`. When the
//!   load case's own load passes it, a warning says so: beyond it the coils are solid and
//!   the linear model does not apply.
//!
//! Units: mm, N, N mm, MPa.

use crate::element::{self, beam, frame};
use crate::model::{ElementId, Model, NodeId, Section, DOFS_PER_NODE};
use std::f64::consts::PI;

/// Section resultants at one element end, local axes: N, V_y, V_z (N), T, M_y, M_z (N mm).
pub type Resultants = [f64; 6];

/// Section forces and wire stresses of one beam element.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ElementForces {
    /// The element id.
    pub element: ElementId,
    /// Resultants at node 1 and node 2 of the element.
    pub ends: [Resultants; 2],
    /// The force resultant at node 2 in global axes (N): its z component is the axial
    /// force a spring's wire carries.
    pub force_global_n: [f64; 3],
    /// Stresses (MPa), `None` for a section that is not a solid circle.
    pub stress: Option<WireStress>,
}

/// Stresses of a solid circular wire, the larger of the element's two ends (MPa).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WireStress {
    /// Torsional shear stress 16 T / (pi d^3) (MPa).
    pub torsion_mpa: f64,
    /// Direct (transverse) shear stress (MPa).
    pub direct_shear_mpa: f64,
    /// `torsion_mpa + direct_shear_mpa`.
    pub shear_mpa: f64,
    /// Bending stress 32 M / (pi d^3) (MPa).
    pub bending_mpa: f64,
    /// Axial stress N / A (MPa).
    pub axial_mpa: f64,
}

impl ElementForces {
    /// The end with the larger |T| and the larger |V|, |M| (independently).
    fn max_abs(&self, f: impl Fn(&Resultants) -> f64) -> f64 {
        f(&self.ends[0]).abs().max(f(&self.ends[1]).abs())
    }

    /// Largest torque magnitude of the two ends (N mm).
    pub fn torque_n_mm(&self) -> f64 {
        self.max_abs(|r| r[3])
    }

    /// Largest shear force magnitude of the two ends (N).
    pub fn shear_force_n(&self) -> f64 {
        self.max_abs(|r| r[1].hypot(r[2]))
    }

    /// Largest bending moment magnitude of the two ends (N mm).
    pub fn bending_moment_n_mm(&self) -> f64 {
        self.max_abs(|r| r[4].hypot(r[5]))
    }
}

fn wire_diameter(model: &Model, element: ElementId) -> Option<f64> {
    match model.geometry_of(element)?.section {
        Section::SolidCircle { diameter } => Some(diameter),
        Section::General { .. } => None,
    }
}

/// Section forces (and stresses of solid circular wires) of every beam element under
/// the full displacement vector `u` (6 per node). Elements whose properties cannot be
/// formed (never the case after a successful analysis) are left out.
pub fn element_forces(model: &Model, u: &[f64]) -> Vec<ElementForces> {
    let mut out = Vec::with_capacity(model.elements.len());
    let mut k = frame::Matrix12::zeros();
    for e in &model.elements {
        let Ok((props, fr)) = element::properties(model, e) else {
            continue;
        };
        let (Some(a), Some(b)) = (model.node_index(e.nodes[0]), model.node_index(e.nodes[1]))
        else {
            continue;
        };
        k.fill(0.0);
        beam::local_stiffness(&props, &mut k);
        let mut u_e = nalgebra::SVector::<f64, 12>::zeros();
        for (slot, node) in [a, b].into_iter().enumerate() {
            for c in 0..DOFS_PER_NODE {
                u_e[slot * DOFS_PER_NODE + c] = u[node * DOFS_PER_NODE + c];
            }
        }
        let f = k * (frame::transformation(&fr.rotation) * u_e);
        let mut ends = [[0.0; 6]; 2];
        for c in 0..6 {
            ends[0][c] = -f[c];
            ends[1][c] = f[6 + c];
        }
        let local = nalgebra::Vector3::new(ends[1][0], ends[1][1], ends[1][2]);
        let global = fr.rotation.transpose() * local;
        let mut forces = ElementForces {
            element: e.id,
            ends,
            force_global_n: [global[0], global[1], global[2]],
            stress: None,
        };
        if let Some(d) = wire_diameter(model, e.id) {
            let area = PI * d * d / 4.0;
            let cube = PI * d * d * d;
            let torsion = 16.0 * forces.torque_n_mm() / cube;
            let direct = forces.shear_force_n() / area;
            forces.stress = Some(WireStress {
                torsion_mpa: torsion,
                direct_shear_mpa: direct,
                shear_mpa: torsion + direct,
                bending_mpa: 32.0 * forces.bending_moment_n_mm() / cube,
                axial_mpa: forces.max_abs(|r| r[0]) / area,
            });
        }
        out.push(forces);
    }
    out
}

/// Where the largest combined shear stress of the wire sits.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StressPeak {
    /// The element id.
    pub element: ElementId,
    /// The stresses there.
    pub stress: WireStress,
    /// Midpoint of the element (mm).
    pub xyz: [f64; 3],
}

/// The element with the largest `shear_mpa`, if any element has a wire stress.
pub fn peak(model: &Model, forces: &[ElementForces]) -> Option<StressPeak> {
    let best = forces
        .iter()
        .filter_map(|f| f.stress.map(|s| (f.element, s)))
        .max_by(|a, b| a.1.shear_mpa.total_cmp(&b.1.shear_mpa))?;
    let e = &model.elements[model.element_index(best.0)?];
    let p = |id: NodeId| model.node_index(id).map(|i| model.nodes[i].xyz);
    let (a, b) = (p(e.nodes[0])?, p(e.nodes[1])?);
    Some(StressPeak {
        element: best.0,
        stress: best.1,
        xyz: [0, 1, 2].map(|c| 0.5 * (a[c] + b[c])),
    })
}

/// Wahl's curvature and direct-shear factor `(4C - 1)/(4C - 4) + 0.615/C`.
pub fn wahl_factor(index: f64) -> f64 {
    (4.0 * index - 1.0) / (4.0 * index - 4.0) + 0.615 / index
}

/// Bergsträsser's factor `(4C + 2)/(4C - 3)`.
pub fn bergstraesser_factor(index: f64) -> f64 {
    (4.0 * index + 2.0) / (4.0 * index - 3.0)
}

/// Nominal torsion stress of a helical spring, `8 F D / (pi d^3)` (MPa).
pub fn nominal_stress_mpa(force_n: f64, mean_diameter_mm: f64, wire_diameter_mm: f64) -> f64 {
    8.0 * force_n * mean_diameter_mm / (PI * wire_diameter_mm.powi(3))
}

/// The helix a model's wire forms (see the module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct Helix {
    /// Node indices (into `model.nodes`) along the wire.
    pub chain: Vec<usize>,
    /// Unwrapped polar angle of each chain node about global z (rad), increasing.
    pub angle: Vec<f64>,
    /// Mean coil diameter D (mm), fitted to the chain.
    pub mean_diameter_mm: f64,
    /// Wire diameter d (mm).
    pub wire_diameter_mm: f64,
    /// Number of coils along the chain.
    pub coils: f64,
    /// Axial rise per coil (mm).
    pub pitch_mm: f64,
}

impl Helix {
    /// Reads the model's solid-circle beams as one helical wire about global z, or
    /// `None` when they are not one.
    pub fn of(model: &Model) -> Option<Helix> {
        let mut diameter = None;
        let mut adjacency: std::collections::HashMap<usize, Vec<usize>> = Default::default();
        for e in &model.elements {
            let d = wire_diameter(model, e.id)?;
            if diameter.is_some_and(|d0: f64| (d - d0).abs() > 1e-9 * d0) {
                return None;
            }
            diameter = Some(d);
            let (a, b) = (model.node_index(e.nodes[0])?, model.node_index(e.nodes[1])?);
            adjacency.entry(a).or_default().push(b);
            adjacency.entry(b).or_default().push(a);
        }
        let wire_diameter_mm = diameter?;
        if adjacency.values().any(|n| n.len() > 2) {
            return None;
        }
        let ends: Vec<usize> = adjacency
            .iter()
            .filter(|(_, n)| n.len() == 1)
            .map(|(&k, _)| k)
            .collect();
        let start = *ends
            .iter()
            .min_by(|&&a, &&b| model.nodes[a].xyz[2].total_cmp(&model.nodes[b].xyz[2]))?;
        // Degrees are at most 2 and `start` has one neighbour: the walk is a path.
        let mut chain = vec![start];
        let mut previous = None;
        while chain.len() <= adjacency.len() {
            let current = chain[chain.len() - 1];
            match adjacency[&current]
                .iter()
                .copied()
                .find(|&n| Some(n) != previous)
            {
                Some(next) => {
                    previous = Some(current);
                    chain.push(next);
                }
                None => break,
            }
        }
        if chain.len() != adjacency.len() || chain.len() < 3 {
            return None;
        }
        let xyz = |i: usize| model.nodes[i].xyz;
        let radii: Vec<f64> = chain.iter().map(|&i| xyz(i)[0].hypot(xyz(i)[1])).collect();
        let mean_radius = radii.iter().sum::<f64>() / radii.len() as f64;
        if mean_radius.is_nan()
            || mean_radius <= 0.0
            || radii
                .iter()
                .any(|r| (r - mean_radius).abs() > 0.02 * mean_radius)
        {
            return None;
        }
        let mut angle = Vec::with_capacity(chain.len());
        let mut total = 0.0;
        let mut last = xyz(chain[0])[1].atan2(xyz(chain[0])[0]);
        for &i in &chain {
            let a = xyz(i)[1].atan2(xyz(i)[0]);
            let mut step = a - last;
            while step > PI {
                step -= 2.0 * PI;
            }
            while step < -PI {
                step += 2.0 * PI;
            }
            total += step;
            last = a;
            angle.push(total);
        }
        // Right- or left-handed: measure the angle along the wire's sense of turning.
        let sign = total.signum();
        angle.iter_mut().for_each(|a| *a *= sign);
        let coils = angle.last()? / (2.0 * PI);
        if coils < 1.0 || angle.windows(2).any(|w| w[1] <= w[0]) {
            return None;
        }
        let rise = xyz(*chain.last()?)[2] - xyz(chain[0])[2];
        Some(Helix {
            chain,
            angle,
            mean_diameter_mm: 2.0 * mean_radius,
            wire_diameter_mm,
            coils,
            pitch_mm: rise / coils,
        })
    }

    /// Spring index C = D / d.
    pub fn index(&self) -> f64 {
        self.mean_diameter_mm / self.wire_diameter_mm
    }

    /// Solid length `(n + 1) d` (mm).
    pub fn solid_length_mm(&self) -> f64 {
        (self.coils + 1.0) * self.wire_diameter_mm
    }

    /// Smallest load factor at which a wire point and the point one coil further touch
    /// axially under the displacement `u` (linear response), with the lower point's node
    /// index; `None` when no gap closes. A factor of 0 means they already touch.
    pub fn contact_factor(&self, model: &Model, u: &[f64]) -> Option<(f64, usize)> {
        let z = |i: usize| model.nodes[i].xyz[2];
        let uz = |i: usize| u[i * DOFS_PER_NODE + 2];
        let d = self.wire_diameter_mm;
        let mut best: Option<(f64, usize)> = None;
        let mut seg = 0;
        for (k, &i) in self.chain.iter().enumerate() {
            let target = self.angle[k] + 2.0 * PI;
            while seg + 1 < self.chain.len() && self.angle[seg + 1] < target {
                seg += 1;
            }
            if seg + 1 >= self.chain.len() {
                break;
            }
            let (a, b) = (self.chain[seg], self.chain[seg + 1]);
            let s = (target - self.angle[seg]) / (self.angle[seg + 1] - self.angle[seg]);
            let gap = z(a) + s * (z(b) - z(a)) - z(i);
            let closing = uz(a) + s * (uz(b) - uz(a)) - uz(i);
            let factor = if gap <= d {
                0.0
            } else if closing < 0.0 {
                (gap - d) / -closing
            } else {
                continue;
            };
            if best.is_none_or(|(f, _)| factor < f) {
                best = Some((factor, i));
            }
        }
        best
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn handbook_factors_match_tabulated_values() {
        // Wahl (1963) and EN 13906-1 tables: C = 8 -> K_W = 1.184, K_B = 1.172;
        // C = 4 -> K_W = 1.404, K_B = 1.385.
        assert!((wahl_factor(8.0) - 1.184).abs() < 5e-4);
        assert!((bergstraesser_factor(8.0) - 1.1724).abs() < 5e-4);
        assert!((wahl_factor(4.0) - 1.404).abs() < 5e-4);
        assert!((bergstraesser_factor(4.0) - 1.3846).abs() < 5e-4);
        assert!((nominal_stress_mpa(10.0, 24.0, 3.0) - 22.635).abs() < 1e-3);
    }
}
