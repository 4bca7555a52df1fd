//! The generalised-alpha step on banded operators: envelope ordering (`profile`),
//! four-row block panels (`blocked`), and one operator eliminated from the
//! right-hand side through the factored effective matrix. The fast path of
//! [`super::Stepper`]; faer's general sparse path (`sparse`) remains for patterns
//! whose envelope is too wide (more panel values than [`MAX_PANEL_RATIO`] times the
//! stored lower triangle).
//!
//! # One operator fewer per step
//! The step solves `S a_{n+1} = f_{n+1-af} - M x - C y - K z` with (the predictor
//! folded in, see `stepper`)
//! ```text
//! x = am a_n,   y = v_n + (1-af) dt (1-gamma) a_n,
//! z = u_n + (1-af) [dt v_n + dt^2 (1/2 - beta) a_n],   S = cm M + cc C + ck K.
//! ```
//! For any vector `w`, `M x + C y + K z = S w + M (x - cm w) + C (y - cc w) + K (z - ck w)`
//! and `S^{-1} S w = w`, so with `w` one operator's vector over its scale (say
//! `w = y / cc` for C)
//! ```text
//! a_{n+1} = S^{-1} [f - M (x - cm w) - K (z - ck w)] - w
//! ```
//! and C is never multiplied: the same `a_{n+1}`, up to round-off. Average
//! acceleration and HHT (`am = 0`) need no M product in the first place (`w = 0`
//! eliminates M). The operator to eliminate is chosen per `(scheme, dt)` to leave the
//! cheapest products (a diagonal operator costs one multiply per DOF, a banded one a
//! pass over its panels).
//!
//! **Rayleigh damping.** When `C = alpha M + beta K + D` with `D` diagonal (coil's
//! `DAMPING` on elements, the weight's point mass left out; recognised to
//! round-off by `MergedOperators::rayleigh_split`), the step is written over the
//! primitives M, K, D instead: `M x + C y + K z = M (x + alpha y) + K (z + beta y) + D y`
//! and `S = (cm + cc alpha) M + (ck + cc beta) K + cc D`. Eliminating M leaves one
//! banded product (K) and a diagonal one (D, nonzero on the weight's DOF only) for
//! every scheme, consistent or lumped mass: a third of the unreduced
//! generalised-alpha step's products.
//!
//! **Round-off.** `g = S^{-1}[..]` carries the eliminated vector `w`, and the
//! factor's backward error acts on `g`: the error of `a_{n+1} = g - w` grows with
//! `|w| / |a_{n+1}|`. For M, `w = am a / (1 - am)` (or `(am a + alpha v) /
//! (cm + cc alpha)`): no larger than `a`. For C, `w ~ v / (gamma dt)`, `1 / (w dt)`
//! times `a` in a mode of frequency `w`. For K, `w ~ u / (beta dt^2)`,
//! `1 / (beta (w dt)^2)` times `a`: thousands for the spring's weight, and
//! measured, the displacement drifted from the unreduced step by 3e-12 of its size
//! in 250 steps on the test helix (1e-14 eliminating M or C). K is therefore never
//! eliminated; ties go to M, then C. The corrector is applied in the basis
//! `(g, u_n, v_n, a_n)` with the coefficients collected beforehand, so that the
//! parts of `w` that cancel the predictor exactly cancel in the coefficients, not in
//! the sums.
//!
//! # Vectors
//! Every vector the step forms is a linear combination of `u_n`, `v_n`, `a_n` with
//! coefficients fixed per `(scheme, dt)` (per DOF for the diagonal primitives), so
//! the predictor is one sweep that reads the caller's state and loads in the
//! caller's order and writes the right-hand side and the product vectors in the
//! envelope order; the corrector reads the solution in envelope order and writes the
//! caller's state. When the ordering is a few ascending runs of the caller's order
//! (the natural order, or hubs moved last) each run is a contiguous slice on both
//! sides and nothing is gathered. Diagonal terms on few DOFs (the weight's `D`) are
//! a short list applied after the sweep.

