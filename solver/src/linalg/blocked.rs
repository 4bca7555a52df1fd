//! Four-row block panels over an envelope: the storage of the step's symmetric
//! products and triangular solves, so that every inner operation works on groups of
//! four consecutive unknowns (one 256-bit register) and the serial dependence of a
//! triangular solve runs block to block instead of unknown to unknown.
//!
//! # Layout
//! Internal unknowns are grouped in blocks of four, `B = 4b..4b+4` (the last block
//! padded with identity rows). Block `b` owns a panel of its four rows over the
//! columns `s_b..4b+4`, where `s_b` is the first column any of its rows reaches
//! (from the envelope, rounded down to a multiple of four). The panel is a row of
//! 4x4 tiles, tile `k` holding the four rows over columns `s_b + 4k..s_b + 4k + 4`,
//! so one pass over a panel reads memory in order. Entries above the diagonal and
//! left of a row's envelope are stored as zeros (on the paper's spring, the panels
//! hold 1.4 times the envelope).
//!
//! # Symmetric product `out -= A p`
//! `A = P + P^T` with `P` the lower triangle of `A` with its diagonal halved. Block
//! `b`'s panel of `P` gives both halves in one pass: four dot products against the
//! window `p[s_b..4b+4]` (the rows of `P`), and the tiles' rows scaled by `p_B`
//! subtracted from `out[s_b..4b+4]` (the columns, `P^T`).
//!
//! # Triangular solves with `L L^T`
//! With `D_B` the 4x4 diagonal block of `L` and `L_B` the block's rows left of it,
//! the panel stores `G_B = D_B^{-1} L_B` (left tiles) and `D_B^{-1}` (last tile).
//! Forward substitution `L y = b` is, block by block,
//! `y_B = D_B^{-1} b_B - G_B y[s_b..4b]`; backward substitution `L^T x = y` runs the
//! blocks from the last, with `z_B = y_B - sum_{C > B} L_{C,B}^T x_C` accumulated in
//! place: `x_B = D_B^{-T} z_B`, and since `L_{C,B}^T x_C = G_{C,B}^T z_C` the
//! contributions pushed from block `C` use the same panel (`z` instead of `x`).
//! Each block depends on its neighbour only through the tile `G_{B,B-1}`: in the
//! forward pass every other term is reduced first and the neighbour enters last, by
//! the columns of that tile (stored transposed as well), straight from its
//! register; in the backward pass the push into the neighbour is carried in a
//! register while the farther pushes go through memory. The explicit inverse of a
//! 4x4 triangular block is as accurate as substitution with it up to its condition
//! number (Higham, "Accuracy and Stability of Numerical Algorithms", 2002, ch. 8 and
//! 14), which for a diagonal block of a Cholesky factor of an SPD matrix is at most
//! that of the whole factor; the tests hold the solves to faer's within 1e-13.
//!
//! # Registers
//! The kernels are written once against [`Quad`], four lanes of `f64`: AVX2 + FMA
//! registers through faer's SIMD dispatch where the CPU has them (the workspace
//! builds for baseline x86-64), plain arrays otherwise. Everything a kernel calls is
//! `#[inline(always)]` and free of closures, so that it is compiled with the
//! dispatched target features.

use super::profile::{Envelope, ProfileCholesky};

/// Four consecutive values: one AVX register.
pub(crate) type Chunk = [f64; 4];

/// A 4x4 tile of a panel: `tile[r]` holds row `r` over four consecutive columns.
pub(crate) type Tile = [Chunk; 4];

/// Block panels over an envelope of `n` unknowns.
#[derive(Debug, Clone)]
pub(crate) struct Blocks {
    n: usize,
    /// First chunk column `s_b / 4` of each block.
    start: Vec<usize>,
    /// Start of each block's panel (in tiles); `offset[nb]` is the total.
    offset: Vec<usize>,
}

/// A factor's panels: `[G_B | D_B^{-1}]` tiles per block, and per block the columns of
/// `G_{B,B-1}` as one tile (`adjacent[b][k]` is column `k`), zero when the block does
/// not reach the previous one.
#[derive(Debug, Clone)]
pub(crate) struct FactorPanels {
    tiles: Vec<Tile>,
    adjacent: Vec<Tile>,
}

