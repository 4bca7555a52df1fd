//! Envelope (profile, skyline) storage of symmetric matrices under a bandwidth-reducing
//! ordering, and the envelope Cholesky factorisation of the direct integrator's
//! effective matrix when the operators are banded, as beam models numbered along
//! the wire are.
//!
//! # Storage
//! Internal unknown `k` is the caller's DOF `perm[k]`. Row `i` of the lower triangle is
//! stored densely from its first structural non-zero `first[i]` to the diagonal,
//! which comes last: `values[ptr[i]..ptr[i + 1]]` holds columns `first[i]..=i`. Every
//! row is one contiguous slice, so the factorisation is dense dot products, no index
//! arrays. The step itself runs on four-row block panels built from the envelope
//! (`blocked`).
//!
//! # Ordering
//! The envelope of Cholesky's `L` is the envelope of the matrix (fill stays inside
//! it; George & Liu, "Computer Solution of Large Sparse Positive Definite Systems",
//! 1981, ch. 4), so the ordering that makes the envelope small makes both the
//! products and the factor small. Three candidates are rated by the caller's cost
//! (the size of the step's block panels on their envelope):
//! 1. the caller's order;
//! 2. the caller's order with "hub" DOFs moved last, keeping their relative order: a
//!    DOF whose neighbours lie far from it in the caller's numbering (a rigid tie's
//!    reference DOF, numbered first, coupled to the far end of the wire: an "arrow"
//!    in the matrix). Moved last, a hub costs one short row instead of making every
//!    row between it and its neighbours long;
//! 3. reverse Cuthill-McKee (Cuthill & McKee 1969, reversed as in George & Liu 1981,
//!    ch. 4.3) from a pseudo-peripheral node of each connected component.
//!
//! The first two keep the caller's order in a few ascending runs, so that vectors
//! move in and out of the step as contiguous slices; reverse Cuthill-McKee must
//! gather through an index every step and is taken only when it is more than a
//! tenth smaller. On the paper's spring (weight DOF numbered first, tied to the top
//! wire node) candidate 2 wins: three runs, the envelope of the bare wire.
//!
//! # Cholesky
//! Row-oriented (Crout / bordering) `A = L L^T`: for each row `i`,
//! `L_ij = (A_ij - sum_k L_ik L_jk) / L_jj` over the common envelope, then
//! `L_ii = sqrt(A_ii - sum_k L_ik^2)`. A pivot that is not positive (or not finite)
//! is reported with the DOF in the caller's numbering. It runs once per `(scheme,
//! dt)`, compiled for AVX2 + FMA where the CPU has them ([`vectorized`]: faer's SIMD
//! dispatch; the workspace itself builds for baseline x86-64). Its envelope solve
//! is kept as the reference of the block solves' tests; faer's sparse Cholesky is the
//! reference of both.

use faer::sparse::SymbolicSparseColMatRef;
use faer::traits::pulp;

use crate::error::integrate::IntegrateError;

/// A bandwidth-reducing ordering: `perm[k]` is the caller's index of internal
/// unknown `k`.
#[derive(Debug, Clone)]
pub(crate) struct Ordering {
    perm: Vec<usize>,
    /// The same permutation as ascending runs `(internal start, caller start, length)`
    /// when it has few of them, so that permuting a vector is a few slice copies.
    runs: Option<Vec<Run>>,
}

/// `internal[start..start + len]` is `caller[caller_start..caller_start + len]`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Run {
    pub(crate) start: usize,
    pub(crate) caller_start: usize,
    pub(crate) len: usize,
}

impl Ordering {
    fn from_perm(perm: Vec<usize>) -> Self {
        let mut runs: Vec<Run> = Vec::new();
        for (k, &i) in perm.iter().enumerate() {
            match runs.last_mut() {
                Some(run) if run.caller_start + run.len == i => run.len += 1,
                _ => runs.push(Run {
                    start: k,
                    caller_start: i,
                    len: 1,
                }),
            }
        }
        // Below about eight DOFs per run a gather through the index is as fast.
        let runs = (runs.len() * 8 <= perm.len().max(8)).then_some(runs);
        Self { perm, runs }
    }

    /// `perm[k]`: the caller's index of internal unknown `k`.
    pub(crate) fn perm(&self) -> &[usize] {
        &self.perm
    }

    /// The ascending runs, when the permutation has few.
    pub(crate) fn runs(&self) -> Option<&[Run]> {
        self.runs.as_deref()
    }
}