use super::operator::{MergedOperators, C, K, M};
use super::scheme::Coefficients;
use super::state::State;
use crate::error::integrate::IntegrateError;
use crate::linalg::blocked::{self, Blocks, Chunk, FactorPanels, Tile};
use crate::linalg::profile::{
    choose_ordering, has_fma, scatter_lower, vectorized, Ordering, ProfileCholesky,
};

/// How an operator enters the step.
#[derive(Debug, Clone)]
enum Form {
    /// Only diagonal entries: its values per internal DOF.
    Diagonal(Vec<f64>),
    /// Product panels (see `blocked`).
    Panels(Vec<Tile>),
}

/// One of the matrices the step is built from: M, C, K, or with Rayleigh damping
/// recognised M, K and the diagonal `D` of `C = alpha M + beta K + D`.
#[derive(Debug, Clone)]
struct Primitive {
    form: Form,
    /// Values on the envelope, to form `S`.
    on_envelope: Vec<f64>,
    /// Its share `(mu_M, mu_C, mu_K)` of the operators: its vector is
    /// `mu_M x + mu_C y + mu_K z` and its scale in `S` is `mu_M cm + mu_C cc + mu_K ck`
    /// (M is `(1, 0, 0)`; under Rayleigh damping M is `(1, alpha, 0)`, K
    /// `(0, beta, 1)`, D `(0, 1, 0)`).
    share: [f64; 3],
    /// Whether its vector over its scale may be eliminated through `S` (not for K:
    /// see the module docs).
    eliminable: bool,
}

impl Primitive {
    fn cost(&self) -> usize {
        match &self.form {
            Form::Diagonal(_) => 1,
            Form::Panels(p) => 16 * p.len(),
        }
    }
}

/// The step's coefficients for the current `(scheme, dt)`.
/// (Default: a placeholder until the first `refactor`.)
#[derive(Debug, Clone, Default)]
struct Plan {
    /// Primitives multiplied each step (by index), with the `(u, v, a)`
    /// coefficients of their vector.
    products: Vec<(usize, [f64; 3])>,
    /// Per internal DOF, the `(u, v, a)` coefficients of the diagonal primitives'
    /// share of the right-hand side; empty when there is none or when it is sparse.
    diagonal: [Vec<f64>; 3],
    /// The same share when few DOFs have one (a point mass left out of Rayleigh
    /// damping): `(internal, caller's index, coefficients)`.
    sparse_diagonal: Vec<(usize, usize, [f64; 3])>,
    /// Load blend `(1-af) f(t_{n+1}) + af f(t_n)`.
    load: [f64; 2],
    corrector: Corrector,
}

/// The banded step engine (internal numbering: the envelope ordering).
#[derive(Clone)]
pub(crate) struct BandedEngine {
    ordering: Ordering,
    blocks: Blocks,
    fma: bool,
    primitives: Vec<Primitive>,
    s_values: Vec<f64>,
    cholesky: ProfileCholesky,
    factor_panels: FactorPanels,
    plan: Plan,
    /// Product vectors and the right-hand side / solution, in envelope order.
    vectors: [Vec<Chunk>; 3],
    rhs: Vec<Chunk>,
    /// u, v, a, f_n, f_next in envelope order when the ordering has no runs.
    gathered: Vec<f64>,
}

impl std::fmt::Debug for BandedEngine {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("BandedEngine")
            .field("n", &self.blocks.dim())
            .field("ordering_runs", &self.ordering.runs().map(<[_]>::len))
            .field("panel_values", &self.blocks.n_values())
            .field("primitives", &self.primitives.len())
            .field("products_per_step", &self.plan.products.len())
            .finish()
    }
}

/// Panels above this many times the stored lower-triangle entries (plus a small
/// allowance) mean a pattern too wide for the envelope: the sparse path is used.
pub(crate) const MAX_PANEL_RATIO: usize = 4;

