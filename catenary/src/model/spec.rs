//! The catenary spec's types (`coil-mesh catenary SPEC.json`, docs/catenary.md, "The
//! catenary spec"): the catenary, the pantograph and the run, each field checked with its
//! name; the built model's static state and the spec file's reader. Units in the field
//! names (`_m`, `_mm`, `_kg`, `_n`, `_n_m`, `_n_s_m`, `_km_h`, `_s`).

use coil_mesher::{check, SpecError};
use coil_solver::model::{Model, NodeId};
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
    /// Run at or above the contact wire's wave speed, a regime the model does not cover
    /// (the wave piles up before the head) [default false: refused].
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub allow_supercritical: bool,
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
                allow_supercritical: false,
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
    /// A run the model does not cover (at or above the wave speed).
    #[error("{0}")]
    Regime(String),
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

    /// The contact wire's wave speed `c = sqrt(T / rho A)` (m/s), EI left out (the
    /// taut string; docs/catenary.md, "Formulation").
    pub fn wave_speed_m_s(&self) -> f64 {
        (self.contact_wire.tension_n / self.contact_wire.mass_kg_m).sqrt()
    }

    /// A speed's share of the wave speed, `v / c` (-).
    pub fn wave_speed_ratio(&self, speed_km_h: f64) -> f64 {
        speed_km_h / 3.6 / self.wave_speed_m_s()
    }
}

/// EN 50119's limit on the speed's share of the contact wire's wave speed (70 %).
pub const EN50119_WAVE_SPEED_SHARE: f64 = 0.7;

/// Refuses a run at or above the contact wire's wave speed unless it allows it.
pub fn check_wave_speed(catenary: &CatenarySpec, run: &RunSpec) -> Result<(), String> {
    let ratio = catenary.wave_speed_ratio(run.speed_km_h);
    if ratio >= 1.0 && !run.allow_supercritical {
        return Err(format!(
            "run.speed_km_h = {}: at or above the contact wire's wave speed sqrt(T / rho A) = \
             {:.1} km/h (ratio {ratio:.3}), a regime the model does not cover; expected a \
             speed below it (EN 50119 asks for at most {:.0} %), or allow it explicitly \
             (`run.allow_supercritical`, `coil-tune catenary --allow-supercritical`)",
            run.speed_km_h,
            catenary.wave_speed_m_s() * 3.6,
            EN50119_WAVE_SPEED_SHARE * 100.0
        ));
    }
    Ok(())
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
