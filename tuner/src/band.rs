//! The damping laws and what each predicts for a spring geometry: the band.
//!
//! Three laws give a mode a damping ratio linear in their parameters (first-order modal
//! damping, the mode shape `phi` mass-normalised; the identification that chooses among
//! them from measured records is `coil_ident::law`, docs/damping.md):
//!
//! | law | zeta of mode r |
//! |---|---|
//! | `rayleigh` | `alpha d_r / (2 w_r) + beta w_r / 2`, `d_r = phi^T M_wire phi` |
//! | `hysteretic` | `loss_factor / 2` |
//! | `external_viscous` | `c phi_w^2 / (2 w_r)` (`phi_w` the weight's axial entry) |
//!
//! `d_r` and `phi_w` come from coil's FE model of the spring at the record's mass (mode
//! shapes do not depend on Young's modulus). A surge mode is the fixed-fixed coil: `d = 1`
//! and `phi_w = 0` exactly. The band calibrates every law to the same measured zeta of the
//! weight mode and predicts each variant of Table 4 and the case's surge mode under each:
//! where the laws spread by more than the repeat scatter, the prediction depends on the
//! assumed law. `coil-tune paper` prints it beside Table 4.
//!
//! Units: `rayleigh_alpha` 1/s, `rayleigh_beta` s, `loss_factor` -, `dashpot_n_s_m` N s/m.

use crate::case::{DecayMode, VariantsFile};
use crate::error::{Result, TuneError};
use crate::fe::{FeSettings, SpringState};
use coil_mesher::{AnalysisKind, WEIGHT_NODE};
use coil_solver::analysis;
use coil_solver::model::{units, FixedDisp};
use serde::Serialize;

/// The laws, in the spec's names.
pub const LAWS: [Law; 3] = [Law::Rayleigh, Law::Hysteretic, Law::ExternalViscous];

/// A damping law of the spec's table.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Law {
    /// `rayleigh`: element Rayleigh damping of the spring's material (alpha 1/s, beta s).
    Rayleigh,
    /// `hysteretic`: a constant loss factor of the spring's material (-).
    Hysteretic,
    /// `external_viscous`: a linear dashpot between the weight and ground (N s/m).
    ExternalViscous,
}

impl Law {
    /// The spec's name of the law.
    pub fn name(self) -> &'static str {
        match self {
            Law::Rayleigh => "rayleigh",
            Law::Hysteretic => "hysteretic",
            Law::ExternalViscous => "external_viscous",
        }
    }

    /// Parameter names (spec) in the order of [`Coefficients::row`].
    pub fn parameters(self) -> &'static [&'static str] {
        match self {
            Law::Rayleigh => &["rayleigh_alpha", "rayleigh_beta"],
            Law::Hysteretic => &["loss_factor"],
            Law::ExternalViscous => &["dashpot_n_s_m"],
        }
    }
}

/// How a mode's damping ratio depends on each law's parameters (first-order modal
/// damping; module docs).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Coefficients {
    /// Undamped circular frequency (rad/s).
    pub omega_rad_s: f64,
    /// `d = phi^T M_wire phi` (-).
    pub wire_share: f64,
    /// `phi_w^2` (1/kg).
    pub weight_participation_per_kg: f64,
}

impl Coefficients {
    /// `zeta = row . parameters` for `law`.
    pub fn row(&self, law: Law) -> Vec<f64> {
        let w = self.omega_rad_s;
        match law {
            Law::Rayleigh => vec![self.wire_share / (2.0 * w), w / 2.0],
            Law::Hysteretic => vec![0.5],
            Law::ExternalViscous => vec![self.weight_participation_per_kg / (2.0 * w)],
        }
    }
}