impl BandedEngine {
    /// The engine for `ops`, or `None` when the pattern's envelope is too wide.
    pub(crate) fn new(ops: &MergedOperators) -> Option<Self> {
        let n = ops.dim();
        let pattern = ops.pattern();
        let (ordering, _, envelope) = choose_ordering(pattern, |e| Blocks::new(e).n_values());
        let blocks = Blocks::new(&envelope);
        if blocks.n_values() > MAX_PANEL_RATIO * ops.nnz() + 256 {
            return None;
        }
        let is_diagonal = |v: &[f64]| {
            (0..n).all(|j| {
                pattern
                    .col_range(j)
                    .all(|p| pattern.row_idx()[p] == j || v[p] == 0.0)
            })
        };
        let primitive = |v: &[f64], share: [f64; 3], eliminable: bool| {
            let on_envelope = scatter_lower(&envelope, &ordering, pattern, v);
            let form = if is_diagonal(v) {
                Form::Diagonal(
                    (0..n)
                        .map(|i| envelope.row(i, &on_envelope).last().copied().unwrap_or(0.0))
                        .collect(),
                )
            } else {
                Form::Panels(blocks.product_panels(&envelope, &on_envelope))
            };
            Primitive {
                form,
                on_envelope,
                share,
                eliminable,
            }
        };
        let (m, k) = (ops.values(M)?, ops.values(K)?);
        let damping = ops.values(C);
        // A damping matrix that is diagonal already costs nothing; otherwise try to
        // express it through M and K.
        let split = damping
            .filter(|c| !is_diagonal(c))
            .and_then(|_| ops.rayleigh_split());
        let mut primitives = Vec::new();
        match split {
            Some(split) => {
                primitives.push(primitive(m, [1.0, split.alpha, 0.0], true));
                primitives.push(primitive(k, [0.0, split.beta, 1.0], false));
                let mut d = vec![0.0; ops.nnz()];
                for j in 0..n {
                    for p in pattern.col_range(j) {
                        if pattern.row_idx()[p] == j {
                            d[p] = split.diagonal[j];
                        }
                    }
                }
                primitives.push(primitive(&d, [0.0, 1.0, 0.0], true));
            }
            None => {
                primitives.push(primitive(m, [1.0, 0.0, 0.0], true));
                if let Some(c) = damping {
                    primitives.push(primitive(c, [0.0, 1.0, 0.0], true));
                }
                primitives.push(primitive(k, [0.0, 0.0, 1.0], false));
            }
        }
        let n_chunks = blocks.n_chunks();
        let gathered = if ordering.runs().is_some() {
            Vec::new()
        } else {
            vec![0.0; 5 * n]
        };
        Some(Self {
            s_values: vec![0.0; envelope.len()],
            factor_panels: blocks.factor_storage(),
            cholesky: ProfileCholesky::new(envelope),
            ordering,
            blocks,
            fma: has_fma(),
            primitives,
            plan: Plan::default(),
            vectors: [
                vec![[0.0; 4]; n_chunks],
                vec![[0.0; 4]; n_chunks],
                vec![[0.0; 4]; n_chunks],
            ],
            rhs: vec![[0.0; 4]; n_chunks],
            gathered,
        })
    }

    /// Whether the damping matrix is used as `alpha M + beta K + D` (tests, docs).
    #[cfg(test)]
    pub(crate) fn rayleigh(&self) -> bool {
        // [M, K, D] rather than [M, C, K]: the second one is K, not eliminable.
        self.primitives.len() == 3 && !self.primitives[1].eliminable
    }

    /// Banded products per step, ascending runs of the ordering (`None` when it
    /// gathers), and panel values over envelope values (tests, docs).
    #[cfg(test)]
    pub(crate) fn shape(&self) -> (usize, Option<usize>, f64) {
        (
            self.plan.products.len(),
            self.ordering.runs().map(<[_]>::len),
            self.blocks.n_values() as f64 / self.cholesky.envelope().len() as f64,
        )
    }

    /// Whether vectors are gathered through the permutation (no ascending runs).
    #[cfg(test)]
    pub(crate) fn gathers(&self) -> bool {
        self.ordering.runs().is_none()
    }

