//! coil-mesher owns the helix mesher: a spring's spec to a validated model or deck (`coil-mesh`)
//! and the handbook closed forms. It may import coil-io and coil-solver (the model) only; the
//! tuner and everything above use it.
//!
//! coil-mesher: helical-spring geometry -> a coil input deck.
//!
//! # Geometry
//! The wire centreline is the helix x = R cos t, y = R sin t, z = h t / (2 pi) for
//! t in [0, 2 pi n], R = D/2, over the n active coils; the spring axis is global z and
//! the base is at z = 0. The helix is cut into `elements_per_coil * n` straight two-node
//! beams (rounded to a whole number) with every node exactly on the helix, so a coarse
//! mesh is a polygon inscribed in the helix: shorter wire, hence a stiffer spring (the
//! bias that the tuner's mesh study measures).
//!
//! # Numbering (stable, documented in docs/mesher.md)
//! - node 1: the weight's reference node on the axis at the top, (0, 0, n h);
//! - nodes 2 ..= N+2: the helix from the base (node 2, t = 0) to the top wire end;
//! - elements 1 ..= N: helix segments, element i joins nodes i+1 and i+2;
//! - sets: `spring` (all elements), `base` (node 2), `weight` (node 1), `wire_top`.
//!
//! So the weight's axial acceleration column of a transient history is always
//! `node1_uz_accel_m_s2`.
//!
//! # Boundary conditions
//! The base wire end is clamped (DOFs 1-6). The top wire end is tied rigidly (RBE2, all
//! six DOFs) to node 1, which carries the weight (point mass and rotary inertia) and the
//! loads. `guided`: only node 1's axial translation is free; `free-rotation`: its rotation
//! about the axis is free too; `held`: node 1 is fixed (a bare spring between two plates,
//! for surge modes).
//!
//! # Nonlinear extras (optional, zero by default)
//! `friction_n`, `quadratic_damping_n_s2_m2` and `cubic_stiffness_n_m3` put the deck
//! cards `FRICTION`, `QUADRATIC DAMPER` and `CUBIC SPRING` on the weight's axial DOF
//! (node 1, DOF 3), converted to solver units (N; 1 N s^2/m^2 = 1e-6 N s^2/mm^2;
//! 1 N/m^3 = 1e-9 N/mm^3). They need the axial DOF free (not `held`) and a Newmark
//! transient.
//!
//! # Units
//! The spec's names carry SI or engineering units (`_mm`, `_mpa`, `_kg`, `_m_s`); the deck
//! is in mm, N, t, s (see `coil_solver::model`). Conversions happen here, once.

#![warn(missing_docs)]

pub mod closed_form;

use coil_solver::model::{
    units, Analysis, Damping, Element, ElementSet, ElementType, FixedDisp, Geometry,
    InitialVelocity, Integrator, LoadCase, Material, Model, ModelParts, Node, NodeSet,
    OutputRequest, PointElement, PointLoad, PointMass, Quantity, RigidTie, Section,
    TransientMethod,
};
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// Node id of the weight's reference node.
pub const WEIGHT_NODE: u32 = 1;
/// Node id of the clamped base end of the wire.
pub const BASE_NODE: u32 = 2;
/// Column of the weight's axial acceleration in a transient `history.csv`.
pub const WEIGHT_ACCEL_COLUMN: &str = "node1_uz_accel_m_s2";

/// Largest number of beam elements a spec may ask for.
pub const MAX_ELEMENTS: usize = 1_000_000;

/// How the top reference node (the weight) is held.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
pub enum Top {
    /// Only the axial translation is free.
    #[default]
    Guided,
    /// Axial translation and rotation about the axis are free.
    FreeRotation,
    /// Fully fixed: the spring is held at both ends.
    Held,
}

/// Which analysis the deck's history runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum AnalysisKind {
    /// A static load case: the axial force on the weight.
    Static,
    /// A modal load case: the lowest `modes` modes.
    Modal,
    /// A free-decay transient from the initial velocity.
    Transient,
}

/// How the transient load case is solved (deck card `DYNAMIC CHANGE`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
pub enum TransientScheme {
    /// Newmark average acceleration: no numerical damping.
    #[default]
    Newmark,
    /// HHT-alpha with [`SpringSpec::hht_alpha`].
    Hht,
    /// Generalised-alpha with [`SpringSpec::rho_inf`].
    Galpha,
    /// Modal superposition over [`SpringSpec::transient_modes`] modes.
    Modal,
}