/// Which candidate ordering was chosen (for the docs and the tests).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum OrderingKind {
    Natural,
    HubsLast,
    ReverseCuthillMcKee,
}

/// The rows' first columns and offsets of a lower envelope.
#[derive(Debug, Clone)]
pub(crate) struct Envelope {
    first: Vec<usize>,
    ptr: Vec<usize>,
}

impl Envelope {
    pub(crate) fn dim(&self) -> usize {
        self.first.len()
    }

    /// Number of stored entries (the diagonal included).
    pub(crate) fn len(&self) -> usize {
        self.ptr[self.dim()]
    }

    /// First stored column of `row`.
    pub(crate) fn first(&self, row: usize) -> usize {
        self.first[row]
    }

    /// The stored entries of `row` (columns `first(row)..=row`) in a value array.
    pub(crate) fn row<'a>(&self, row: usize, values: &'a [f64]) -> &'a [f64] {
        &values[self.ptr[row]..self.ptr[row + 1]]
    }

    /// Position of entry `(row, col)` (`first[row] <= col <= row`) in a value array.
    fn position(&self, row: usize, col: usize) -> usize {
        self.ptr[row] + col - self.first[row]
    }
}

/// Symmetric adjacency (both directions, no diagonal) of a pattern given by its lower
/// triangle in compressed sparse columns, as `(offsets, neighbours)`.
fn adjacency(pattern: SymbolicSparseColMatRef<'_, usize>) -> (Vec<usize>, Vec<usize>) {
    let n = pattern.ncols();
    let mut degree = vec![0usize; n];
    for j in 0..n {
        for &i in pattern.row_idx_of_col_raw(j) {
            if i != j {
                degree[i] += 1;
                degree[j] += 1;
            }
        }
    }
    let mut offsets = vec![0usize; n + 1];
    for i in 0..n {
        offsets[i + 1] = offsets[i] + degree[i];
    }
    let mut next = offsets[..n].to_vec();
    let mut neighbours = vec![0usize; offsets[n]];
    for j in 0..n {
        for &i in pattern.row_idx_of_col_raw(j) {
            if i != j {
                neighbours[next[i]] = j;
                next[i] += 1;
                neighbours[next[j]] = i;
                next[j] += 1;
            }
        }
    }
    (offsets, neighbours)
}

/// First column of each internal row under `perm` (`inverse[old] = new`).
fn envelope_firsts(offsets: &[usize], neighbours: &[usize], perm: &[usize]) -> Vec<usize> {
    let n = perm.len();
    let mut inverse = vec![0usize; n];
    for (new, &old) in perm.iter().enumerate() {
        inverse[old] = new;
    }
    perm.iter()
        .enumerate()
        .map(|(new, &old)| {
            neighbours[offsets[old]..offsets[old + 1]]
                .iter()
                .map(|&j| inverse[j])
                .fold(new, usize::min)
        })
        .collect()
}

/// The caller's order with hub DOFs (neighbours much farther away than typical) moved
/// last, or `None` when there are none or too many to call them hubs.
fn hubs_last(offsets: &[usize], neighbours: &[usize]) -> Option<Vec<usize>> {
    let n = offsets.len() - 1;
    if n == 0 {
        return None;
    }
    let span: Vec<usize> = (0..n)
        .map(|i| {
            neighbours[offsets[i]..offsets[i + 1]]
                .iter()
                .map(|&j| j.abs_diff(i))
                .max()
                .unwrap_or(0)
        })
        .collect();
    let mut sorted = span.clone();
    sorted.sort_unstable();
    let median = sorted[n / 2];
    // A hub reaches more than four typical bandwidths away (and beyond a 6-DOF
    // node pair, so that a plain chain has none).
    let threshold = 4 * median.max(12);
    let is_hub: Vec<bool> = span.iter().map(|&s| s > threshold).collect();
    let hubs = is_hub.iter().filter(|&&h| h).count();
    if hubs == 0 || hubs * 8 > n {
        return None;
    }
    let mut perm: Vec<usize> = (0..n).filter(|&i| !is_hub[i]).collect();
    perm.extend((0..n).filter(|&i| is_hub[i]));
    Some(perm)
}

