//! The catalogue of effects the diagnosis can name (`docs/measured-case.md`).
//!
//! One [`Effect`] per physical cause carries everything about it: its name, parameter
//! and unit (exactly the spec's), how it extends the reduced FE model (the point law it
//! adds at the weight or the rotary inertia it frees, [`Effect::apply`], and the mount
//! it needs, [`Mount`]), its static force if it shows in the static record, the
//! evidence and starting values its signature gives ([`Effect::propose`]) and the check
//! that a fitted value agrees with that signature ([`Effect::signature`]). Adding an
//! effect is one more entry in [`CATALOGUE`]: the model, the fit, the choice and the
//! report iterate over the catalogue and know no effect by name.
//!
//! Signatures (weak nonlinearity, first-order harmonic balance / energy balance per
//! cycle, displacement amplitude `A`, `k = m w^2`):
//! - `coulomb_friction`: constant amplitude loss `4F/k` per cycle (a linear envelope),
//!   static hysteresis of half-width `F`;
//! - `quadratic_damping`: loss `(8/3) c2 A^2 / m` per cycle;
//! - `cubic_stiffness`: curvature of the static record (`k x + k3 x^3`), and a backbone
//!   `w(A)^2 = w0^2 (1 + b A^2)`;
//! - `axial_torsional_coupling`: a second spectral line beside the axial one and a
//!   beating envelope; with the reduced model's 2x2 boundary stiffness `[kz c; c kt]`
//!   the two lines give the weight's mass and rotary inertia through
//!   `w1^2 + w2^2 = kz/m + kt/J` and `w1^2 w2^2 = (kz kt - c^2)/(m J)`. The second
//!   line is the coupling's only if it is no stronger than the helix's coupling makes
//!   it after a start along the axis ([`CoupledPair`]): within
//!   [`COUPLED_LINE_MARGIN`] of the ratio of the lines' axial shares.

use super::evidence::{robust_backbone, robust_loss, LossSummary, Signatures};
use coil_solver::integrate::PointLaw;
use coil_solver::model::units;

/// How the weight is mounted.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mount {
    /// The paper's model: the weight moves along the axis only.
    Guided,
    /// The weight also turns about the axis.
    FreeRotation,
}

/// What a set of effects adds to the linear model: a point law at the weight's axial
/// DOF (solver units) and the weight's rotary inertia (kg m^2, a free rotation).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Extension {
    /// The point law at the weight's axial DOF (solver units).
    pub law: PointLaw,
    /// The weight's rotary inertia about the spring axis (kg m^2); 0 while the weight is guided.
    pub rotary_inertia_kg_m2: f64,
}

/// Whether a fitted value agrees with the effect's own signature in the records.
#[derive(Debug, Clone, serde::Serialize)]
pub struct SignatureCheck {
    /// True when `value` is finite and reaches `limit`.
    pub passed: bool,
    /// The signature's strength (standard errors; relative amplitude over its threshold
    /// for a spectral line) and the limit it must reach.
    pub value: f64,
    /// The strength the signature must reach.
    pub limit: f64,
    /// The check in words with its numbers, for the report.
    pub text: String,
}

/// A signature term must stand this many standard errors clear of zero (95 %, two-sided).
pub const SIGNATURE_Z: f64 = 2.0;

/// The starting point and evidence an effect draws from the records.
#[derive(Debug, Clone)]
pub struct Proposal {
    /// What the records say about this effect, for a person.
    pub evidence: String,
    /// Starting values of the parameter (SI, the spec's unit), best first.
    pub starts: Vec<f64>,
    /// Strength of the signature in standard errors (0 when absent).
    pub z_score: f64,
}

/// What an effect needs from the baseline to turn a signature into a parameter.
#[derive(Debug, Clone, Copy)]
pub struct BaselineFigures {
    /// Weight's mass (kg) and the axial stiffness (N/m) of the calibrated model.
    pub mass_kg: f64,
    /// Axial stiffness of the calibrated model (N/m).
    pub stiffness_n_m: f64,
    /// Axial frequency (Hz).
    pub frequency_hz: f64,
    /// Largest displacement amplitude in the record (m).
    pub amplitude_m: f64,
    /// Static deflection under gravity (m).
    pub preload_m: f64,
    /// The damping ratio the linear reference gives the axial mode, `beta w / 2` (-):
    /// all the record's loss, counted as viscous.
    pub damping_ratio: f64,
    /// Boundary stiffness of the free-rotation model: axial (N/m), coupling (N/rad),
    /// torsional (N m/rad).
    pub kz: f64,
    /// Axial-torsional coupling of the free-rotation boundary stiffness (N/rad).
    pub c: f64,
    /// Torsional stiffness of the free-rotation boundary (N m/rad).
    pub kt: f64,
}