/// The initial velocity field of the transient (deck card `INITIAL VEL`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
pub enum VelocityField {
    /// The weight's velocity extended along the spring by the quasi-static shape
    /// (`INITIAL VEL, QUASI STATIC`): no velocity jump, no stiff-mode ripple.
    #[default]
    QuasiStatic,
    /// The weight (and the wire end tied to it) alone: a velocity jump against a spring
    /// at rest, as a peer code given only a nodal velocity does it.
    Nodal,
}

/// Everything `coil-mesh` needs, from flags or a JSON spec file. Field names carry units.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SpringSpec {
    /// Title of the deck (`TITLE`).
    pub title: String,
    /// Number of coils (active turns), at least 1.
    pub coils: f64,
    /// Mean coil diameter D (mm).
    pub mean_diameter_mm: f64,
    /// Wire diameter d (mm).
    pub wire_diameter_mm: f64,
    /// Pitch: axial rise per coil (mm).
    pub pitch_mm: f64,
    /// Beam elements per coil (at least 3).
    pub elements_per_coil: u32,
    /// Marc element type: 98 (Timoshenko) or 52 (Euler-Bernoulli).
    pub element: u32,
    /// Lumped instead of consistent mass (`LUMP`).
    pub lumped_mass: bool,
    /// Young's modulus E (MPa).
    pub youngs_modulus_mpa: f64,
    /// Poisson's ratio nu (-).
    pub poisson: f64,
    /// Wire density (kg/m^3).
    pub density_kg_m3: f64,
    /// The weight's mass (kg); 0 = no weight.
    pub mass_kg: f64,
    /// The weight's rotary inertia about the spring axis (kg m^2).
    pub rotary_inertia_kg_m2: f64,
    /// How the top reference node (the weight) is supported.
    pub top: Top,
    /// Load cases, in order.
    pub analyses: Vec<AnalysisKind>,
    /// Static: compressive axial force on the weight (N).
    pub force_n: f64,
    /// Modal: number of modes.
    pub modes: u32,
    /// Transient: time step (s).
    pub dt_s: f64,
    /// Transient: total time (s).
    pub duration_s: f64,
    /// Transient: initial axial velocity of the weight (m/s, + away from the base).
    pub initial_velocity_m_s: f64,
    /// Rayleigh alpha on the spring's elements (1/s).
    pub alpha: f64,
    /// Rayleigh beta on the spring's elements (s).
    pub beta: f64,
    /// Transient: record every k-th step.
    pub output_every: u32,
    /// Transient: also record the displacement of every node every k-th step (0 = not),
    /// so that coil-solve writes the moving model as a ParaView series (`.pvd`).
    pub snapshot_every: u32,
    /// Transient: how the initial velocity is spread over the spring.
    pub initial_velocity_field: VelocityField,
    /// Transient: the time integration scheme or modal superposition.
    pub transient_method: TransientScheme,
    /// Transient, `hht`: alpha in [-1/3, 0].
    pub hht_alpha: f64,
    /// Transient, `galpha`: spectral radius at infinity in [0, 1].
    pub rho_inf: f64,
    /// Transient, `modal`: number of modes.
    pub transient_modes: u32,
    /// Rayleigh alpha on the weight's point mass too (a DAMPING entry naming node 1).
    /// Off by default: the paper's damping is the wire's material damping.
    pub alpha_on_weight: bool,
    /// Dry (Coulomb) friction force on the weight's axial motion (N): a `FRICTION`
    /// card on node 1, DOF 3. 0 = none.
    pub friction_n: f64,
    /// Velocity-squared drag `c2 v|v|` on the weight's axial motion (N s^2/m^2): a
    /// `QUADRATIC DAMPER` card on node 1, DOF 3. 0 = none.
    pub quadratic_damping_n_s2_m2: f64,
    /// Cubic restoring force `k3 u^3` on the weight's axial displacement from the free
    /// length (N/m^3): a `CUBIC SPRING` card on node 1, DOF 3. 0 = none.
    pub cubic_stiffness_n_m3: f64,
}