    /// Forms and factors `S` for `(coefficients, dt)` and plans the step.
    pub(crate) fn refactor(
        &mut self,
        coefficients: &Coefficients,
        dt: f64,
        name: &'static str,
    ) -> Result<(), IntegrateError> {
        let scale = effective(coefficients, dt);
        self.s_values.fill(0.0);
        for primitive in &self.primitives {
            let s = dot3(primitive.share, scale);
            for (target, &v) in self.s_values.iter_mut().zip(&primitive.on_envelope) {
                *target += s * v;
            }
        }
        self.cholesky
            .factor(&self.s_values, name, self.ordering.perm())?;
        self.blocks
            .factor_panels(&self.cholesky, &mut self.factor_panels);
        self.plan = self.plan_step(coefficients, dt);
        Ok(())
    }

    /// Chooses the primitive to eliminate and derives every coefficient of the step.
    fn plan_step(&self, coefficients: &Coefficients, dt: f64) -> Plan {
        let Coefficients {
            alpha_m: am,
            alpha_f: af,
            beta,
            gamma,
        } = *coefficients;
        let scale = effective(coefficients, dt);
        let du = 1.0 - af;
        // (u, v, a) coefficients of x, y, z (module docs).
        let xyz = [
            [0.0, 0.0, am],
            [0.0, 1.0, du * dt * (1.0 - gamma)],
            [1.0, du * dt, du * dt * dt * (0.5 - beta)],
        ];
        let vector = |p: &Primitive| -> [f64; 3] {
            std::array::from_fn(|k| (0..3).map(|o| p.share[o] * xyz[o][k]).sum())
        };
        let primitive_scale = |p: &Primitive| dot3(p.share, scale);
        // Vectors left after eliminating primitive `e` (None: nothing eliminated).
        let reduced = |e: Option<usize>| -> Vec<[f64; 3]> {
            let w = e.map_or([0.0; 3], |e| {
                let p = &self.primitives[e];
                vector(p).map(|c| c / primitive_scale(p))
            });
            self.primitives
                .iter()
                .enumerate()
                .map(|(i, p)| {
                    if Some(i) == e {
                        [0.0; 3]
                    } else {
                        let (v, s) = (vector(p), primitive_scale(p));
                        std::array::from_fn(|k| v[k] - s * w[k])
                    }
                })
                .collect()
        };
        let total = |e: Option<usize>| -> usize {
            reduced(e)
                .iter()
                .zip(&self.primitives)
                .filter(|(r, _)| **r != [0.0; 3])
                .map(|(_, p)| p.cost())
                .sum()
        };
        // Ties keep the earlier choice: no elimination, then M, then C (module docs).
        let mut eliminated = None;
        for (i, p) in self.primitives.iter().enumerate() {
            if p.eliminable && total(Some(i)) < total(eliminated) {
                eliminated = Some(i);
            }
        }
        let r = reduced(eliminated);
        let n = self.blocks.dim();
        let mut products = Vec::new();
        let mut diagonal: [Vec<f64>; 3] = Default::default();
        for (i, (p, r)) in self.primitives.iter().zip(&r).enumerate() {
            if *r == [0.0; 3] {
                continue;
            }
            match &p.form {
                Form::Panels(_) => products.push((i, *r)),
                Form::Diagonal(d) => {
                    for (k, coefficients) in diagonal.iter_mut().enumerate() {
                        coefficients.resize(n, 0.0);
                        for (c, &dv) in coefficients.iter_mut().zip(d) {
                            *c += dv * r[k];
                        }
                    }
                }
            }
        }
        // Few rows: a short list beats three more streams through the predictor.
        let mut sparse_diagonal = Vec::new();
        if !diagonal[0].is_empty() {
            let rows: Vec<usize> = (0..n)
                .filter(|&k| diagonal.iter().any(|d| d[k] != 0.0))
                .collect();
            if rows.len() * 16 <= n {
                let perm = self.ordering.perm();
                sparse_diagonal = rows
                    .into_iter()
                    .map(|k| (k, perm[k], [diagonal[0][k], diagonal[1][k], diagonal[2][k]]))
                    .collect();
                diagonal = Default::default();
            }
        }
        let w = eliminated.map_or([0.0; 3], |e| {
            let p = &self.primitives[e];
            vector(p).map(|c| c / primitive_scale(p))
        });
        Plan {
            products,
            diagonal,
            sparse_diagonal,
            load: [du, af],
            corrector: Corrector::new(w, dt, beta, gamma),
        }
    }

