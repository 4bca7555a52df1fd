//! The zeta band of a design's candidates: each damping law calibrated to the same
//! measured decay (the calibration's spring at its weight) and carried to a candidate
//! at the target's weight with first-order modal damping (`crate::law`'s formulation:
//! `rayleigh` `alpha d / (2 w) + beta w / 2`, `hysteretic` `eta / 2`, `external_viscous`
//! `c phi_w^2 / (2 w)`, from coil's FE weight mode).
//!
//! Laws: the calibration's own Rayleigh pair (`calibrated_rayleigh`), and the four of
//! `crate::law::BAND_LAWS` (Rayleigh with beta alone, with alpha alone, a loss factor, a
//! dashpot at the weight), each fitted to the reference zeta alone.
//!
//! What geometry can buy: at a fixed weight the viscous laws give `zeta ~ sqrt(K)`
//! (`beta w / 2` with `w^2 = K / m_eff`), the loss factor gives the same zeta whatever
//! the spring; so a target (K, zeta) off those curves cannot be met by the wire alone.

use super::target::DampingReference;
use crate::case::DecayMode;
use crate::error::Result;
use crate::fe::{FeSettings, SpringState};
use crate::law::{mode_coefficients, Coefficients, Law, BAND_LAWS};
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
    out
}

impl LawBand {
    /// Calibrates every law to the reference's measured zeta on its own weight mode.
    pub fn calibrate(reference: &DampingReference, fe: &FeSettings) -> Result<Self> {
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