impl Default for SpringSpec {
    /// The paper's spring (n = 14, D = 24, d = 3, h = 6.2) with handbook steel.
    fn default() -> Self {
        SpringSpec {
            title: "helical spring".into(),
            coils: 14.0,
            mean_diameter_mm: 24.0,
            wire_diameter_mm: 3.0,
            pitch_mm: 6.2,
            elements_per_coil: 24,
            element: 98,
            lumped_mass: false,
            youngs_modulus_mpa: 206000.0,
            poisson: 0.3,
            density_kg_m3: 7850.0,
            mass_kg: 0.0,
            rotary_inertia_kg_m2: 0.0,
            top: Top::Guided,
            analyses: vec![AnalysisKind::Static],
            force_n: 10.0,
            modes: 10,
            dt_s: 1e-3,
            duration_s: 20.0,
            initial_velocity_m_s: 0.1,
            alpha: 0.0,
            beta: 0.0,
            output_every: 1,
            snapshot_every: 0,
            initial_velocity_field: VelocityField::QuasiStatic,
            transient_method: TransientScheme::Newmark,
            hht_alpha: -0.05,
            rho_inf: 0.8,
            transient_modes: 20,
            alpha_on_weight: false,
            friction_n: 0.0,
            quadratic_damping_n_s2_m2: 0.0,
            cubic_stiffness_n_m3: 0.0,
        }
    }
}

/// The fewest coils a spec may have.
pub const MIN_COILS: f64 = 1.0;

/// The admissible spring index D/d (mean coil diameter over wire diameter). EN 13906-1
/// (cylindrical helical compression springs) recommends 4 <= D/d <= 20 for manufacture,
/// but soft laboratory and instrument springs are coiled well above 20 (30-60), and the
/// beam model only gets more accurate as the wire straightens. So coil accepts [3, 100]:
/// below 3 the curved-wire stress correction (Wahl factor 1.58 at 3) says straight beams
/// misrepresent the wire; above 100 the numbers are almost surely a unit slip (D in mm, d
/// in m) rather than a spring. Outside, the mesher refuses (docs/files.md).
pub const SPRING_INDEX: (f64, f64) = (3.0, 100.0);

/// A spec that cannot be meshed, naming the field and what was expected.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{field} = {value}: expected {expected}")]
pub struct SpecError {
    /// The spec field at fault.
    pub field: &'static str,
    /// Its value.
    pub value: String,
    /// What was expected instead.
    pub expected: &'static str,
}

/// `Ok` when `ok` holds and `value` is finite, else the [`SpecError`] naming `field`, the
/// value and what was `expected` (the one check of every spec field).
pub fn check(
    ok: bool,
    field: &'static str,
    value: f64,
    expected: &'static str,
) -> Result<(), SpecError> {
    if ok && value.is_finite() {
        Ok(())
    } else {
        Err(SpecError {
            field,
            value: value.to_string(),
            expected,
        })
    }
}

/// The longest text a spec puts into a deck line (a title), characters.
pub const MAX_TITLE_CHARS: usize = 200;

/// Text that reaches a deck (a title): one printable line of at most
/// [`MAX_TITLE_CHARS`] characters. A line break would start a new card (`END OPTION`
/// injected through a title), a control character garbles the file and the terminal.
pub fn check_deck_text(field: &'static str, text: &str) -> Result<(), SpecError> {
    let printable = !text.chars().any(|c| {
        c.is_control()
            || ('\u{202a}'..='\u{202e}').contains(&c)
            || ('\u{2066}'..='\u{2069}').contains(&c)
    });
    if printable && text.chars().count() <= MAX_TITLE_CHARS {
        Ok(())
    } else {
        Err(SpecError {
            field,
            value: format!("`{}`", coil_io::excerpt(text)),
            expected:
                "one printable line of at most 200 characters (no line break or control character)",
        })
    }
}

impl SpringSpec {
    /// The helix geometry part of the spec.
    pub fn geometry(&self) -> closed_form::HelixGeometry {
        closed_form::HelixGeometry {
            coils: self.coils,
            mean_diameter_mm: self.mean_diameter_mm,
            wire_diameter_mm: self.wire_diameter_mm,
            pitch_mm: self.pitch_mm,
        }
    }

    /// Number of beam elements along the wire.
    pub fn element_count(&self) -> usize {
        ((self.coils * f64::from(self.elements_per_coil)).round() as usize).max(1)
    }