impl Blocks {
    /// The panels covering `envelope` (padded to a multiple of four unknowns).
    pub(crate) fn new(envelope: &Envelope) -> Self {
        let n = envelope.dim();
        let nb = n.div_ceil(4);
        let mut start = Vec::with_capacity(nb);
        let mut offset = Vec::with_capacity(nb + 1);
        offset.push(0usize);
        for b in 0..nb {
            let first = (4 * b..(4 * b + 4).min(n))
                .map(|row| envelope.first(row))
                .min()
                .unwrap_or(4 * b);
            let s = first / 4;
            start.push(s);
            offset.push(offset[b] + b + 1 - s);
        }
        Self { n, start, offset }
    }

    /// Number of unknowns (before padding).
    pub(crate) fn dim(&self) -> usize {
        self.n
    }

    /// Number of blocks.
    pub(crate) fn n_blocks(&self) -> usize {
        self.start.len()
    }

    /// Tiles of one matrix's panels.
    pub(crate) fn len(&self) -> usize {
        self.offset[self.n_blocks()]
    }

    /// Stored values of one matrix's panels.
    pub(crate) fn n_values(&self) -> usize {
        16 * self.len()
    }

    /// Panels of a symmetric matrix given on the envelope, with its diagonal halved
    /// (the product's `P`).
    pub(crate) fn product_panels(&self, envelope: &Envelope, values: &[f64]) -> Vec<Tile> {
        let mut panels = vec![[[0.0; 4]; 4]; self.len()];
        for row in 0..self.n {
            let (b, r) = (row / 4, row % 4);
            let s = 4 * self.start[b];
            let first = envelope.first(row);
            for (k, &v) in envelope.row(row, values).iter().enumerate() {
                let col = first + k;
                let v = if col == row { 0.5 * v } else { v };
                let at = col - s;
                panels[self.offset[b] + at / 4][r][at % 4] = v;
            }
        }
        panels
    }

    /// Zeroed storage for [`Blocks::factor_panels`].
    pub(crate) fn factor_storage(&self) -> FactorPanels {
        FactorPanels {
            tiles: vec![[[0.0; 4]; 4]; self.len()],
            adjacent: vec![[[0.0; 4]; 4]; self.n_blocks()],
        }
    }

    /// The panels of a factored `L` (see the module docs). Padding rows get the
    /// identity.
    // The 4x4 triangular inverse reads as the textbook index formulas.
    #[allow(clippy::needless_range_loop)]
    pub(crate) fn factor_panels(&self, factor: &ProfileCholesky, out: &mut FactorPanels) {
        let envelope = factor.envelope();
        let l = factor.values();
        for b in 0..self.n_blocks() {
            let s = 4 * self.start[b];
            let width = 4 * (b + 1 - self.start[b]);
            // Dense copy of the block's four rows over s..4b+4 (set-up time only).
            let mut rows = vec![vec![0.0; width]; 4];
            for (r, target) in rows.iter_mut().enumerate() {
                let row = 4 * b + r;
                if row < self.n {
                    let first = envelope.first(row);
                    for (k, &v) in envelope.row(row, l).iter().enumerate() {
                        target[first + k - s] = v;
                    }
                } else {
                    target[row - s] = 1.0;
                }
            }
            let diag = width - 4;
            // D^{-1} by forward substitution on the unit vectors (lower triangular).
            let mut inv = [[0.0; 4]; 4];
            for c in 0..4 {
                for r in c..4 {
                    let mut x = if r == c { 1.0 } else { 0.0 };
                    for k in c..r {
                        x -= rows[r][diag + k] * inv[k][c];
                    }
                    inv[r][c] = x / rows[r][diag + r];
                }
            }
            let tiles = &mut out.tiles[self.offset[b]..self.offset[b + 1]];
            for r in 0..4 {
                // G = D^{-1} L_left, row r: sum_k inv[r][k] * rows[k][left].
                for col in 0..diag {
                    let g: f64 = (0..=r).map(|k| inv[r][k] * rows[k][col]).sum();
                    tiles[col / 4][r][col % 4] = g;
                }
                tiles[diag / 4][r] = inv[r];
            }
            let mut adjacent = [[0.0; 4]; 4];
            if diag >= 4 {
                let tile = tiles[diag / 4 - 1];
                for (r, row) in tile.iter().enumerate() {
                    for (k, &g) in row.iter().enumerate() {
                        adjacent[k][r] = g;
                    }
                }
            }
            out.adjacent[b] = adjacent;
        }
    }