    /// Solves `S x = b` in place, `b` in the caller's numbering, through the step's
    /// right-hand-side buffer (the point laws' columns `S^{-1} e_i`, once per
    /// `(scheme, dt)`).
    pub(crate) fn solve_in_place(&mut self, b: &mut [f64]) {
        let perm = self.ordering.perm();
        let rhs = self.rhs.as_flattened_mut();
        rhs.fill(0.0);
        for (r, &i) in rhs.iter_mut().zip(perm) {
            *r = b[i];
        }
        blocked::solve(&self.blocks, self.fma, &self.factor_panels, &mut self.rhs);
        let rhs = self.rhs.as_flattened();
        for (&r, &i) in rhs.iter().zip(perm) {
            b[i] = r;
        }
    }

    /// One step (see the module docs); returns false when the new state is not
    /// finite. The state and loads are in the caller's numbering, of checked sizes.
    pub(crate) fn step(&mut self, state: &mut State, f_n: &[f64], f_next: &[f64]) -> bool {
        let diagonal = !self.plan.diagonal[0].is_empty();
        match (self.plan.products.len(), diagonal) {
            (0, false) => self.step_with::<0, false>(state, f_n, f_next),
            (0, true) => self.step_with::<0, true>(state, f_n, f_next),
            (1, false) => self.step_with::<1, false>(state, f_n, f_next),
            (1, true) => self.step_with::<1, true>(state, f_n, f_next),
            (2, false) => self.step_with::<2, false>(state, f_n, f_next),
            (2, true) => self.step_with::<2, true>(state, f_n, f_next),
            (_, false) => self.step_with::<3, false>(state, f_n, f_next),
            (_, true) => self.step_with::<3, true>(state, f_n, f_next),
        }
    }

    fn step_with<const N: usize, const DIAG: bool>(
        &mut self,
        state: &mut State,
        f_n: &[f64],
        f_next: &[f64],
    ) -> bool {
        let plan = &self.plan;
        let mut products = [[0.0; 3]; 3];
        for (p, &(_, c)) in products.iter_mut().zip(&plan.products) {
            *p = c;
        }
        let predictor = Predictor::<N, DIAG> {
            products,
            load: plan.load,
        };
        let n = self.blocks.dim();
        // Without a load blend (af = 0) the old load is not read: the new one stands
        // in, already in cache.
        let f_n = if plan.load[1] == 0.0 { f_next } else { f_n };
        {
            let [p0, p1, p2] = &mut self.vectors;
            let mut out = Outputs {
                rhs: &mut self.rhs.as_flattened_mut()[..n],
                p: [
                    &mut p0.as_flattened_mut()[..n],
                    &mut p1.as_flattened_mut()[..n],
                    &mut p2.as_flattened_mut()[..n],
                ],
            };
            let diag = [
                plan.diagonal[0].as_slice(),
                plan.diagonal[1].as_slice(),
                plan.diagonal[2].as_slice(),
            ];
            match self.ordering.runs() {
                Some(runs) => {
                    for run in runs {
                        let caller = run.caller_start..run.caller_start + run.len;
                        let internal = run.start..run.start + run.len;
                        let input = Inputs {
                            u: &state.u[caller.clone()],
                            v: &state.v[caller.clone()],
                            a: &state.a[caller.clone()],
                            f_n: &f_n[caller.clone()],
                            f_next: &f_next[caller],
                        };
                        predictor.run(
                            input,
                            sub_diag(&diag, internal.clone()),
                            out.range(internal),
                        );
                    }
                }
                None => {
                    let perm = self.ordering.perm();
                    let (u, rest) = self.gathered.split_at_mut(n);
                    let (v, rest) = rest.split_at_mut(n);
                    let (a, rest) = rest.split_at_mut(n);
                    let (g_n, g_next) = rest.split_at_mut(n);
                    for (target, source) in [
                        (&mut *u, state.u.as_slice()),
                        (&mut *v, &state.v),
                        (&mut *a, &state.a),
                        (&mut *g_n, f_n),
                        (&mut *g_next, f_next),
                    ] {
                        for (t, &i) in target.iter_mut().zip(perm) {
                            *t = source[i];
                        }
                    }
                    let input = Inputs {
                        u,
                        v,
                        a,
                        f_n: g_n,
                        f_next: g_next,
                    };
                    predictor.run(input, sub_diag(&diag, 0..n), out.range(0..n));
                }
            }
        }
        let rhs = self.rhs.as_flattened_mut();
        for &(k, i, [cu, cv, ca]) in &plan.sparse_diagonal {
            rhs[k] -= cu * state.u[i] + cv * state.v[i] + ca * state.a[i];
        }
        let panels: [&[Tile]; N] =
            std::array::from_fn(|j| match &self.primitives[plan.products[j].0].form {
                Form::Panels(p) => p.as_slice(),
                Form::Diagonal(_) => &[],
            });
        let vectors: [&[Chunk]; N] = std::array::from_fn(|j| self.vectors[j].as_slice());
        blocked::subtract_product(&self.blocks, self.fma, panels, vectors, &mut self.rhs);
        blocked::solve(&self.blocks, self.fma, &self.factor_panels, &mut self.rhs);

        let corrector = &plan.corrector;
        let solution = &self.rhs.as_flattened()[..n];
        let mut finite = true;
        match self.ordering.runs() {
            Some(runs) => {
                for run in runs {
                    let caller = run.caller_start..run.caller_start + run.len;
                    finite &= corrector.run(
                        &mut state.u[caller.clone()],
                        &mut state.v[caller.clone()],
                        &mut state.a[caller],
                        &solution[run.start..run.start + run.len],
                    );
                }
            }
            None => {
                let perm = self.ordering.perm();
                let (u, rest) = self.gathered.split_at_mut(n);
                let (v, rest) = rest.split_at_mut(n);
                let (a, _) = rest.split_at_mut(n);
                finite = corrector.run(u, v, a, solution);
                for (target, source) in [(&mut state.u, u), (&mut state.v, v), (&mut state.a, a)] {
                    for (&s, &i) in source.iter().zip(perm) {
                        target[i] = s;
                    }
                }
            }
        }
        finite
    }
}