    /// Checks every field; the deck reader would catch most of these later, but the
    /// message is clearer in the spec's own terms.
    pub fn validate(&self) -> Result<(), SpecError> {
        check_deck_text("title", &self.title)?;
        self.validate_geometry()?;
        self.validate_material_and_loads()?;
        self.validate_analyses()
    }

    /// The helix and its mesh: coils, diameters, spring index, pitch, element count
    /// and type.
    fn validate_geometry(&self) -> Result<(), SpecError> {
        check(
            self.coils >= MIN_COILS,
            "coils",
            self.coils,
            "at least 1 coil (EN 13906-1 asks for at least 2 active coils)",
        )?;
        check(
            self.mean_diameter_mm > 0.0,
            "mean_diameter_mm",
            self.mean_diameter_mm,
            "a positive diameter",
        )?;
        check(
            self.wire_diameter_mm > 0.0 && self.wire_diameter_mm < self.mean_diameter_mm,
            "wire_diameter_mm",
            self.wire_diameter_mm,
            "a positive wire diameter smaller than the mean diameter",
        )?;
        let index = self.mean_diameter_mm / self.wire_diameter_mm;
        check(
            (SPRING_INDEX.0..=SPRING_INDEX.1).contains(&index),
            "spring index D/d",
            index,
            "D/d between 3 and 100 (EN 13906-1 recommends 4 to 20 for manufacture; below 3 the \
             wire is too curved for beam theory, above 100 the figures are likely a unit slip)",
        )?;
        // Coils through each other (pitch at or below the wire diameter) is not a spring;
        // a pitch angle near 90 degrees would make the axis-parallel orientation vector
        // parallel to the wire.
        check(
            self.pitch_mm > self.wire_diameter_mm
                && self.pitch_mm < 2.0 * PI * self.mean_diameter_mm,
            "pitch_mm",
            self.pitch_mm,
            "a pitch above the wire diameter (coils that do not pass through each other) and \
             below 2 pi D (pitch angle under 63 degrees)",
        )?;
        if self.elements_per_coil < 3 {
            return Err(SpecError {
                field: "elements_per_coil",
                value: self.elements_per_coil.to_string(),
                expected: "at least 3 elements per coil",
            });
        }
        // Bound the mesh before anything is allocated: node ids are u32 and a deck of a
        // million beams is already far past any mesh-convergence need.
        let total = self.coils * f64::from(self.elements_per_coil);
        if total.round() > MAX_ELEMENTS as f64 {
            return Err(SpecError {
                field: "elements_per_coil",
                value: format!(
                    "{} (x {} coils = {total:.0} elements)",
                    self.elements_per_coil, self.coils
                ),
                expected: "at most 1000000 elements in all",
            });
        }
        if ElementType::from_number(self.element).is_none() {
            return Err(SpecError {
                field: "element",
                value: self.element.to_string(),
                expected: "98 (Timoshenko) or 52 (Euler-Bernoulli)",
            });
        }
        Ok(())
    }

    /// Material, weight, load and point-law values.
    fn validate_material_and_loads(&self) -> Result<(), SpecError> {
        check(
            self.youngs_modulus_mpa > 0.0,
            "youngs_modulus_mpa",
            self.youngs_modulus_mpa,
            "a positive modulus",
        )?;
        check(
            self.poisson > -1.0 && self.poisson < 0.5,
            "poisson",
            self.poisson,
            "a Poisson ratio in (-1, 0.5)",
        )?;
        check(
            self.density_kg_m3 >= 0.0,
            "density_kg_m3",
            self.density_kg_m3,
            "a density >= 0",
        )?;
        check(self.mass_kg >= 0.0, "mass_kg", self.mass_kg, "a mass >= 0")?;
        check(
            self.rotary_inertia_kg_m2 >= 0.0,
            "rotary_inertia_kg_m2",
            self.rotary_inertia_kg_m2,
            "an inertia >= 0",
        )?;
        check(
            self.force_n.is_finite(),
            "force_n",
            self.force_n,
            "a finite force",
        )?;
        for (value, field) in [
            (self.friction_n, "friction_n"),
            (self.quadratic_damping_n_s2_m2, "quadratic_damping_n_s2_m2"),
            (self.cubic_stiffness_n_m3, "cubic_stiffness_n_m3"),
        ] {
            check(value >= 0.0, field, value, "a value >= 0")?;
            if value > 0.0 && self.top == Top::Held {
                return Err(SpecError {
                    field,
                    value: value.to_string(),
                    expected: "0 with top = held (the weight's axial DOF is fixed)",
                });
            }
            if value > 0.0
                && self.analyses.contains(&AnalysisKind::Transient)
                && self.transient_method != TransientScheme::Newmark
            {
                return Err(SpecError {
                    field,
                    value: value.to_string(),
                    expected: "0 unless transient_method = newmark (nonlinear point \
                               elements need direct average acceleration)",
                });
            }
        }
        check(self.alpha >= 0.0, "alpha", self.alpha, "alpha >= 0")?;
        check(self.beta >= 0.0, "beta", self.beta, "beta >= 0")?;
        check(
            self.initial_velocity_m_s.is_finite(),
            "initial_velocity_m_s",
            self.initial_velocity_m_s,
            "a finite velocity",
        )?;
        Ok(())
    }

