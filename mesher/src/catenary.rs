//! A pantograph-catenary model as a deck: a catenary spec and a pantograph spec -> one
//! coil [`Model`] with its static state (`coil-mesh catenary SPEC.json -o DECK`;
//! docs/catenary.md, "The catenary spec").
//!
//! # Model
//! Planar (x along the track, z up), two DOFs per wire node (u_z and theta_y; u_x, u_y,
//! theta_x, theta_z fixed): the contact and messenger wires are straight lines of type-52
//! beams at z = 0 and z = system height, each under `BEAM TENSION` (the taut string
//! `rho w_tt = N w_xx` stiffened by EI). Both wires share one grid in x: every span is cut
//! at its droppers, each piece into equal elements no longer than `element_length_m`.
//! Droppers are `TENSION LINK`s (contact-wire node a, messenger node b, u_z); steady arms
//! and messenger supports are vertical bars (axial stiffness `EA / L = k`, L = 1 m) to a
//! ground node, with point masses on the wire nodes; the wires' ends are pinned at the
//! first and last support. The pantograph is a chain of lumped stages from the head down
//! (stage i's spring and damper join mass i to mass i+1, the last to the ground), on bars
//! (springs) and Rayleigh `beta = c / k` on each bar (its dashpot), the static uplift force
//! on the lowest mass; the head presses on the contact wire by a `MOVING CONTACT`. A
//! stage given as matrices ([`StageMatrix`], a reduced spring model) gets no bar and no
//! dashpot but one `DMIG` over its two ends' u_z and its modal coordinates (DOF 1 of
//! extra nodes, the other DOFs held).
//! Gravity acts on the catenary (lumped nodal weights `q h / 2` per element end and the
//! point masses' weights), not on the pantograph, whose uplift force is the net static
//! force of the standard's models.
//!
//! # Static state (the classical construction, exact for the linear model)
//! 1. The contact wire's heights are prescribed: 0 at the supports, the presag parabola
//!    `-presag 4 xi (1 - xi)` (`xi` the position in the span) at the droppers. The contact
//!    wire alone (its weight, its clamps, the steady arms' masses) with those heights
//!    prescribed gives, as reactions, each dropper's force `F_j` and each steady arm's.
//! 2. The messenger alone, loaded by its weight, its clamps and the dropper forces, its
//!    supports at 0, gives the messenger's deflection at each dropper and the support
//!    forces.
//! 3. Dropper lengths: `slack_j = u_m,j - u_c,j - F_j / k` (a pretensioned link); the
//!    steady arms' and messenger supports' ground nodes are set at `R / k` (the hinge
//!    height that holds the wire at its support height under its static force).
//! 4. The full catenary's STATIC case is solved; where the contact wire misses a
//!    prescribed height by more than [`PRESAG_TOLERANCE_MM`], the dropper lengths are
//!    corrected by the miss and the case solved again (at most [`MAX_PRESAG_ITERATIONS`]).
//!    The linear model meets the heights after step 3 up to round-off.
//!
//! The deck's first load case is the STATIC case of the whole model with the head pressed
//! on the wire at the start (the pinned first support by default, so the pantograph does
//! not move the catenary there); the transient (`NEWMARK`) starts from it.
//!
//! # Units
//! Spec fields carry their units in the name (`_m`, `_mm`, `_kg`, `_n`, `_n_m`,
//! `_n_s_m`, `_km_h`, `_s`); the deck is in mm, N, t, s.
//!
//! # Numbering (stable)
//! Contact-wire nodes and elements from [`CONTACT_BASE`] (+ grid index), messenger from
//! [`MESSENGER_BASE`], steady-arm ground nodes and bars from [`STEADY_ARM_BASE`] (+ support
//! index), messenger-support ground nodes and bars from [`SUPPORT_BASE`], the pantograph's
//! masses from [`PANTOGRAPH_BASE`] (the head first; the ground node last), its bars from
//! [`PANTOGRAPH_BASE`] (stage index), a stage matrix's modal nodes from
//! [`PANTOGRAPH_MODAL_BASE`] (+ 1000 stage index + mode index).

use crate::{check, SpecError};
use coil_solver::analysis::{run, CaseSolution, StaticSolution};
use coil_solver::model::{
    Analysis, BeamTension, Damping, Dashpot, Element, ElementType, FixedDisp, Geometry, Integrator,
    LoadCase, Material, MatrixElement, Model, ModelParts, MovingContact, Node, NodeId, NodeSet,
    OutputRequest, PointLoad, PointMass, Quantity, Section, TensionLink, TransientMethod,
};
use serde::{Deserialize, Serialize};

/// First contact-wire node and element id.
pub const CONTACT_BASE: u32 = 1;
/// First messenger node and element id.
pub const MESSENGER_BASE: u32 = 1_000_001;
/// First steady-arm ground node and bar id.
pub const STEADY_ARM_BASE: u32 = 2_000_001;
/// First messenger-support ground node and bar id.
pub const SUPPORT_BASE: u32 = 3_000_001;
/// The pantograph's head node; its lower masses follow, then its ground node.
pub const PANTOGRAPH_BASE: u32 = 9_000_001;
/// First modal node of a stage matrix: stage `i`'s mode `j` (from 0) is node
/// `PANTOGRAPH_MODAL_BASE + 1000 i + j`.
pub const PANTOGRAPH_MODAL_BASE: u32 = 9_100_001;
/// Most grid nodes per wire.
pub const MAX_WIRE_NODES: usize = 999_999;
/// The contact wire's largest miss of its prescribed heights (mm) in the static state.
pub const PRESAG_TOLERANCE_MM: f64 = 1e-3;
/// Most dropper-length corrections of the static state.
pub const MAX_PRESAG_ITERATIONS: usize = 5;
/// The history column of the contact force (N).
pub const CONTACT_FORCE_COLUMN: &str = "contact1_force_n";
/// Length of every spring bar (mm).
const BAR_MM: f64 = 1000.0;
/// Section of the wires' beams (mm^2, mm^4): E and the density carry EI and rho A.
const WIRE_AREA: f64 = 100.0;
const WIRE_INERTIA: f64 = 1000.0;

/// A wire: mass per length, tension, bending stiffness.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WireSpec {
    /// Mass per length (kg/m), > 0.
    pub mass_kg_m: f64,
    /// Axial tension (N), > 0.
    pub tension_n: f64,
    /// Bending stiffness EI (N m^2), > 0.
    pub ei_n_m2: f64,
}

/// The droppers, the same in every span.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DropperSpec {
    /// Positions from the span's first support (m), increasing, inside the span.
    pub positions_m: Vec<f64>,
    /// Stiffness in tension (N/m), > 0; slack in compression.
    pub stiffness_n_m: f64,
    /// Mass on the contact wire at each dropper (clamp and half the dropper, kg), >= 0.
    pub contact_clamp_mass_kg: f64,
    /// Mass on the messenger at each dropper (clamp and half the dropper, kg), >= 0.
    pub messenger_clamp_mass_kg: f64,
}

/// A vertical support: a spring to the ground and a mass on the wire.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SupportSpec {
    /// Vertical stiffness (N/m), > 0.
    pub stiffness_n_m: f64,
    /// Mass on the wire's support node (kg), >= 0.
    pub mass_kg: f64,
}

/// Rayleigh damping of the catenary with the ratio `ratio` at two frequencies.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DampingSpec {
    /// Damping ratio at both frequencies (-), in [0, 1).
    pub ratio: f64,
    /// The two frequencies (Hz), 0 < f1 < f2: alpha = 2 zeta w1 w2 / (w1 + w2),
    /// beta = 2 zeta / (w1 + w2); between them the ratio is below `ratio`, outside above.
    pub frequencies_hz: [f64; 2],
}

impl DampingSpec {
    /// Rayleigh (alpha 1/s, beta s).
    pub fn rayleigh(&self) -> (f64, f64) {
        let w1 = 2.0 * std::f64::consts::PI * self.frequencies_hz[0];
        let w2 = 2.0 * std::f64::consts::PI * self.frequencies_hz[1];
        (
            2.0 * self.ratio * w1 * w2 / (w1 + w2),
            2.0 * self.ratio / (w1 + w2),
        )
    }
}

fn default_gravity() -> f64 {
    9.81
}