/// `(cm, cc, ck)` of `S = cm M + cc C + ck K`, indexed by [`M`], [`C`], [`K`].
fn effective(coefficients: &Coefficients, dt: f64) -> [f64; 3] {
    let (cm, cc, ck) = coefficients.effective(dt);
    let mut s = [0.0; 3];
    s[M] = cm;
    s[C] = cc;
    s[K] = ck;
    s
}

fn dot3(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn sub_diag<'a>(diag: &[&'a [f64]; 3], range: std::ops::Range<usize>) -> [&'a [f64]; 3] {
    diag.map(|d| if d.is_empty() { d } else { &d[range.clone()] })
}

/// One contiguous stretch of the caller's state and loads.
struct Inputs<'a> {
    u: &'a [f64],
    v: &'a [f64],
    a: &'a [f64],
    f_n: &'a [f64],
    f_next: &'a [f64],
}

/// The predictor's outputs in envelope order.
struct Outputs<'a> {
    rhs: &'a mut [f64],
    p: [&'a mut [f64]; 3],
}

impl Outputs<'_> {
    fn range(&mut self, r: std::ops::Range<usize>) -> Outputs<'_> {
        let [p0, p1, p2] = &mut self.p;
        Outputs {
            rhs: &mut self.rhs[r.clone()],
            p: [&mut p0[r.clone()], &mut p1[r.clone()], &mut p2[r]],
        }
    }
}

/// Right-hand side and product vectors from the state (module docs); the first `N`
/// product vectors are written.
struct Predictor<const N: usize, const DIAG: bool> {
    products: [[f64; 3]; 3],
    load: [f64; 2],
}

impl<const N: usize, const DIAG: bool> Predictor<N, DIAG> {
    fn run(&self, input: Inputs<'_>, diag: [&[f64]; 3], out: Outputs<'_>) {
        vectorized(
            #[inline(always)]
            || self.kernel(input, diag, out),
        )
    }