/// The mode shape quantities of the weight mode (axial) or the surge mode (weight held)
/// of `state`'s spring, with its FE frequency.
pub fn mode_coefficients(
    state: &SpringState,
    settings: &FeSettings,
    mode: DecayMode,
) -> Result<Coefficients> {
    let fe = FeSettings {
        modes: match mode {
            DecayMode::Axial => settings.modes.max(3),
            DecayMode::Surge => settings.modes.max(20),
        },
        ..settings.clone()
    };
    let mut model = state.model(&fe, &[AnalysisKind::Modal])?;
    if mode == DecayMode::Surge {
        let mut parts = model.into_parts();
        parts.fixed_disp.push(FixedDisp {
            dofs: vec![(3, 0.0)],
            nodes: vec![WEIGHT_NODE],
        });
        model = parts
            .build()
            .map_err(|e| TuneError::Invalid(format!("the surge model: {e}")))?;
    }
    let context = format!("modal run of the {mode:?} mode");
    let results = analysis::run(&model).map_err(|source| TuneError::Solve {
        context: context.clone(),
        source: Box::new(source),
    })?;
    let axial = crate::fe::modal_of(&results, &context)?
        .modes
        .iter()
        .max_by(|a, b| a.effective_mass[2].total_cmp(&b.effective_mass[2]))
        .filter(|m| m.effective_mass[2] > 0.0)
        .ok_or_else(|| TuneError::Missing {
            context,
            what: "no mode moves along the spring axis".into(),
        })?;
    let weight = model
        .node_index(WEIGHT_NODE)
        .map(|i| axial.shape[i * 6 + 2])
        .unwrap_or(0.0);
    let (wire_share, participation) = match mode {
        DecayMode::Surge => (1.0, 0.0),
        DecayMode::Axial => {
            let m_t = units::mass_from_si(state.mass_kg);
            // phi_w^2 in 1/t -> 1/kg.
            (1.0 - m_t * weight * weight, weight * weight * 1e-3)
        }
    };
    Ok(Coefficients {
        omega_rad_s: axial.omega_squared.sqrt(),
        wire_share,
        weight_participation_per_kg: participation,
    })
}

/// `(max - min) / min` in percent.
pub fn spread_percent(values: impl Iterator<Item = f64>) -> f64 {
    let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), x| {
        (l.min(x), h.max(x))
    });
    if lo > 0.0 && hi.is_finite() {
        100.0 * (hi - lo) / lo
    } else {
        f64::NAN
    }
}

/// The laws a single decay allows, each calibrated to the same zeta of the case's weight
/// mode: Rayleigh at both ends of its valley (beta alone, alpha
/// alone), hysteretic, a dashpot at the weight.
pub const BAND_LAWS: [&str; 4] = [
    "rayleigh_beta_only",
    "rayleigh_alpha_only",
    "hysteretic",
    "external_viscous",
];

/// One spring's zeta under every law of the band.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BandRow {
    /// The variant's name.
    pub name: String,
    /// zeta per law, in [`BAND_LAWS`] order.
    pub zeta: Vec<f64>,
    /// `(max - min) / min` (%).
    pub spread_percent: f64,
    /// The paper's printed zeta of the variant, when given (-).
    pub paper_damping_ratio: Option<f64>,
    /// Each law's zeta relative to the paper's printed value (%).
    pub against_paper_percent: Vec<f64>,
}

/// The band: Table 4's variants and the case's surge mode under each calibrated law.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Band {
    /// The measured zeta every law is calibrated to (-).
    pub calibrated_zeta: f64,
    /// The laws' names, [`BAND_LAWS`].
    pub laws: Vec<String>,
    /// The calibrated parameters: beta (s), alpha (1/s), loss factor, dashpot (N s/m).
    pub parameters: Vec<f64>,
    /// Each variant's row.
    pub variants: Vec<BandRow>,
    /// The case's spring with the weight held: its surge mode's frequency and zeta.
    pub surge_frequency_hz: f64,
    /// The surge mode's zeta per law, in [`BAND_LAWS`] order (-).
    pub surge_zeta: Vec<f64>,
    /// The measured repeat scatter a spread is compared with (relative).
    pub scatter: f64,
}

impl Band {
    /// zeta of a mode with coefficients `c` under each calibrated law.
    fn zetas(&self, c: &Coefficients) -> Vec<f64> {
        let r = c.row(Law::Rayleigh);
        vec![
            self.parameters[0] * r[1],
            self.parameters[1] * r[0],
            self.parameters[2] * c.row(Law::Hysteretic)[0],
            self.parameters[3] * c.row(Law::ExternalViscous)[0],
        ]
    }
}