/// A simple catenary: contact wire hung from a messenger by droppers, over `spans`
/// equal spans.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CatenarySpec {
    /// Number of spans, >= 1.
    pub spans: u32,
    /// Span length (m), > 0.
    pub span_length_m: f64,
    /// Messenger height above the contact wire at the supports (m), > 0.
    pub system_height_m: f64,
    /// Contact wire's presag at mid-span (mm, downwards), >= 0.
    pub presag_mm: f64,
    /// The contact wire.
    pub contact_wire: WireSpec,
    /// The messenger wire.
    pub messenger_wire: WireSpec,
    /// The droppers.
    pub droppers: DropperSpec,
    /// Steady arms (on the contact wire at the supports).
    pub steady_arm: SupportSpec,
    /// Messenger supports.
    pub messenger_support: SupportSpec,
    /// Rayleigh damping of the wires and the catenary's point masses.
    pub damping: DampingSpec,
    /// Largest element length (m), > 0.
    pub element_length_m: f64,
    /// Gravity (m/s^2), >= 0 [default 9.81].
    #[serde(default = "default_gravity")]
    pub gravity_m_s2: f64,
}

/// One stage of a pantograph: a mass, and the spring and damper below it, either lumped
/// (a bar and its dashpot) or a reduced model given as matrices ([`StageMatrix`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StageSpec {
    /// Mass (kg), > 0.
    pub mass_kg: f64,
    /// Spring to the next stage down, or the ground for the last (N/m), > 0. With
    /// `matrix`, the matrix's static stiffness (checked to [`STAGE_STIFFNESS_TOLERANCE`]).
    pub stiffness_n_m: f64,
    /// Damper beside it (N s/m), >= 0; 0 with `matrix` (its damping is the matrix's).
    pub damping_n_s_m: f64,
    /// The stage's spring and damper as a reduced model in place of the lumped bar and
    /// dashpot [default: none].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub matrix: Option<StageMatrix>,
}

/// A stage's spring as symmetric matrices (a Craig-Bampton model, say) over the
/// coordinates `[lower end u, upper end u, eta_1, .., eta_r]`: the axial (z)
/// displacements of the stage's two ends (the next mass down, or the ground, and the
/// stage's own mass), then `r >= 0` modal amplitudes. Row-major `n x n` with `n = 2 + r`,
/// in deck units: N/mm, t, N s/mm on the ends (a modal coordinate's units are its own,
/// sqrt(t) mm for a mass-normalised mode). The deck holds it as one `DMIG`; each modal
/// coordinate is DOF 1 of its own node (the other DOFs held).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StageMatrix {
    /// Stiffness, `n x n` row-major.
    pub stiffness: Vec<f64>,
    /// Mass, `n x n` row-major (the spring's own mass; the stage's `mass_kg` stays a
    /// point mass on its upper end).
    pub mass: Vec<f64>,
    /// Damping, `n x n` row-major [default: none].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub damping: Option<Vec<f64>>,
}

impl StageMatrix {
    /// The order `n` of the matrices, if `stiffness` holds a square number >= 4 of
    /// entries.
    pub fn order(&self) -> Option<usize> {
        let n = (self.stiffness.len() as f64).sqrt().round() as usize;
        (n >= 2 && n * n == self.stiffness.len()).then_some(n)
    }

    /// The static stiffness between the ends with the modal coordinates relaxed (N/mm):
    /// the upper end's entry of the Schur complement `K_bb - K_bm K_mm^-1 K_mb`, or
    /// `None` if the modal block is singular or the size is wrong.
    pub fn static_stiffness_n_mm(&self) -> Option<f64> {
        let n = self.order()?;
        let k = nalgebra::DMatrix::from_row_slice(n, n, &self.stiffness);
        if n == 2 {
            return Some(k[(1, 1)]);
        }
        let kmm = k.view((2, 2), (n - 2, n - 2)).into_owned();
        let kbm = k.view((1, 2), (1, n - 2)).into_owned();
        let solved = kmm.lu().solve(&kbm.transpose())?;
        let s = k[(1, 1)] - (kbm * solved)[(0, 0)];
        s.is_finite().then_some(s)
    }
}

/// A stage matrix's static stiffness and the stage's `stiffness_n_m` agree to this
/// fraction (a matrix exported with 9 significant digits passes, a unit slip does not).
pub const STAGE_STIFFNESS_TOLERANCE: f64 = 1e-6;
/// Most modal coordinates of one stage matrix.
pub const MAX_STAGE_MODES: usize = 999;

/// A lumped pantograph: its stages from the head down, a static uplift force on the
/// lowest mass, and the contact's penalty stiffness.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PantographSpec {
    /// Stages from the head (the head stage first), >= 1.
    pub stages: Vec<StageSpec>,
    /// Static uplift force on the lowest mass (N), finite.
    pub uplift_force_n: f64,
    /// Penalty stiffness of the contact (N/m), > 0.
    pub contact_stiffness_n_m: f64,
}

fn default_every() -> u32 {
    1
}

/// How one run goes: the speed, the step, where the pantograph starts and stops.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RunSpec {
    /// Speed (km/h), > 0.
    pub speed_km_h: f64,
    /// Time step (s), > 0.
    pub time_step_s: f64,
    /// Where the head starts, from the first support (m) [default 0].
    #[serde(default)]
    pub start_m: f64,
    /// Where the run ends (m) [default: the last support].
    #[serde(default)]
    pub end_m: Option<f64>,
    /// Record every k-th step [default 1].
    #[serde(default = "default_every")]
    pub output_every: u32,
}

/// The file `coil-mesh catenary` reads.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CatenaryDeckSpec {
    /// The catenary.
    pub catenary: CatenarySpec,
    /// The pantograph.
    pub pantograph: PantographSpec,
    /// The run.
    pub run: RunSpec,
}

impl CatenaryDeckSpec {
    /// The EN 50318:2002 reference model's values as `cases/catenary-en50318-2002` gives
    /// them (its README cites each and marks the assumptions: no presag, 120 N uplift, 50
    /// kN/m contact), on `spans` spans of `element_length_m` (m) elements, run at 250 km/h
    /// in 1 ms steps: a starting point for tests and examples.
    pub fn en50318_reference(spans: u32, element_length_m: f64) -> Self {
        CatenaryDeckSpec {
            catenary: CatenarySpec {
                spans,
                span_length_m: 60.0,
                system_height_m: 1.2,
                presag_mm: 0.0,
                contact_wire: WireSpec {
                    mass_kg_m: 1.35,
                    tension_n: 20_000.0,
                    ei_n_m2: 195.0,
                },
                messenger_wire: WireSpec {
                    mass_kg_m: 1.07,
                    tension_n: 16_000.0,
                    ei_n_m2: 131.7,
                },
                droppers: DropperSpec {
                    positions_m: vec![5.0, 10.5, 17.0, 23.5, 30.0, 36.5, 43.0, 49.5, 55.0],
                    stiffness_n_m: 100_000.0,
                    contact_clamp_mass_kg: 0.195,
                    messenger_clamp_mass_kg: 0.165,
                },
                steady_arm: SupportSpec {
                    stiffness_n_m: 300.0,
                    mass_kg: 1.0,
                },
                messenger_support: SupportSpec {
                    stiffness_n_m: 50_000.0,
                    mass_kg: 0.0,
                },
                damping: DampingSpec {
                    ratio: 0.005,
                    frequencies_hz: [1.0, 20.0],
                },
                element_length_m,
                gravity_m_s2: 9.81,
            },
            pantograph: PantographSpec {
                stages: vec![
                    StageSpec {
                        mass_kg: 7.2,
                        stiffness_n_m: 4200.0,
                        damping_n_s_m: 10.0,
                        matrix: None,
                    },
                    StageSpec {
                        mass_kg: 15.0,
                        stiffness_n_m: 50.0,
                        damping_n_s_m: 90.0,
                        matrix: None,
                    },
                ],
                uplift_force_n: 120.0,
                contact_stiffness_n_m: 50_000.0,
            },
            run: RunSpec {
                speed_km_h: 250.0,
                time_step_s: 1e-3,
                start_m: 0.0,
                end_m: None,
                output_every: 1,
            },
        }
    }
}