    #[inline(always)]
    fn kernel(&self, input: Inputs<'_>, diag: [&[f64]; 3], out: Outputs<'_>) {
        let len = out.rhs.len();
        let (u, v, a) = (&input.u[..len], &input.v[..len], &input.a[..len]);
        let (f_n, f_next) = (&input.f_n[..len], &input.f_next[..len]);
        let [du, af] = self.load;
        let rhs = &mut out.rhs[..len];
        let [p0, p1, p2] = out.p;
        let (p0, p1, p2) = (&mut p0[..len], &mut p1[..len], &mut p2[..len]);
        let [c0, c1, c2] = self.products;
        let d = if DIAG {
            [&diag[0][..len], &diag[1][..len], &diag[2][..len]]
        } else {
            [&[][..]; 3]
        };
        for k in 0..len {
            let (uk, vk, ak) = (u[k], v[k], a[k]);
            let mut r = du * f_next[k] + af * f_n[k];
            if DIAG {
                r -= d[0][k] * uk + d[1][k] * vk + d[2][k] * ak;
            }
            rhs[k] = r;
            if N > 0 {
                p0[k] = c0[0] * uk + c0[1] * vk + c0[2] * ak;
            }
            if N > 1 {
                p1[k] = c1[0] * uk + c1[1] * vk + c1[2] * ak;
            }
            if N > 2 {
                p2[k] = c2[0] * uk + c2[1] * vk + c2[2] * ak;
            }
        }
    }
}

/// The corrector in the basis `(g, u_n, v_n, a_n)`, `g` the solution of the reduced
/// system: `a_{n+1} = g - w`, `u_{n+1} = u~ + beta dt^2 a_{n+1}`,
/// `v_{n+1} = v~ + gamma dt a_{n+1}` with the coefficients collected beforehand, so
/// that the parts of `w` that cancel the predictor exactly (all of `u~` when K is
/// eliminated, all of `v~` when C is) cancel in the coefficients, not in the sums.
#[derive(Debug, Clone, Default)]
struct Corrector {
    /// Rows `a_{n+1}`, `u_{n+1}`, `v_{n+1}`; columns `g`, `u_n`, `v_n`, `a_n`.
    c: [[f64; 4]; 3],
}

impl Corrector {
    fn new(w: [f64; 3], dt: f64, beta: f64, gamma: f64) -> Self {
        let (bdt2, gdt) = (beta * dt * dt, gamma * dt);
        Self {
            c: [
                [1.0, -w[0], -w[1], -w[2]],
                [
                    bdt2,
                    1.0 - bdt2 * w[0],
                    dt - bdt2 * w[1],
                    dt * dt * (0.5 - beta) - bdt2 * w[2],
                ],
                [
                    gdt,
                    -gdt * w[0],
                    1.0 - gdt * w[1],
                    dt * (1.0 - gamma) - gdt * w[2],
                ],
            ],
        }
    }

    /// Updates one stretch in place; returns whether every new value is finite.
    fn run(&self, u: &mut [f64], v: &mut [f64], a: &mut [f64], g: &[f64]) -> bool {
        vectorized(
            #[inline(always)]
            || self.kernel(u, v, a, g),
        )
    }

    #[inline(always)]
    fn kernel(&self, u: &mut [f64], v: &mut [f64], a: &mut [f64], g: &[f64]) -> bool {
        let len = g.len();
        let (u, v, a) = (&mut u[..len], &mut v[..len], &mut a[..len]);
        let [ca, cu, cv] = self.c;
        let mut finite = true;
        for k in 0..len {
            let (gk, uk, vk, ak) = (g[k], u[k], v[k], a[k]);
            let a_new = gk + (ca[1] * uk + ca[2] * vk + ca[3] * ak);
            let u_new = cu[0] * gk + (cu[1] * uk + cu[2] * vk + cu[3] * ak);
            let v_new = cv[0] * gk + (cv[1] * uk + cv[2] * vk + cv[3] * ak);
            u[k] = u_new;
            v[k] = v_new;
            a[k] = a_new;
            finite &= u_new.is_finite() & v_new.is_finite() & a_new.is_finite();
        }
        finite
    }
}
