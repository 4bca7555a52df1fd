//! Tension links and moving contacts in direct integration (average acceleration): each
//! step is taken linear (taut links in `K`, no contact force at its end), then the
//! unilateral elements' end-of-step forces are found exactly and their response removed
//! (`crate::analysis::unilateral`, "Solve"). A step is affine in its end load, so the
//! response to an element's `b` as end load from rest, `(u_j, v_j, a_j)`, turns the
//! forces `lambda` into the state change `-sum_j s_j lambda_j (u_j, v_j, a_j)`, and the
//! end-of-step gaps are `g* - G S lambda`, `G_ij = b_i^T u_j`. The links' responses are
//! computed once per stepper. The contact's `b` moves with its point, but over the free
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
//! `du = sum_j s_j lambda_j u_j` applied as `(du, 2 du/dt, 4 du/dt^2)`: a third of the
//! passes over the state that three stored vectors per response cost (a profile of the
//! same run put a quarter of its time in those passes).

use super::error::integrate_error;
use super::recording::Recorder;
use crate::analysis::system::System;
use crate::analysis::unilateral::{link_gaps, solve_forces, ContactLine, Gap};
use crate::error::solve::SolveError;
use crate::integrate::{Scheme, State, Stepper};

/// The links' slack corrections with their step responses, the contacts, and the
/// elements closed at the last step.
pub(super) struct UnilateralTerm {
    links: Vec<Gap>,
    /// The displacement of each link's step response from rest (module docs).
    link_response: Vec<Vec<f64>>,
    contacts: Vec<ContactLine>,
    /// Closed links (indices into `links`).
    slack: Vec<usize>,
    /// Each contact's force at the end of the last step (N).
    pub(super) contact_force: Vec<f64>,
    /// Displacements of the step responses from rest to a unit end load on one free
    /// equation, for the equations the contacts' `b` read at the last step.
    unit_response: Vec<(usize, Vec<f64>)>,
    /// The step's `dt` (s): a response's velocity is `2u/dt`, its acceleration `4u/dt^2`.
    dt: f64,
    zero: Vec<f64>,
    load: Vec<f64>,
    /// The correction `du` being summed (length `n`, reused between steps).
    du: Vec<f64>,
}

impl UnilateralTerm {
    pub(super) fn new(
        system: &System,
        stepper: &mut Stepper,
        title: &str,
    ) -> Result<Self, SolveError> {
        let fail = |e| integrate_error(system, title, false, e);
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
        let zero = vec![0.0; n];
        let mut load = vec![0.0; n];
        let mut link_response = Vec::with_capacity(links.len());
        for gap in &links {
            load.fill(0.0);
            gap.add_to(1.0, &mut load);
            let mut state = State::zeros(n, 0.0);
            stepper.step(&mut state, &zero, &load, 0).map_err(fail)?;
            link_response.push(state.u);
        }
        let contacts = system
            .model
            .moving_contacts()
            .iter()
            .map(|c| ContactLine::new(system, c))
            .collect::<Result<Vec<_>, _>>()?;
        Ok(UnilateralTerm {
            contact_force: vec![0.0; contacts.len()],
            unit_response: Vec::new(),
            dt: stepper.dt(),
            links,
            link_response,
            contacts,
            slack: Vec::new(),
            zero,
            load,
            du: vec![0.0; n],
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
        let n = state.u.len();
        // Candidates: links slack before or predicted slack, every contact on its line.
        let mut ids: Vec<usize> = (0..self.links.len())
            .filter(|&i| self.slack.contains(&i) || self.links[i].gap(&state.u) > 0.0)
            .collect();
        let n_links = ids.len();
        let mut gaps: Vec<&Gap> = ids.iter().map(|&i| &self.links[i]).collect();
        let contact_gaps: Vec<(usize, Gap)> = self
            .contacts
            .iter()
            .enumerate()
            .filter_map(|(i, c)| c.gap_at(t).map(|g| (i, g)))
            .collect();
        let mut responses: Vec<&[f64]> = ids
            .iter()
            .map(|&i| self.link_response[i].as_slice())
            .collect();
        let mut contact_response = Vec::with_capacity(contact_gaps.len());
        let mut used: Vec<usize> = Vec::new();
        for (_, gap) in &contact_gaps {
            let mut r = vec![0.0; n];
            for &(eq, c) in &gap.b {
                let at = match self.unit_response.iter().position(|(e, _)| *e == eq) {
                    Some(at) => at,
                    None => {
                        self.load.fill(0.0);
                        self.load[eq] = 1.0;
                        let mut unit = State::zeros(n, 0.0);
                        stepper
                            .step(&mut unit, &self.zero, &self.load, 0)
                            .map_err(fail)?;
                        self.unit_response.push((eq, unit.u));
                        self.unit_response.len() - 1
                    }
                };
                used.push(eq);
                for (x, y) in r.iter_mut().zip(&self.unit_response[at].1) {
                    *x += c * y;
                }
            }
            contact_response.push(r);
        }
        self.unit_response.retain(|(e, _)| used.contains(e));
        gaps.extend(contact_gaps.iter().map(|(_, g)| g));
        responses.extend(contact_response.iter().map(Vec::as_slice));
        ids.extend(contact_gaps.iter().map(|(i, _)| usize::MAX - i));
        self.contact_force.fill(0.0);
        if gaps.is_empty() {
            self.slack.clear();
            return Ok(());
        }
        let gstar: Vec<f64> = gaps.iter().map(|g| g.gap(&state.u)).collect();
        let k: Vec<f64> = gaps.iter().map(|g| g.k).collect();
        let mut active: Vec<usize> = (0..gaps.len())
            .filter(|&p| p >= n_links || self.slack.contains(&ids[p]))
            .filter(|&p| gstar[p] > 0.0 || p < n_links)
            .collect();
        let lambda = solve_forces(&gstar, &k, |i, j| gaps[i].dot(responses[j]), &mut active)
            .ok_or_else(|| SolveError::BadInput {
                what: format!(
                    "load case '{title}' at t = {t} s: the tension links and contacts found no \
                 consistent set of closed elements"
                ),
            })?;
        self.du.fill(0.0);
        let mut moved = false;
        for ((&l, r), gap) in lambda.iter().zip(&responses).zip(&gaps) {
            let l = l * gap.sign;
            if l != 0.0 {
                moved = true;
                for (x, c) in self.du.iter_mut().zip(r.iter()) {
                    *x += l * c;
                }
            }
        }
        if moved {
            let (dv, da) = (2.0 / self.dt, 4.0 / (self.dt * self.dt));
            for (((u, v), a), d) in state
                .u
                .iter_mut()
                .zip(state.v.iter_mut())
                .zip(state.a.iter_mut())
                .zip(&self.du)
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