/// What the catenary's static state came to.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StaticState {
    /// Dropper positions along the track (m), span after span.
    pub dropper_x_m: Vec<f64>,
    /// Dropper forces in the static state (N).
    pub dropper_force_n: Vec<f64>,
    /// Dropper slack in the deck (mm; negative: pretensioned).
    pub dropper_slack_mm: Vec<f64>,
    /// Prescribed contact-wire heights at the droppers (mm).
    pub target_mm: Vec<f64>,
    /// The contact wire's height at the droppers in the full model's static case (mm).
    pub contact_wire_mm: Vec<f64>,
    /// Largest miss |height - target| over droppers and supports (mm).
    pub presag_miss_mm: f64,
    /// Dropper-length corrections made (0: the construction met the heights at once).
    pub iterations: usize,
    /// Static force in each interior steady arm (N, up).
    pub steady_arm_force_n: Vec<f64>,
    /// Static force in each interior messenger support (N, up).
    pub messenger_support_force_n: Vec<f64>,
    /// The catenary's total weight (N).
    pub weight_n: f64,
    /// Sum of the vertical reactions of all the catenary's supports (N, up).
    pub support_reactions_n: f64,
}

/// A built pantograph-catenary model with what a run needs to read its results.
#[derive(Debug, Clone)]
pub struct CatenaryModel {
    /// The model: a STATIC case, then the transient.
    pub model: Model,
    /// The static state.
    pub state: StaticState,
    /// Interior support positions along the track (m).
    pub support_x_m: Vec<f64>,
    /// Contact-wire node at each interior support (their u_z is recorded).
    pub support_nodes: Vec<NodeId>,
    /// The head's node (the pantograph's lower masses follow it).
    pub head: NodeId,
    /// The pantograph.
    pub pantograph: PantographSpec,
    /// Where the head starts (m).
    pub start_m: f64,
    /// Speed (m/s).
    pub speed_m_s: f64,
    /// The line's length (m).
    pub length_m: f64,
    /// Nodes per wire.
    pub wire_nodes: usize,
}

/// A catenary model that cannot be built.
#[derive(Debug, thiserror::Error)]
pub enum CatenaryError {
    /// A spec field is out of range.
    #[error("invalid catenary spec: {0}")]
    Spec(#[from] SpecError),
    /// A solve of the static state failed.
    #[error("static state ({stage}): {source}")]
    Solve {
        /// Which step of the construction.
        stage: &'static str,
        /// The solver's error.
        #[source]
        source: Box<coil_solver::analysis::SolveError>,
    },
    /// The spec's values give a state no catenary can be in.
    #[error("static state: {0}")]
    State(String),
}

impl CatenarySpec {
    /// Checks every field.
    pub fn validate(&self) -> Result<(), SpecError> {
        check(
            self.spans >= 1 && self.spans <= 1000,
            "catenary.spans",
            f64::from(self.spans),
            "1 to 1000",
        )?;
        check(
            self.span_length_m > 0.0,
            "catenary.span_length_m",
            self.span_length_m,
            "> 0",
        )?;
        check(
            self.system_height_m > 0.0,
            "catenary.system_height_m",
            self.system_height_m,
            "> 0",
        )?;
        check(
            self.presag_mm >= 0.0,
            "catenary.presag_mm",
            self.presag_mm,
            ">= 0",
        )?;
        for (wire, names) in [
            (
                &self.contact_wire,
                [
                    "catenary.contact_wire.mass_kg_m",
                    "catenary.contact_wire.tension_n",
                    "catenary.contact_wire.ei_n_m2",
                ],
            ),
            (
                &self.messenger_wire,
                [
                    "catenary.messenger_wire.mass_kg_m",
                    "catenary.messenger_wire.tension_n",
                    "catenary.messenger_wire.ei_n_m2",
                ],
            ),
        ] {
            check(wire.mass_kg_m > 0.0, names[0], wire.mass_kg_m, "> 0")?;
            check(wire.tension_n > 0.0, names[1], wire.tension_n, "> 0")?;
            check(wire.ei_n_m2 > 0.0, names[2], wire.ei_n_m2, "> 0")?;
        }
        let d = &self.droppers;
        let mut last = 0.0;
        for &x in &d.positions_m {
            check(
                x > last && x < self.span_length_m,
                "catenary.droppers.positions_m",
                x,
                "increasing positions strictly inside the span (0, span_length_m)",
            )?;
            last = x;
        }
        check(
            d.stiffness_n_m > 0.0,
            "catenary.droppers.stiffness_n_m",
            d.stiffness_n_m,
            "> 0",
        )?;
        check(
            d.contact_clamp_mass_kg >= 0.0,
            "catenary.droppers.contact_clamp_mass_kg",
            d.contact_clamp_mass_kg,
            ">= 0",
        )?;
        check(
            d.messenger_clamp_mass_kg >= 0.0,
            "catenary.droppers.messenger_clamp_mass_kg",
            d.messenger_clamp_mass_kg,
            ">= 0",
        )?;
        check(
            self.steady_arm.stiffness_n_m > 0.0,
            "catenary.steady_arm.stiffness_n_m",
            self.steady_arm.stiffness_n_m,
            "> 0",
        )?;
        check(
            self.steady_arm.mass_kg >= 0.0,
            "catenary.steady_arm.mass_kg",
            self.steady_arm.mass_kg,
            ">= 0",
        )?;
        check(
            self.messenger_support.stiffness_n_m > 0.0,
            "catenary.messenger_support.stiffness_n_m",
            self.messenger_support.stiffness_n_m,
            "> 0",
        )?;
        check(
            self.messenger_support.mass_kg >= 0.0,
            "catenary.messenger_support.mass_kg",
            self.messenger_support.mass_kg,
            ">= 0",
        )?;
        check(
            (0.0..1.0).contains(&self.damping.ratio),
            "catenary.damping.ratio",
            self.damping.ratio,
            "in [0, 1)",
        )?;
        let [f1, f2] = self.damping.frequencies_hz;
        check(
            f1 > 0.0,
            "catenary.damping.frequencies_hz",
            f1,
            "0 < f1 < f2",
        )?;
        check(
            f2 > f1,
            "catenary.damping.frequencies_hz",
            f2,
            "0 < f1 < f2",
        )?;
        check(
            self.element_length_m > 0.0,
            "catenary.element_length_m",
            self.element_length_m,
            "> 0",
        )?;
        check(
            self.gravity_m_s2 >= 0.0,
            "catenary.gravity_m_s2",
            self.gravity_m_s2,
            ">= 0",
        )?;
        let per_span =
            self.span_length_m / self.element_length_m + d.positions_m.len() as f64 + 1.0;
        check(
            per_span * f64::from(self.spans) < MAX_WIRE_NODES as f64,
            "catenary.element_length_m",
            self.element_length_m,
            "at most 999999 nodes per wire (a longer element or fewer spans)",
        )
    }

