//! Step responses of the unilateral term ([`super::contact`]) kept sparse and inside a
//! memory budget, so that a catenary's memory does not grow as links x DOFs.
//!
//! # Sparse responses
//! A response is the displacement of one average-acceleration step from rest under a
//! unit end load `e`, `u = beta dt^2 S^-1 e` with `S = M + gamma dt C + beta dt^2 K`. At
//! the time steps a wave problem needs, `S` is dominated by `M` and `S^-1 e` decays
//! geometrically away from the loaded DOF (the discrete wave cannot travel further than
//! a few elements in one step): on the EN 50318 catenary (0.25 m elements, 0.125 ms) a
//! dropper's response falls below 1e-20 of its peak within a few metres of the dropper,
//! on both wires. A response is kept as runs of consecutive entries; an entry below
//! [`CUT`] times the vector's largest is left out, and a run is cut where more than
//! [`GAP`] entries in a row are left out. A left-out entry `x` enters the state as
//! `lambda x`, less than `CUT` (2^-64) times the response's largest contribution: far
//! below its round-off (2^-53 of it), so the step is the dense one to round-off. Where a
//! response does not decay (a large step, a stiff problem), it is simply kept whole.
//!
//! # Budget
//! The links' responses are computed when a link is first a candidate for slackness and
//! kept, at most [`BUDGET_BYTES`] of them; past it, the least recently used are dropped
//! (and computed again if needed). A response needed in a step in which the kept ones
//! leave no room is used once ([`LinkResponses::prepare`] reports it): its entries of
//! `G` are read from the dense vector, which is then dropped, and its share of the
//! correction comes from one more step from rest under the combined load. Memory is
//! therefore at most the budget plus one dense vector and the step's `G` (elements
//! squared), whatever the number of links.

use crate::analysis::unilateral::Gap;

/// Entries below this share of a response's largest are left out (2^-64).
pub const CUT: f64 = 5.421_010_862_427_522e-20;

/// Most left-out entries inside one run.
pub const GAP: usize = 16;

/// Most bytes of kept link responses.
pub const BUDGET_BYTES: usize = 64 << 20;

/// A vector kept as runs of consecutive entries (module docs).
#[derive(Debug, Clone, Default, PartialEq)]
pub(super) struct Sparse {
    /// `(first index, entries)` of each run, ascending, not overlapping.
    runs: Vec<(usize, Vec<f64>)>,
}

impl Sparse {
    /// The runs of `x` (module docs).
    pub(super) fn new(x: &[f64]) -> Self {
        let largest = x.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        let cut = CUT * largest;
        let mut runs: Vec<(usize, Vec<f64>)> = Vec::new();
        for (i, &v) in x.iter().enumerate() {
            if v.abs() <= cut {
                continue;
            }
            match runs.last_mut() {
                Some((start, values)) if i <= *start + values.len() + GAP => {
                    let end = *start + values.len();
                    values.extend_from_slice(&x[end..=i]);
                }
                _ => runs.push((i, vec![v])),
            }
        }
        Sparse { runs }
    }

    /// The entry at `i` (0 outside the runs).
    fn get(&self, i: usize) -> f64 {
        let p = self.runs.partition_point(|(start, _)| *start <= i);
        match p.checked_sub(1).map(|p| &self.runs[p]) {
            Some((start, values)) => values.get(i - start).copied().unwrap_or(0.0),
            None => 0.0,
        }
    }

    /// `b^T x` of a gap's linear part.
    pub(super) fn dot(&self, gap: &Gap) -> f64 {
        gap.b.iter().map(|&(r, c)| c * self.get(r)).sum()
    }

    /// `u -= l x`, `v -= l dv x`, `a -= l da x` over the runs.
    pub(super) fn subtract(
        &self,
        l: f64,
        [dv, da]: [f64; 2],
        u: &mut [f64],
        v: &mut [f64],
        a: &mut [f64],
    ) {
        for (start, values) in &self.runs {
            let end = start + values.len();
            let rows = u[*start..end]
                .iter_mut()
                .zip(&mut v[*start..end])
                .zip(&mut a[*start..end]);
            for (((u, v), a), x) in rows.zip(values) {
                let d = l * x;
                *u -= d;
                *v -= dv * d;
                *a -= da * d;
            }
        }
    }

    /// Bytes held.
    pub(super) fn bytes(&self) -> usize {
        self.runs
            .iter()
            .map(|(_, v)| 8 * v.len() + std::mem::size_of::<(usize, Vec<f64>)>())
            .sum::<usize>()
            + std::mem::size_of::<Self>()
    }
}

/// The links' kept responses, least recently used dropped first (module docs).
#[derive(Debug)]
pub(super) struct LinkResponses {
    /// Per link: its response and the step it was last used in.
    kept: Vec<Option<(Sparse, u64)>>,
    bytes: usize,
    budget: usize,
    /// The current step's number (the use stamp).
    clock: u64,
}