/// Reverse Cuthill-McKee: breadth-first from a pseudo-peripheral node of each
/// component, neighbours by increasing degree, the whole order reversed.
fn reverse_cuthill_mckee(offsets: &[usize], neighbours: &[usize]) -> Vec<usize> {
    let n = offsets.len() - 1;
    let degree = |i: usize| offsets[i + 1] - offsets[i];
    let mut order = Vec::with_capacity(n);
    let mut placed = vec![false; n];
    let mut level = vec![usize::MAX; n];
    let mut scratch = Vec::new();
    for seed in 0..n {
        if placed[seed] {
            continue;
        }
        // Pseudo-peripheral node (George & Liu 1979): restart from a node of least
        // degree in the last level while the eccentricity grows.
        let mut root = seed;
        let mut eccentricity = 0;
        loop {
            let (depth, last) =
                bfs_levels(root, offsets, neighbours, &placed, &mut level, &mut scratch);
            let candidate = last
                .iter()
                .copied()
                .min_by_key(|&i| degree(i))
                .unwrap_or(root);
            if depth > eccentricity {
                eccentricity = depth;
                root = candidate;
            } else {
                break;
            }
        }
        let start = order.len();
        order.push(root);
        placed[root] = true;
        let mut head = start;
        let mut children = Vec::new();
        while head < order.len() {
            let i = order[head];
            head += 1;
            children.clear();
            children.extend(
                neighbours[offsets[i]..offsets[i + 1]]
                    .iter()
                    .copied()
                    .filter(|&j| !placed[j]),
            );
            children.sort_by_key(|&j| (degree(j), j));
            children.dedup();
            for &j in &children {
                placed[j] = true;
                order.push(j);
            }
        }
    }
    order.reverse();
    order
}

/// Level structure of the unplaced component of `root`: its depth and the nodes of
/// its last level.
fn bfs_levels(
    root: usize,
    offsets: &[usize],
    neighbours: &[usize],
    placed: &[bool],
    level: &mut [usize],
    queue: &mut Vec<usize>,
) -> (usize, Vec<usize>) {
    queue.clear();
    queue.push(root);
    level[root] = 0;
    let mut head = 0;
    while head < queue.len() {
        let i = queue[head];
        head += 1;
        for &j in &neighbours[offsets[i]..offsets[i + 1]] {
            if !placed[j] && level[j] == usize::MAX {
                level[j] = level[i] + 1;
                queue.push(j);
            }
        }
    }
    let depth = queue.last().map_or(0, |&i| level[i]);
    let last = queue
        .iter()
        .copied()
        .filter(|&i| level[i] == depth)
        .collect();
    for &i in queue.iter() {
        level[i] = usize::MAX;
    }
    (depth, last)
}

/// The chosen ordering among the candidates (module docs), with its envelope. `cost`
/// rates an envelope (the step's storage built on it); reverse Cuthill-McKee, whose
/// permutation must be gathered through an index every step, has to beat the
/// run-based orderings by more than a tenth.
pub(crate) fn choose_ordering(
    pattern: SymbolicSparseColMatRef<'_, usize>,
    cost: impl Fn(&Envelope) -> usize,
) -> (Ordering, OrderingKind, Envelope) {
    let n = pattern.ncols();
    let (offsets, neighbours) = adjacency(pattern);
    let envelope_of = |perm: &[usize]| {
        let first = envelope_firsts(&offsets, &neighbours, perm);
        let mut ptr = Vec::with_capacity(n + 1);
        ptr.push(0usize);
        for (i, &f) in first.iter().enumerate() {
            ptr.push(ptr[i] + i - f + 1);
        }
        Envelope { first, ptr }
    };
    let natural: Vec<usize> = (0..n).collect();
    let mut best_envelope = envelope_of(&natural);
    let mut best_cost = cost(&best_envelope);
    let mut best = (natural, OrderingKind::Natural);
    if let Some(perm) = hubs_last(&offsets, &neighbours) {
        let envelope = envelope_of(&perm);
        let c = cost(&envelope);
        if c < best_cost {
            (best_envelope, best_cost, best) = (envelope, c, (perm, OrderingKind::HubsLast));
        }
    }
    if n > 0 {
        let perm = reverse_cuthill_mckee(&offsets, &neighbours);
        let envelope = envelope_of(&perm);
        let c = cost(&envelope);
        if 10 * c < 9 * best_cost {
            (best_envelope, best) = (envelope, (perm, OrderingKind::ReverseCuthillMcKee));
        }
    }
    (Ordering::from_perm(best.0), best.1, best_envelope)
}