    /// The line's length (m).
    pub fn length_m(&self) -> f64 {
        self.span_length_m * f64::from(self.spans)
    }
}

impl PantographSpec {
    /// Checks every field.
    pub fn validate(&self) -> Result<(), SpecError> {
        check(
            !self.stages.is_empty() && self.stages.len() <= 10,
            "pantograph.stages",
            self.stages.len() as f64,
            "1 to 10 stages",
        )?;
        for s in &self.stages {
            check(
                s.mass_kg > 0.0,
                "pantograph.stages.mass_kg",
                s.mass_kg,
                "> 0",
            )?;
            check(
                s.stiffness_n_m > 0.0,
                "pantograph.stages.stiffness_n_m",
                s.stiffness_n_m,
                "> 0",
            )?;
            check(
                s.damping_n_s_m >= 0.0,
                "pantograph.stages.damping_n_s_m",
                s.damping_n_s_m,
                ">= 0",
            )?;
            if let Some(m) = &s.matrix {
                m.validate(s)?;
            }
        }
        check(
            self.uplift_force_n.is_finite(),
            "pantograph.uplift_force_n",
            self.uplift_force_n,
            "finite",
        )?;
        check(
            self.contact_stiffness_n_m > 0.0,
            "pantograph.contact_stiffness_n_m",
            self.contact_stiffness_n_m,
            "> 0",
        )
    }
}

impl StageMatrix {
    /// Checks the sizes and the static stiffness against `stage` (symmetry and the
    /// mass's and damping's semi-definiteness are the model's checks, reported under
    /// `pantograph.stages.matrix` by [`build`]).
    fn validate(&self, stage: &StageSpec) -> Result<(), SpecError> {
        let len = self.stiffness.len() as f64;
        let Some(n) = self.order() else {
            return Err(SpecError {
                field: "pantograph.stages.matrix.stiffness",
                value: format!("{len} entries"),
                expected: "n x n entries, n >= 2 (two ends, then the modal coordinates)",
            });
        };
        check(
            n - 2 <= MAX_STAGE_MODES,
            "pantograph.stages.matrix.stiffness",
            len,
            "at most 999 modal coordinates",
        )?;
        let same = [
            ("pantograph.stages.matrix.mass", Some(&self.mass)),
            ("pantograph.stages.matrix.damping", self.damping.as_ref()),
        ];
        for (field, a) in same {
            if let Some(a) = a {
                if a.len() != n * n {
                    return Err(SpecError {
                        field,
                        value: format!("{} entries", a.len()),
                        expected: "as many entries as the stiffness (n x n)",
                    });
                }
            }
        }
        check(
            stage.damping_n_s_m == 0.0,
            "pantograph.stages.damping_n_s_m",
            stage.damping_n_s_m,
            "0 with a matrix (the matrix's damping stands for the dashpot)",
        )?;
        let k = self.static_stiffness_n_mm().unwrap_or(f64::NAN) * 1e3;
        check(
            (k - stage.stiffness_n_m).abs() <= STAGE_STIFFNESS_TOLERANCE * stage.stiffness_n_m,
            "pantograph.stages.stiffness_n_m",
            stage.stiffness_n_m,
            "the matrix's static stiffness (its Schur complement on the upper end, N/m, \
             to 1e-6)",
        )
    }
}

impl RunSpec {
    /// Checks every field against the catenary's length.
    pub fn validate(&self, length_m: f64) -> Result<(), SpecError> {
        check(
            self.speed_km_h > 0.0,
            "run.speed_km_h",
            self.speed_km_h,
            "> 0",
        )?;
        check(
            self.time_step_s > 0.0,
            "run.time_step_s",
            self.time_step_s,
            "> 0",
        )?;
        check(
            self.start_m >= 0.0 && self.start_m < length_m,
            "run.start_m",
            self.start_m,
            "on the line: 0 <= start_m < spans x span_length_m",
        )?;
        let end = self.end_m(length_m);
        check(
            end > self.start_m && end <= length_m,
            "run.end_m",
            end,
            "after start_m and not beyond the last support",
        )?;
        check(
            self.output_every >= 1,
            "run.output_every",
            f64::from(self.output_every),
            ">= 1",
        )
    }

    /// Where the run ends (m).
    pub fn end_m(&self, length_m: f64) -> f64 {
        self.end_m.unwrap_or(length_m)
    }

    /// The speed (m/s).
    pub fn speed_m_s(&self) -> f64 {
        self.speed_km_h / 3.6
    }
}

/// The wires' common grid along x (mm), with the droppers' and supports' grid indices.
struct Grid {
    x: Vec<f64>,
    droppers: Vec<usize>,
    supports: Vec<usize>,
}

impl Grid {
    fn new(spec: &CatenarySpec) -> Grid {
        let span = spec.span_length_m * 1e3;
        let h = spec.element_length_m * 1e3;
        let mut keys = vec![0.0];
        keys.extend(spec.droppers.positions_m.iter().map(|x| x * 1e3));
        keys.push(span);
        let mut grid = Grid {
            x: vec![0.0],
            droppers: Vec::new(),
            supports: vec![0],
        };
        for s in 0..spec.spans {
            let x0 = f64::from(s) * span;
            for (k, pair) in keys.windows(2).enumerate() {
                let (a, b) = (pair[0], pair[1]);
                let n = ((b - a) / h - 1e-9).ceil().max(1.0) as usize;
                for i in 1..=n {
                    grid.x.push(x0 + a + (b - a) * i as f64 / n as f64);
                }
                if k + 2 < keys.len() {
                    grid.droppers.push(grid.x.len() - 1);
                }
            }
            grid.supports.push(grid.x.len() - 1);
        }
        grid
    }
}

fn kg_to_t(kg: f64) -> f64 {
    kg * 1e-3
}

fn n_m_to_n_mm(k: f64) -> f64 {
    k * 1e-3
}

/// Which parts of the catenary a model holds.
#[derive(Clone, Copy, PartialEq)]
enum Part {
    /// The contact wire alone, its heights prescribed at the droppers and supports.
    ContactWire,
    /// The messenger alone, loaded by the dropper forces, its supports prescribed.
    Messenger,
    /// Both wires with droppers, steady arms and supports.
    Catenary,
}

/// What the construction has found so far: dropper forces and slack, support offsets.
struct Setting {
    slack_mm: Vec<f64>,
    dropper_force_n: Vec<f64>,
    steady_arm_offset_mm: Vec<f64>,
    support_offset_mm: Vec<f64>,
}

/// Parts shared by every model of the construction, in ModelParts's fields.
#[derive(Default)]
struct Pieces {
    nodes: Vec<Node>,
    elements: Vec<Element>,
    materials: Vec<Material>,
    geometries: Vec<Geometry>,
    damping: Vec<Damping>,
    point_masses: Vec<PointMass>,
    fixed_disp: Vec<FixedDisp>,
    point_loads: Vec<PointLoad>,
    beam_tensions: Vec<BeamTension>,
    tension_links: Vec<TensionLink>,
    node_sets: Vec<NodeSet>,
    dashpots: Vec<Dashpot>,
    matrix_elements: Vec<MatrixElement>,
}

impl Pieces {
    /// A wire along the grid at height `z` (mm), node and element ids from `base`.
    fn wire(&mut self, grid: &Grid, base: u32, z: f64, wire: &WireSpec, name: &str, gravity: f64) {
        let ids: Vec<u32> = (0..grid.x.len() as u32).map(|i| base + i).collect();
        for (&id, &x) in ids.iter().zip(&grid.x) {
            self.nodes.push(Node {
                id,
                xyz: [x, 0.0, z],
            });
        }
        let elements: Vec<u32> = (0..ids.len() as u32 - 1).map(|i| base + i).collect();
        for (i, &e) in elements.iter().enumerate() {
            self.elements.push(Element {
                id: e,
                kind: ElementType::Beam52,
                nodes: [ids[i], ids[i + 1]],
            });
        }
        let rho_a = kg_to_t(wire.mass_kg_m) * 1e-3; // t/mm
        self.materials.push(Material {
            name: name.into(),
            youngs_modulus: wire.ei_n_m2 * 1e6 / WIRE_INERTIA,
            poisson: 0.3,
            density: rho_a / WIRE_AREA,
            elements: elements.clone(),
        });
        self.geometries.push(Geometry {
            name: name.into(),
            section: Section::General {
                area: WIRE_AREA,
                iyy: WIRE_INERTIA,
                izz: WIRE_INERTIA,
                torsion: 2.0 * WIRE_INERTIA,
                shear_coefficient: 0.0,
            },
            orientation: [0.0, 0.0, 1.0],
            elements: elements.clone(),
        });
        self.beam_tensions.push(BeamTension {
            force: wire.tension_n,
            elements,
        });
        // Planar: u_z and theta_y free; the ends pinned.
        self.fixed_disp.push(FixedDisp {
            dofs: vec![(1, 0.0), (2, 0.0), (4, 0.0), (6, 0.0)],
            nodes: ids.clone(),
        });
        self.fixed_disp.push(FixedDisp {
            dofs: vec![(3, 0.0)],
            nodes: vec![ids[0], ids[ids.len() - 1]],
        });
        // Lumped weights q h / 2 at each element end.
        let q = wire.mass_kg_m * gravity * 1e-3; // N/mm
        let mut w = vec![0.0; ids.len()];
        for i in 0..ids.len() - 1 {
            let half = 0.5 * q * (grid.x[i + 1] - grid.x[i]);
            w[i] += half;
            w[i + 1] += half;
        }
        for (&id, &wi) in ids.iter().zip(&w) {
            self.point_loads.push(PointLoad {
                dofs: vec![(3, -wi)],
                nodes: vec![id],
                table: None,
            });
        }
        self.node_sets.push(NodeSet {
            name: name.into(),
            nodes: ids,
        });
    }

