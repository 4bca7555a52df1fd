//! Tension links and moving contacts in direct integration (average acceleration): each
//! step is taken linear (taut links in `K`, no contact force at its end), then the
//! unilateral elements' end-of-step forces are found exactly and their response removed
//! (`crate::analysis::unilateral`, "Solve"). A step is affine in its end load, so the
//! response to an element's `b` as end load from rest, `(u_j, v_j, a_j)`, turns the
//! forces `lambda` into the state change `-sum_j s_j lambda_j (u_j, v_j, a_j)`, and the
//! end-of-step gaps are `g* - G S lambda`, `G_ij = b_i^T u_j`. A link's response is
//! computed when the link is first a candidate for slackness and kept, sparse and within
//! a memory budget ([`super::responses`]: it decays within a few elements of the link, so
//! a catenary's memory does not grow as links x DOFs). The contact's `b` moves with its point, but over the free
//! equations of the segment under it (the head's and the two line nodes' translation and
//! rotation): its response is the combination `sum_r b_r (u_r, v_r, a_r)` of the
//! responses to a unit load on each of those equations, kept while the point stays on
//! the segment, so a solve is spent only when the point reaches a new node (two per
//! segment instead of one per step; a profile of the EN 50318 catenary at 0.125 ms steps
//! put half the run's time in that solve).
//!
//! Only the displacement of a response is kept. Average acceleration from rest gives
//! `u = dt^2/4 a` and `v = dt/2 a` (`u_{n+1} = u_n + dt v_n + dt^2/4 (a_n + a_{n+1})`,
//! `v_{n+1} = v_n + dt/2 (a_n + a_{n+1})` with `u_n = v_n = a_n = 0`), so a response is
//! `(u, 2u/dt, 4u/dt^2)` and the elements' whole correction is one vector
//! `sum_j s_j lambda_j u_j` applied as `(du, 2 du/dt, 4 du/dt^2)`, each response over its
//! runs only (a profile of the same run put a quarter of its time in dense passes over
//! the state).

use super::error::integrate_error;
use super::recording::Recorder;
use super::responses::{LinkResponses, Sparse, BUDGET_BYTES};
use crate::analysis::system::System;
use crate::analysis::unilateral::{link_gaps, solve_forces, ContactLine, Gap};
use crate::error::solve::SolveError;
use crate::integrate::{Scheme, State, Stepper};

/// The links' slack corrections with their step responses, the contacts, and the
/// elements closed at the last step.
pub(super) struct UnilateralTerm {
    links: Vec<Gap>,
    /// The displacements of the links' step responses from rest (module docs), kept
    /// sparse within a budget ([`super::responses`]).
    link_response: LinkResponses,
    contacts: Vec<ContactLine>,
    /// Closed links (indices into `links`).
    slack: Vec<usize>,
    /// Each contact's force at the end of the last step (N).
    pub(super) contact_force: Vec<f64>,
    /// Displacements of the step responses from rest to a unit end load on one free
    /// equation, for the equations the contacts' `b` read at the last step.
    unit_response: Vec<(usize, Sparse)>,
    /// `[2/dt, 4/dt^2]`: a response's velocity is `2u/dt`, its acceleration `4u/dt^2`.
    rates: [f64; 2],
    zero: Vec<f64>,
    load: Vec<f64>,
}

