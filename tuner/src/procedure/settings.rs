//! The values a procedure's `set` changes: one table ([`SETTINGS`]: name, kind, meaning,
//! from which `docs/procedures.md` is written), the parsing of a value by its kind and its
//! effect on the session.

use super::session::Session;
use super::words::{number, Parsed};
use crate::decay::{Method, VelocityField};
use crate::error::{ProcedureError, Result, TuneError};

/// What a setting's value is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Kind {
    /// A number > 0.
    Positive,
    /// A number >= 0.
    NonNegative,
    /// A number in an open interval.
    Open(f64, f64),
    /// A whole number >= the minimum.
    Count(u32),
    /// One of the words.
    Choice(&'static [&'static str]),
    /// `on` or `off`.
    Switch,
    /// A number > 0 or `off`.
    PositiveOrOff,
    /// Comma-separated numbers >= 0.
    List,
}

/// A settable value: its name, what it is and its unit.
#[derive(Debug, Clone, Copy)]
pub struct SettingSpec {
    /// The name after `set`.
    pub name: &'static str,
    /// What its value is.
    pub kind: Kind,
    /// What it sets, with its unit.
    pub meaning: &'static str,
}

/// Every setting, once. Model values need a `case` first.
pub const SETTINGS: &[SettingSpec] = &[
    SettingSpec {
        name: "youngs_modulus_mpa",
        kind: Kind::Positive,
        meaning: "Young's modulus E (MPa)",
    },
    SettingSpec {
        name: "poisson_ratio",
        kind: Kind::Open(-1.0, 0.5),
        meaning: "Poisson's ratio",
    },
    SettingSpec {
        name: "density_kg_m3",
        kind: Kind::Positive,
        meaning: "wire density (kg/m^3)",
    },
    SettingSpec {
        name: "mass_kg",
        kind: Kind::Positive,
        meaning: "the weight's mass (kg)",
    },
    SettingSpec {
        name: "alpha",
        kind: Kind::NonNegative,
        meaning: "Rayleigh alpha on the wire (1/s)",
    },
    SettingSpec {
        name: "beta",
        kind: Kind::NonNegative,
        meaning: "Rayleigh beta on the wire (s)",
    },
    SettingSpec {
        name: "active_coils",
        kind: Kind::Positive,
        meaning: "number of active coils n",
    },
    SettingSpec {
        name: "mean_diameter_mm",
        kind: Kind::Positive,
        meaning: "mean coil diameter D (mm)",
    },
    SettingSpec {
        name: "wire_diameter_mm",
        kind: Kind::Positive,
        meaning: "wire diameter d (mm)",
    },
    SettingSpec {
        name: "pitch_mm",
        kind: Kind::Positive,
        meaning: "pitch h (mm)",
    },
    SettingSpec {
        name: "elements_per_coil",
        kind: Kind::Count(3),
        meaning: "beams per coil",
    },
    SettingSpec {
        name: "element",
        kind: Kind::Choice(&["98", "52"]),
        meaning: "Marc element type: 98 Timoshenko, 52 Euler-Bernoulli",
    },
    SettingSpec {
        name: "lumped_mass",
        kind: Kind::Switch,
        meaning: "lumped instead of consistent mass",
    },
    SettingSpec {
        name: "static_force_n",
        kind: Kind::Positive,
        meaning: "static load on the weight for K (N)",
    },
    SettingSpec {
        name: "modes",
        kind: Kind::Count(1),
        meaning: "modes computed to find the axial mode",
    },
    SettingSpec {
        name: "method",
        kind: Kind::Choice(&["modal", "direct"]),
        meaning: "how decay transients run: modal superposition or direct integration",
    },
    SettingSpec {
        name: "check_direct",
        kind: Kind::Switch,
        meaning: "re-check the chosen point by direct integration (modal method)",
    },
    SettingSpec {
        name: "dt_s",
        kind: Kind::Positive,
        meaning: "transient time step (s)",
    },
    SettingSpec {
        name: "duration_s",
        kind: Kind::Positive,
        meaning: "transient record length (s)",
    },
    SettingSpec {
        name: "initial_velocity_m_s",
        kind: Kind::Positive,
        meaning: "the weight's initial axial velocity (m/s)",
    },
    SettingSpec {
        name: "velocity_field",
        kind: Kind::Choice(&["quasi-static", "nodal"]),
        meaning:
            "initial velocity spread along the spring by the static shape, or on the weight alone",
    },
    SettingSpec {
        name: "modal_modes",
        kind: Kind::Count(1),
        meaning: "modes of the modal method",
    },
    SettingSpec {
        name: "every",
        kind: Kind::Count(1),
        meaning: "crest intervals per decrement span (the paper: 10)",
    },
    SettingSpec {
        name: "lowpass_hz",
        kind: Kind::PositiveOrOff,
        meaning: "zero-phase low-pass before crest picking (Hz), or off",
    },
    SettingSpec {
        name: "valley_alphas",
        kind: Kind::List,
        meaning: "alphas at which `choose` solves the valley's beta (comma-separated)",
    },
    SettingSpec {
        name: "valley_tolerance",
        kind: Kind::Open(0.0, 1.0),
        meaning: "relative tolerance on zeta of the valley points",
    },
    SettingSpec {
        name: "stiffness_tolerance",
        kind: Kind::Open(0.0, 1.0),
        meaning: "default tolerance of `tune youngs_modulus`",
    },
    SettingSpec {
        name: "period_tolerance",
        kind: Kind::Open(0.0, 1.0),
        meaning: "default tolerance of `tune mass`",
    },
    SettingSpec {
        name: "progress",
        kind: Kind::Switch,
        meaning: "progress bars on stderr",
    },
];