/// Values of a symmetric matrix, given by its lower triangle (compressed sparse
/// columns, caller numbering), laid out on `envelope` under `ordering`. Entries
/// outside the envelope cannot occur: the envelope was built from this pattern.
pub(crate) fn scatter_lower(
    envelope: &Envelope,
    ordering: &Ordering,
    pattern: SymbolicSparseColMatRef<'_, usize>,
    values: &[f64],
) -> Vec<f64> {
    let n = envelope.dim();
    let mut inverse = vec![0usize; n];
    for (new, &old) in ordering.perm.iter().enumerate() {
        inverse[old] = new;
    }
    let mut out = vec![0.0; envelope.len()];
    for j in 0..n {
        for p in pattern.col_range(j) {
            let (a, b) = (inverse[pattern.row_idx()[p]], inverse[j]);
            let (row, col) = (a.max(b), a.min(b));
            out[envelope.position(row, col)] += values[p];
        }
    }
    out
}

/// Runs `f` compiled for the best instruction set of this CPU (AVX2 + FMA on x86-64
/// where available), through faer's SIMD dispatch. `f` and everything it calls must
/// be inlined into it (`#[inline(always)]`) to benefit.
#[inline(always)]
pub(crate) fn vectorized<R>(f: impl FnOnce() -> R) -> R {
    struct Op<F>(F);
    impl<R, F: FnOnce() -> R> pulp::WithSimd for Op<F> {
        type Output = R;
        #[inline(always)]
        fn with_simd<S: pulp::Simd>(self, _simd: S) -> R {
            (self.0)()
        }
    }
    pulp::Arch::new().dispatch(Op(f))
}

/// Whether `f64::mul_add` is one instruction here (otherwise it is a slow library
/// call and the kernels multiply and add separately).
pub(crate) fn has_fma() -> bool {
    #[cfg(any(target_arch = "x86", target_arch = "x86_64"))]
    {
        std::is_x86_feature_detected!("fma")
    }
    #[cfg(target_arch = "aarch64")]
    {
        true
    }
    #[cfg(not(any(target_arch = "x86", target_arch = "x86_64", target_arch = "aarch64")))]
    {
        false
    }
}

/// `a b + c`, fused when `FMA`.
#[inline(always)]
fn madd<const FMA: bool>(a: f64, b: f64, c: f64) -> f64 {
    if FMA {
        a.mul_add(b, c)
    } else {
        a * b + c
    }
}

/// `sum_k a[k] b[k]` in four partial sums (`a`, `b` of equal length).
#[inline(always)]
fn dot<const FMA: bool>(a: &[f64], b: &[f64]) -> f64 {
    let (a4, b4) = (a.chunks_exact(4), b.chunks_exact(4));
    let (a_rest, b_rest) = (a4.remainder(), b4.remainder());
    let mut acc = [0.0; 4];
    for (x, y) in a4.zip(b4) {
        for k in 0..4 {
            acc[k] = madd::<FMA>(x[k], y[k], acc[k]);
        }
    }
    for (k, (&x, &y)) in a_rest.iter().zip(b_rest).enumerate() {
        acc[k] = madd::<FMA>(x, y, acc[k]);
    }
    (acc[0] + acc[1]) + (acc[2] + acc[3])
}

/// A Cholesky factor `A = L L^T` on an envelope (internal numbering).
#[derive(Debug, Clone)]
pub(crate) struct ProfileCholesky {
    envelope: Envelope,
    /// `L` by rows on the envelope, diagonal last.
    values: Vec<f64>,
    inv_diag: Vec<f64>,
    fma: bool,
    factored: bool,
}

impl ProfileCholesky {
    pub(crate) fn new(envelope: Envelope) -> Self {
        let n = envelope.dim();
        Self {
            values: vec![0.0; envelope.len()],
            envelope,
            inv_diag: vec![0.0; n],
            fma: has_fma(),
            factored: false,
        }
    }

    pub(crate) fn envelope(&self) -> &Envelope {
        &self.envelope
    }

    /// `L` by rows on the envelope.
    pub(crate) fn values(&self) -> &[f64] {
        &self.values
    }

