//! The zeta band of a design's candidates: each damping law calibrated to the same
//! measured decay (the calibration's spring at its weight) and carried to a candidate
//! at the target's weight with first-order modal damping (`coil_tuner::band`'s formulation:
//! `rayleigh` `alpha d / (2 w) + beta w / 2`, `hysteretic` `eta / 2`, `external_viscous`
//! `c phi_w^2 / (2 w)`, from coil's FE weight mode).
//!
//! Laws: the calibration's own Rayleigh pair (`calibrated_rayleigh`), the four of
//! `coil_tuner::band::BAND_LAWS` (Rayleigh with beta alone, with alpha alone, a loss factor, a
//! dashpot at the weight), each fitted to the reference zeta alone, and, when a
//! damping.json of `coil-tune damping` identified one, that law with its fitted
//! parameters (`identified_<law>`).
//!
//! What geometry can buy: at a fixed weight Rayleigh beta gives `zeta ~ sqrt(K)`
//! (`beta w / 2` with `w^2 = K / m_eff`), a dashpot at the weight `zeta ~ 1/sqrt(K)`, a
//! loss factor the same zeta whatever the spring; so a target (K, zeta) off those curves
//! cannot be met by the wire alone.

use super::target::{DampingReference, IdentifiedLaw};
use crate::case::DecayMode;
use crate::error::Result;
use crate::fe::{FeSettings, SpringState};
use coil_tuner::band::{mode_coefficients, Coefficients, Law, BAND_LAWS};
use std::collections::BTreeMap;

/// The calibrated laws of the band.
#[derive(Debug, Clone, PartialEq)]
pub struct LawBand {
    /// The calibration's alpha (1/s) and beta (s).
    pub calibrated: (f64, f64),
    /// The [`BAND_LAWS`] parameters: beta (s), alpha (1/s), loss factor, dashpot (N s/m).
    pub parameters: [f64; 4],
    /// FE settings of the modal runs.
    pub fe: FeSettings,
    /// The law a damping.json identified, with its parameters in the law's order.
    pub identified: Option<(Law, Vec<f64>)>,
}

/// zeta per law for the mode coefficients `c`.
fn zetas(band: &LawBand, c: &Coefficients) -> BTreeMap<String, f64> {
    let r = c.row(Law::Rayleigh);
    let (alpha, beta) = band.calibrated;
    let p = band.parameters;
    let values = [
        p[0] * r[1],
        p[1] * r[0],
        p[2] * c.row(Law::Hysteretic)[0],
        p[3] * c.row(Law::ExternalViscous)[0],
    ];
    let mut out: BTreeMap<String, f64> = BAND_LAWS
        .iter()
        .zip(values)
        .map(|(name, z)| (name.to_string(), z))
        .collect();
    out.insert("calibrated_rayleigh".into(), alpha * r[0] + beta * r[1]);
    if let Some((law, p)) = &band.identified {
        let z = c.row(*law).iter().zip(p).map(|(a, b)| a * b).sum();
        out.insert(format!("identified_{}", law.name()), z);
    }
    out
}

/// A damping.json's law by name with its parameters in [`Law::parameters`] order.
fn identified_law(found: &IdentifiedLaw) -> Result<(Law, Vec<f64>)> {
    let (name, parameters) = found;
    let law = coil_tuner::band::LAWS
        .into_iter()
        .find(|l| l.name() == name)
        .ok_or_else(|| {
            crate::TuneError::Invalid(format!(
                "damping.json: law \"{name}\"; expected rayleigh, hysteretic or external_viscous"
            ))
        })?;
    let values = law
        .parameters()
        .iter()
        .map(|p| {
            parameters.get(*p).copied().ok_or_else(|| {
                crate::TuneError::Invalid(format!("damping.json: the {name} law without {p}"))
            })
        })
        .collect::<Result<Vec<f64>>>()?;
    Ok((law, values))
}

impl LawBand {
    /// Calibrates every law to the reference's measured zeta on its own weight mode;
    /// `identified` is a damping.json's law and parameters (spec names), predicted as
    /// `identified_<law>`.
    pub fn calibrate(
        reference: &DampingReference,
        fe: &FeSettings,
        identified: Option<&IdentifiedLaw>,
    ) -> Result<Self> {
        let c = mode_coefficients(&reference.state, fe, DecayMode::Axial)?;
        let r = c.row(Law::Rayleigh);
        let z = reference.damping_ratio;
        Ok(LawBand {
            calibrated: (reference.state.alpha, reference.state.beta),
            parameters: [
                z / r[1],
                z / r[0],
                z / c.row(Law::Hysteretic)[0],
                z / c.row(Law::ExternalViscous)[0],
            ],
            fe: fe.clone(),
            identified: identified.map(identified_law).transpose()?,
        })
    }

    /// zeta of `state`'s weight mode (its mass is the weight) under every law.
    pub fn zeta(&self, state: &SpringState) -> Result<BTreeMap<String, f64>> {
        Ok(zetas(
            self,
            &mode_coefficients(state, &self.fe, DecayMode::Axial)?,
        ))
    }
}
