//! The search over the catalogue: each effect alone from its signature's starts, then
//! the combinations of the effects with evidence of their own (up to
//! [`MAX_COMBINED`]), every set fitted by output error with continuation over growing
//! windows (the rolling origins of [`select::ORIGINS`]).

use super::effects::{self, BaselineFigures, Mount, CATALOGUE};
use super::evidence::{self, Signatures};
use super::fit::{self, Fitted, Knob, Problem, StaticBlock};
use super::model::{Physical, ReducedSpring};
use super::run::{model_run, CandidateRun, Joint, ModelRun};
use super::select;
use rayon::prelude::*;

/// Most effects in one combination.
pub const MAX_COMBINED: usize = 3;

/// Levenberg-Marquardt iterations of each start's first-quarter fit.
const SEED_ITERATIONS: usize = 10;

/// What every candidate's fit shares: the reduced models (weight guided, and free to
/// turn for the coupling), the reference fit, the records and their noise, the static
/// block, the signatures.
pub struct Job<'a> {
    /// The reduced model with the weight guided along the axis.
    pub guided: &'a ReducedSpring,
    /// The reduced model with the weight also free to turn about the axis (coupling).
    pub free: &'a ReducedSpring,
    /// The reference fit every candidate starts from.
    pub reference: &'a ModelRun,
    /// The records laid end to end.
    pub joint: &'a Joint,
    /// RMS of the reference's residual (the records' unit, SI): divides the decay residuals.
    pub noise: f64,
    /// The static block, fitted with the effects that show in the static record.
    pub statics: Option<&'a StaticBlock>,
    /// The static record's fits (the cubic fit's stiffness starts a static effect's fit).
    pub static_fit: Option<&'a evidence::StaticSummary>,
    /// Levenberg-Marquardt iterations per fit.
    pub max_iterations: usize,
    /// The records' signatures, for the effects' starts and checks.
    pub signatures: &'a Signatures,
    /// The baseline's figures, for the effects' starts and checks.
    pub figures: &'a BaselineFigures,
}