    /// Factors `a` (values on the envelope). A pivot that is not positive is reported
    /// as `NotPositiveDefinite` naming `perm[row]`, the DOF in the caller's numbering.
    pub(crate) fn factor(
        &mut self,
        a: &[f64],
        name: &'static str,
        perm: &[usize],
    ) -> Result<(), IntegrateError> {
        self.factored = false;
        self.values.copy_from_slice(a);
        let failed_row = if self.fma {
            vectorized(
                #[inline(always)]
                || factor_kernel::<true>(&self.envelope, &mut self.values, &mut self.inv_diag),
            )
        } else {
            vectorized(
                #[inline(always)]
                || factor_kernel::<false>(&self.envelope, &mut self.values, &mut self.inv_diag),
            )
        };
        match failed_row {
            Some(row) => Err(IntegrateError::NotPositiveDefinite {
                matrix: name,
                dof: perm.get(row).copied().unwrap_or(row),
            }),
            None => {
                self.factored = true;
                Ok(())
            }
        }
    }

    /// Solves `L L^T x = b` in place (internal numbering): the reference for the
    /// block solves (tests).
    #[cfg(test)]
    ///
    /// Only called after a successful [`ProfileCholesky::factor`]; the stepper checks
    /// that first, so a stale factor is a logic error, reported by a debug assertion.
    pub(crate) fn solve_in_place(&self, b: &mut [f64]) {
        debug_assert!(
            self.factored,
            "solve with a failed or missing factorisation"
        );
        if self.fma {
            vectorized(
                #[inline(always)]
                || solve_kernel::<true>(&self.envelope, &self.values, &self.inv_diag, b),
            );
        } else {
            vectorized(
                #[inline(always)]
                || solve_kernel::<false>(&self.envelope, &self.values, &self.inv_diag, b),
            );
        }
    }
}

/// Row-oriented Cholesky in place; returns the row whose pivot failed.
#[inline(always)]
fn factor_kernel<const FMA: bool>(
    envelope: &Envelope,
    values: &mut [f64],
    inv_diag: &mut [f64],
) -> Option<usize> {
    let Envelope { first, ptr } = envelope;
    for i in 0..first.len() {
        let (done, rest) = values.split_at_mut(ptr[i]);
        let row = &mut rest[..ptr[i + 1] - ptr[i]];
        let fi = first[i];
        for j in fi..i {
            let fj = first[j];
            let lo = fi.max(fj);
            let row_j = &done[ptr[j]..ptr[j + 1]];
            let s = dot::<FMA>(&row[lo - fi..j - fi], &row_j[lo - fj..j - fj]);
            row[j - fi] = (row[j - fi] - s) * inv_diag[j];
        }
        let (off, diag) = row.split_at_mut(i - fi);
        let d = diag[0] - dot::<FMA>(off, off);
        // Not positive, or NaN.
        if !(d > 0.0 && d.is_finite()) {
            return Some(i);
        }
        diag[0] = d.sqrt();
        inv_diag[i] = 1.0 / diag[0];
    }
    None
}