/// One catalogue entry.
pub trait Effect: Sync {
    /// The spec's name.
    fn name(&self) -> &'static str;
    /// The spec's parameter name (with its unit).
    fn parameter(&self) -> &'static str;
    /// The parameter's unit, in words for the report.
    fn unit(&self) -> &'static str;
    /// True when the parameter takes either sign (fitted as itself, not as a logarithm).
    fn signed(&self) -> bool {
        false
    }
    /// Adds the effect at magnitude `value` (SI, the spec's unit) to the model.
    fn apply(&self, value: f64, extension: &mut Extension);
    /// The weight's mounting it needs.
    fn mount(&self) -> Mount {
        Mount::Guided
    }
    /// True when it dissipates energy beside the linear damping (its fit then also
    /// starts with only the viscous part of the damping in beta).
    fn dissipative(&self) -> bool {
        false
    }
    /// Its force in the static record at compression `x_m` (N), when it shows there:
    /// the static record is then fitted with the decay.
    fn static_force(&self, _value: f64, _x_m: f64) -> Option<f64> {
        None
    }
    /// Evidence and starting values.
    fn propose(&self, s: &Signatures, b: &BaselineFigures) -> Proposal;
    /// Whether the fitted `value` agrees with the effect's own signature.
    fn signature(&self, s: &Signatures, b: &BaselineFigures, value: f64) -> SignatureCheck;
    /// The magnitude at which the effect matters on this record (the parameter's unit):
    /// a dissipative effect's viscous equivalent ([`viscous_loss_m`]), a cubic spring's
    /// `k / A^2`, a rotary inertia's tuned value `k_t / w^2`. A fitted value below
    /// [`BOUND_SHARE`] of it did not move from its bound, zero.
    fn scale(&self, s: &Signatures, b: &BaselineFigures) -> f64;
}

/// The share of an effect's [`Effect::scale`] below which a fitted value is at its
/// bound (zero): it changes the simulated record by less than a millionth of what the
/// effect at its scale would.
pub const BOUND_SHARE: f64 = 1e-6;

/// Whether `value` of effect `e` sits at its bound, and the note the report gives
/// then (in words, with the reason).
pub fn at_bound(e: &dyn Effect, value: f64, s: &Signatures, b: &BaselineFigures) -> Option<String> {
    let scale = e.scale(s, b);
    (scale.is_finite() && scale > 0.0 && value.abs() < BOUND_SHARE * scale).then(|| {
        format!(
            "{} did not move from its bound (0 {}): the fit walked it below {BOUND_SHARE:e} of \
             the magnitude at which it would matter on this record ({scale:.3e} {}), so the \
             records give it no support; its standard error is not defined",
            e.parameter(),
            e.unit(),
            e.unit()
        )
    })
}

fn check(value: f64, limit: f64, text: String) -> SignatureCheck {
    SignatureCheck {
        passed: value.is_finite() && value >= limit,
        value,
        limit,
        text,
    }
}

/// Starts of a dissipative effect: its signature's estimate `value` (and a third and
/// three times it), or without one a short scan of its magnitude, a quarter, a half and
/// one times `equivalent`, the value that would carry all the loss the linear model
/// attributes to viscous damping ([`viscous_loss_m`]).
fn starts(value: f64, equivalent: f64) -> Vec<f64> {
    if value.is_finite() && value > 0.0 {
        vec![value, 0.3 * value, 3.0 * value]
    } else {
        SCAN.iter().map(|s| s * equivalent).collect()
    }
}

/// The shares of the viscous equivalent a dissipative effect without a signature
/// starts from.
pub const SCAN: [f64; 3] = [1.0, 0.5, 0.25];

/// The loss per cycle the linear model attributes to viscous damping at the record's
/// largest amplitude `A`, `2 pi zeta A` (m), from the reference's damping ratio; a
/// tenth of the amplitude over the record's cycles when that ratio is not positive.
pub fn viscous_loss_m(s: &Signatures, b: &BaselineFigures) -> f64 {
    let linear = std::f64::consts::TAU * b.damping_ratio * b.amplitude_m;
    if linear.is_finite() && linear > 0.0 {
        linear
    } else {
        0.1 * b.amplitude_m / s.cycles.max(1.0)
    }
}