    /// A point mass with its weight.
    fn mass(&mut self, node: NodeId, kg: f64, gravity: f64) {
        if kg > 0.0 {
            self.point_masses.push(PointMass {
                node,
                mass: kg_to_t(kg),
                inertia: [0.0; 3],
            });
            if gravity > 0.0 {
                self.point_loads.push(PointLoad {
                    dofs: vec![(3, -kg * gravity)],
                    nodes: vec![node],
                    table: None,
                });
            }
        }
    }

    /// A spring bar of axial stiffness `k` (N/mm) between two nodes `BAR_MM` apart: EA / L
    /// = k with A = 1 mm^2; I = 1e-3 mm^4 leaves its bending negligible beside the wires'
    /// (4 E I / L below 1e-3 of theirs). No mass.
    fn bar(&mut self, id: u32, nodes: [NodeId; 2], k: f64, name: String) {
        self.elements.push(Element {
            id,
            kind: ElementType::Beam52,
            nodes,
        });
        self.materials.push(Material {
            name: name.clone(),
            youngs_modulus: k * BAR_MM,
            poisson: 0.3,
            density: 0.0,
            elements: vec![id],
        });
        self.geometries.push(Geometry {
            name,
            section: Section::General {
                area: 1.0,
                iyy: 1e-3,
                izz: 1e-3,
                torsion: 2e-3,
                shear_coefficient: 0.0,
            },
            orientation: [1.0, 0.0, 0.0],
            elements: vec![id],
        });
    }

    /// Stage `stage`'s matrix on the u_z of `ends` (lower, upper) and its modal
    /// coordinates on DOF 1 of new nodes from [`PANTOGRAPH_MODAL_BASE`] (the other DOFs
    /// held), as one matrix element `pantograph_stage_<stage + 1>`.
    fn stage_matrix(&mut self, stage: u32, ends: [NodeId; 2], matrix: &StageMatrix) {
        let n = matrix.order().unwrap_or(2);
        let modal: Vec<NodeId> = (0..n as u32 - 2)
            .map(|j| PANTOGRAPH_MODAL_BASE + 1000 * stage + j)
            .collect();
        for (j, &id) in modal.iter().enumerate() {
            self.nodes.push(Node {
                id,
                xyz: [
                    -5000.0,
                    BAR_MM * (j + 1) as f64,
                    -BAR_MM * (f64::from(stage) + 0.5),
                ],
            });
        }
        if !modal.is_empty() {
            self.fixed_disp.push(FixedDisp {
                dofs: (2..=6).map(|d| (d, 0.0)).collect(),
                nodes: modal.clone(),
            });
        }
        let mut dofs = vec![(ends[0], 3), (ends[1], 3)];
        dofs.extend(modal.iter().map(|&id| (id, 1)));
        self.matrix_elements.push(MatrixElement {
            name: format!("pantograph_stage_{}", stage + 1),
            dofs,
            stiffness: matrix.stiffness.clone(),
            mass: matrix.mass.clone(),
            damping: matrix.damping.clone().unwrap_or_default(),
        });
    }