    /// The analyses: modes, time step, duration, scheme parameters.
    fn validate_analyses(&self) -> Result<(), SpecError> {
        if self.analyses.contains(&AnalysisKind::Modal) && self.modes == 0 {
            return Err(SpecError {
                field: "modes",
                value: "0".into(),
                expected: "at least one mode",
            });
        }
        if self.analyses.contains(&AnalysisKind::Transient) {
            check(self.dt_s > 0.0, "dt_s", self.dt_s, "a positive time step")?;
            check(
                self.duration_s >= self.dt_s,
                "duration_s",
                self.duration_s,
                "a duration of at least one time step",
            )?;
            if self.output_every == 0 {
                return Err(SpecError {
                    field: "output_every",
                    value: "0".into(),
                    expected: "a positive step interval",
                });
            }
            match self.transient_method {
                TransientScheme::Newmark => {}
                TransientScheme::Hht => check(
                    (-1.0 / 3.0..=0.0).contains(&self.hht_alpha),
                    "hht_alpha",
                    self.hht_alpha,
                    "alpha in [-1/3, 0]",
                )?,
                TransientScheme::Galpha => check(
                    (0.0..=1.0).contains(&self.rho_inf),
                    "rho_inf",
                    self.rho_inf,
                    "rho_inf in [0, 1]",
                )?,
                TransientScheme::Modal => {
                    if self.transient_modes == 0 {
                        return Err(SpecError {
                            field: "transient_modes",
                            value: "0".into(),
                            expected: "at least one mode",
                        });
                    }
                }
            }
        }
        if self.alpha_on_weight && self.mass_kg <= 0.0 {
            return Err(SpecError {
                field: "alpha_on_weight",
                value: "true".into(),
                expected: "a weight (mass_kg > 0) to damp",
            });
        }
        Ok(())
    }

    /// The deck's transient method for [`SpringSpec::transient_method`].
    pub fn transient_method(&self) -> TransientMethod {
        match self.transient_method {
            TransientScheme::Newmark => TransientMethod::Direct(Integrator::AverageAcceleration),
            TransientScheme::Hht => TransientMethod::Direct(Integrator::Hht {
                alpha: self.hht_alpha,
            }),
            TransientScheme::Galpha => TransientMethod::Direct(Integrator::GeneralizedAlpha {
                rho_inf: self.rho_inf,
            }),
            TransientScheme::Modal => TransientMethod::Modal {
                modes: self.transient_modes,
            },
        }
    }