/// The largest of a loss term's z-scores over the estimators that formed it: the
/// windowed per-cycle fit (`loss`), the per-cycle refit without outliers and the
/// half-cycle fit; NaN when none could.
fn best_z(s: &Signatures, term: usize, limit: f64) -> f64 {
    let of = |l: &LossSummary| match term {
        0 => l.friction_z(limit),
        _ => l.drag_z(limit),
    };
    let windowed = s.loss.as_ref().map_or(f64::NAN, of);
    let half = s.half_cycle_loss.as_ref().map_or(f64::NAN, of);
    windowed.max(half).max(robust_z(s, term))
}

/// `coulomb_friction`: a dry friction force of constant magnitude `friction_force_n` (N).
pub struct CoulombFriction;
impl Effect for CoulombFriction {
    fn dissipative(&self) -> bool {
        true
    }
    fn name(&self) -> &'static str {
        "coulomb_friction"
    }
    fn parameter(&self) -> &'static str {
        "friction_force_n"
    }
    fn unit(&self) -> &'static str {
        "N"
    }
    fn apply(&self, value: f64, e: &mut Extension) {
        e.law.friction += value;
    }
    fn scale(&self, s: &Signatures, b: &BaselineFigures) -> f64 {
        viscous_loss_m(s, b) * b.stiffness_n_m / 4.0
    }
    fn signature(&self, s: &Signatures, _b: &BaselineFigures, _value: f64) -> SignatureCheck {
        // A constant term in the loss per cycle, or the static record's hysteresis.
        let loss = best_z(s, 0, SIGNATURE_Z);
        let hysteresis = s
            .statics
            .map_or(f64::NAN, |st| st.friction_n / st.friction_se);
        let z = loss.max(hysteresis);
        check(
            if z.is_nan() { 0.0 } else { z },
            SIGNATURE_Z,
            format!(
                "constant loss per cycle a0 at {} standard errors{}",
                show_z(loss),
                if hysteresis.is_finite() {
                    format!(", static hysteresis at {hysteresis:.1}")
                } else {
                    String::new()
                }
            ),
        )
    }
    fn propose(&self, s: &Signatures, b: &BaselineFigures) -> Proposal {
        let from_loss = s
            .loss
            .map(|l| (l.a0_m * b.stiffness_n_m / 4.0, l.a0_m / l.a0_se));
        let mut text = match from_loss {
            Some((f, z)) if f > 0.0 => format!(
                "constant loss per cycle a0 = 4F/k gives F = {f:.4} N ({z:.1} standard errors); \
                 envelope {} (R^2 linear {:.4}, exponential {:.4})",
                s.envelope.kind, s.envelope.r2_linear, s.envelope.r2_exponential
            ),
            Some((_, z)) => format!(
                "no constant loss per cycle (a0 <= 0, {z:.1} standard errors); envelope {}",
                s.envelope.kind
            ),
            None => "no per-cycle loss curve".to_string(),
        };
        if let Some(st) = &s.statics {
            if st.friction_n > 0.0 && st.friction_se.is_finite() {
                text.push_str(&format!(
                    "; static hysteresis half-width {:.4} N ({:.1} standard errors)",
                    st.friction_n,
                    st.friction_n / st.friction_se
                ));
            } else {
                text.push_str("; no static hysteresis");
            }
        }
        // Without a signature: the friction whose constant loss 4F/k equals the viscous
        // loss at the largest amplitude, scanned.
        let equivalent = self.scale(s, b);
        let (value, z) = from_loss.unwrap_or((f64::NAN, 0.0));
        let mut starts = starts(value, equivalent);
        push_half_start(
            &mut starts,
            s.half_cycle_loss.map(|l| l.a0_m * b.stiffness_n_m / 4.0),
        );
        Proposal {
            evidence: text,
            starts,
            z_score: z.max(0.0),
        }
    }
}

