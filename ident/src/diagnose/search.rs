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

/// The share of its proposed start an added effect is seeded with at a part's optimum.
const NEAR_ZERO: f64 = 0.05;

/// Most effects in one combination.
pub const MAX_COMBINED: usize = 3;

/// Levenberg-Marquardt iterations of each start's first-quarter fit.
const SEED_ITERATIONS: usize = 10;

/// The share of the bounded-motion limit a softening start is kept within
/// ([`Job::inside_limit`]).
pub const STABLE_SHARE: f64 = 0.9;

/// The share of its value each effect restarts from when every start failed.
pub const SAFER: f64 = 0.25;

/// Cycles a nonlinear start's initial state is also taken from ([`Job::early_state`]).
const EARLY_CYCLES: f64 = 3.0;

/// Cycles of the short window a nonlinear start is also fitted on first, when the first
/// quarter holds more than twice as many.
const SHORT_CYCLES: f64 = 8.0;

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
    /// The baseline's beta, from the paper's decrement (s).
    pub decrement_beta_s: f64,
}

/// One set's fit at any window: the model, the knobs and the records (what each step of
/// [`Job::fit`] builds its problems from).
struct Plan<'p> {
    model: &'p ReducedSpring,
    knobs: Vec<Knob>,
    statics: Option<&'p StaticBlock>,
    /// The set adds a point law: the initial state is fitted beside the knobs.
    nonlinear: bool,
    joint: &'p Joint,
    sigma: f64,
}