    /// Chunks of a vector of `n` unknowns (padded with zeros).
    pub(crate) fn n_chunks(&self) -> usize {
        self.n_blocks()
    }
}

/// Lane-wise arithmetic on [`Chunk`]s: AVX2 + FMA registers where the CPU has them
/// (`pulp::x86::V3`, through faer), plain arrays otherwise. The kernels are written once against
/// this trait; LLVM's own vectorisation of the array form transposes the four
/// accumulators of a block into a shuffle storm, hence the explicit registers.
pub(crate) trait Quad: Copy {
    type V: Copy;
    fn load(self, c: &Chunk) -> Self::V;
    fn store(self, v: Self::V) -> Chunk;
    fn zero(self) -> Self::V;
    /// `a b + c`.
    fn mul_add(self, a: Self::V, b: Self::V, c: Self::V) -> Self::V;
    /// `c - a b`.
    fn neg_mul_add(self, a: Self::V, b: Self::V, c: Self::V) -> Self::V;
    fn mul(self, a: Self::V, b: Self::V) -> Self::V;
    fn add(self, a: Self::V, b: Self::V) -> Self::V;
    fn sub(self, a: Self::V, b: Self::V) -> Self::V;
    /// Lane `k` of `v` in every lane.
    fn lane(self, v: Self::V, k: usize) -> Self::V;
    /// `[sum(acc[0]), sum(acc[1]), sum(acc[2]), sum(acc[3])]`, each summed as
    /// `(x0 + x1) + (x2 + x3)`.
    fn reduce(self, acc: [Self::V; 4]) -> Self::V;
}

/// Plain arrays, multiply-add fused when `FMA`.
#[derive(Clone, Copy)]
pub(crate) struct Plain<const FMA: bool>;

impl<const FMA: bool> Quad for Plain<FMA> {
    type V = Chunk;
    #[inline(always)]
    fn load(self, c: &Chunk) -> Chunk {
        *c
    }
    #[inline(always)]
    fn store(self, v: Chunk) -> Chunk {
        v
    }
    #[inline(always)]
    fn zero(self) -> Chunk {
        [0.0; 4]
    }
    #[inline(always)]
    fn mul_add(self, a: Chunk, b: Chunk, c: Chunk) -> Chunk {
        let mut out = [0.0; 4];
        for k in 0..4 {
            out[k] = if FMA {
                a[k].mul_add(b[k], c[k])
            } else {
                a[k] * b[k] + c[k]
            };
        }
        out
    }
    #[inline(always)]
    fn neg_mul_add(self, a: Chunk, b: Chunk, c: Chunk) -> Chunk {
        let mut out = [0.0; 4];
        for k in 0..4 {
            out[k] = if FMA {
                (-a[k]).mul_add(b[k], c[k])
            } else {
                c[k] - a[k] * b[k]
            };
        }
        out
    }
    #[inline(always)]
    fn mul(self, a: Chunk, b: Chunk) -> Chunk {
        [a[0] * b[0], a[1] * b[1], a[2] * b[2], a[3] * b[3]]
    }
    #[inline(always)]
    fn add(self, a: Chunk, b: Chunk) -> Chunk {
        [a[0] + b[0], a[1] + b[1], a[2] + b[2], a[3] + b[3]]
    }
    #[inline(always)]
    fn sub(self, a: Chunk, b: Chunk) -> Chunk {
        [a[0] - b[0], a[1] - b[1], a[2] - b[2], a[3] - b[3]]
    }
    #[inline(always)]
    fn lane(self, v: Chunk, k: usize) -> Chunk {
        [v[k]; 4]
    }
    #[inline(always)]
    fn reduce(self, acc: [Chunk; 4]) -> Chunk {
        let mut out = [0.0; 4];
        for r in 0..4 {
            out[r] = (acc[r][0] + acc[r][1]) + (acc[r][2] + acc[r][3]);
        }
        out
    }
}