/// `quadratic_damping`: a drag `c2 v |v|` on the weight, `quadratic_damping_n_s2_m2` (N s^2/m^2).
pub struct QuadraticDamping;
impl Effect for QuadraticDamping {
    fn dissipative(&self) -> bool {
        true
    }
    fn name(&self) -> &'static str {
        "quadratic_damping"
    }
    fn parameter(&self) -> &'static str {
        "quadratic_damping_n_s2_m2"
    }
    fn unit(&self) -> &'static str {
        "N s^2/m^2"
    }
    fn apply(&self, value: f64, e: &mut Extension) {
        e.law.quadratic += units::quadratic_damping_from_si(value);
    }
    fn scale(&self, s: &Signatures, b: &BaselineFigures) -> f64 {
        let amplitude = b.amplitude_m.max(1e-9);
        3.0 * viscous_loss_m(s, b) * b.mass_kg / (8.0 * amplitude * amplitude)
    }
    fn signature(&self, s: &Signatures, _b: &BaselineFigures, _value: f64) -> SignatureCheck {
        // A loss per cycle growing as A^2.
        let z = best_z(s, 2, SIGNATURE_Z);
        check(
            if z.is_nan() { 0.0 } else { z },
            SIGNATURE_Z,
            format!(
                "loss per cycle growing as A^2 (a2) at {} standard errors",
                show_z(z)
            ),
        )
    }
    fn propose(&self, s: &Signatures, b: &BaselineFigures) -> Proposal {
        let from_loss = s
            .loss
            .map(|l| (3.0 * l.a2_per_m * b.mass_kg / 8.0, l.a2_per_m / l.a2_se));
        let text = match from_loss {
            Some((c2, z)) if c2 > 0.0 => format!(
                "loss per cycle growing with A^2: a2 = (8/3) c2/m gives c2 = {c2:.4} N s^2/m^2 \
                 ({z:.1} standard errors)"
            ),
            Some((_, z)) => format!("no loss growing with A^2 (a2 <= 0, {z:.1} standard errors)"),
            None => "no per-cycle loss curve".to_string(),
        };
        // Without a signature: the drag whose loss (8/3) c2 A^2 / m equals the viscous
        // loss at the largest amplitude A, scanned.
        let equivalent = self.scale(s, b);
        let (value, z) = from_loss.unwrap_or((f64::NAN, 0.0));
        let mut starts = starts(value, equivalent);
        push_half_start(
            &mut starts,
            s.half_cycle_loss
                .map(|l| 3.0 * l.a2_per_m * b.mass_kg / 8.0),
        );
        Proposal {
            evidence: text,
            starts,
            z_score: z.max(0.0),
        }
    }
}

/// `cubic_stiffness`: the spring force `k x + k3 x^3`, `cubic_stiffness_n_m3` (N/m^3, either sign).
pub struct CubicStiffness;
impl Effect for CubicStiffness {
    fn name(&self) -> &'static str {
        "cubic_stiffness"
    }
    fn parameter(&self) -> &'static str {
        "cubic_stiffness_n_m3"
    }
    fn unit(&self) -> &'static str {
        "N/m^3"
    }
    fn signed(&self) -> bool {
        true
    }
    fn apply(&self, value: f64, e: &mut Extension) {
        e.law.cubic += units::cubic_stiffness_from_si(value);
    }
    fn scale(&self, _s: &Signatures, b: &BaselineFigures) -> f64 {
        b.stiffness_n_m / b.amplitude_m.max(1e-9).powi(2)
    }
    fn static_force(&self, value: f64, x_m: f64) -> Option<f64> {
        Some(value * x_m * x_m * x_m)
    }
    fn signature(&self, s: &Signatures, b: &BaselineFigures, value: f64) -> SignatureCheck {
        // The backbone's slope, of the sign the fitted k3 gives about the preload
        // (b = 3 k3/(4 k_t) - 7.5 (k3 x_s)^2 / k_t^2), or the static curvature of the
        // fitted k3's sign.
        let kt = b.stiffness_n_m + 3.0 * value * b.preload_m * b.preload_m;
        let predicted = 3.0 * value / (4.0 * kt) - 7.5 * (value * b.preload_m / kt).powi(2);
        // The larger of the two estimates (the post-processor's and the per-cycle
        // refit without outlying cycles), in the direction the fitted k3 predicts.
        let sign = predicted.signum();
        let robust = robust_backbone(&s.per_cycle).map_or(f64::NAN, |(b, se)| b / se * sign);
        let backbone = s
            .backbone
            .map_or(f64::NAN, |bb| bb.b_per_m2 / bb.b_se * sign)
            .max(robust);
        let statics = s
            .statics
            .map_or(f64::NAN, |st| st.k3_n_m3 / st.k3_se * value.signum());
        let z = backbone.max(statics);
        check(
            if z.is_nan() { 0.0 } else { z },
            SIGNATURE_Z,
            format!(
                "backbone slope of the fitted k3's sign (predicted b = {predicted:.3e} 1/m^2) at \
                 {} standard errors{}",
                show_z(backbone),
                if statics.is_finite() {
                    format!(", static curvature of its sign at {statics:.1}")
                } else {
                    // About a preload x_s the backbone is quadratic in k3: its two roots
                    // sum to k_t / (10 x_s^2), so the backbone alone also admits the
                    // other one (a hanging rig without a static record).
                    let other = b.stiffness_n_m / (10.0 * b.preload_m * b.preload_m) - value;
                    format!(
                        ", no static record (the backbone alone also admits k3 = {other:.3e} \
                         N/m^3 at this preload; a static record decides)"
                    )
                }
            ),
        )
    }
    fn propose(&self, s: &Signatures, b: &BaselineFigures) -> Proposal {
        let mut text = Vec::new();
        let mut values = Vec::new();
        let mut z_score: f64 = 0.0;
        // The static curvature first: a direct measurement of k3 at the free length;
        // the backbone's value rests on a first-order expansion about the preload.
        if let Some(st) = &s.statics {
            let z = st.k3_n_m3 / st.k3_se;
            text.push(format!(
                "static curvature k3 = {:.4e} N/m^3 ({z:.1} standard errors; residual RMS \
                 linear {:.4} N, cubic {:.4} N)",
                st.k3_n_m3, st.linear_rms_n, st.cubic_rms_n
            ));
            values.push(st.k3_n_m3);
            z_score = z_score.max(z);
        }
        if let Some(bb) = s.backbone {
            let z = bb.b_per_m2 / bb.b_se;
            text.push(format!(
                "backbone f^2 = f0^2 (1 + b A^2), b = {:.4e} 1/m^2 ({z:.1} standard errors){}",
                bb.b_per_m2,
                if bb.k3_n_m3.is_finite() {
                    format!(" gives k3 = {:.4e} N/m^3", bb.k3_n_m3)
                } else {
                    ", more bend than a cubic spring at this preload can give".to_string()
                }
            ));
            values.push(bb.k3_n_m3);
            z_score = z_score.max(z);
        }
        let fallback = 0.01 * b.stiffness_n_m / b.amplitude_m.max(b.preload_m).max(1e-6).powi(2);
        // Either sign: a softening spring (k3 < 0) is as likely as a hardening one.
        let mut starts: Vec<f64> = values
            .into_iter()
            .filter(|v| v.is_finite() && *v != 0.0)
            .collect();
        if starts.is_empty() {
            starts = vec![fallback, -fallback];
        }
        Proposal {
            evidence: if text.is_empty() {
                "no static record and no backbone".into()
            } else {
                text.join("; ")
            },
            starts,
            z_score,
        }
    }
}