impl Plan<'_> {
    /// The problem on the first `fraction` of every record from `start` (and, for a
    /// nonlinear set, the initial state `init`).
    fn problem(&self, start: Physical, fraction: f64, init: Option<Vec<f64>>) -> Problem<'_> {
        Problem {
            model: self.model,
            start,
            knobs: self.knobs.clone(),
            measured: &self.joint.measured,
            segments: &self.joint.segments,
            fraction,
            sigma: self.sigma,
            statics: self.statics,
            initial_state: init,
        }
    }

    /// The initial state a fit hands to the next window (a nonlinear set's only).
    fn state(&self, f: &Fitted) -> Option<Vec<f64>> {
        self.nonlinear.then(|| f.initial_state.clone())
    }
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

    /// Every record's initial state from a linear fit on its first
    /// [`EARLY_CYCLES`] cycles only, with the mass moved to the first measured cycle's
    /// frequency (`m (f_axial / f_first)^2`) and fitted there: the amplitude and phase
    /// at the start of a record whose frequency sweeps, where the whole record's linear
    /// fit averages over the sweep. `None` without per-cycle signatures or a fit.
    fn early_state(&self) -> Option<Vec<f64>> {
        let sigs = self.signatures;
        let first = sigs.per_cycle.first()?;
        let fraction = (EARLY_CYCLES / sigs.cycles).min(select::ORIGINS[0]);
        let mut start = self.reference.full.physical;
        start.mass_kg *= (sigs.axial_hz / first.frequency_hz).powi(2);
        let problem = Problem {
            model: self.guided,
            start,
            knobs: vec![Knob::Mass],
            measured: &self.joint.measured,
            segments: &self.joint.segments,
            fraction,
            sigma: self.noise.max(1e-300),
            statics: None,
            initial_state: None,
        };
        fit::run(&problem, SEED_ITERATIONS)
            .ok()
            .map(|f| f.initial_state)
    }

    /// The seeds, and each again with the paper decrement's beta when the reference's
    /// is more than a factor of 2 away from it: a linear model that cannot follow the
    /// record (a frequency swept by a strong nonlinearity) walks its beta anywhere (to
    /// zero on a 10 % sweep), and an effect started from there keeps the amplitude,
    /// and with it the frequency, wrong from the first cycles.
    pub fn with_decrement_seed(&self, seeds: Vec<Physical>) -> Vec<Physical> {
        let (reference, decrement) = (self.reference.full.physical.beta_s, self.decrement_beta_s);
        if decrement.is_nan()
            || decrement <= 0.0
            || (reference / decrement).ln().abs() <= std::f64::consts::LN_2
        {
            return seeds;
        }
        let again: Vec<Physical> = seeds
            .iter()
            .map(|p| Physical {
                beta_s: decrement,
                ..*p
            })
            .collect();
        seeds.into_iter().chain(again).collect()
    }

    /// `seed` with a softening start (a negative signed effect, the cubic spring) inside
    /// [`STABLE_SHARE`] of the largest softening whose free motion at the record's
    /// amplitude stays bounded, at the record's gravity preload
    /// ([`bounded_softening_n_m3`]): a start past it cannot run the record at all.
    pub fn inside_limit(&self, mut seed: Physical) -> Physical {
        let k = self.guided.stiffness_n_m(&seed);
        let limit = bounded_softening_n_m3(k, k * self.figures.preload_m, self.figures.amplitude_m);
        if !(limit.is_finite() && limit > 0.0) {
            return seed;
        }
        for (v, e) in seed.effects.iter_mut().zip(CATALOGUE.iter()) {
            if e.signed() && *v < -STABLE_SHARE * limit {
                *v = -STABLE_SHARE * limit;
            }
        }
        seed
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
        self.finish(set, evidence, run)
    }

    /// A fitted set as a candidate: every effect that did not move from its bound
    /// (`effects::at_bound`) is set to its bound, zero, with the note that says so and
    /// an infinite standard error (it is not identified), and each effect's signature
    /// is checked at the fitted values.
    fn finish(
        &self,
        set: Vec<usize>,
        evidence: String,
        mut run: Result<ModelRun, String>,
    ) -> CandidateRun {
        let mut bounds = Vec::new();
        if let Ok(r) = &mut run {
            for &i in &set {
                let value = r.full.physical.effects[i];
                let Some(note) =
                    effects::at_bound(CATALOGUE[i], value, self.signatures, self.figures)
                else {
                    continue;
                };
                bounds.push(note);
                for fitted in [&mut r.full, &mut r.half] {
                    fitted.physical.effects[i] = 0.0;
                    if let Some(k) = fitted.knobs.iter().position(|k| *k == Knob::Effect(i)) {
                        fitted.knob_rel_errors[k] = f64::INFINITY;
                    }
                }
            }
        }
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
            bounds,
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
        let mut seeds = if set.iter().any(|&i| CATALOGUE[i].dissipative()) {
            self.with_viscous_seed(vec![seed, proposed])
        } else {
            vec![seed, proposed]
        };
        // Each part's own optimum (its mass, beta and value) with the added effects
        // near zero ([`NEAR_ZERO`] of their proposed start): the combination nests
        // every part, so from there it can only gain.
        let parts = self.parts_on_mount(set, singles);
        for part in &parts {
            let mut p = part.full.physical;
            for &j in set {
                if p.effects[j] == 0.0 {
                    p.effects[j] = NEAR_ZERO * proposed.effects[j];
                }
            }
            seeds.push(self.with_consistent_mass(p));
        }
        let evidence = evidence.join("; ");
        let fitted = self.candidate(set.to_vec(), evidence.clone(), &seeds, init);
        // Nesting: the combination at its best part's optimum, the added effects at
        // zero, is one of its own models; a fit that ended above that part's residual
        // did not converge, and the combination is reported at the part's optimum.
        let best_part = parts
            .into_iter()
            .min_by(|a, b| a.full.rss.total_cmp(&b.full.rss));
        match (best_part, &fitted.run) {
            (Some(part), Ok(r)) if r.full.rss <= part.full.rss => fitted,
            (Some(part), _) => {
                let mut run = part.clone();
                for f in [&mut run.full, &mut run.half] {
                    for &j in set {
                        if !f.knobs.contains(&Knob::Effect(j)) {
                            f.knobs.push(Knob::Effect(j));
                            f.knob_rel_errors.push(f64::INFINITY);
                            f.n_params += 1;
                        }
                    }
                }
                self.finish(set.to_vec(), evidence, Ok(run))
            }
            (None, _) => fitted,
        }
    }

    /// The fitted runs of the set's parts (every candidate fitted so far whose effects
    /// are a proper subset of the set) that use the set's mount: a part on another
    /// mount (the guided weight beside the coupling's free one) carries another initial
    /// state and is no point of the set's model.
    fn parts_on_mount<'c>(&self, set: &[usize], fitted: &'c [CandidateRun]) -> Vec<&'c ModelRun> {
        let mount = self.model(set).mount();
        fitted
            .iter()
            .filter(|c| c.effects.len() < set.len() && c.effects.iter().all(|e| set.contains(e)))
            .filter(|c| self.model(&c.effects).mount() == mount)
            .filter_map(|c| c.run.as_ref().ok())
            .collect()
    }

    /// Fits `set` from `seeds` (and the records' initial state `init`): a seed fit
    /// picks the best start ([`Job::seed_fit`]), continuation over growing windows
    /// fits it to the whole record ([`Job::window_fits`]), and a window whose forecast
    /// misses is fitted again from the whole record's values ([`Job::refit_missed`]).
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
        let plan = Plan {
            model,
            knobs,
            statics: self.statics.filter(|_| Self::uses_static(set)),
            nonlinear,
            joint: self.joint,
            sigma: self.noise.max(1e-300),
        };
        let inits = self.starting_states(nonlinear, init);
        let seed = self.seed_fit(&plan, set, seeds, &inits)?;
        if std::env::var_os("COIL_DIAGNOSE_TRACE").is_some() {
            eprintln!(
                "  {set:?}: seed rss {:.4e} {:?}",
                seed.rss, seed.physical.effects
            );
        }
        let [quarter, half_fit, full, three] = self.window_fits(&plan, set, &seed)?;
        if std::env::var_os("COIL_DIAGNOSE_TRACE").is_some() {
            eprintln!(
                "  {:?}: full {} iterations {} runs, half {} iterations {} runs",
                set, full.iterations, full.evaluations, half_fit.iterations, half_fit.evaluations
            );
        }
        let rolling = [quarter, half_fit, three];
        Ok(self.refit_missed(&plan, full, rolling))
    }

    /// The initial states a nonlinear fit starts from: `init`, and also the state of the
    /// first cycles ([`Job::early_state`]) when it differs from `init` by more than 5 %:
    /// a record whose frequency sweeps (a strong softening spring) leaves the whole
    /// record's linear fit with the wrong amplitude and phase at the start, and the
    /// nonlinear fit, whose frequency depends on the amplitude, loses the phase from
    /// there. A linear fit solves its state by least squares (`None`).
    fn starting_states(&self, nonlinear: bool, init: Vec<f64>) -> Vec<Option<Vec<f64>>> {
        if !nonlinear {
            return vec![None];
        }
        let early = self.early_state().unwrap_or_default();
        let norm = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
        let differs = early.len() == init.len() && {
            let d: Vec<f64> = early.iter().zip(&init).map(|(a, b)| a - b).collect();
            norm(&d) > 0.05 * norm(&init)
        };
        if differs {
            vec![Some(init), Some(early)]
        } else {
            vec![Some(init)]
        }
    }

    /// Each start fitted on the first quarter for a few iterations (a seed only: they
    /// tell a good start from a bad one); the best goes on. A start beyond a softening
    /// spring's stability limit starts inside it; when every start fails (a
    /// factorisation, a point law that does not converge, a motion past the limit),
    /// they are tried again from a safer start, each effect at [`SAFER`] of its value,
    /// and a set that still fails is reported as failed with the reason.
    fn seed_fit(
        &self,
        plan: &Plan<'_>,
        set: &[usize],
        seeds: &[Physical],
        inits: &[Option<Vec<f64>>],
    ) -> std::result::Result<Fitted, String> {
        let seeds: Vec<Physical> = seeds.iter().map(|p| self.inside_limit(*p)).collect();
        self.best_seed(plan, set, &seeds, inits).or_else(|first| {
            let safer: Vec<Physical> = seeds
                .iter()
                .map(|p| {
                    let mut q = *p;
                    q.effects.iter_mut().for_each(|v| *v *= SAFER);
                    q
                })
                .collect();
            self.best_seed(plan, set, &safer, inits).map_err(|again| {
                format!(
                    "every start failed ({first}), and again with each effect at {SAFER} of \
                     its start ({again})"
                )
            })
        })
    }

    /// The best first-quarter seed fit over `seeds` and `inits` ([`Job::seed_fit`]). A
    /// long record's first quarter may hold more cycles than a nonlinear seed keeps its
    /// phase over: the start is also fitted on the first [`SHORT_CYCLES`] cycles, then
    /// on the quarter, and the better quarter fit goes on.
    fn best_seed(
        &self,
        plan: &Plan<'_>,
        set: &[usize],
        seeds: &[Physical],
        inits: &[Option<Vec<f64>>],
    ) -> std::result::Result<Fitted, String> {
        let mut best: Option<Fitted> = None;
        let mut last_error = String::from("no starting value");
        let iterations = self.max_iterations.min(SEED_ITERATIONS);
        let cycles = self.signatures.cycles;
        // The starts are independent: fitted in parallel, then compared in their order
        // (the same choice as one after another).
        let starts: Vec<(Physical, &Option<Vec<f64>>)> = seeds
            .iter()
            .flat_map(|s| inits.iter().map(move |i| (*s, i)))
            .collect();
        let fitted: Vec<(Physical, std::result::Result<Fitted, String>)> = starts
            .into_par_iter()
            .map(|(start, first)| {
                (
                    start,
                    self.start_fit(plan, start, first, iterations, cycles),
                )
            })
            .collect();
        for (start, seed) in fitted {
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
        best.ok_or(last_error)
    }

    /// One start's first-quarter fit ([`Job::best_seed`]): on the quarter, and for a
    /// nonlinear set on a record with many cycles also on the first [`SHORT_CYCLES`]
    /// cycles then the quarter; the better of the two.
    fn start_fit(
        &self,
        plan: &Plan<'_>,
        start: Physical,
        first: &Option<Vec<f64>>,
        iterations: usize,
        cycles: f64,
    ) -> std::result::Result<Fitted, String> {
        let mut seed = fit::run(
            &plan.problem(start, select::ORIGINS[0], first.clone()),
            iterations,
        );
        if plan.nonlinear && cycles * select::ORIGINS[0] > 2.0 * SHORT_CYCLES {
            let short = fit::run(
                &plan.problem(start, SHORT_CYCLES / cycles, first.clone()),
                iterations,
            )
            .and_then(|f| {
                fit::run(
                    &plan.problem(f.physical, select::ORIGINS[0], plan.state(&f)),
                    iterations,
                )
            });
            seed = match (seed, short) {
                (Ok(a), Ok(b)) => Ok(if b.rss < a.rss { b } else { a }),
                (Err(_), Ok(b)) => Ok(b),
                (a, Err(_)) => a,
            };
        }
        seed
    }

    /// Continuation from the seed over growing windows: the first quarter to
    /// convergence (the first rolling origin), the first half (the forecast's), the
    /// whole record and the first three quarters (the last rolling origin). The set
    /// nests the reference (its effects at zero): a fit that ends above the reference's
    /// misfit on the same window lost the phase on the way from the shorter window (a
    /// short record, a strong drift); it restarts from the reference's mass, beta and
    /// initial state with the first quarter's effect values, and keeps the better.
    fn window_fits(
        &self,
        plan: &Plan<'_>,
        set: &[usize],
        seed: &Fitted,
    ) -> std::result::Result<[Fitted; 4], String> {
        let stage = |name: &'static str| move |e: String| format!("the {name} fit: {e}");
        let run = |start: Physical, fraction: f64, init: Option<Vec<f64>>| {
            fit::run(&plan.problem(start, fraction, init), self.max_iterations)
        };
        let quarter = run(seed.physical, select::ORIGINS[0], plan.state(seed))
            .map_err(stage("first quarter's"))?;
        let rescue = |fitted: Fitted, fraction: f64, reference: &Fitted| -> Fitted {
            if fitted.rss <= reference.rss {
                return fitted;
            }
            let mut restart = self.base(set);
            for &i in set {
                restart.effects[i] = quarter.physical.effects[i];
            }
            let init = plan.nonlinear.then(|| reference.initial_state.clone());
            match run(restart, fraction, init) {
                Ok(again) if again.rss < fitted.rss => again,
                _ => fitted,
            }
        };
        let half_fit =
            run(quarter.physical, 0.5, plan.state(&quarter)).map_err(stage("first half's"))?;
        let half_fit = rescue(half_fit, 0.5, &self.reference.half);
        let full =
            run(half_fit.physical, 1.0, plan.state(&half_fit)).map_err(stage("whole record's"))?;
        let full = rescue(full, 1.0, &self.reference.full);
        let three = run(full.physical, select::ORIGINS[2], plan.state(&full))
            .map_err(stage("first three quarters'"))?;
        Ok([quarter, half_fit, full, three])
    }

    /// A window's fit whose forecast misses may sit in another local minimum of its own
    /// objective than the whole record's (a short record: the mass and the effect trade
    /// off over a few cycles). It is fitted again from the whole record's values and
    /// kept only if that lowers its own window's misfit: a better optimum of the same
    /// objective, chosen without the held-out samples.
    fn refit_missed(&self, plan: &Plan<'_>, full: Fitted, mut rolling: [Fitted; 3]) -> ModelRun {
        let first = model_run(full.clone(), rolling[1].clone(), self.joint, &rolling);
        let mut changed = false;
        for (i, window) in rolling.iter_mut().enumerate() {
            let missed = first.rolling[i] > select::FORECAST_RATIO * self.reference.rolling[i];
            if !missed {
                continue;
            }
            let again = fit::run(
                &plan.problem(full.physical, select::ORIGINS[i], plan.state(&full)),
                self.max_iterations,
            );
            if let Some(again) = again.ok().filter(|a| a.rss < window.rss) {
                *window = again;
                changed = true;
            }
        }
        if !changed {
            return first;
        }
        model_run(full, rolling[1].clone(), self.joint, &rolling)
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
            let seeds = job.with_decrement_seed(seeds);
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
    // The dissipative effects together are always tried: dry friction's constant loss
    // and drag's loss growing as A^2 add up to nearly a viscous one over a record, so
    // each alone may gain nothing (the reference's beta takes the loss) and walk to
    // zero while the pair explains the record.
    let dissipative: Vec<usize> = (0..effects::COUNT)
        .filter(|&i| CATALOGUE[i].dissipative())
        .collect();
    if dissipative.len() >= 2 && !sets.contains(&dissipative) {
        sets.push(dissipative);
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

/// The largest softening `c = -k3` (N/m^3) for which the free motion of a weight on a
/// spring `k x - c x^3` (N; x the compression from the free length, m) under its
/// weight `w` (N) stays bounded when it swings `amplitude` (m) either side of its
/// equilibrium; `NaN` when an input is not positive and finite (`w` may be 0).
///
/// The potential `V(x) = k x^2 / 2 - c x^4 / 4 - w x` has its well at the smaller
/// positive root `x_s` of `k x - c x^3 = w` and saddles at the larger one `x_u+` and at
/// the negative one `x_u-`. The motion is bounded when `x_u- < x_s - A`,
/// `x_s + A < x_u+` and `max(V(x_s + A), V(x_s - A)) < min(V(x_u+), V(x_u-))`; the set
/// of such `c` is an interval from 0, bisected here. Without a weight it is
/// `c < k / A^2`, three times the `k / (3 A^2)` where the tangent stiffness vanishes at
/// the amplitude, a region a motion passes through and turns back from (a pendulum
/// beyond 90 degrees).
pub fn bounded_softening_n_m3(k: f64, w: f64, amplitude: f64) -> f64 {
    let positive = |x: f64| x > 0.0 && x.is_finite();
    if !(positive(k) && positive(amplitude) && w >= 0.0 && w.is_finite()) {
        return f64::NAN;
    }
    let bounded = |c: f64| -> bool {
        let g = |x: f64| k * x - c * x * x * x - w;
        let v = |x: f64| 0.5 * k * x * x - 0.25 * c * x.powi(4) - w * x;
        // A root of g on [lo, hi], where g changes sign, by bisection to rounding.
        let root = |mut lo: f64, mut hi: f64| {
            let rising = g(hi) > g(lo);
            for _ in 0..200 {
                let mid = 0.5 * (lo + hi);
                if (g(mid) < 0.0) == rising {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            0.5 * (lo + hi)
        };
        let peak = (k / (3.0 * c)).sqrt();
        if g(peak) <= 0.0 {
            // No equilibrium: the weight crushes the spring.
            return false;
        }
        let x_s = root(0.0, peak);
        let x_up = root(peak, (k / c).sqrt());
        let mut far = -(k / c).sqrt();
        while g(far) < 0.0 {
            far *= 2.0;
        }
        let x_um = root(far, -peak);
        let (top, bottom) = (x_s + amplitude, x_s - amplitude);
        top < x_up && bottom > x_um && v(top).max(v(bottom)) < v(x_up).min(v(x_um))
    };
    let (mut lo, mut hi) = (0.0, k / (amplitude * amplitude));
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if bounded(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    lo
}

#[cfg(test)]
mod tests {
    use super::bounded_softening_n_m3;

    /// The largest |u - x_s| of a free motion released at rest from `x_s + a` (`a` of
    /// either sign) under
    /// `m x'' = w - k x + c x^3` (m = 1), by classical RK4 over `periods` linear periods;
    /// infinite when it passes the point where the spring pushes outwards.
    fn swing(k: f64, c: f64, w: f64, a: f64, periods: f64) -> f64 {
        let f = |x: f64| w - k * x + c * x * x * x;
        // The equilibrium, by Newton from the linear deflection.
        let mut x_s = w / k;
        for _ in 0..100 {
            x_s -= (k * x_s - c * x_s.powi(3) - w) / (k - 3.0 * c * x_s * x_s);
        }
        let (mut x, mut v) = (x_s + a, 0.0);
        let dt = 1e-3 * std::f64::consts::TAU / k.sqrt();
        let mut widest = 0.0_f64;
        for _ in 0..(periods * 1000.0) as usize {
            let (k1x, k1v) = (v, f(x));
            let (k2x, k2v) = (v + 0.5 * dt * k1v, f(x + 0.5 * dt * k1x));
            let (k3x, k3v) = (v + 0.5 * dt * k2v, f(x + 0.5 * dt * k2x));
            let (k4x, k4v) = (v + dt * k3v, f(x + dt * k3x));
            x += dt / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x);
            v += dt / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
            if x.abs() >= (k / c).sqrt() {
                return f64::INFINITY;
            }
            widest = widest.max((x - x_s).abs());
        }
        widest
    }

    #[test]
    fn the_bounded_softening_limit_is_where_the_motion_escapes() {
        // Without a weight: c A^2 < k, the closed form.
        let c = bounded_softening_n_m3(4.0, 0.0, 0.5);
        assert!((c / 16.0 - 1.0).abs() < 1e-6, "{c}");
        // With a weight of 40 % of k A (a hanging weight: the saddle on the
        // compression side is near), the motions released at rest `A` either side of
        // the equilibrium stay bounded just inside the limit, and one of them escapes
        // just outside it; the limit lies below the unpreloaded one.
        let (k, a) = (100.0, 0.1);
        let w = 0.4 * k * a;
        let c = bounded_softening_n_m3(k, w, a);
        assert!(c > 0.0 && c < k / (a * a), "{c}");
        let both = |c: f64| swing(k, c, w, a, 20.0).max(swing(k, c, w, -a, 20.0));
        assert!(both(0.98 * c).is_finite());
        assert!(both(1.02 * c).is_infinite());
        assert!(bounded_softening_n_m3(k, w, 0.0).is_nan());
    }
}