#[cfg(target_arch = "x86_64")]
mod avx {
    use super::{Chunk, Quad};
    use core::arch::x86_64::__m256d;
    use faer::traits::pulp::{cast, x86::V3};

    impl Quad for V3 {
        type V = __m256d;
        #[inline(always)]
        fn load(self, c: &Chunk) -> __m256d {
            cast(*c)
        }
        #[inline(always)]
        fn store(self, v: __m256d) -> Chunk {
            cast(v)
        }
        #[inline(always)]
        fn zero(self) -> __m256d {
            self.avx._mm256_setzero_pd()
        }
        #[inline(always)]
        fn mul_add(self, a: __m256d, b: __m256d, c: __m256d) -> __m256d {
            self.fma._mm256_fmadd_pd(a, b, c)
        }
        #[inline(always)]
        fn neg_mul_add(self, a: __m256d, b: __m256d, c: __m256d) -> __m256d {
            self.fma._mm256_fnmadd_pd(a, b, c)
        }
        #[inline(always)]
        fn mul(self, a: __m256d, b: __m256d) -> __m256d {
            self.avx._mm256_mul_pd(a, b)
        }
        #[inline(always)]
        fn add(self, a: __m256d, b: __m256d) -> __m256d {
            self.avx._mm256_add_pd(a, b)
        }
        #[inline(always)]
        fn sub(self, a: __m256d, b: __m256d) -> __m256d {
            self.avx._mm256_sub_pd(a, b)
        }
        #[inline(always)]
        fn lane(self, v: __m256d, k: usize) -> __m256d {
            match k {
                0 => self.avx2._mm256_permute4x64_pd::<0b00_00_00_00>(v),
                1 => self.avx2._mm256_permute4x64_pd::<0b01_01_01_01>(v),
                2 => self.avx2._mm256_permute4x64_pd::<0b10_10_10_10>(v),
                _ => self.avx2._mm256_permute4x64_pd::<0b11_11_11_11>(v),
            }
        }
        #[inline(always)]
        fn reduce(self, acc: [__m256d; 4]) -> __m256d {
            // hadd pairs lanes (0+1, 2+3) of two registers; the two 128-bit halves
            // then hold the partial sums to add.
            let t0 = self.avx._mm256_hadd_pd(acc[0], acc[1]);
            let t1 = self.avx._mm256_hadd_pd(acc[2], acc[3]);
            let lo = self.avx._mm256_permute2f128_pd::<0x20>(t0, t1);
            let hi = self.avx._mm256_permute2f128_pd::<0x31>(t0, t1);
            self.avx._mm256_add_pd(lo, hi)
        }
    }
}

/// Runs `$body` with `$q` bound to the best [`Quad`] of this CPU, compiled for it.
macro_rules! with_quad {
    ($fma:expr, $q:ident => $body:expr) => {{
        #[cfg(target_arch = "x86_64")]
        if let Some(simd) = faer::traits::pulp::x86::V3::try_new() {
            return faer::traits::pulp::Simd::vectorize(
                simd,
                #[inline(always)]
                || {
                    let $q = simd;
                    $body
                },
            );
        }
        if $fma {
            let $q = Plain::<true>;
            $body
        } else {
            let $q = Plain::<false>;
            $body
        }
    }};
}

/// `out -= sum_m A_m p_m` for `N` matrices given as product panels. No allocation.
pub(crate) fn subtract_product<const N: usize>(
    blocks: &Blocks,
    fma_available: bool,
    a: [&[Tile]; N],
    p: [&[Chunk]; N],
    out: &mut [Chunk],
) {
    with_quad!(fma_available, q => product_kernel(q, blocks, a, p, out))
}

/// The four rows of a tile.
#[inline(always)]
fn rows<Q: Quad>(q: Q, tile: &Tile) -> [Q::V; 4] {
    [
        q.load(&tile[0]),
        q.load(&tile[1]),
        q.load(&tile[2]),
        q.load(&tile[3]),
    ]
}

/// The four lanes of `v`, each broadcast.
#[inline(always)]
fn lanes<Q: Quad>(q: Q, v: Q::V) -> [Q::V; 4] {
    [q.lane(v, 0), q.lane(v, 1), q.lane(v, 2), q.lane(v, 3)]
}