/// How one element's response enters a step's `G` and correction.
enum Response<'a> {
    /// A kept link response.
    Kept(&'a Sparse),
    /// A contact's: `sum_r c_r` times the unit responses of its equations.
    Combined(Vec<(f64, &'a Sparse)>),
    /// A link response used once: its column of `G` over the step's elements.
    Once(Vec<f64>),
}

impl Response<'_> {
    /// `b^T` of the response for `gap`, the element at `i` of the step.
    fn seen_by(&self, i: usize, gap: &Gap) -> f64 {
        match self {
            Response::Kept(x) => x.dot(gap),
            Response::Combined(terms) => terms.iter().map(|(c, x)| c * x.dot(gap)).sum(),
            Response::Once(column) => column[i],
        }
    }
}

impl UnilateralTerm {
    pub(super) fn new(
        system: &System,
        stepper: &mut Stepper,
        title: &str,
    ) -> Result<Self, SolveError> {
        if stepper.scheme() != Scheme::AverageAcceleration {
            return Err(SolveError::BadInput {
                what: format!(
                    "load case '{title}': TENSION LINK and MOVING CONTACT run by direct \
                     integration with NEWMARK (average acceleration) only"
                ),
            });
        }
        let n = system.dim();
        let links = link_gaps(system)?;
        let contacts = system
            .model
            .moving_contacts()
            .iter()
            .map(|c| ContactLine::new(system, c))
            .collect::<Result<Vec<_>, _>>()?;
        let dt = stepper.dt();
        Ok(UnilateralTerm {
            contact_force: vec![0.0; contacts.len()],
            unit_response: Vec::new(),
            rates: [2.0 / dt, 4.0 / (dt * dt)],
            link_response: LinkResponses::new(links.len(), BUDGET_BYTES),
            links,
            contacts,
            slack: Vec::new(),
            zero: vec![0.0; n],
            load: vec![0.0; n],
        })
    }

    /// Subtracts the elements' forces at `u` (time `t`) from the load `f` (the balance
    /// `M a = f - B lambda - ...` of the initial acceleration), without a solve.
    pub(super) fn add_initial_force(&mut self, t: f64, u: &[f64], f: &mut [f64]) {
        for gap in &self.links {
            let l = gap.k * gap.gap(u).max(0.0);
            gap.add_to(-gap.sign * l, f);
        }
        for (c, force) in self.contacts.iter().zip(&mut self.contact_force) {
            *force = 0.0;
            if let Some(gap) = c.gap_at(t) {
                *force = gap.k * gap.gap(u).max(0.0);
                gap.add_to(-*force, f);
            }
        }
    }

    /// The displacement of one step from rest under the end load in `self.load`.
    fn response(
        &mut self,
        stepper: &mut Stepper,
    ) -> Result<Vec<f64>, crate::error::IntegrateError> {
        let mut state = State::zeros(self.load.len(), 0.0);
        stepper.step(&mut state, &self.zero, &self.load, 0)?;
        Ok(state.u)
    }

    /// Computes what the step's elements need before their responses are borrowed:
    /// the unit responses of the contacts' equations and the candidate links'
    /// responses, kept or, past the budget, as their columns of `G` over the step's
    /// elements (returned by position among the candidates).
    fn prepare(
        &mut self,
        stepper: &mut Stepper,
        ids: &[usize],
        contact_gaps: &[(usize, Gap)],
    ) -> Result<Vec<Option<Vec<f64>>>, crate::error::IntegrateError> {
        let mut used: Vec<usize> = Vec::new();
        for (_, gap) in contact_gaps {
            for &(eq, _) in &gap.b {
                used.push(eq);
                if self.unit_response.iter().all(|(e, _)| *e != eq) {
                    self.load.fill(0.0);
                    self.load[eq] = 1.0;
                    let u = self.response(stepper)?;
                    self.unit_response.push((eq, Sparse::new(&u)));
                }
            }
        }
        self.unit_response.retain(|(e, _)| used.contains(e));
        self.link_response.next_step();
        let mut once = vec![None; ids.len()];
        for (p, &j) in ids.iter().enumerate() {
            if self.link_response.touch(j) {
                continue;
            }
            self.load.fill(0.0);
            self.links[j].add_to(1.0, &mut self.load);
            let u = self.response(stepper)?;
            if !self.link_response.insert(j, Sparse::new(&u)) {
                let column = ids
                    .iter()
                    .map(|&i| self.links[i].dot(&u))
                    .chain(contact_gaps.iter().map(|(_, g)| g.dot(&u)))
                    .collect();
                once[p] = Some(column);
            }
        }
        Ok(once)
    }

    /// Turns the linear step just taken (ending at `t`) into the one with the elements'
    /// forces.
    pub(super) fn correct(
        &mut self,
        system: &System,
        stepper: &mut Stepper,
        state: &mut State,
        t: f64,
        title: &str,
    ) -> Result<(), SolveError> {
        let fail = |e| integrate_error(system, title, false, e);
        // Candidates: links slack before or predicted slack, every contact on its line.
        let ids: Vec<usize> = (0..self.links.len())
            .filter(|&i| self.slack.contains(&i) || self.links[i].gap(&state.u) > 0.0)
            .collect();
        let n_links = ids.len();
        let contact_gaps: Vec<(usize, Gap)> = self
            .contacts
            .iter()
            .enumerate()
            .filter_map(|(i, c)| c.gap_at(t).map(|g| (i, g)))
            .collect();
        let mut once = self.prepare(stepper, &ids, &contact_gaps).map_err(fail)?;
        self.contact_force.fill(0.0);
        if ids.is_empty() && contact_gaps.is_empty() {
            self.slack.clear();
            return Ok(());
        }
        let gaps: Vec<&Gap> = ids
            .iter()
            .map(|&i| &self.links[i])
            .chain(contact_gaps.iter().map(|(_, g)| g))
            .collect();
        let mut responses: Vec<Response> = Vec::with_capacity(gaps.len());
        for (&j, column) in ids.iter().zip(&mut once) {
            responses.push(match (column.take(), self.link_response.get(j)) {
                (Some(column), _) => Response::Once(column),
                (None, Some(x)) => Response::Kept(x),
                (None, None) => {
                    return Err(SolveError::BadInput {
                        what: format!(
                            "load case '{title}' at t = {t} s: the response of tension link {} \
                             was neither kept nor computed (coil's bug)",
                            j + 1
                        ),
                    })
                }
            });
        }
        for (_, gap) in &contact_gaps {
            let terms = gap
                .b
                .iter()
                .filter_map(|&(eq, c)| {
                    let unit = self.unit_response.iter().find(|(e, _)| *e == eq)?;
                    Some((c, &unit.1))
                })
                .collect();
            responses.push(Response::Combined(terms));
        }
        let gstar: Vec<f64> = gaps.iter().map(|g| g.gap(&state.u)).collect();
        let k: Vec<f64> = gaps.iter().map(|g| g.k).collect();
        let mut active: Vec<usize> = (0..gaps.len())
            .filter(|&p| p >= n_links || self.slack.contains(&ids[p]))
            .filter(|&p| gstar[p] > 0.0 || p < n_links)
            .collect();
        // `G S`: element j's response seen by element i, in the direction of j's force
        // (module docs of `crate::analysis::unilateral`, "Solve").
        let g = |i: usize, j: usize| responses[j].seen_by(i, gaps[i]) * gaps[j].sign;
        let lambda =
            solve_forces(&gstar, &k, g, &mut active).map_err(|e| SolveError::BadInput {
                what: format!("load case '{title}' at t = {t} s: {}", e.describe()),
            })?;
        // The correction `sum_j s_j lambda_j (u_j, 2 u_j/dt, 4 u_j/dt^2)`; the responses
        // used once together through one more step from rest.
        let mut combined = false;
        self.load.fill(0.0);
        for ((&l, response), gap) in lambda.iter().zip(&responses).zip(&gaps) {
            let l = l * gap.sign;
            if l == 0.0 {
                continue;
            }
            match response {
                Response::Kept(x) => {
                    x.subtract(l, self.rates, &mut state.u, &mut state.v, &mut state.a)
                }
                Response::Combined(terms) => {
                    for (c, x) in terms {
                        x.subtract(l * c, self.rates, &mut state.u, &mut state.v, &mut state.a);
                    }
                }
                Response::Once(_) => {
                    combined = true;
                    gap.add_to(l, &mut self.load);
                }
            }
        }
        drop(responses);
        if combined {
            let du = self.response(stepper).map_err(fail)?;
            let [dv, da] = self.rates;
            for (((u, v), a), d) in state
                .u
                .iter_mut()
                .zip(state.v.iter_mut())
                .zip(state.a.iter_mut())
                .zip(&du)
            {
                *u -= d;
                *v -= dv * d;
                *a -= da * d;
            }
        }
        self.slack = active
            .iter()
            .filter(|&&p| p < n_links)
            .map(|&p| ids[p])
            .collect();
        for (p, (i, _)) in contact_gaps.iter().enumerate() {
            self.contact_force[*i] = lambda[n_links + p];
        }
        Ok(())
    }
}

/// The run loop of a direct transient with links or contacts: `stepper` bound to the
/// linear system, `f(t, out)` the load.
#[allow(clippy::too_many_arguments)]
pub(super) fn run_unilateral(
    system: &System,
    stepper: &mut Stepper,
    title: &str,
    steps: usize,
    u0: &[f64],
    v0: &[f64],
    force: &mut dyn FnMut(f64, &mut [f64]),
    recorder: &mut Recorder,
    progress: &coil_io::Progress,
) -> Result<(), SolveError> {
    let fail = |e| integrate_error(system, title, false, e);
    let n = system.dim();
    let dt = stepper.dt();
    let mut term = UnilateralTerm::new(system, stepper, title)?;
    let mut f_n = vec![0.0; n];
    force(0.0, &mut f_n);
    let mut f0 = f_n.clone();
    term.add_initial_force(0.0, u0, &mut f0);
    let mut state = stepper.initial_state(0.0, u0, v0, &f0).map_err(fail)?;
    let record = |recorder: &mut Recorder, state: &State, term: &UnilateralTerm| {
        recorder.record_free(state.t, &state.u, &state.v, &state.a);
        for (column, f) in recorder.extras.iter_mut().zip(&term.contact_force) {
            column.values.push(*f);
        }
    };
    if recorder.wants(0) {
        record(recorder, &state, &term);
    }
    let mut f_next = vec![0.0; n];
    for k in 1..=steps {
        let t = k as f64 * dt;
        f_next.fill(0.0);
        force(t, &mut f_next);
        stepper.step(&mut state, &f_n, &f_next, k).map_err(fail)?;
        state.t = t;
        term.correct(system, stepper, &mut state, t, title)?;
        std::mem::swap(&mut f_n, &mut f_next);
        if k % 64 == 0 {
            progress.set(k as u64);
        }
        if recorder.wants(k) {
            record(recorder, &state, &term);
        }
    }
    Ok(())
}