/// A parsed setting value.
#[derive(Debug, Clone, PartialEq)]
pub enum SetValue {
    /// A number (counts too).
    Number(f64),
    /// One of a [`Kind::Choice`]'s words.
    Word(String),
    /// `on` (true) or `off`.
    Switch(bool),
    /// `off` for a [`Kind::PositiveOrOff`].
    Off,
    /// A [`Kind::List`].
    List(Vec<f64>),
}

/// Parses `set NAME VALUE`: the setting's name as the table spells it and its value.
pub(crate) fn parse_setting(name: &str, value: &str) -> Parsed<(&'static str, SetValue)> {
    let spec =
        SETTINGS
            .iter()
            .find(|s| s.name == name)
            .ok_or_else(|| ProcedureError::UnknownSetting {
                name: name.to_string(),
                known: SETTINGS
                    .iter()
                    .map(|s| s.name)
                    .collect::<Vec<_>>()
                    .join(", "),
            })?;
    let bad = |expected: &str| ProcedureError::BadSetting {
        name: name.to_string(),
        value: value.to_string(),
        expected: expected.to_string(),
    };
    let parsed = match spec.kind {
        Kind::Positive => match number(value, "a number > 0")? {
            x if x > 0.0 => SetValue::Number(x),
            _ => return Err(bad("a number > 0")),
        },
        Kind::NonNegative => match number(value, "a number >= 0")? {
            x if x >= 0.0 => SetValue::Number(x),
            _ => return Err(bad("a number >= 0")),
        },
        Kind::Open(lo, hi) => match number(value, "a number")? {
            x if x > lo && x < hi => SetValue::Number(x),
            _ => return Err(bad(&format!("a number strictly between {lo} and {hi}"))),
        },
        Kind::Count(min) => match value.parse::<u32>() {
            Ok(n) if n >= min => SetValue::Number(f64::from(n)),
            _ => return Err(bad(&format!("a whole number >= {min}"))),
        },
        Kind::Choice(words) => {
            if words.contains(&value) {
                SetValue::Word(value.to_string())
            } else {
                return Err(bad(&format!("one of {}", words.join(", "))));
            }
        }
        Kind::Switch => match value {
            "on" => SetValue::Switch(true),
            "off" => SetValue::Switch(false),
            _ => return Err(bad("on or off")),
        },
        Kind::PositiveOrOff => match value {
            "off" => SetValue::Off,
            _ => match number(value, "a number > 0 or off")? {
                x if x > 0.0 => SetValue::Number(x),
                _ => return Err(bad("a number > 0 or off")),
            },
        },
        Kind::List => {
            let list = value
                .split(',')
                .map(|w| number(w.trim(), "a number >= 0"))
                .collect::<Parsed<Vec<f64>>>()?;
            if list.iter().any(|x| *x < 0.0) || list.is_empty() {
                return Err(bad("comma-separated numbers >= 0"));
            }
            SetValue::List(list)
        }
    };
    Ok((spec.name, parsed))
}