    /// A vertical spring bar of `k` (N/mm) from `node` at `xyz` to a ground node `ground`
    /// `BAR_MM` above (`up`) or below it, the ground at `offset` (mm) along z.
    #[allow(clippy::too_many_arguments)]
    fn spring(
        &mut self,
        id: u32,
        node: NodeId,
        xyz: [f64; 3],
        ground: NodeId,
        up: bool,
        k: f64,
        offset: f64,
        name: String,
    ) {
        let dz = if up { BAR_MM } else { -BAR_MM };
        self.nodes.push(Node {
            id: ground,
            xyz: [xyz[0], xyz[1], xyz[2] + dz],
        });
        self.bar(id, [node, ground], k, name);
        self.fixed_disp.push(FixedDisp {
            dofs: vec![
                (1, 0.0),
                (2, 0.0),
                (3, offset),
                (4, 0.0),
                (5, 0.0),
                (6, 0.0),
            ],
            nodes: vec![ground],
        });
    }
}

/// The presag parabola at `x` mm (mm, up positive: <= 0).
fn target_height(spec: &CatenarySpec, x_mm: f64) -> f64 {
    let span = spec.span_length_m * 1e3;
    let xi = (x_mm / span).fract();
    -spec.presag_mm * 4.0 * xi * (1.0 - xi)
}

/// The catenary's pieces (no pantograph) for `part`.
fn catenary_pieces(spec: &CatenarySpec, grid: &Grid, part: Part, setting: &Setting) -> Pieces {
    let g = spec.gravity_m_s2;
    let mut p = Pieces::default();
    let height = spec.system_height_m * 1e3;
    let interior = &grid.supports[1..grid.supports.len() - 1];
    // Each wire with its clamps and support masses; the contact wire is left out of the
    // messenger's model and the messenger out of the contact wire's.
    let wires = [
        (
            Part::Messenger,
            CONTACT_BASE,
            0.0,
            &spec.contact_wire,
            "contact_wire",
            spec.droppers.contact_clamp_mass_kg,
            spec.steady_arm.mass_kg,
        ),
        (
            Part::ContactWire,
            MESSENGER_BASE,
            height,
            &spec.messenger_wire,
            "messenger",
            spec.droppers.messenger_clamp_mass_kg,
            spec.messenger_support.mass_kg,
        ),
    ];
    for (without, base, z, wire, name, clamp_kg, support_kg) in wires {
        if part == without {
            continue;
        }
        p.wire(grid, base, z, wire, name, g);
        for &i in &grid.droppers {
            p.mass(base + i as u32, clamp_kg, g);
        }
        for &i in interior {
            p.mass(base + i as u32, support_kg, g);
        }
    }
    match part {
        Part::ContactWire => {
            let dofs: Vec<(u32, f64)> = grid
                .droppers
                .iter()
                .map(|&i| (CONTACT_BASE + i as u32, target_height(spec, grid.x[i])))
                .chain(interior.iter().map(|&i| (CONTACT_BASE + i as u32, 0.0)))
                .collect();
            for (node, z) in dofs {
                p.fixed_disp.push(FixedDisp {
                    dofs: vec![(3, z)],
                    nodes: vec![node],
                });
            }
        }
        Part::Messenger => {
            for (&i, &f) in grid.droppers.iter().zip(&setting.dropper_force_n) {
                p.point_loads.push(PointLoad {
                    dofs: vec![(3, -f)],
                    nodes: vec![MESSENGER_BASE + i as u32],
                    table: None,
                });
            }
            for &i in interior {
                p.fixed_disp.push(FixedDisp {
                    dofs: vec![(3, 0.0)],
                    nodes: vec![MESSENGER_BASE + i as u32],
                });
            }
        }
        Part::Catenary => {
            for (j, &i) in grid.droppers.iter().enumerate() {
                p.tension_links.push(TensionLink {
                    nodes: [CONTACT_BASE + i as u32, MESSENGER_BASE + i as u32],
                    dof: 3,
                    stiffness: n_m_to_n_mm(spec.droppers.stiffness_n_m),
                    slack: setting.slack_mm[j],
                });
            }
            for (s, &i) in interior.iter().enumerate() {
                let x = grid.x[i];
                p.spring(
                    STEADY_ARM_BASE + s as u32,
                    CONTACT_BASE + i as u32,
                    [x, 0.0, 0.0],
                    STEADY_ARM_BASE + s as u32,
                    false,
                    n_m_to_n_mm(spec.steady_arm.stiffness_n_m),
                    setting.steady_arm_offset_mm[s],
                    format!("steady_arm_{}", s + 1),
                );
                p.spring(
                    SUPPORT_BASE + s as u32,
                    MESSENGER_BASE + i as u32,
                    [x, 0.0, height],
                    SUPPORT_BASE + s as u32,
                    true,
                    n_m_to_n_mm(spec.messenger_support.stiffness_n_m),
                    setting.support_offset_mm[s],
                    format!("messenger_support_{}", s + 1),
                );
            }
        }
    }
    // Damping of the wires and of the catenary's point masses (Rayleigh).
    let (alpha, beta) = spec.damping.rayleigh();
    if alpha > 0.0 || beta > 0.0 {
        let wires: Vec<u32> = p
            .elements
            .iter()
            .filter(|e| e.id < STEADY_ARM_BASE)
            .map(|e| e.id)
            .collect();
        let mut mass_nodes: Vec<u32> = if alpha > 0.0 {
            p.point_masses.iter().map(|m| m.node).collect()
        } else {
            Vec::new()
        };
        mass_nodes.sort_unstable();
        p.damping.push(Damping {
            alpha,
            beta,
            elements: wires,
            mass_nodes,
        });
    }
    p
}

fn parts(
    title: String,
    p: Pieces,
    load_cases: Vec<LoadCase>,
    outputs: Vec<OutputRequest>,
    contacts: Vec<MovingContact>,
) -> ModelParts {
    let mut nodes = p.nodes;
    nodes.sort_by_key(|n| n.id);
    let mut elements = p.elements;
    elements.sort_by_key(|e| e.id);
    let mut point_masses = p.point_masses;
    point_masses.sort_by_key(|m| m.node);
    ModelParts {
        title,
        element_types: vec![ElementType::Beam52],
        lumped_mass: false,
        nodes,
        elements,
        node_sets: p.node_sets,
        element_sets: Vec::new(),
        materials: p.materials,
        geometries: p.geometries,
        damping: p.damping,
        point_masses,
        rigid_ties: Vec::new(),
        fixed_disp: p.fixed_disp,
        point_loads: p.point_loads,
        tables: Vec::new(),
        initial_velocities: Vec::new(),
        outputs,
        load_cases,
        point_laws: Vec::new(),
        dashpots: p.dashpots,
        modal_damping: Default::default(),
        beam_tensions: p.beam_tensions,
        tension_links: p.tension_links,
        moving_contacts: contacts,
        matrix_elements: p.matrix_elements,
    }
}

fn static_case(title: &str) -> LoadCase {
    LoadCase {
        title: title.into(),
        analysis: Analysis::Static {
            steps: 1,
            time: 1.0,
        },
        point_loads: Vec::new(),
    }
}

fn model_of(parts: ModelParts) -> Result<Model, CatenaryError> {
    Model::try_new(parts).map_err(|e| {
        if let coil_solver::model::Site::MatrixElement(_) = e.site {
            // The catenary's only matrix elements are the pantograph's stage matrices.
            return CatenaryError::Spec(SpecError {
                field: "pantograph.stages.matrix",
                value: e.to_string(),
                expected: "symmetric matrices, the mass and damping positive semi-definite",
            });
        }
        CatenaryError::State(format!(
            "the mesh is not a valid model ({e}); expected a spec whose mesh is one"
        ))
    })
}

fn solve_static(model: &Model, stage: &'static str) -> Result<StaticSolution, CatenaryError> {
    let results = run(model).map_err(|source| CatenaryError::Solve {
        stage,
        source: Box::new(source),
    })?;
    match results.into_iter().next().map(|r| r.solution) {
        Some(CaseSolution::Static(s)) => Ok(s),
        _ => Err(CatenaryError::State(format!("{stage}: no static solution"))),
    }
}

fn reaction(solution: &StaticSolution, node: NodeId) -> f64 {
    solution
        .reactions
        .iter()
        .filter(|r| r.node == node && r.dof == 3)
        .map(|r| r.value)
        .sum()
}

fn uz(solution: &StaticSolution, model: &Model, node: NodeId) -> f64 {
    solution
        .node_displacement(model, node)
        .map_or(f64::NAN, |u| u[2])
}

/// The static solution of `part` of the catenary (a model of its own with one STATIC
/// case).
fn solve_part(
    spec: &CatenarySpec,
    grid: &Grid,
    part: Part,
    setting: &Setting,
) -> Result<(Model, StaticSolution), CatenaryError> {
    let (title, stage) = match part {
        Part::ContactWire => ("contact wire at its prescribed heights", "contact wire"),
        Part::Messenger => ("messenger under the dropper forces", "messenger"),
        Part::Catenary => ("catenary at rest", "catenary"),
    };
    let p = catenary_pieces(spec, grid, part, setting);
    let model = model_of(parts(
        title.into(),
        p,
        vec![static_case(title)],
        vec![],
        vec![],
    ))?;
    let solution = solve_static(&model, stage)?;
    Ok((model, solution))
}

/// The static state of the catenary alone (module doc, steps 1-4): dropper forces and
/// lengths, support offsets, and the full catenary's static check.
fn static_state(spec: &CatenarySpec, grid: &Grid) -> Result<(Setting, StaticState), CatenaryError> {
    let interior: Vec<usize> = grid.supports[1..grid.supports.len() - 1].to_vec();
    let n_d = grid.droppers.len();
    let mut setting = Setting {
        slack_mm: vec![0.0; n_d],
        dropper_force_n: vec![0.0; n_d],
        steady_arm_offset_mm: vec![0.0; interior.len()],
        support_offset_mm: vec![0.0; interior.len()],
    };
    // 1. The contact wire with its heights prescribed.
    let (_, sol) = solve_part(spec, grid, Part::ContactWire, &setting)?;
    let targets: Vec<f64> = grid
        .droppers
        .iter()
        .map(|&i| target_height(spec, grid.x[i]))
        .collect();
    for (j, &i) in grid.droppers.iter().enumerate() {
        let f = reaction(&sol, CONTACT_BASE + i as u32);
        if f <= 0.0 {
            return Err(CatenaryError::State(format!(
                "the dropper at {:.3} m would push the contact wire ({f:.2} N): a dropper \
                 only pulls; expected a presag the wire's weight can hang in (a smaller \
                 catenary.presag_mm)",
                grid.x[i] * 1e-3
            )));
        }
        setting.dropper_force_n[j] = f;
    }
    let k_sa = n_m_to_n_mm(spec.steady_arm.stiffness_n_m);
    let steady_arm_force: Vec<f64> = interior
        .iter()
        .map(|&i| reaction(&sol, CONTACT_BASE + i as u32))
        .collect();
    for (s, f) in steady_arm_force.iter().enumerate() {
        // The bar pulls the node up by k (u_ground - u_node), the node at 0.
        setting.steady_arm_offset_mm[s] = f / k_sa;
    }
    // 2. The messenger under the dropper forces.
    let (model, sol) = solve_part(spec, grid, Part::Messenger, &setting)?;
    let k_ms = n_m_to_n_mm(spec.messenger_support.stiffness_n_m);
    let support_force: Vec<f64> = interior
        .iter()
        .map(|&i| reaction(&sol, MESSENGER_BASE + i as u32))
        .collect();
    for (s, f) in support_force.iter().enumerate() {
        // The ground node is above: the bar pulls the node up by k (u_ground - u_node).
        setting.support_offset_mm[s] = f / k_ms;
    }
    // 3. Dropper lengths.
    let k_d = n_m_to_n_mm(spec.droppers.stiffness_n_m);
    for (j, &i) in grid.droppers.iter().enumerate() {
        let u_m = uz(&sol, &model, MESSENGER_BASE + i as u32);
        setting.slack_mm[j] = u_m - targets[j] - setting.dropper_force_n[j] / k_d;
    }
    // 4. The whole catenary, corrected until it meets the heights.
    let mut iterations = 0;
    loop {
        let (model, sol) = solve_part(spec, grid, Part::Catenary, &setting)?;
        let heights: Vec<f64> = grid
            .droppers
            .iter()
            .map(|&i| uz(&sol, &model, CONTACT_BASE + i as u32))
            .collect();
        let mut miss = heights
            .iter()
            .zip(&targets)
            .fold(0.0_f64, |m, (h, t)| m.max((h - t).abs()));
        for &i in &interior {
            miss = miss.max(uz(&sol, &model, CONTACT_BASE + i as u32).abs());
        }
        if miss <= PRESAG_TOLERANCE_MM || iterations == MAX_PRESAG_ITERATIONS {
            if miss > PRESAG_TOLERANCE_MM || !miss.is_finite() {
                return Err(CatenaryError::State(format!(
                    "the contact wire misses its prescribed heights by {miss:.3e} mm after \
                     {iterations} dropper-length corrections; expected at most \
                     {PRESAG_TOLERANCE_MM} mm (a slack dropper? check the presag and the \
                     dropper stiffness)"
                )));
            }
            let weight = model
                .point_loads()
                .iter()
                .flat_map(|l| {
                    l.dofs.iter().map(move |&(d, v)| {
                        if d == 3 {
                            -v * l.nodes.len() as f64
                        } else {
                            0.0
                        }
                    })
                })
                .sum::<f64>();
            let reactions = sol
                .reactions
                .iter()
                .filter(|r| r.dof == 3)
                .map(|r| r.value)
                .sum::<f64>();
            let forces: Vec<f64> = grid
                .droppers
                .iter()
                .zip(&setting.slack_mm)
                .map(|(&i, &slack)| {
                    let e = uz(&sol, &model, MESSENGER_BASE + i as u32)
                        - uz(&sol, &model, CONTACT_BASE + i as u32)
                        - slack;
                    k_d * e.max(0.0)
                })
                .collect();
            let state = StaticState {
                dropper_x_m: grid.droppers.iter().map(|&i| grid.x[i] * 1e-3).collect(),
                dropper_force_n: forces,
                dropper_slack_mm: setting.slack_mm.clone(),
                target_mm: targets,
                contact_wire_mm: heights,
                presag_miss_mm: miss,
                iterations,
                steady_arm_force_n: steady_arm_force,
                messenger_support_force_n: support_force,
                weight_n: weight,
                support_reactions_n: reactions,
            };
            return Ok((setting, state));
        }
        // Too low (h < t): a shorter dropper (smaller slack) lifts the wire.
        for (j, (h, t)) in heights.iter().zip(&targets).enumerate() {
            setting.slack_mm[j] += h - t;
        }
        iterations += 1;
    }
}

/// Builds the pantograph-catenary model of `spec`: the static state first (module doc),
/// then the deck's model with its STATIC case (head pressed at the start) and the
/// transient at `run`'s speed.
pub fn build(spec: &CatenaryDeckSpec) -> Result<CatenaryModel, CatenaryError> {
    build_parts(&spec.catenary, &spec.pantograph, &spec.run)
}

/// [`build`] from the three parts.
pub fn build_parts(
    catenary: &CatenarySpec,
    pantograph: &PantographSpec,
    run_spec: &RunSpec,
) -> Result<CatenaryModel, CatenaryError> {
    catenary.validate()?;
    pantograph.validate()?;
    let length = catenary.length_m();
    run_spec.validate(length)?;
    let grid = Grid::new(catenary);
    let (setting, state) = static_state(catenary, &grid)?;
    let mut p = catenary_pieces(catenary, &grid, Part::Catenary, &setting);
    // The pantograph: masses from the head down at x = -5 m, 1 m apart, then the ground.
    let n = pantograph.stages.len() as u32;
    let head = PANTOGRAPH_BASE;
    let ground = PANTOGRAPH_BASE + n;
    for i in 0..=n {
        p.nodes.push(Node {
            id: PANTOGRAPH_BASE + i,
            xyz: [-5000.0, 0.0, -BAR_MM * f64::from(i)],
        });
    }
    for (i, stage) in pantograph.stages.iter().enumerate() {
        let node = PANTOGRAPH_BASE + i as u32;
        let id = PANTOGRAPH_BASE + i as u32;
        p.point_masses.push(PointMass {
            node,
            mass: kg_to_t(stage.mass_kg),
            inertia: [0.0; 3],
        });
        if let Some(matrix) = &stage.matrix {
            p.stage_matrix(i as u32, [node + 1, node], matrix);
            continue;
        }
        p.bar(
            id,
            [node, node + 1],
            n_m_to_n_mm(stage.stiffness_n_m),
            format!("pantograph_stage_{}", i + 1),
        );
        if stage.damping_n_s_m > 0.0 {
            // C_e = beta K_e on the bar: the dashpot c = beta k beside the spring.
            p.damping.push(Damping {
                alpha: 0.0,
                beta: stage.damping_n_s_m / stage.stiffness_n_m,
                elements: vec![id],
                mass_nodes: Vec::new(),
            });
        }
    }
    p.fixed_disp.push(FixedDisp {
        dofs: vec![(1, 0.0), (2, 0.0), (4, 0.0), (5, 0.0), (6, 0.0)],
        nodes: (PANTOGRAPH_BASE..ground).collect(),
    });
    p.fixed_disp.push(FixedDisp {
        dofs: (1..=6).map(|d| (d, 0.0)).collect(),
        nodes: vec![ground],
    });
    p.point_loads.push(PointLoad {
        dofs: vec![(3, pantograph.uplift_force_n)],
        nodes: vec![ground - 1],
        table: None,
    });
    p.node_sets.push(NodeSet {
        name: "pantograph".into(),
        nodes: (PANTOGRAPH_BASE..=ground).collect(),
    });
    let interior: Vec<usize> = grid.supports[1..grid.supports.len() - 1].to_vec();
    let support_nodes: Vec<NodeId> = interior.iter().map(|&i| CONTACT_BASE + i as u32).collect();
    let mut outputs = vec![OutputRequest {
        nodes: (PANTOGRAPH_BASE..ground).collect(),
        dofs: vec![3],
        quantities: vec![Quantity::Displacement, Quantity::Velocity],
        every: run_spec.output_every,
    }];
    if !support_nodes.is_empty() {
        outputs.insert(
            0,
            OutputRequest {
                nodes: support_nodes.clone(),
                dofs: vec![3],
                quantities: vec![Quantity::Displacement],
                every: run_spec.output_every,
            },
        );
    }
    let speed_mm_s = run_spec.speed_m_s() * 1e3;
    let contact = MovingContact {
        head,
        dof: 3,
        stiffness: n_m_to_n_mm(pantograph.contact_stiffness_n_m),
        speed: speed_mm_s,
        start: run_spec.start_m * 1e3,
        line: (0..grid.x.len() as u32).map(|i| CONTACT_BASE + i).collect(),
    };
    let dt = run_spec.time_step_s;
    let travel = (run_spec.end_m(length) - run_spec.start_m) * 1e3 / speed_mm_s;
    let steps = (travel / dt - 1e-9).ceil().max(1.0);
    let cases = vec![
        static_case("static state"),
        LoadCase {
            title: format!("pantograph at {} km/h", run_spec.speed_km_h),
            analysis: Analysis::Transient {
                dt,
                total_time: steps * dt,
                method: TransientMethod::Direct(Integrator::AverageAcceleration),
            },
            point_loads: Vec::new(),
        },
    ];
    let title = format!(
        "catenary {} x {} m, pantograph at {} km/h",
        catenary.spans, catenary.span_length_m, run_spec.speed_km_h
    );
    let model = model_of(parts(title, p, cases, outputs, vec![contact]))?;
    Ok(CatenaryModel {
        model,
        state,
        support_x_m: interior.iter().map(|&i| grid.x[i] * 1e-3).collect(),
        support_nodes,
        head,
        pantograph: pantograph.clone(),
        start_m: run_spec.start_m,
        speed_m_s: run_spec.speed_m_s(),
        length_m: length,
        wire_nodes: grid.x.len(),
    })
}

/// Reading a catenary spec file failed.
#[derive(Debug, thiserror::Error)]
pub enum ReadCatenaryError {
    /// The file cannot be read, is not a regular file or is larger than
    /// [`MAX_SPEC_BYTES`].
    #[error(transparent)]
    Read(#[from] coil_io::ConfineError),
    /// The file is not a catenary spec.
    #[error("{path}:{line}:{column}: {message}; expected a JSON object with `catenary`, `pantograph` and `run` (docs/catenary.md, \"The catenary spec\")")]
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

/// Largest spec file read (bytes).
pub const MAX_SPEC_BYTES: u64 = 1 << 20;

/// Reads a JSON document of type `T` of at most [`MAX_SPEC_BYTES`] (unknown fields are
/// errors), naming the file, line and column of a fault.
pub fn read_json<T: serde::de::DeserializeOwned>(
    path: &std::path::Path,
) -> Result<T, ReadCatenaryError> {
    let text = coil_io::read_bounded(path, MAX_SPEC_BYTES, "catenary spec")?;
    serde_json::from_str(&text).map_err(|e| ReadCatenaryError::Json {
        path: path.display().to_string(),
        line: e.line(),
        column: e.column(),
        message: e.to_string(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 2-span catenary of the EN 50318 wires, 1 m elements, 30 mm presag.
    pub(crate) fn small() -> CatenaryDeckSpec {
        let mut spec = CatenaryDeckSpec::en50318_reference(2, 1.0);
        spec.catenary.presag_mm = 30.0;
        spec
    }

    #[test]
    fn the_grid_has_nodes_at_droppers_and_supports() {
        let spec = small();
        let grid = Grid::new(&spec.catenary);
        assert_eq!(grid.droppers.len(), 18);
        assert_eq!(grid.supports.len(), 3);
        assert!((grid.x[grid.droppers[9]] - 65_000.0).abs() < 1e-9);
        assert!((grid.x[grid.supports[2]] - 120_000.0).abs() < 1e-9);
        let longest = grid.x.windows(2).fold(0.0_f64, |m, w| m.max(w[1] - w[0]));
        assert!(longest <= 1000.0 + 1e-9, "{longest}");
    }

    #[test]
    fn the_static_state_meets_the_presag_and_balances_the_weight() {
        let spec = small();
        let built = build(&spec).unwrap();
        let s = &built.state;
        println!(
            "presag miss {:.3e} mm after {} corrections; weight {:.3} N, reactions {:.3} N; \
             dropper forces {:.2}..{:.2} N",
            s.presag_miss_mm,
            s.iterations,
            s.weight_n,
            s.support_reactions_n,
            s.dropper_force_n.iter().cloned().fold(f64::MAX, f64::min),
            s.dropper_force_n.iter().cloned().fold(f64::MIN, f64::max),
        );
        assert!(s.presag_miss_mm <= PRESAG_TOLERANCE_MM);
        // The linear construction is exact: a miss of round-off, no correction needed.
        assert_eq!(s.iterations, 0);
        let mid = s.target_mm[4];
        assert!((mid + 30.0).abs() < 1e-9, "{mid}");
        // Weight: 2 x 60 m of both wires, 18 x 2 clamps, 1 steady arm (interior support).
        let weight = 9.81 * (120.0 * (1.35 + 1.07) + 18.0 * (0.195 + 0.165) + 1.0);
        assert!(
            (s.weight_n - weight).abs() < 1e-9 * weight,
            "{} {weight}",
            s.weight_n
        );
        // Every support (ground nodes, pinned ends) together carries the weight.
        assert!(
            (s.support_reactions_n - weight).abs() < 1e-8 * weight,
            "{} against {weight}",
            s.support_reactions_n
        );
        // Each dropper carries at least the contact wire between it and its neighbours
        // less what the presag's curvature takes (positive: all taut).
        assert!(s.dropper_force_n.iter().all(|&f| f > 0.0));
    }

    #[test]
    fn a_bad_field_is_named() {
        let mut spec = small();
        spec.catenary.droppers.positions_m = vec![5.0, 4.0];
        let e = build(&spec).unwrap_err().to_string();
        assert!(e.contains("catenary.droppers.positions_m"), "{e}");
        let mut spec = small();
        spec.pantograph.stages.clear();
        let e = build(&spec).unwrap_err().to_string();
        assert!(e.contains("pantograph.stages"), "{e}");
        let json = r#"{"catenary": {}, "pantograph": {}, "run": {}, "extra": 1}"#;
        assert!(serde_json::from_str::<CatenaryDeckSpec>(json).is_err());
    }

    /// The static state's pantograph displacements and a short run's contact force.
    fn static_and_force(spec: &CatenaryDeckSpec) -> (Vec<f64>, Vec<f64>) {
        let built = build(spec).unwrap();
        let results = run(&built.model).unwrap();
        let CaseSolution::Static(rest) = &results[0].solution else {
            panic!("not static")
        };
        let CaseSolution::Transient(moving) = &results[1].solution else {
            panic!("not transient")
        };
        let u = (0..spec.pantograph.stages.len() as u32)
            .map(|i| {
                rest.node_displacement(&built.model, PANTOGRAPH_BASE + i)
                    .unwrap()[2]
            })
            .collect();
        let force = moving
            .history
            .column(CONTACT_FORCE_COLUMN)
            .unwrap()
            .to_vec();
        (u, force)
    }

    #[test]
    fn a_stage_matrix_equal_to_the_bar_is_the_lumped_stage() {
        // 2 spans, the head run over the first 15 m (216 steps at 250 km/h).
        let mut lumped = small();
        lumped.run.end_m = Some(15.0);
        let mut matrix = lumped.clone();
        let (k, c) = (4.2, 10e-3); // N/mm, N s/mm: the head stage's bar and dashpot
        let stage = &mut matrix.pantograph.stages[0];
        stage.damping_n_s_m = 0.0;
        stage.matrix = Some(StageMatrix {
            stiffness: vec![k, -k, -k, k],
            mass: vec![0.0; 4],
            damping: Some(vec![c, -c, -c, c]),
        });
        let built = build(&matrix).unwrap();
        assert_eq!(built.model.matrix_elements().len(), 1);
        let (u0, f0) = static_and_force(&lumped);
        let (u1, f1) = static_and_force(&matrix);
        let scale = f0.iter().fold(0.0_f64, |m, f| m.max(f.abs()));
        let worst = f0
            .iter()
            .zip(&f1)
            .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()));
        println!(
            "static u {u0:?} / {u1:?} mm; {} samples, contact force up to {scale:.2} N, \
             largest difference {worst:e} N",
            f0.len()
        );
        assert_eq!(f0.len(), f1.len());
        for (a, b) in u0.iter().zip(&u1) {
            assert!((a - b).abs() <= 1e-9 * a.abs().max(1.0), "{a} {b}");
        }
        assert!(worst <= 1e-9 * scale, "{worst} N of {scale} N");
        // The force moves during the run (the comparison is not of a constant).
        let spread =
            f0.iter().fold(f64::MIN, |m, &f| m.max(f)) - f0.iter().fold(f64::MAX, |m, &f| m.min(f));
        assert!(spread > 1.0, "{spread}");
    }

    #[test]
    fn a_stage_matrix_with_modes_gets_its_nodes_and_a_bad_one_is_named() {
        // One modal coordinate: a mass-normalised mode of 100 rad/s coupled to the ends.
        let mut spec = small();
        spec.run.end_m = Some(1.0);
        let (k, w2, g) = (4.2, 1e4, 50.0);
        let stage = &mut spec.pantograph.stages[0];
        stage.damping_n_s_m = 0.0;
        // K_bm = [-g, g]: the static stiffness is k - g^2 / w2 on the upper end.
        stage.stiffness_n_m = (k - g * g / w2) * 1e3;
        stage.matrix = Some(StageMatrix {
            stiffness: vec![k, -k, -g, -k, k, g, -g, g, w2],
            mass: vec![1e-4, 0.0, 0.0, 0.0, 1e-4, 0.0, 0.0, 0.0, 1.0],
            damping: None,
        });
        let built = build(&spec).unwrap();
        let e = &built.model.matrix_elements()[0];
        assert_eq!(
            e.dofs,
            [
                (PANTOGRAPH_BASE + 1, 3),
                (PANTOGRAPH_BASE, 3),
                (PANTOGRAPH_MODAL_BASE, 1)
            ]
        );
        assert!(run(&built.model).is_ok());
        let text = coil_solver::deck::write(&built.model);
        let back = coil_solver::deck::read_str(&text, "catenary.dat").unwrap();
        assert_eq!(back, built.model);

        let bad = |f: &dyn Fn(&mut StageSpec)| {
            let mut s = spec.clone();
            f(&mut s.pantograph.stages[0]);
            build(&s).unwrap_err().to_string()
        };
        let e = bad(&|s| {
            s.matrix
                .as_mut()
                .unwrap()
                .stiffness
                .pop()
                .map(drop)
                .unwrap()
        });
        assert!(e.contains("pantograph.stages.matrix.stiffness"), "{e}");
        let e = bad(&|s| s.matrix.as_mut().unwrap().damping = Some(vec![0.0; 4]));
        assert!(e.contains("pantograph.stages.matrix.damping"), "{e}");
        let e = bad(&|s| s.stiffness_n_m = 4200.0);
        assert!(e.contains("pantograph.stages.stiffness_n_m"), "{e}");
        let e = bad(&|s| s.damping_n_s_m = 10.0);
        assert!(e.contains("pantograph.stages.damping_n_s_m"), "{e}");
        let e = bad(&|s| s.matrix.as_mut().unwrap().mass[1] = 1.0);
        assert!(
            e.contains("pantograph.stages.matrix") && e.contains("symmetric"),
            "{e}"
        );
    }

    #[test]
    fn the_deck_reads_back_to_the_same_model() {
        let mut spec = small();
        spec.catenary.spans = 1;
        let built = build(&spec).unwrap();
        let text = coil_solver::deck::write(&built.model);
        let back = coil_solver::deck::read_str(&text, "catenary.dat").unwrap();
        assert_eq!(back, built.model);
    }
}