    /// Builds the finite-element model.
    pub fn build(&self) -> Result<Model, SpecError> {
        self.validate()?;
        let kind = ElementType::from_number(self.element).unwrap_or(ElementType::Beam98);
        let (nodes, elements, wire_top) = self.helix(kind);
        let all_elements: Vec<u32> = elements.iter().map(|e| e.id).collect();

        let mut fixed_disp = vec![FixedDisp {
            dofs: (1..=6).map(|d| (d, 0.0)).collect(),
            nodes: vec![BASE_NODE],
        }];
        let held: Vec<u8> = match self.top {
            Top::Guided => vec![1, 2, 4, 5, 6],
            Top::FreeRotation => vec![1, 2, 4, 5],
            Top::Held => vec![1, 2, 3, 4, 5, 6],
        };
        fixed_disp.push(FixedDisp {
            dofs: held.into_iter().map(|d| (d, 0.0)).collect(),
            nodes: vec![WEIGHT_NODE],
        });

        let mut point_masses = Vec::new();
        if self.mass_kg > 0.0 || self.rotary_inertia_kg_m2 > 0.0 {
            point_masses.push(PointMass {
                node: WEIGHT_NODE,
                mass: units::mass_from_si(self.mass_kg),
                inertia: [0.0, 0.0, units::inertia_from_si(self.rotary_inertia_kg_m2)],
            });
        }

        let mut damping = Vec::new();
        if self.alpha > 0.0 || self.beta > 0.0 {
            // Alpha acts on the spring's own elements only; the weight only when asked.
            damping.push(Damping {
                alpha: self.alpha,
                beta: self.beta,
                elements: all_elements.clone(),
                mass_nodes: if self.alpha_on_weight && !point_masses.is_empty() {
                    vec![WEIGHT_NODE]
                } else {
                    vec![]
                },
            });
        }

        let point_laws = self.point_laws();

        let (initial_velocities, outputs, load_cases) = self.history();

        let parts = ModelParts {
            title: self.title.clone(),
            element_types: vec![kind],
            lumped_mass: self.lumped_mass,
            nodes,
            elements,
            node_sets: vec![
                NodeSet {
                    name: "weight".into(),
                    nodes: vec![WEIGHT_NODE],
                },
                NodeSet {
                    name: "base".into(),
                    nodes: vec![BASE_NODE],
                },
                NodeSet {
                    name: "wire_top".into(),
                    nodes: vec![wire_top],
                },
            ],
            element_sets: vec![ElementSet {
                name: "spring".into(),
                elements: all_elements.clone(),
            }],
            materials: vec![Material {
                name: "steel".into(),
                youngs_modulus: self.youngs_modulus_mpa,
                poisson: self.poisson,
                density: units::density_from_si(self.density_kg_m3),
                elements: all_elements.clone(),
            }],
            geometries: vec![Geometry {
                name: "wire".into(),
                section: Section::SolidCircle {
                    diameter: self.wire_diameter_mm,
                },
                orientation: [0.0, 0.0, 1.0],
                elements: all_elements,
            }],
            damping,
            point_masses,
            rigid_ties: vec![RigidTie {
                name: "top".into(),
                reference: WEIGHT_NODE,
                dofs: vec![1, 2, 3, 4, 5, 6],
                tied: vec![wire_top],
            }],
            fixed_disp,
            point_loads: vec![],
            tables: vec![],
            initial_velocities,
            outputs,
            load_cases,
            point_laws,
            dashpots: vec![],
            modal_damping: Default::default(),
            beam_tensions: Vec::new(),
            tension_links: Vec::new(),
            moving_contacts: Vec::new(),
            matrix_elements: Vec::new(),
        };
        // The spec was validated above, so this fails only on a mesher bug; it still
        // goes through the model's checks like every other model.
        Model::try_new(parts).map_err(|e| SpecError {
            field: "model",
            value: e.to_string(),
            expected: "a spec whose mesh is a valid model",
        })
    }

    /// The helix's nodes (the weight's node first, then the wire from the base up) and
    /// its elements of type `kind`, with the wire's top node.
    fn helix(&self, kind: ElementType) -> (Vec<Node>, Vec<Element>, u32) {
        let n_el = self.element_count();
        let r = 0.5 * self.mean_diameter_mm;
        let t_end = 2.0 * PI * self.coils;
        let height = self.pitch_mm * self.coils;

        let mut nodes = Vec::with_capacity(n_el + 2);
        nodes.push(Node {
            id: WEIGHT_NODE,
            xyz: [0.0, 0.0, height],
        });
        for i in 0..=n_el {
            let t = t_end * i as f64 / n_el as f64;
            nodes.push(Node {
                id: BASE_NODE + i as u32,
                xyz: [r * t.cos(), r * t.sin(), self.pitch_mm * t / (2.0 * PI)],
            });
        }
        let wire_top = BASE_NODE + n_el as u32;
        let elements: Vec<Element> = (0..n_el as u32)
            .map(|i| Element {
                id: i + 1,
                kind,
                nodes: [BASE_NODE + i, BASE_NODE + i + 1],
            })
            .collect();
        (nodes, elements, wire_top)
    }