/// `axial_torsional_coupling`: the weight turns, rotary inertia `rotary_inertia_kg_m2` (kg m^2).
pub struct AxialTorsionalCoupling;
impl Effect for AxialTorsionalCoupling {
    fn name(&self) -> &'static str {
        "axial_torsional_coupling"
    }
    fn parameter(&self) -> &'static str {
        "rotary_inertia_kg_m2"
    }
    fn unit(&self) -> &'static str {
        "kg m^2"
    }
    fn apply(&self, value: f64, e: &mut Extension) {
        e.rotary_inertia_kg_m2 += value;
    }
    fn scale(&self, _s: &Signatures, b: &BaselineFigures) -> f64 {
        let w = std::f64::consts::TAU * b.frequency_hz;
        b.kt / (w * w)
    }
    fn signature(&self, s: &Signatures, b: &BaselineFigures, value: f64) -> SignatureCheck {
        // A second spectral line, or a beating envelope ...
        let line = s.second_peak.map_or(0.0, |p| p.z_score);
        let beat = if s.envelope.kind == "beating" {
            1.0
        } else {
            0.0
        };
        let seen = format!(
            "{}; envelope {}",
            s.second_peak
                .map_or("one spectral line".to_string(), |p| format!(
                    "a second line at {:.4} Hz, {:.1} % of the axial one",
                    p.frequency_hz,
                    100.0 * p.relative_amplitude
                )),
            s.envelope.kind
        );
        // ... no stronger than the helix's coupling makes it at the fitted inertia.
        let pair = s.second_peak.zip(CoupledPair::of(b, value));
        let Some((peak, pair)) = pair else {
            return check(line.max(beat), 1.0, seen);
        };
        let excess = peak.relative_amplitude / pair.axial_start_ratio;
        let room = COUPLED_LINE_MARGIN / excess;
        check(
            line.max(beat).min(room),
            1.0,
            format!(
                "{seen}; at the fitted rotary inertia the helix's coupling gives lines at \
                 {:.4} and {:.4} Hz with axial shares {:.3} and {:.3}, so a start along \
                 the axis shows the weaker at most {:.1} % of the stronger: the record's \
                 line is {excess:.2} times that ({}, limit {COUPLED_LINE_MARGIN})",
                pair.frequency_hz[0],
                pair.frequency_hz[1],
                pair.axial_share[0],
                pair.axial_share[1],
                100.0 * pair.axial_start_ratio,
                if room >= 1.0 {
                    "the coupling's own line"
                } else {
                    "a start that turned the weight, or a mode the helix does not couple"
                }
            ),
        )
    }
    fn mount(&self) -> Mount {
        Mount::FreeRotation
    }
    fn propose(&self, s: &Signatures, b: &BaselineFigures) -> Proposal {
        // Torsion tuned to the axial frequency: the largest beating, the fallback.
        let w = std::f64::consts::TAU * b.frequency_hz;
        let tuned = b.kt / (w * w);
        let Some(p) = s.second_peak else {
            return Proposal {
                evidence: format!(
                    "one spectral line; envelope {} (beat period {})",
                    s.envelope.kind,
                    s.envelope
                        .beat_period_s
                        .map_or("none".into(), |t| format!("{t:.2} s"))
                ),
                starts: vec![tuned, 0.9 * tuned, 1.1 * tuned],
                z_score: 0.0,
            };
        };
        let (w1, w2) = (
            std::f64::consts::TAU * s.axial_hz,
            std::f64::consts::TAU * p.frequency_hz,
        );
        let (sum, product) = (w1 * w1 + w2 * w2, w1 * w1 * w2 * w2);
        // x = 1/m, y = 1/J: kz x + kt y = sum, (kz kt - c^2) x y = product.
        let det = b.kz * b.kt - b.c * b.c;
        let mut candidates = Vec::new();
        let disc = sum * sum - 4.0 * b.kz * b.kt * product / det;
        if disc >= 0.0 && det > 0.0 {
            for sign in [1.0, -1.0] {
                let x = (sum + sign * disc.sqrt()) / (2.0 * b.kz);
                let y = (sum - b.kz * x) / b.kt;
                if x > 0.0 && y > 0.0 {
                    candidates.push((1.0 / x, 1.0 / y));
                }
            }
        }
        // Of the two assignments, the one whose mass is nearer the calibrated one.
        candidates.sort_by(|a, c| (a.0 - b.mass_kg).abs().total_cmp(&(c.0 - b.mass_kg).abs()));
        let mut starts: Vec<f64> = candidates.iter().map(|c| c.1).collect();
        // Uncoupled torsion at the second line (weak coupling).
        starts.push(b.kt / (w2 * w2));
        starts.push(tuned);
        Proposal {
            evidence: format!(
                "second spectral line at {:.4} Hz beside {:.4} Hz ({:.1} % of its amplitude), \
                 beat period {:.2} s; envelope {}",
                p.frequency_hz,
                s.axial_hz,
                100.0 * p.relative_amplitude,
                1.0 / (p.frequency_hz - s.axial_hz).abs(),
                s.envelope.kind
            ),
            starts,
            z_score: p.z_score,
        }
    }
}