/// `sum_r rows[r] * lanes[r]` (a tile transposed times a chunk), as two pairs.
#[inline(always)]
fn combine<Q: Quad>(q: Q, rows: [Q::V; 4], lanes: &[Q::V; 4]) -> Q::V {
    let t01 = q.mul_add(rows[1], lanes[1], q.mul(rows[0], lanes[0]));
    let t23 = q.mul_add(rows[3], lanes[3], q.mul(rows[2], lanes[2]));
    q.add(t01, t23)
}

#[inline(always)]
fn product_kernel<Q: Quad, const N: usize>(
    q: Q,
    blocks: &Blocks,
    a: [&[Tile]; N],
    p: [&[Chunk]; N],
    out: &mut [Chunk],
) {
    for b in 0..blocks.n_blocks() {
        let s = blocks.start[b];
        let panel = blocks.offset[b]..blocks.offset[b + 1];
        let mut acc = [q.zero(); 4];
        for m in 0..N {
            let bcast = lanes(q, q.load(&p[m][b]));
            let window = out[s..=b].iter_mut().zip(&p[m][s..=b]);
            for (tile, (o, pk)) in a[m][panel.clone()].iter().zip(window) {
                let rows = rows(q, tile);
                // Columns (P^T): the tile's rows scaled by p_B.
                *o = q.store(q.sub(q.load(o), combine(q, rows, &bcast)));
                // Rows (P): four dot products against the window.
                let pk = q.load(pk);
                for r in 0..4 {
                    acc[r] = q.mul_add(rows[r], pk, acc[r]);
                }
            }
        }
        out[b] = q.store(q.sub(q.load(&out[b]), q.reduce(acc)));
    }
}

/// Solves `L L^T x = rhs` in place with factor panels. No allocation.
pub(crate) fn solve(
    blocks: &Blocks,
    fma_available: bool,
    factor: &FactorPanels,
    rhs: &mut [Chunk],
) {
    with_quad!(fma_available, q => solve_kernel(q, blocks, factor, rhs))
}