impl Job<'_> {
    fn uses_static(set: &[usize]) -> bool {
        set.iter()
            .any(|&i| CATALOGUE[i].static_force(1.0, 1.0).is_some())
    }

    /// The reference's parameters, with the stiffness the set's static record gives.
    fn base(&self, set: &[usize]) -> Physical {
        let mut base = self.reference.full.physical;
        if let (true, Some(s)) = (Self::uses_static(set), self.static_fit) {
            // A cubic static fit's linear coefficient is the spring's stiffness at the
            // free length; the straight line's slope (the baseline's) is a secant.
            base.k_scale = s.k_n_mm / s.linear_k_n_mm;
        }
        base
    }

    /// A seed whose effects change the spring's static force (a cubic spring) gets the
    /// weight's mass that keeps the reference's axial frequency about the preload it
    /// then hangs at: with `F(x) = k x + F_e(x)` the preload `x0` solves
    /// `w^2 F(x0) / g = F'(x0)` (the tangent over the mass that `F(x0) = m g` carries),
    /// found by bisection below the first `x` where `F'` vanishes. Without it a strong
    /// softening spring would start with the linear calibration's mass, which it may
    /// not be able to hold at all (no static equilibrium). Unchanged when there is no
    /// such force, no gravity, or no root.
    pub fn with_consistent_mass(&self, mut seed: Physical) -> Physical {
        let g = seed.gravity_m_s2;
        let model = self.guided;
        let extra = |x: f64, p: &Physical| -> Option<f64> {
            CATALOGUE
                .iter()
                .zip(&p.effects)
                .filter(|(_, v)| **v != 0.0)
                .filter_map(|(e, &v)| e.static_force(v, x))
                .reduce(|a, b| a + b)
        };
        if g <= 0.0 || extra(1e-3, &seed).is_none() {
            return seed;
        }
        let reference = self.reference.full.physical;
        let w2 = model.stiffness_n_m(&reference) / reference.mass_kg;
        let k = model.stiffness_n_m(&seed);
        let force = |x: f64| k * x + extra(x, &seed).unwrap_or(0.0);
        let tangent = |x: f64| {
            let h = 1e-7 * x.abs().max(1e-6);
            (force(x + h) - force(x - h)) / (2.0 * h)
        };
        // Bracket: from the linear preload outwards while the tangent stays positive.
        let x_lin = reference.mass_kg * g / k;
        let gap = |x: f64| w2 * force(x) / g - tangent(x);
        let (mut lo, mut hi) = (0.0_f64, x_lin.max(1e-9));
        while gap(hi) < 0.0 && tangent(hi) > 0.0 && hi < 1e3 * x_lin.max(1e-9) {
            lo = hi;
            hi *= 1.5;
        }
        if !(gap(hi) >= 0.0 && tangent(hi) > 0.0) {
            // The frequency is reached only beyond the stable range, or never: bisect
            // the tangent's zero instead and stay just inside it.
            return seed;
        }
        for _ in 0..100 {
            let mid = 0.5 * (lo + hi);
            if gap(mid) < 0.0 {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        let mass = force(hi) / g;
        if mass.is_finite() && mass > 0.0 {
            seed.mass_kg = mass;
        }
        seed
    }

    /// The seeds of a set holding a dissipative effect, and each again with only the
    /// viscous part of the damping in beta:
    /// the reference's beta holds every loss, so an added dissipative effect starts
    /// with its loss counted twice, and a fit from there may walk the effect to zero
    /// rather than hand it beta's share. The viscous part is the loss per cycle's
    /// linear term, `a1 = 2 pi zeta` (`beta = 2 zeta / w`), when it stands above two
    /// standard errors and below 0.9 of the reference's beta.
    pub fn with_viscous_seed(&self, seeds: Vec<Physical>) -> Vec<Physical> {
        let Some(l) = self.signatures.loss else {
            return seeds;
        };
        let w = std::f64::consts::TAU * self.signatures.axial_hz;
        let beta = l.a1 / (std::f64::consts::PI * w);
        let reference = self.reference.full.physical.beta_s;
        if !(l.a1 / l.a1_se > 2.0 && beta.is_finite() && beta < 0.9 * reference) {
            return seeds;
        }
        let viscous: Vec<Physical> = seeds
            .iter()
            .map(|p| Physical { beta_s: beta, ..*p })
            .collect();
        seeds.into_iter().chain(viscous).collect()
    }

    fn model(&self, set: &[usize]) -> &ReducedSpring {
        if set
            .iter()
            .any(|&i| CATALOGUE[i].mount() == Mount::FreeRotation)
        {
            self.free
        } else {
            self.guided
        }
    }

    /// Fits the set of effects from `seeds` (and a starting initial state for a
    /// nonlinear model) and checks each effect's signature at the fitted values.
    fn candidate(
        &self,
        set: Vec<usize>,
        evidence: String,
        seeds: &[Physical],
        init: Vec<f64>,
    ) -> CandidateRun {
        let run = self.fit(&set, seeds, init);
        let signatures = run.as_ref().map_or(Vec::new(), |r| {
            set.iter()
                .map(|&i| {
                    CATALOGUE[i].signature(
                        self.signatures,
                        self.figures,
                        r.full.physical.effects[i],
                    )
                })
                .collect()
        });
        CandidateRun {
            effects: set,
            evidence,
            signatures,
            run,
        }
    }

    /// A combination, started from its parts' fitted values (the best part's mass,
    /// beta and initial state).
    fn combined(&self, set: &[usize], singles: &[CandidateRun]) -> CandidateRun {
        let mut seed = self.base(set);
        let mut best: Option<&ModelRun> = None;
        let mut evidence = Vec::new();
        for &i in set {
            let Some(single) = singles.iter().find(|c| c.effects == [i]) else {
                continue;
            };
            evidence.push(format!("{}: {}", CATALOGUE[i].name(), single.evidence));
            if let Ok(r) = &single.run {
                seed.effects[i] = r.full.physical.effects[i];
                if best.is_none_or(|b| r.full.rss < b.full.rss) {
                    best = Some(r);
                }
            }
        }
        let model = self.model(set);
        let states = 2 * if model.mount() == Mount::FreeRotation {
            2
        } else {
            1
        };
        // The initial state of a part fitted on the same mount (the coupling's carries
        // the rotation), else the best part's padded with a rotation at rest.
        let mut init = set
            .iter()
            .filter_map(|&i| singles.iter().find(|c| c.effects == [i]))
            .filter_map(|c| c.run.as_ref().ok())
            .map(|r| r.full.initial_state.clone())
            .find(|s| s.len() == states)
            .unwrap_or_else(|| {
                best.map_or(self.reference.full.initial_state.clone(), |b| {
                    b.full.initial_state.clone()
                })
            });
        // Every record's state padded the same way.
        let records = self.joint.segments.len();
        let per = init.len() / records.max(1);
        if per != states {
            init = init
                .chunks(per.max(1))
                .take(records)
                .flat_map(|c| {
                    let mut c = c.to_vec();
                    c.resize(states, 0.0);
                    c
                })
                .collect();
            init.resize(states * records, 0.0);
        }
        if let Some(b) = best {
            seed.mass_kg = b.full.physical.mass_kg;
            seed.beta_s = b.full.physical.beta_s;
        }
        // Also from the signatures' own values: effects that mimic viscous damping
        // together (friction's constant loss and drag's A^2 loss add up to nearly a
        // linear one over a record) each fail alone and walk to zero, so their fitted
        // values are no start for the pair.
        let mut proposed = self.base(set);
        for &i in set {
            if let Some(&v) = CATALOGUE[i]
                .propose(self.signatures, self.figures)
                .starts
                .first()
            {
                proposed.effects[i] = v;
            }
        }
        let proposed = self.with_consistent_mass(proposed);
        let seeds = if set.iter().any(|&i| CATALOGUE[i].dissipative()) {
            self.with_viscous_seed(vec![seed, proposed])
        } else {
            vec![seed, proposed]
        };
        self.candidate(set.to_vec(), evidence.join("; "), &seeds, init)
    }

    fn fit(
        &self,
        set: &[usize],
        seeds: &[Physical],
        init: Vec<f64>,
    ) -> std::result::Result<ModelRun, String> {
        let model = self.model(set);
        let nonlinear = seeds.iter().any(|s| model.is_nonlinear(s));
        let mut knobs: Vec<Knob> = set.iter().map(|&i| Knob::Effect(i)).collect();
        knobs.extend(self.joint.knobs());
        let statics = self.statics.filter(|_| Self::uses_static(set));
        let problem = |start: Physical, fraction: f64, init: Option<Vec<f64>>| Problem {
            model,
            start,
            knobs: knobs.clone(),
            measured: &self.joint.measured,
            segments: &self.joint.segments,
            fraction,
            sigma: self.noise.max(1e-300),
            statics,
            initial_state: init,
        };
        let state = |f: &Fitted| nonlinear.then(|| f.initial_state.clone());
        let first = nonlinear.then_some(init);
        // Each start is fitted on the first quarter for a few iterations (a seed only:
        // they tell a good start from a bad one); the best is fitted to convergence
        // there (the first rolling origin), then on the first half (the forecast's),
        // the whole record, and the first three quarters (the last rolling origin).
        let mut best: Option<Fitted> = None;
        let mut last_error = String::from("no starting value");
        for &start in seeds {
            let seed = fit::run(
                &problem(start, select::ORIGINS[0], first.clone()),
                self.max_iterations.min(SEED_ITERATIONS),
            );
            match seed {
                Ok(f) if best.as_ref().is_none_or(|b| f.rss < b.rss) => best = Some(f),
                Ok(_) => {}
                Err(e) => {
                    if std::env::var_os("COIL_DIAGNOSE_TRACE").is_some() {
                        eprintln!("  {set:?}: start {start:?} failed: {e}");
                    }
                    last_error = e
                }
            }
        }
        let seed = best.ok_or(last_error)?;
        let quarter = fit::run(
            &problem(seed.physical, select::ORIGINS[0], state(&seed)),
            self.max_iterations,
        )?;
        // The set nests the reference (its effects at zero): a fit that ends above the
        // reference's misfit on the same window lost the phase on the way from the
        // shorter window (a short record, a strong drift). It restarts from the
        // reference's mass, beta and initial state with the first quarter's effect
        // values, and keeps the better of the two.
        let rescue = |fitted: Fitted, fraction: f64, reference: &Fitted| -> Fitted {
            if fitted.rss <= reference.rss {
                return fitted;
            }
            let mut restart = self.base(set);
            for &i in set {
                restart.effects[i] = quarter.physical.effects[i];
            }
            let init = nonlinear.then(|| reference.initial_state.clone());
            match fit::run(&problem(restart, fraction, init), self.max_iterations) {
                Ok(again) if again.rss < fitted.rss => again,
                _ => fitted,
            }
        };
        let half_fit = fit::run(
            &problem(quarter.physical, 0.5, state(&quarter)),
            self.max_iterations,
        )?;
        let half_fit = rescue(half_fit, 0.5, &self.reference.half);
        let full = fit::run(
            &problem(half_fit.physical, 1.0, state(&half_fit)),
            self.max_iterations,
        )?;
        let full = rescue(full, 1.0, &self.reference.full);
        let three = fit::run(
            &problem(full.physical, select::ORIGINS[2], state(&full)),
            self.max_iterations,
        )?;
        if std::env::var_os("COIL_DIAGNOSE_TRACE").is_some() {
            eprintln!(
                "  {:?}: full {} iterations {} runs, half {} iterations {} runs",
                set, full.iterations, full.evaluations, half_fit.iterations, half_fit.evaluations
            );
        }
        let mut rolling = [quarter, half_fit, three];
        let first = model_run(full.clone(), rolling[1].clone(), self.joint, &rolling);
        // A window's fit whose forecast misses may sit in another local minimum of its
        // own objective than the whole record's (a short record: the mass and the
        // effect trade off over a few cycles). It is fitted again from the whole
        // record's values and kept only if that lowers its own window's misfit: a
        // better optimum of the same objective, chosen without the held-out samples.
        let mut changed = false;
        for (i, window) in rolling.iter_mut().enumerate() {
            let missed = first.rolling[i] > select::FORECAST_RATIO * self.reference.rolling[i];
            if !missed {
                continue;
            }
            let again = fit::run(
                &problem(full.physical, select::ORIGINS[i], state(&full)),
                self.max_iterations,
            );
            if let Some(again) = again.ok().filter(|a| a.rss < window.rss) {
                *window = again;
                changed = true;
            }
        }
        if !changed {
            return Ok(first);
        }
        Ok(model_run(full, rolling[1].clone(), self.joint, &rolling))
    }
}

/// Every catalogue effect alone, in parallel (each fit's Jacobian columns run in
/// parallel too), then the combinations of the effects with evidence of their own.
pub fn candidates(
    job: &Job<'_>,
    ctx: &select::Context<'_>,
    progress: &(dyn Fn(&str) + Sync),
) -> Vec<CandidateRun> {
    let reference = job.reference;
    let (sigs, figures) = (job.signatures, job.figures);
    // Every effect alone, in parallel (each fit's Jacobian columns run in parallel too).
    progress("candidates: each effect alone");
    let mut candidates: Vec<CandidateRun> = (0..effects::COUNT)
        .into_par_iter()
        .map(|i| {
            let proposal = CATALOGUE[i].propose(sigs, figures);
            let seeds: Vec<Physical> = proposal
                .starts
                .iter()
                .map(|&v| {
                    let mut p = job.base(&[i]);
                    p.effects[i] = v;
                    job.with_consistent_mass(p)
                })
                .collect();
            let seeds = if CATALOGUE[i].dissipative() {
                job.with_viscous_seed(seeds)
            } else {
                seeds
            };
            let init = reference.full.initial_state.clone();
            job.candidate(vec![i], proposal.evidence, &seeds, init)
        })
        .collect();
    // Combinations of the effects with evidence of their own, up to three: strong
    // evidence alone (dBIC above the limit), or a signature that agrees (an effect
    // masked alone by another one: friction or drag beside a softening drift, whose
    // phase error swamps their gain when fitted alone). Each combination starts from
    // its parts' fitted values.
    let mut gaining: Vec<(usize, f64)> = candidates
        .iter()
        .filter_map(|c| {
            select::score(ctx, c)
                .filter(|s| s.delta_bic > select::DELTA_BIC || s.tests.signature.passed)
                .map(|s| (c.effects[0], s.delta_bic))
        })
        .collect();
    gaining.sort_by(|a, b| b.1.total_cmp(&a.1));
    gaining.truncate(MAX_COMBINED);
    let gaining: Vec<usize> = gaining.into_iter().map(|g| g.0).collect();
    let mut sets: Vec<Vec<usize>> = Vec::new();
    for (a, &i) in gaining.iter().enumerate() {
        for &j in &gaining[a + 1..] {
            sets.push(sorted(vec![i, j]));
        }
    }
    if !sets.is_empty() {
        progress("candidates: pairs of effects");
        let pairs: Vec<CandidateRun> = sets
            .par_iter()
            .map(|set| job.combined(set, &candidates))
            .collect();
        candidates.extend(pairs);
    }
    if gaining.len() >= 3 {
        progress("candidates: three effects");
        let triple = job.combined(&sorted(gaining.clone()), &candidates);
        candidates.push(triple);
    }

    candidates
}

fn sorted(mut v: Vec<usize>) -> Vec<usize> {
    v.sort_unstable();
    v
}