/// How many times stronger than a start along the axis gives it (through the helix's
/// coupling, [`CoupledPair::axial_start_ratio`]) the record's second line may be and
/// still be the coupling's: the bound covers the line's spectral height (Hann window,
/// the two lines decaying at rates that differ by `beta (w2^2 - w1^2) / 2`, under 20 %
/// over the generated coupling records) and the reduced model's boundary against the
/// spring's distributed mass (a few per cent). A second mode the helix does not couple
/// (a frame, a pendulum), or a start that turned the weight, shows a line many times
/// stronger (8 and 30 times on `close_mode_g2` and `close_mode_g1`).
pub const COUPLED_LINE_MARGIN: f64 = 2.0;

/// The two lines of the weight on the free-rotation boundary `[kz c; c kt]` (N/m,
/// N/rad, N m/rad) with its mass `m` and rotary inertia `J`: in the mass-scaled
/// coordinates `(sqrt(m) u, sqrt(J) theta)` the stiffness is
/// `[kz/m, c/sqrt(m J); c/sqrt(m J), kt/J]`, symmetric; its eigenvalues are the lines'
/// `w^2` and the squared axial component of each unit eigenvector is that line's axial
/// share `p` (the shares sum to one).
///
/// A start along the axis (the weight displaced by `u0` and moving at `v0`, not
/// turned) puts `p_i u0 cos(w_i t) + p_i v0 sin(w_i t) / w_i` of line `i` in the axial
/// displacement; a release from a static axial pull (the weight free to turn, so the
/// pull twists it by the helix's own coupling) `p_i F cos(w_i t) / (m w_i^2)`. In the
/// acceleration the lines then stand in the ratio `(p_w / p_s) (w_w / w_s)^k`, `k`
/// between 0 (the pull) and 2 (a displacement), `w` the weaker line, `s` the stronger.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CoupledPair {
    /// The lines' frequencies, lower first (Hz).
    pub frequency_hz: [f64; 2],
    /// Each line's axial share `p` (-).
    pub axial_share: [f64; 2],
    /// The largest ratio of the weaker line's acceleration amplitude to the stronger's
    /// that a start along the axis gives: `(p_w / p_s) max(1, w_w / w_s)^2` (-).
    pub axial_start_ratio: f64,
}