#[inline(always)]
fn solve_kernel<Q: Quad>(q: Q, blocks: &Blocks, factor: &FactorPanels, y: &mut [Chunk]) {
    let nb = blocks.n_blocks();
    // Forward: y_B = D^{-1} b_B - G_B y[s..B]. The serial dependence is on y_{B-1}
    // only: everything else is reduced first (rows as dot products), and the
    // previous block enters last, by columns, straight from its register.
    let mut previous = q.zero();
    for b in 0..nb {
        let s = blocks.start[b];
        let tiles = &factor.tiles[blocks.offset[b]..blocks.offset[b + 1]];
        let width = tiles.len();
        let linked = width > 1;
        let far = if linked { width - 2 } else { 0 };
        let bb = q.load(&y[b]);
        let d = rows(q, &tiles[width - 1]);
        let mut acc = [
            q.mul(d[0], bb),
            q.mul(d[1], bb),
            q.mul(d[2], bb),
            q.mul(d[3], bb),
        ];
        for (tile, yk) in tiles[..far].iter().zip(&y[s..s + far]) {
            let (g, yk) = (rows(q, tile), q.load(yk));
            for r in 0..4 {
                acc[r] = q.neg_mul_add(g[r], yk, acc[r]);
            }
        }
        let mut yb = q.reduce(acc);
        if linked {
            let columns = rows(q, &factor.adjacent[b]);
            yb = q.sub(yb, combine(q, columns, &lanes(q, previous)));
        }
        y[b] = q.store(yb);
        previous = yb;
    }
    // Backward: z_B = y_B minus what the later blocks push into it; x_B = D^{-T} z_B.
    // The push into the previous block is carried in a register (the serial
    // dependence), the others go through memory.
    let mut carry = q.zero();
    for b in (0..nb).rev() {
        let s = blocks.start[b];
        let tiles = &factor.tiles[blocks.offset[b]..blocks.offset[b + 1]];
        let width = tiles.len();
        let linked = width > 1;
        let far = if linked { width - 2 } else { 0 };
        let z = q.sub(q.load(&y[b]), carry);
        let bcast = lanes(q, z);
        carry = if linked {
            combine(q, rows(q, &tiles[width - 2]), &bcast)
        } else {
            q.zero()
        };
        for (tile, o) in tiles[..far].iter().zip(&mut y[s..s + far]) {
            *o = q.store(q.sub(q.load(o), combine(q, rows(q, tile), &bcast)));
        }
        y[b] = q.store(combine(q, rows(q, &tiles[width - 1]), &bcast));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrate::tests::{chain_with_hub, lower, mul};
    use crate::linalg::profile::{choose_ordering, has_fma, scatter_lower};

    fn to_chunks(x: &[f64], n_chunks: usize) -> Vec<Chunk> {
        let mut out = vec![[0.0; 4]; n_chunks];
        for (i, &v) in x.iter().enumerate() {
            out[i / 4][i % 4] = v;
        }
        out
    }

    fn from_chunks(x: &[Chunk], n: usize) -> Vec<f64> {
        x.iter().flatten().copied().take(n).collect()
    }

    #[test]
    fn blocked_product_and_solve_match_the_sparse_reference() {
        // Sizes with every padding of the last block.
        for nodes in [1, 2, 7, 30] {
            let full = chain_with_hub(nodes, 17);
            let a = lower(&full);
            let n = a.nrows();
            let (ordering, _, envelope) =
                choose_ordering(a.symbolic(), |e| Blocks::new(e).n_values());
            let perm = ordering.perm();
            let values = scatter_lower(&envelope, &ordering, a.symbolic(), a.val());
            let blocks = Blocks::new(&envelope);
            let fma = has_fma();

            let p: Vec<f64> = (0..n).map(|i| (0.37 * i as f64).sin()).collect();
            let f: Vec<f64> = (0..n).map(|i| (0.11 * i as f64).cos()).collect();
            let ap = mul(&full, &p);
            let p_int: Vec<f64> = perm.iter().map(|&i| p[i]).collect();
            let f_int: Vec<f64> = perm.iter().map(|&i| f[i]).collect();
            let panels = blocks.product_panels(&envelope, &values);
            let p_chunks = to_chunks(&p_int, blocks.n_chunks());
            let mut out = to_chunks(&f_int, blocks.n_chunks());
            subtract_product(&blocks, fma, [&panels], [&p_chunks], &mut out);
            let out = from_chunks(&out, n);
            for (k, &i) in perm.iter().enumerate() {
                assert!(
                    (out[k] - (f[i] - ap[i])).abs() < 1e-12,
                    "{nodes} nodes, row {i}"
                );
            }

            let mut factor = ProfileCholesky::new(envelope.clone());
            factor.factor(&values, "test", perm).unwrap();
            let mut factor_panels = blocks.factor_storage();
            blocks.factor_panels(&factor, &mut factor_panels);
            let mut x = to_chunks(&f_int, blocks.n_chunks());
            solve(&blocks, fma, &factor_panels, &mut x);
            let x = from_chunks(&x, n);
            let mut reference = f_int.clone();
            factor.solve_in_place(&mut reference);
            let scale = reference.iter().fold(0.0f64, |s, v| s.max(v.abs()));
            for k in 0..n {
                // Diagonally dominant: round-off level agreement.
                assert!(
                    (x[k] - reference[k]).abs() < 1e-13 * scale,
                    "{nodes} nodes, unknown {k}: {} vs {}",
                    x[k],
                    reference[k]
                );
            }
        }
    }

    /// The plain-array fallback (CPUs without AVX2, other architectures) computes
    /// what the dispatched kernels compute, to round-off.
    #[test]
    fn plain_fallback_matches_the_dispatched_kernels() {
        let full = chain_with_hub(9, 4);
        let a = lower(&full);
        let n = a.nrows();
        let (ordering, _, envelope) = choose_ordering(a.symbolic(), |e| Blocks::new(e).n_values());
        let values = scatter_lower(&envelope, &ordering, a.symbolic(), a.val());
        let blocks = Blocks::new(&envelope);
        let panels = blocks.product_panels(&envelope, &values);
        let mut factor = ProfileCholesky::new(envelope);
        factor.factor(&values, "test", ordering.perm()).unwrap();
        let mut factor_panels = blocks.factor_storage();
        blocks.factor_panels(&factor, &mut factor_panels);
        let p: Vec<f64> = (0..n).map(|i| (0.37 * i as f64).sin()).collect();
        let p = to_chunks(&p, blocks.n_chunks());
        let run = |plain: Option<bool>| {
            let mut out = p.clone();
            let mut x = p.clone();
            match plain {
                None => {
                    subtract_product(&blocks, has_fma(), [&panels], [&p], &mut out);
                    solve(&blocks, has_fma(), &factor_panels, &mut x);
                }
                Some(true) => {
                    product_kernel(Plain::<true>, &blocks, [&panels], [&p], &mut out);
                    solve_kernel(Plain::<true>, &blocks, &factor_panels, &mut x);
                }
                Some(false) => {
                    product_kernel(Plain::<false>, &blocks, [&panels], [&p], &mut out);
                    solve_kernel(Plain::<false>, &blocks, &factor_panels, &mut x);
                }
            }
            (from_chunks(&out, n), from_chunks(&x, n))
        };
        let (out, x) = run(None);
        for fused in [true, false] {
            let (out_plain, x_plain) = run(Some(fused));
            for k in 0..n {
                assert!(
                    (out[k] - out_plain[k]).abs() < 1e-13,
                    "product, unknown {k}"
                );
                assert!((x[k] - x_plain[k]).abs() < 1e-13, "solve, unknown {k}");
            }
        }
    }

    /// Timings on a chain the size of the benchmark spring: `cargo test --release -p
    /// coil-solver --lib blocked_kernel_timings -- --ignored --nocapture`.
    #[test]
    #[ignore = "timings, not a test (speed is measured by benchmarks): cargo test --release -p coil-solver --lib blocked_kernel_timings -- --ignored --nocapture"]
    fn blocked_kernel_timings() {
        let full = chain_with_hub(666, 1);
        let a = lower(&full);
        let n = a.nrows();
        let (ordering, _, envelope) = choose_ordering(a.symbolic(), |e| Blocks::new(e).n_values());
        let values = scatter_lower(&envelope, &ordering, a.symbolic(), a.val());
        let blocks = Blocks::new(&envelope);
        let fma = has_fma();
        eprintln!(
            "n = {n}, envelope {}, panels {} values, fma {fma}",
            envelope.len(),
            blocks.n_values()
        );
        // Best of 20 batches of 1000: the machine is shared.
        let time = |label: &str, f: &mut dyn FnMut()| {
            let mut best = f64::INFINITY;
            for _ in 0..20 {
                let start = std::time::Instant::now();
                for _ in 0..1000 {
                    f();
                }
                best = best.min(start.elapsed().as_secs_f64() / 1000.0);
            }
            eprintln!("{label}: {:.2} us", best * 1e6);
        };
        let panels = blocks.product_panels(&envelope, &values);
        let p: Vec<f64> = (0..n).map(|i| (0.37 * i as f64).sin()).collect();
        let p = to_chunks(&p, blocks.n_chunks());
        let mut out = p.clone();
        time("blocked product, 1 matrix", &mut || {
            subtract_product(&blocks, fma, [&panels], [&p], &mut out)
        });
        time("blocked product, 2 matrices", &mut || {
            subtract_product(&blocks, fma, [&panels, &panels], [&p, &p], &mut out)
        });
        let mut factor = ProfileCholesky::new(envelope);
        factor.factor(&values, "test", ordering.perm()).unwrap();
        let mut factor_panels = blocks.factor_storage();
        blocks.factor_panels(&factor, &mut factor_panels);
        let mut x = p.clone();
        time("blocked solve pair", &mut || {
            x.copy_from_slice(&p);
            solve(&blocks, fma, &factor_panels, &mut x)
        });
        // The sparse engine's factor (faer's simplicial Cholesky under AMD, with its
        // own dot-form solves) on the same matrix.
        let mut sparse =
            crate::linalg::sparse_spd::SpdFactor::analyse("test", a.symbolic()).unwrap();
        sparse.factor(a.as_ref()).unwrap();
        let p_flat: Vec<f64> = p.iter().flatten().copied().take(n).collect();
        let mut x_flat = p_flat.clone();
        time("sparse engine's solve pair", &mut || {
            x_flat.copy_from_slice(&p_flat);
            sparse.solve_in_place(&mut x_flat)
        });
    }
}