/// Calibrates each law to `zeta` on `state`'s weight mode and predicts `variants`
/// (first-order modal damping from coil's FE modes, module docs).
pub fn band(
    state: &SpringState,
    variants: &VariantsFile,
    fe: &FeSettings,
    zeta: f64,
    scatter: f64,
) -> Result<Band> {
    let base = mode_coefficients(state, fe, DecayMode::Axial)?;
    let r = base.row(Law::Rayleigh);
    let mut b = Band {
        calibrated_zeta: zeta,
        laws: BAND_LAWS.iter().map(|s| s.to_string()).collect(),
        parameters: vec![
            zeta / r[1],
            zeta / r[0],
            zeta / base.row(Law::Hysteretic)[0],
            zeta / base.row(Law::ExternalViscous)[0],
        ],
        variants: Vec::new(),
        surge_frequency_hz: 0.0,
        surge_zeta: Vec::new(),
        scatter,
    };
    for v in &variants.variants {
        let c = mode_coefficients(&state.with_spring(v.spring), fe, DecayMode::Axial)?;
        let z = b.zetas(&c);
        b.variants.push(BandRow {
            name: v.name.clone(),
            spread_percent: spread_percent(z.iter().copied()),
            against_paper_percent: v
                .paper_damping_ratio
                .map(|p| z.iter().map(|x| 100.0 * (x / p - 1.0)).collect())
                .unwrap_or_default(),
            paper_damping_ratio: v.paper_damping_ratio,
            zeta: z,
        });
    }
    let surge = mode_coefficients(state, fe, DecayMode::Surge)?;
    b.surge_frequency_hz = surge.omega_rad_s / std::f64::consts::TAU;
    b.surge_zeta = b.zetas(&surge);
    Ok(b)
}

/// The band as markdown: the table and which variants depend on the assumption.
pub fn band_markdown(b: &Band) -> String {
    use std::fmt::Write as _;
    let mut s = format!(
        "Each law calibrated to the same measured decay (zeta = {:.6} on the case's spring): \
         beta alone = {:.5e} s (the valley's alpha = 0 end), alpha alone = {:.4} 1/s (its \
         beta = 0 end), loss factor = {:.5}, dashpot at the weight = {:.4} N s/m. First-order \
         modal damping on coil's FE modes of each variant (same E, weight).\n\n",
        b.calibrated_zeta, b.parameters[0], b.parameters[1], b.parameters[2], b.parameters[3]
    );
    s.push_str("| | beta only | alpha only | hysteretic | dashpot | spread | paper | paper vs laws |\n|---|---:|---:|---:|---:|---:|---:|---|\n");
    for v in &b.variants {
        let range = if v.against_paper_percent.is_empty() {
            "-".to_string()
        } else {
            let lo = v
                .against_paper_percent
                .iter()
                .copied()
                .fold(f64::INFINITY, f64::min);
            let hi = v
                .against_paper_percent
                .iter()
                .copied()
                .fold(f64::NEG_INFINITY, f64::max);
            format!("{lo:+.1}% .. {hi:+.1}%")
        };
        let _ = writeln!(
            s,
            "| {} | {:.5} | {:.5} | {:.5} | {:.5} | {:.1}% | {} | {} |",
            v.name,
            v.zeta[0],
            v.zeta[1],
            v.zeta[2],
            v.zeta[3],
            v.spread_percent,
            v.paper_damping_ratio
                .map_or("-".to_string(), |p| format!("{p}")),
            range
        );
    }
    let _ = writeln!(
        s,
        "| surge, weight held ({:.1} Hz) | {:.5} | {:.5} | {:.5} | {:.5} | | | |\n",
        b.surge_frequency_hz, b.surge_zeta[0], b.surge_zeta[1], b.surge_zeta[2], b.surge_zeta[3]
    );
    let dependent: Vec<String> = b
        .variants
        .iter()
        .filter(|v| v.spread_percent > 200.0 * b.scatter)
        .map(|v| format!("{} ({:.0}%)", v.name, v.spread_percent))
        .collect();
    if b.variants.iter().any(|v| v.paper_damping_ratio.is_some()) {
        let _ = write!(
            s,
            "The paper's printed zeta is the beta-only column's assumption. A variant depends \
             on the assumption when the laws spread by more than twice the {:.0}% repeat \
             scatter of one measurement (the paper's Table 1): {}. ",
            100.0 * b.scatter,
            if dependent.is_empty() {
                "none".to_string()
            } else {
                dependent.join(", ")
            },
        );
    }
    let _ = writeln!(
        s,
        "The one measurement that closes the band is the surge mode (last row): beta predicts \
         {:.3}, a loss factor {:.5}, a dashpot at the weight 0.",
        b.surge_zeta[0], b.surge_zeta[2]
    );
    s
}