impl CoupledPair {
    /// The pair of the figures' boundary with the calibrated mass and rotary inertia
    /// `j` (kg m^2); `None` without a free rotation or a positive inertia.
    pub fn of(b: &BaselineFigures, j: f64) -> Option<CoupledPair> {
        let m = b.mass_kg;
        if !(m > 0.0 && j > 0.0 && b.kz > 0.0 && b.kt > 0.0 && b.c.is_finite()) {
            return None;
        }
        let (a, d, g) = (b.kz / m, b.kt / j, b.c / (m * j).sqrt());
        let mean = 0.5 * (a + d);
        let half = (0.25 * (a - d) * (a - d) + g * g).sqrt();
        let lambda = [mean - half, mean + half];
        if lambda[0] <= 0.0 {
            return None;
        }
        // The unit eigenvector for lambda is (g, lambda - a) normalised; uncoupled
        // (g = 0) the line at `a` is all axial.
        let share = |l: f64| {
            let n = g * g + (l - a) * (l - a);
            if n > 0.0 && g != 0.0 {
                g * g / n
            } else if (l - a).abs() <= (l - d).abs() {
                1.0
            } else {
                0.0
            }
        };
        let axial_share = [share(lambda[0]), share(lambda[1])];
        let frequency_hz = lambda.map(|l| l.sqrt() / std::f64::consts::TAU);
        let (s, w) = if axial_share[0] >= axial_share[1] {
            (0, 1)
        } else {
            (1, 0)
        };
        let r = (frequency_hz[w] / frequency_hz[s]).max(1.0);
        Some(CoupledPair {
            frequency_hz,
            axial_share,
            axial_start_ratio: axial_share[w] / axial_share[s].max(f64::MIN_POSITIVE) * r * r,
        })
    }
}

/// The half-cycle fit's estimate as one more start, when it is positive and not
/// within 20 % of a start already there.
fn push_half_start(starts: &mut Vec<f64>, half: Option<f64>) {
    if let Some(v) = half.filter(|v| v.is_finite() && *v > 0.0) {
        if starts.iter().all(|s| (s / v - 1.0).abs() > 0.2) {
            starts.push(v);
        }
    }
}

/// The z-score of loss term `term` (0: a0, 1: a1, 2: a2) of the per-cycle loss refitted
/// without outlying cycles (`evidence::robust_loss`); NaN when it cannot be formed.
fn robust_z(s: &Signatures, term: usize) -> f64 {
    robust_loss(&s.per_cycle).map_or(f64::NAN, |(c, se)| c[term] / se[term])
}

fn show_z(z: f64) -> String {
    if z.is_finite() {
        format!("{z:.1}")
    } else {
        "- (no estimate)".into()
    }
}

/// Number of entries in [`CATALOGUE`].
pub const COUNT: usize = 4;

/// What the effects at `values` (indexed as [`CATALOGUE`]) add to the model.
pub fn extension(values: &[f64; COUNT]) -> Extension {
    let mut e = Extension::default();
    for (effect, &v) in CATALOGUE.iter().zip(values) {
        if v != 0.0 {
            effect.apply(v, &mut e);
        }
    }
    e
}

/// Every effect the diagnosis tries, in report order.
pub static CATALOGUE: [&dyn Effect; COUNT] = [
    &CoulombFriction,
    &QuadraticDamping,
    &CubicStiffness,
    &AxialTorsionalCoupling,
];

#[cfg(test)]
mod tests {
    use super::*;
    use crate::diagnose::evidence::{EnvelopeSummary, PeakSummary};