    /// The weight's nonlinear point element (friction, drag, cubic spring), if any.
    fn point_laws(&self) -> Vec<PointElement> {
        if self.friction_n > 0.0
            || self.quadratic_damping_n_s2_m2 > 0.0
            || self.cubic_stiffness_n_m3 > 0.0
        {
            vec![PointElement {
                node: WEIGHT_NODE,
                dof: 3,
                cubic: units::cubic_stiffness_from_si(self.cubic_stiffness_n_m3),
                quadratic: units::quadratic_damping_from_si(self.quadratic_damping_n_s2_m2),
                friction: self.friction_n,
            }]
        } else {
            Vec::new()
        }
    }

    /// The load cases of [`SpringSpec::analyses`] in order, with the initial velocity
    /// and history outputs the transient cases share.
    fn history(&self) -> (Vec<InitialVelocity>, Vec<OutputRequest>, Vec<LoadCase>) {
        let mut initial_velocities = Vec::new();
        let mut outputs = Vec::new();
        let mut load_cases = Vec::new();
        for analysis in &self.analyses {
            match analysis {
                AnalysisKind::Static => load_cases.push(LoadCase {
                    title: format!("static axial force {} N", self.force_n),
                    analysis: Analysis::Static {
                        steps: 1,
                        time: 1.0,
                    },
                    point_loads: vec![PointLoad {
                        dofs: vec![(3, -self.force_n)],
                        nodes: vec![WEIGHT_NODE],
                        table: None,
                    }],
                }),
                AnalysisKind::Modal => load_cases.push(LoadCase {
                    title: format!("lowest {} modes", self.modes),
                    analysis: Analysis::Modal { modes: self.modes },
                    point_loads: vec![],
                }),
                // INITIAL VEL and HISTORY OUTPUT are model-level: one of each serves every
                // transient case.
                AnalysisKind::Transient => {
                    if self.initial_velocity_m_s != 0.0 && initial_velocities.is_empty() {
                        initial_velocities.push(InitialVelocity {
                            dofs: vec![(3, units::length_from_si(self.initial_velocity_m_s))],
                            nodes: vec![WEIGHT_NODE],
                            quasi_static: self.initial_velocity_field == VelocityField::QuasiStatic,
                        });
                    }
                    if outputs.is_empty() {
                        outputs.push(OutputRequest {
                            nodes: vec![WEIGHT_NODE],
                            dofs: vec![3],
                            quantities: vec![
                                Quantity::Displacement,
                                Quantity::Velocity,
                                Quantity::Acceleration,
                            ],
                            every: self.output_every,
                        });
                        if self.snapshot_every > 0 {
                            outputs.push(OutputRequest {
                                nodes: (1..=self.element_count() as u32 + 2).collect(),
                                dofs: vec![1, 2, 3],
                                quantities: vec![Quantity::Displacement],
                                every: self.snapshot_every,
                            });
                        }
                    }
                    load_cases.push(LoadCase {
                        title: "free decay".into(),
                        analysis: Analysis::Transient {
                            dt: self.dt_s,
                            total_time: self.duration_s,
                            method: self.transient_method(),
                        },
                        point_loads: vec![],
                    });
                }
            }
        }
        (initial_velocities, outputs, load_cases)
    }
}

#[cfg(test)]
mod tests;

/// Reading a spec file failed.
#[derive(Debug, thiserror::Error)]
pub enum ReadSpecError {
    /// The spec file cannot be read.
    #[error("{path}: {source}")]
    Io {
        /// The spec file.
        path: String,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },
    /// The spec file is not a JSON spring spec.
    #[error("{path}:{line}:{column}: {message}; expected a JSON object with the fields of a spring spec (see docs/mesher.md)")]
    Json {
        /// The spec file.
        path: String,
        /// Line of the JSON error (1-based).
        line: usize,
        /// Column of the JSON error (1-based).
        column: usize,
        /// What the JSON reader found.
        message: String,
    },
}

/// Reads a JSON spring spec; missing fields take the defaults, unknown fields are errors.
pub fn read_spec(path: &std::path::Path) -> Result<SpringSpec, ReadSpecError> {
    let name = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|source| ReadSpecError::Io {
        path: name.clone(),
        source,
    })?;
    serde_json::from_str(&text).map_err(|e| ReadSpecError::Json {
        path: name,
        line: e.line(),
        column: e.column(),
        message: e.to_string(),
    })
}