impl LinkResponses {
    /// No response kept yet for `links` links, at most `budget` bytes.
    pub(super) fn new(links: usize, budget: usize) -> Self {
        LinkResponses {
            kept: vec![None; links],
            bytes: 0,
            budget,
            clock: 0,
        }
    }

    /// Starts a step: responses used from now on are not dropped until the next.
    pub(super) fn next_step(&mut self) {
        self.clock += 1;
    }

    /// Marks link `j`'s response used in this step; false when it is not kept.
    pub(super) fn touch(&mut self, j: usize) -> bool {
        match &mut self.kept[j] {
            Some((_, used)) => {
                *used = self.clock;
                true
            }
            None => false,
        }
    }

    /// Keeps `x` as link `j`'s response if it fits in the budget once responses not
    /// used in this step are dropped (least recently used first); false when it does not.
    pub(super) fn insert(&mut self, j: usize, x: Sparse) -> bool {
        let size = x.bytes();
        while self.bytes + size > self.budget {
            let oldest = self
                .kept
                .iter()
                .enumerate()
                .filter_map(|(i, e)| e.as_ref().map(|(_, used)| (i, *used)))
                .filter(|&(_, used)| used < self.clock)
                .min_by_key(|&(_, used)| used);
            match oldest {
                Some((i, _)) => {
                    if let Some((dropped, _)) = self.kept[i].take() {
                        self.bytes -= dropped.bytes();
                    }
                }
                None => return false,
            }
        }
        self.bytes += size;
        self.kept[j] = Some((x, self.clock));
        true
    }

    /// Link `j`'s kept response.
    pub(super) fn get(&self, j: usize) -> Option<&Sparse> {
        self.kept[j].as_ref().map(|(x, _)| x)
    }

    /// Bytes of the kept responses.
    #[cfg(test)]
    pub(super) fn bytes(&self) -> usize {
        self.bytes
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn runs_keep_every_entry_above_the_cut_and_join_across_short_gaps() {
        let mut x = vec![0.0; 100];
        x[3] = 1.0;
        x[5] = -0.5;
        x[10] = 1e-25; // below the cut of 2^-64: left out
        x[40] = 2.0;
        x[41] = 1e-3;
        let s = Sparse::new(&x);
        assert_eq!(s.runs.len(), 2);
        assert_eq!(s.runs[0].0, 3);
        assert_eq!(s.runs[0].1, vec![1.0, 0.0, -0.5]);
        assert_eq!(s.runs[1], (40, vec![2.0, 1e-3]));
        for (i, &v) in x.iter().enumerate() {
            let want = if i == 10 { 0.0 } else { v };
            assert_eq!(s.get(i), want, "entry {i}");
        }
        // A gap of GAP left-out entries stays inside one run, one more splits it.
        let mut y = vec![0.0; 60];
        y[0] = 1.0;
        y[GAP + 1] = 1.0;
        assert_eq!(Sparse::new(&y).runs.len(), 1);
        y[GAP + 1] = 0.0;
        y[GAP + 2] = 1.0;
        assert_eq!(Sparse::new(&y).runs.len(), 2);
        assert!(Sparse::new(&[0.0; 8]).runs.is_empty());
    }

    #[test]
    fn subtracting_a_sparse_vector_matches_the_dense_update() {
        let x: Vec<f64> = (0..50)
            .map(|i| if i % 7 < 3 { i as f64 } else { 0.0 })
            .collect();
        let s = Sparse::new(&x);
        let (mut u, mut v, mut a) = (vec![1.0; 50], vec![2.0; 50], vec![3.0; 50]);
        s.subtract(0.5, [10.0, 100.0], &mut u, &mut v, &mut a);
        for i in 0..50 {
            assert_eq!(u[i], 1.0 - 0.5 * x[i]);
            assert_eq!(v[i], 2.0 - 10.0 * (0.5 * x[i]));
            assert_eq!(a[i], 3.0 - 100.0 * (0.5 * x[i]));
        }
    }

    #[test]
    fn the_budget_drops_the_least_recently_used_but_never_this_steps() {
        let one = |v: f64| Sparse::new(&[v; 10]);
        let size = one(1.0).bytes();
        let mut kept = LinkResponses::new(4, 2 * size);
        kept.next_step();
        assert!(kept.insert(0, one(1.0)));
        kept.next_step();
        assert!(kept.insert(1, one(2.0)));
        kept.next_step();
        assert!(kept.touch(1));
        // Link 0 (last used two steps ago) goes to make room for link 2.
        assert!(kept.insert(2, one(3.0)));
        assert!(kept.get(0).is_none() && kept.get(1).is_some() && kept.get(2).is_some());
        assert_eq!(kept.bytes(), 2 * size);
        // Both kept ones were used in this step: link 3 does not fit and is refused.
        assert!(!kept.insert(3, one(4.0)));
        assert!(kept.get(3).is_none());
        assert_eq!(kept.bytes(), 2 * size);
    }
}