/// Applies a parsed setting to the session.
pub(crate) fn apply(session: &mut Session, name: &str, value: &SetValue) -> Result<()> {
    let number = match value {
        SetValue::Number(x) => *x,
        _ => f64::NAN,
    };
    let switch = matches!(value, SetValue::Switch(true));
    let s = &mut session.settings;
    match name {
        "youngs_modulus_mpa" | "poisson_ratio" | "density_kg_m3" | "mass_kg" | "alpha" | "beta"
        | "active_coils" | "mean_diameter_mm" | "wire_diameter_mm" | "pitch_mm" => {
            let state = session.state()?;
            match name {
                "youngs_modulus_mpa" => state.youngs_modulus_mpa = number,
                "poisson_ratio" => state.poisson_ratio = number,
                "density_kg_m3" => state.density_kg_m3 = number,
                "mass_kg" => state.mass_kg = number,
                "alpha" => state.alpha = number,
                "beta" => state.beta = number,
                "active_coils" => state.spring.active_coils = number,
                "mean_diameter_mm" => state.spring.mean_diameter_mm = number,
                "wire_diameter_mm" => state.spring.wire_diameter_mm = number,
                _ => state.spring.pitch_mm = number,
            }
            if name != "alpha" && name != "beta" {
                session.model_changed();
            }
            return Ok(());
        }
        "elements_per_coil" => s.fe.elements_per_coil = number as u32,
        "element" => {
            s.fe.element = if matches!(value, SetValue::Word(w) if w == "52") {
                52
            } else {
                98
            }
        }
        "lumped_mass" => s.fe.lumped_mass = switch,
        "static_force_n" => s.fe.static_force_n = number,
        "modes" => s.fe.modes = number as u32,
        "method" => {
            s.damping.decay.method = if matches!(value, SetValue::Word(w) if w == "direct") {
                Method::Direct
            } else {
                Method::Modal
            }
        }
        "check_direct" => s.damping.check_direct = switch,
        "dt_s" => s.damping.decay.dt_s = number,
        "duration_s" => s.damping.decay.duration_s = number,
        "initial_velocity_m_s" => s.damping.decay.initial_velocity_m_s = number,
        "velocity_field" => {
            s.damping.decay.velocity_field = if matches!(value, SetValue::Word(w) if w == "nodal") {
                VelocityField::Nodal
            } else {
                VelocityField::QuasiStatic
            }
        }
        "modal_modes" => s.damping.decay.modal_modes = number as u32,
        "every" => s.damping.decay.every = number as usize,
        "lowpass_hz" => {
            s.damping.decay.lowpass_hz = match value {
                SetValue::Off => None,
                _ => Some(number),
            }
        }
        "valley_alphas" => {
            if let SetValue::List(list) = value {
                s.damping.valley_alphas = list.clone();
            }
            return Ok(());
        }
        "valley_tolerance" => {
            s.damping.valley_tolerance = number;
            return Ok(());
        }
        "stiffness_tolerance" => {
            s.stiffness_tolerance = number;
            return Ok(());
        }
        "period_tolerance" => {
            s.period_tolerance = number;
            return Ok(());
        }
        "progress" => {
            s.damping.progress = switch;
            return Ok(());
        }
        other => {
            return Err(TuneError::Invalid(format!(
                "setting `{other}` has no effect here"
            )))
        }
    }
    session.model_changed();
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::damping::RunControl;
    use crate::fe::SpringState;
    use crate::procedure::tests::assert_parse_errors;
    use std::path::Path;

    #[test]
    fn every_setting_is_defined_once() {
        for (i, s) in SETTINGS.iter().enumerate() {
            assert!(
                SETTINGS[i + 1..].iter().all(|t| t.name != s.name),
                "{}",
                s.name
            );
        }
    }

    /// Every setting in the table is parsed and applied (none falls through to "no
    /// effect").
    #[test]
    fn every_setting_applies() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../cases/160ect");
        let mut session = Session::new(&root.join("x.proc"), None, &RunControl::default());
        // What `case .` does.
        let case = crate::case::read_case(&root).unwrap();
        session.state = Some(SpringState::nominal(&case));
        session.case = Some(case);
        for s in SETTINGS {
            let value = match s.kind {
                Kind::Positive | Kind::NonNegative | Kind::PositiveOrOff => "1".to_string(),
                Kind::Open(lo, hi) => format!("{}", 0.5 * (lo.max(-0.5) + hi)),
                Kind::Count(_) => "8".to_string(),
                Kind::Choice(words) => words[0].to_string(),
                Kind::Switch => "on".to_string(),
                Kind::List => "0,1".to_string(),
            };
            let (name, parsed) = parse_setting(s.name, &value).unwrap();
            apply(&mut session, name, &parsed).unwrap();
        }
        assert_eq!(session.settings.fe.elements_per_coil, 8);
        assert_eq!(session.state.unwrap().youngs_modulus_mpa, 1.0);
    }

    #[test]
    fn bad_settings_name_the_line() {
        assert_parse_errors(&[
            ("set youngs 3\n", 1, "unknown setting `youngs`"),
            ("set elements_per_coil 2\n", 1, "a whole number >= 3"),
            ("set lowpass_hz -3\n", 1, "or off"),
        ]);
    }
}