#[cfg(test)]
#[inline(always)]
fn solve_kernel<const FMA: bool>(
    envelope: &Envelope,
    values: &[f64],
    inv_diag: &[f64],
    b: &mut [f64],
) {
    let Envelope { first, ptr } = envelope;
    let n = first.len();
    // L y = b, row by row.
    for i in 0..n {
        let fi = first[i];
        let row = &values[ptr[i]..ptr[i + 1] - 1];
        let (before, rest) = b.split_at_mut(i);
        rest[0] = (rest[0] - dot::<FMA>(row, &before[fi..])) * inv_diag[i];
    }
    // L^T x = y: x_i is final once the rows below have been subtracted from it.
    for i in (0..n).rev() {
        let fi = first[i];
        let row = &values[ptr[i]..ptr[i + 1] - 1];
        let (before, rest) = b.split_at_mut(i);
        let x = rest[0] * inv_diag[i];
        rest[0] = x;
        for (y, &l) in before[fi..].iter_mut().zip(row) {
            *y = madd::<FMA>(-l, x, *y);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrate::tests::{chain_with_hub, lower};
    use faer::sparse::{SparseColMat, Triplet};

    #[test]
    fn hub_is_moved_last_and_the_envelope_stays_banded() {
        let a = lower(&chain_with_hub(50, 3));
        let (ordering, kind, envelope) = choose_ordering(a.symbolic(), Envelope::len);
        let n = a.nrows();
        assert_eq!(kind, OrderingKind::HubsLast);
        // The hub and the last node's DOFs (which reach back to the hub) go last, in
        // their original order: three ascending runs.
        assert_eq!(
            ordering.runs().unwrap(),
            &[
                Run {
                    start: 0,
                    caller_start: 1,
                    len: n - 7
                },
                Run {
                    start: n - 7,
                    caller_start: 0,
                    len: 1
                },
                Run {
                    start: n - 6,
                    caller_start: n - 6,
                    len: 6
                },
            ]
        );
        // Rows of the chain reach back at most 11 columns; the hub row 6.
        let natural = 1 + (1..n).map(|i| (i - 1).min(11) + 1).sum::<usize>();
        assert!(envelope.len() <= natural, "{} > {natural}", envelope.len());
    }

    #[test]
    fn reverse_cuthill_mckee_restores_a_scrambled_band() {
        // A chain numbered in a scrambled order: only RCM can find the band again.
        let n = 200;
        let scramble = |i: usize| (i * 73) % n;
        let mut t = Vec::new();
        for i in 0..n {
            t.push(Triplet::new(scramble(i), scramble(i), 4.0));
            if i > 0 {
                let (p, q) = (scramble(i), scramble(i - 1));
                t.push(Triplet::new(p.max(q), p.min(q), -1.0));
            }
        }
        let a = SparseColMat::<usize, f64>::try_new_from_triplets(n, n, &t).unwrap();
        let (ordering, kind, envelope) = choose_ordering(a.symbolic(), Envelope::len);
        assert_eq!(kind, OrderingKind::ReverseCuthillMcKee);
        assert!(ordering.runs().is_none());
        assert_eq!(envelope.len(), 2 * n - 1);
    }

    #[test]
    fn profile_factor_solves_like_faer() {
        let full = chain_with_hub(40, 11);
        let a = lower(&full);
        let n = a.nrows();
        let (ordering, _, envelope) = choose_ordering(a.symbolic(), Envelope::len);
        let values = scatter_lower(&envelope, &ordering, a.symbolic(), a.val());
        let perm = ordering.perm().to_vec();

        let f: Vec<f64> = (0..n).map(|i| (0.11 * i as f64).cos()).collect();
        // Solve: against faer's sparse Cholesky on the same matrix.
        let llt = faer::sparse::linalg::solvers::Llt::try_new_with_symbolic(
            faer::sparse::linalg::solvers::SymbolicLlt::try_new(a.symbolic(), faer::Side::Lower)
                .unwrap(),
            a.as_ref(),
            faer::Side::Lower,
        )
        .unwrap();
        let mut reference = faer::Mat::from_fn(n, 1, |i, _| f[i]);
        faer::linalg::solvers::SolveCore::solve_in_place_with_conj(
            &llt,
            faer::Conj::No,
            reference.as_mut(),
        );
        let mut factor = ProfileCholesky::new(envelope);
        factor.factor(&values, "test", &perm).unwrap();
        let mut x: Vec<f64> = perm.iter().map(|&i| f[i]).collect();
        factor.solve_in_place(&mut x);
        let scale = (0..n).fold(0.0f64, |s, i| s.max(reference[(i, 0)].abs()));
        for (k, &i) in perm.iter().enumerate() {
            // Diagonally dominant: condition number O(1), round-off level agreement.
            assert!(
                (x[k] - reference[(i, 0)]).abs() < 1e-13 * scale,
                "dof {i}: {} vs {}",
                x[k],
                reference[(i, 0)]
            );
        }
    }

    #[test]
    fn failed_pivot_names_the_dof_in_the_callers_numbering() {
        let full = chain_with_hub(10, 5);
        let n = full.nrows();
        for bad in [0, 7, n - 1] {
            let a = lower(&full);
            let mut values = a.val().to_vec();
            for j in 0..n {
                for p in a.symbolic().col_range(j) {
                    if a.symbolic().row_idx()[p] == j && j == bad {
                        values[p] = -1.0;
                    }
                }
            }
            let (ordering, _, envelope) = choose_ordering(a.symbolic(), Envelope::len);
            let on_envelope = scatter_lower(&envelope, &ordering, a.symbolic(), &values);
            let mut factor = ProfileCholesky::new(envelope);
            match factor.factor(&on_envelope, "test", ordering.perm()) {
                Err(IntegrateError::NotPositiveDefinite { dof, .. }) => assert_eq!(dof, bad),
                other => panic!("expected a pivot failure at {bad}, got {other:?}"),
            }
        }
    }
}