    fn figures(kz: f64, c: f64, kt: f64, m: f64) -> BaselineFigures {
        BaselineFigures {
            mass_kg: m,
            stiffness_n_m: kz,
            frequency_hz: (kz / m).sqrt() / std::f64::consts::TAU,
            amplitude_m: 1e-3,
            preload_m: 0.0,
            damping_ratio: 1e-3,
            kz,
            c,
            kt,
        }
    }

    /// The pair's lines satisfy the two closed forms of the module docs, its shares
    /// sum to one, and the tuned pair (kz/m = kt/J) shares the axial motion equally.
    #[test]
    fn coupled_pair_against_closed_forms() {
        let (kz, c, kt, m) = (3000.0, 0.8, 0.02, 2.8);
        for j in [2e-5, 6.67e-6, 3e-6] {
            let p = CoupledPair::of(&figures(kz, c, kt, m), j).expect("a pair");
            let w = p.frequency_hz.map(|f| (std::f64::consts::TAU * f).powi(2));
            let sum = kz / m + kt / j;
            let product = (kz * kt - c * c) / (m * j);
            assert!((w[0] + w[1] - sum).abs() <= 1e-12 * sum, "{p:?}");
            assert!((w[0] * w[1] - product).abs() <= 1e-10 * product, "{p:?}");
            assert!((p.axial_share[0] + p.axial_share[1] - 1.0).abs() <= 1e-12);
        }
        let tuned = CoupledPair::of(&figures(kz, c, kt, m), kt * m / kz).expect("a pair");
        assert!((tuned.axial_share[0] - 0.5).abs() < 1e-12, "{tuned:?}");
        // Uncoupled, the torsional line never shows in the axial record.
        let free = CoupledPair::of(&figures(kz, 0.0, kt, m), 2e-5).expect("a pair");
        assert_eq!(free.axial_start_ratio, 0.0, "{free:?}");
    }

    fn quiet_record() -> Signatures {
        Signatures {
            axial_hz: 5.0,
            noise_rms_m_s2: 1e-3,
            cycles: 40.0,
            loss: None,
            half_cycle_loss: None,
            backbone: None,
            envelope: EnvelopeSummary {
                kind: "exponential".into(),
                r2_exponential: 1.0,
                r2_linear: 0.9,
                beat_period_s: None,
            },
            second_peak: None,
            statics: None,
            per_cycle: Vec::new(),
        }
    }

    /// The note on a value at its bound reads as one sentence: no runs of spaces.
    #[test]
    fn bound_note_has_single_spaces() {
        let b = figures(3000.0, 0.0, 0.0, 2.8);
        let note = at_bound(&CubicStiffness, 1e-9, &quiet_record(), &b).expect("at its bound");
        assert!(!note.contains("  "), "{note}");
        assert!(note.contains("did not move from its bound"), "{note}");
    }

    /// A second line 30 % of the axial one beside a pair the helix couples weakly
    /// fails the coupling's signature; the pair's own line passes.
    #[test]
    fn a_line_stronger_than_the_coupling_gives_fails() {
        let (kz, c, kt, m) = (3000.0, 0.5, 0.02, 2.8);
        let b = figures(kz, c, kt, m);
        let j = 0.8 * kt * m / kz;
        let pair = CoupledPair::of(&b, j).expect("a pair");
        let mut s = quiet_record();
        for (relative, passes) in [
            (0.3, false),
            (pair.axial_start_ratio, true),
            (1.9 * pair.axial_start_ratio, true),
        ] {
            s.second_peak = Some(PeakSummary {
                frequency_hz: pair.frequency_hz[1],
                relative_amplitude: relative,
                z_score: relative / 0.02,
            });
            let check = AxialTorsionalCoupling.signature(&s, &b, j);
            let strong = relative >= 0.02;
            assert_eq!(check.passed, passes && strong, "{relative}: {}", check.text);
        }
    }

    /// Far detuned, the weaker line's share falls as the square of the coupling over
    /// the detuning: `p_w / p_s = g^2 / (a - d)^2` to first order.
    #[test]
    fn detuned_pair_shows_a_weak_line() {
        let (kz, c, kt, m) = (3000.0, 0.3, 0.02, 2.8);
        let j = 0.5 * kt * m / kz;
        let p = CoupledPair::of(&figures(kz, c, kt, m), j).expect("a pair");
        let (a, d, g2) = (kz / m, kt / j, c * c / (m * j));
        let first_order = g2 / (a - d).powi(2);
        let ratio = p.axial_share[1].min(p.axial_share[0]) / p.axial_share[1].max(p.axial_share[0]);
        assert!(
            (ratio / first_order - 1.0).abs() < 0.01,
            "{ratio} {first_order}"
        );
    }
}
