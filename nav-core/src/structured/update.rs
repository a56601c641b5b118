//! The measurement update: `P Hᵀ` over the observed blocks, the 3×3 Cholesky factor and the
//! expanded Joseph update (module docs of [`super`]).

use super::{Cholesky3, ObservedCovariance, StateRows};
use nalgebra::{Matrix3, SMatrix, Vector3};

use crate::block::{
    self, add, dot, mul_transpose_add, mul_vector_add, transpose, Block, FiniteCheck, Row, ZERO,
};
use crate::discretise::CovarianceMatrix;
use crate::measurement::MeasurementJacobian;
use crate::state::{BlockMask, STATE_DIMENSION};

impl<'a> ObservedCovariance<'a> {
    /// `M = P Hᵀ` and `H P Hᵀ` over the blocks of `H` that are not all zero (`observed`,
    /// [`observed_blocks`]): from `products` zero, for each observed block `K`,
    /// `M_j += H_K P_{K,j}` over the 24 columns `j` (the symmetric `P` read by columns),
    /// then `H P Hᵀ = Σ_K H_K P_{K,·} H_Kᵀ`'s sum `Σ_K (M_K)ᵀ H_Kᵀ`, and the border's terms
    /// ([`add_border`]) when in use. `M` stays in the caller's `products`.
    pub(crate) fn new(
        products: &'a mut StateRows,
        (jacobian, observed): (&MeasurementJacobian, &[bool; BLOCKS]),
        p: &CovarianceMatrix,
        border: Option<(&StateRows, &crate::block_interface::MeasuredBorder)>,
    ) -> Self {
        for (block, _) in observed.iter().enumerate().filter(|(_, o)| **o) {
            if let Some([c0, c1, c2]) = jacobian.data.0.get(3 * block..3 * block + 3) {
                add_observed_block(products, p, 3 * block, &[*c0, *c1, *c2]);
            }
        }
        let mut projected = ZERO;
        // H P Hᵀ = Σ_K (H P)_{·,K} H_Kᵀ, with (H P)_{·,K} = [M_K, M_K+1, M_K+2] as columns.
        for (block, _) in observed.iter().enumerate().filter(|(_, o)| **o) {
            let offset = 3 * block;
            if let Some([m0, m1, m2]) = products.get(offset..offset + 3) {
                let h = jacobian_block(jacobian, block);
                projected = mul_transpose_add(&projected, &transpose(&[*m0, *m1, *m2]), &h);
            }
        }
        // With `h_ε = 0` (a star or velocity measurement) the border adds `0·C_j` and zeros:
        // `M` and `H P Hᵀ` are sums started from +0, never −0, so adding ±0 leaves every
        // bit as it is and is skipped (a non-finite `C` would still fail the update, through
        // `M_ε = Gᵀ`).
        if let Some((cross, border)) = border.filter(|(_, border)| border.coefficient != 0.0) {
            add_border(products, &mut projected, cross, border);
        }
        Self {
            products,
            projected,
        }
    }

    /// `M = P Hᵀ`, row `j` for state `j`.
    pub(crate) fn products(&self) -> &StateRows {
        self.products
    }

    /// `H P Hᵀ`.
    pub(crate) fn projected(&self) -> Matrix3<f64> {
        block::to_matrix(&self.projected)
    }

    /// The gain `K = P Hᵀ S⁻¹`, row `j` = `S⁻¹ M_j`, the rows of the `frozen` blocks zero.
    #[cfg(target_arch = "arm")]
    pub(crate) fn gain(&self, cholesky: &Cholesky3, frozen: &BlockMask) -> StateRows {
        // Built element by element (no zero-fill of the whole array first).
        core::array::from_fn(|state_index| match self.products.get(state_index) {
            Some(product) if !frozen.contains_state(state_index) => cholesky.solve(*product),
            _ => [0.0; 3],
        })
    }

    /// The gain `K = P Hᵀ S⁻¹`, row `j` = `S⁻¹ M_j`, the rows of the `frozen` blocks zero:
    /// the host's form, every row solved (no branch between the rows, so the compiler
    /// solves several rows in one vector) and the frozen ones replaced by zero after; the
    /// same values as the target's, which solves the unfrozen rows only.
    #[cfg(not(target_arch = "arm"))]
    pub(crate) fn gain(&self, cholesky: &Cholesky3, frozen: &BlockMask) -> StateRows {
        let mut gains: StateRows = core::array::from_fn(|state_index| {
            let product = self.products.get(state_index).copied();
            cholesky.solve(product.unwrap_or([f64::NAN; 3]))
        });
        for (state_index, gain) in gains.iter_mut().enumerate() {
            if frozen.contains_state(state_index) {
                *gain = [0.0; 3];
            }
        }
        gains
    }
}

/// The number of 3-state blocks.
pub(crate) const BLOCKS: usize = STATE_DIMENSION / 3;

/// Adds the measured border (a block a measurement sees directly): `h_ε C_j` to each
/// `M_j` and the border's terms to `H P Hᵀ`.
fn add_border(
    products: &mut StateRows,
    projected: &mut Block,
    cross: &StateRows,
    border: &crate::block_interface::MeasuredBorder,
) {
    for (product, c) in products.iter_mut().zip(cross) {
        *product = block::row_add_scaled(*product, *c, border.coefficient);
    }
    *projected = add(projected, &border.projected);
}

/// Which 3-state blocks of `H` have a non-zero value: the sum of a block's nine magnitudes
/// is zero only if every one is (one `vabs` and one addition per value, no branch; a NaN
/// counts as non-zero, as `v != 0` does).
#[inline(always)]
pub(crate) fn observed_blocks(jacobian: &MeasurementJacobian) -> [bool; BLOCKS] {
    core::array::from_fn(
        |block| match jacobian.data.0.get(3 * block..3 * block + 3) {
            Some([c0, c1, c2]) => {
                let magnitude = |[x, y, z]: Row| (libm::fabs(x) + libm::fabs(y)) + libm::fabs(z);
                (magnitude(*c0) + magnitude(*c1)) + magnitude(*c2) != 0.0
            }
            _ => false,
        },
    )
}

/// Block `block` of `H` (states `3 block..3 block + 3`), row-major; zero outside.
#[inline(always)]
fn jacobian_block(jacobian: &MeasurementJacobian, block: usize) -> Block {
    // nalgebra stores columns: data.0[column][row].
    let column = |i: usize| jacobian.data.0.get(3 * block + i).copied();
    match (column(0), column(1), column(2)) {
        (Some(c0), Some(c1), Some(c2)) => transpose(&[c0, c1, c2]),
        _ => ZERO,
    }
}

/// `M_j += H_K P_{K,j}` for all 24 columns `j` (`offset` = `K`'s first state, `h_columns`
/// the block's three columns as `H` stores them). Not inlined: `H_K` stays in nine
/// registers over the loop.
#[inline(never)]
fn add_observed_block(
    products: &mut StateRows,
    p: &CovarianceMatrix,
    offset: usize,
    h_columns: &[Row; 3],
) {
    let [h0, h1, h2] = transpose(h_columns);
    for (product, column) in products.iter_mut().zip(p.data.0.iter()) {
        if let Some(&[x0, x1, x2]) = column.get(offset..offset + 3) {
            let x = [x0, x1, x2];
            let [r0, r1, r2] = *product;
            *product = [r0 + dot(h0, x), r1 + dot(h1, x), r2 + dot(h2, x)];
        }
    }
}

/// `x += K ν` (the state correction) from the gain rows, in place.
pub(crate) fn add_gain_times(
    state: &mut SMatrix<f64, 24, 1>,
    gains: &StateRows,
    innovation: &Vector3<f64>,
) {
    let nu = block::from_vector(innovation);
    let [values] = &mut state.data.0;
    for (value, row) in values.iter_mut().zip(gains) {
        *value += dot(*row, nu);
    }
}

/// Whether every element of `x + K ν` is finite ([`add_gain_times`]'s values, not stored).
pub(crate) fn corrected_state_is_finite(
    state: &SMatrix<f64, 24, 1>,
    gains: &StateRows,
    innovation: &Vector3<f64>,
) -> bool {
    let nu = block::from_vector(innovation);
    let [values] = &state.data.0;
    let mut check = FiniteCheck::new();
    for (value, row) in values.iter().zip(gains) {
        check.value(*value + dot(*row, nu));
    }
    check.all_finite()
}

impl Cholesky3 {
    /// `None` if `s` is not positive definite (or not finite).
    pub(crate) fn new(s: &Matrix3<f64>) -> Option<Self> {
        let [[s00, _, _], [s10, s11, _], [s20, s21, s22]] = block::from_matrix(s);
        let pivot =
            |value: f64| (value.is_finite() && value > 0.0).then(|| crate::float::sqrt(value));
        let l00 = pivot(s00)?;
        let i00 = 1.0 / l00;
        let l10 = s10 * i00;
        let l20 = s20 * i00;
        let l11 = pivot(s11 - l10 * l10)?;
        let i11 = 1.0 / l11;
        let l21 = (s21 - l20 * l10) * i11;
        let l22 = pivot(s22 - l20 * l20 - l21 * l21)?;
        Some(Self {
            l10,
            l20,
            l21,
            inverse_diagonal: [i00, i11, 1.0 / l22],
        })
    }

    /// `y = L⁻¹ b` (forward substitution).
    #[inline(always)]
    pub(crate) fn whiten(&self, b: Row) -> Row {
        let ([b0, b1, b2], [i0, i1, i2]) = (b, self.inverse_diagonal);
        let y0 = b0 * i0;
        let y1 = (b1 - self.l10 * y0) * i1;
        let y2 = (b2 - self.l20 * y0 - self.l21 * y1) * i2;
        [y0, y1, y2]
    }

    /// `x = S⁻¹ b = L⁻ᵀ L⁻¹ b`.
    #[inline(always)]
    pub(crate) fn solve(&self, b: Row) -> Row {
        let [y0, y1, y2] = self.whiten(b);
        let [i0, i1, i2] = self.inverse_diagonal;
        let x2 = y2 * i2;
        let x1 = (y1 - self.l21 * x2) * i1;
        let x0 = (y0 - self.l10 * x1 - self.l20 * x2) * i0;
        [x0, x1, x2]
    }
}

/// `P⁺_ij` of the expanded Joseph form (module docs) for row `i` (`n_i = N_i`, `k_i = K_i`)
/// and column `j` (`k_j = K_j`, `m_j = M_j`):
/// `((((((P_ij + n_i0 k_j0) + n_i1 k_j1) + n_i2 k_j2) − k_i0 m_j0) − k_i1 m_j1) − k_i2 m_j2)`,
/// the `+ N_i·K_j` rank-3 term first, then the `− K_i·M_j` one, each summed in index order.
#[inline(always)]
fn joseph_element(p: f64, [n0, n1, n2]: Row, [a0, a1, a2]: Row, kj: Row, mj: Row) -> f64 {
    let ([k0, k1, k2], [m0, m1, m2]) = (kj, mj);
    p + n0 * k0 + n1 * k1 + n2 * k2 - a0 * m0 - a1 * m1 - a2 * m2
}

/// Rows `row` and `row + 1` of the expanded Joseph update, upper triangle, in one pass
/// ([`joseph_element`]: the six multiply-adds of an element in the order of the two
/// rank-3 terms, so each `P` element is loaded and stored once). The rows' twelve
/// coefficients (`n`, `k`) stay in registers while the columns stream past, two at a time;
/// each column's two rows (contiguous in the column-major `P`) and its `K_j`, `M_j` are
/// loaded once. Column `row` reaches only row `row`; it and column `row + 1` go first, so
/// the remaining columns pair up with none left over. Returns the sum of the new values,
/// finite only if every one of them is (a sum with ±∞ or NaN in it is not finite): one
/// addition per value and no constant in a register ([`upper_triangle_is_finite`] decides
/// when the sum is not). Two rows, not three: three rows' eighteen coefficients do not fit
/// the Cortex-M7's sixteen double registers, and two rows' twelve leave exactly four.
#[cfg(any(test, target_arch = "arm"))]
#[inline(always)]
fn joseph_row_pair(
    columns: &mut [[f64; STATE_DIMENSION]; STATE_DIMENSION],
    row: usize,
    (n, k): (&[Row; 2], &[Row; 2]),
    gains: &StateRows,
    products: &StateRows,
) -> f64 {
    let mut sum = 0.0;
    let ([n0, n1], [k0, k1]) = (*n, *k);
    let head = (
        columns.get_mut(row..row + 2),
        gains.get(row..row + 2),
        products.get(row..row + 2),
    );
    let (Some([first, second]), Some([g0, g1]), Some([m0, m1])) = head else {
        return sum;
    };
    if let Some(p0) = first.get_mut(row) {
        *p0 = joseph_element(*p0, n0, k0, *g0, *m0);
        sum += *p0;
    }
    let mut pair = |column: &mut [f64; STATE_DIMENSION], kj: Row, mj: Row| {
        if let Some([p0, p1]) = column.get_mut(row..row + 2) {
            *p0 = joseph_element(*p0, n0, k0, kj, mj);
            *p1 = joseph_element(*p1, n1, k1, kj, mj);
            sum += *p0;
            sum += *p1;
        }
    };
    pair(second, *g1, *m1);
    // Plain slice chunks (no iterator state kept in memory across iterations).
    let rest = (
        columns.get_mut(row + 2..),
        gains.get(row + 2..),
        products.get(row + 2..),
    );
    if let (Some(rest_columns), Some(rest_gains), Some(rest_products)) = rest {
        let chunks = rest_columns
            .chunks_exact_mut(2)
            .zip(rest_gains.chunks_exact(2))
            .zip(rest_products.chunks_exact(2));
        for ((columns, gains), products) in chunks {
            if let ([c0, c1], [g0, g1], [m0, m1]) = (columns, gains, products) {
                pair(c0, *g0, *m0);
                pair(c1, *g1, *m1);
            }
        }
    }
    sum
}

/// The upper triangle of the expanded Joseph update (module docs), pair of rows by pair of
/// rows (`joseph_row_pair`, with the pair's `N_i = K_i S − M_i` computed first); returns
/// the sum of the new values (`joseph_row_pair`). Not inlined: one prologue for the
/// twelve pairs.
#[cfg(any(test, target_arch = "arm"))]
#[inline(never)]
fn joseph_upper(
    columns: &mut [[f64; STATE_DIMENSION]; STATE_DIMENSION],
    gains: &StateRows,
    products: &StateRows,
    s: &Block,
) -> f64 {
    let mut sum = 0.0;
    let pairs = gains.chunks_exact(2).zip(products.chunks_exact(2));
    for (pair, (k, m)) in pairs.enumerate() {
        if let ([k0, k1], [m0, m1]) = (k, m) {
            let n = [n_row(*k0, s, *m0), n_row(*k1, s, *m1)];
            sum += joseph_row_pair(columns, 2 * pair, (&n, &[*k0, *k1]), gains, products);
        }
    }
    sum
}

/// Four rows' coefficients by term: `[c][r]` is coefficient `c` of row `r` (one vector
/// register per term on x86-64-v3).
#[cfg(any(test, not(target_arch = "arm")))]
type QuadCoefficients = [[f64; 4]; 3];

/// `rows` (four rows of three) by term ([`QuadCoefficients`]).
#[cfg(any(test, not(target_arch = "arm")))]
#[inline(always)]
fn by_term(rows: &[Row; 4]) -> QuadCoefficients {
    let [[a0, a1, a2], [b0, b1, b2], [c0, c1, c2], [d0, d1, d2]] = *rows;
    [[a0, b0, c0, d0], [a1, b1, c1, d1], [a2, b2, c2, d2]]
}

/// [`joseph_element`] for four rows of one column at once (`n`, `k` by term), lane by
/// lane: the compiler makes each of its six multiply-adds one whole-vector step.
#[cfg(any(test, not(target_arch = "arm")))]
#[inline(always)]
fn joseph_lanes(
    p: [f64; 4],
    (n, k): (&QuadCoefficients, &QuadCoefficients),
    kj: Row,
    mj: Row,
) -> [f64; 4] {
    let lane = |i: usize| {
        let row = |terms: &QuadCoefficients| {
            terms.map(|values| values.get(i).copied().unwrap_or(f64::NAN))
        };
        let x = p.get(i).copied().unwrap_or(f64::NAN);
        joseph_element(x, row(n), row(k), kj, mj)
    };
    [lane(0), lane(1), lane(2), lane(3)]
}

/// Lanes `0..=c` of `new`, the others of `old` (rows on and above the diagonal of column
/// `row + c`).
#[cfg(any(test, not(target_arch = "arm")))]
#[inline(always)]
fn on_and_above(c: usize, new: [f64; 4], old: [f64; 4]) -> [f64; 4] {
    let ([n0, n1, n2, n3], [_, o1, o2, o3]) = (new, old);
    let pick = |lane: usize, n: f64, o: f64| if lane <= c { n } else { o };
    [n0, pick(1, n1, o1), pick(2, n2, o2), pick(3, n3, o3)]
}

/// `a + b` lane by lane.
#[cfg(any(test, not(target_arch = "arm")))]
#[inline(always)]
fn add_lanes(a: [f64; 4], b: [f64; 4]) -> [f64; 4] {
    let ([a0, a1, a2, a3], [b0, b1, b2, b3]) = (a, b);
    [a0 + b0, a1 + b1, a2 + b2, a3 + b3]
}

/// Rows `row..row + 4` of a column.
#[cfg(any(test, not(target_arch = "arm")))]
#[inline(always)]
fn quad_of(column: &mut [f64; STATE_DIMENSION], row: usize) -> Option<&mut [f64; 4]> {
    column
        .get_mut(row..row + 4)
        .and_then(|values| <&mut [f64; 4]>::try_from(values).ok())
}

/// Rows `row..row + 4` of the expanded Joseph update, upper triangle, in one pass: the
/// host's form of `joseph_row_pair` (the same [`joseph_element`] per element, so the same
/// bits), four rows at a time so each column's four values are one 256-bit vector on
/// x86-64-v3 and each row's coefficients, by term ([`by_term`]), a vector register (sixteen
/// of them there; the Cortex-M7's sixteen scalar registers hold two rows' only). Column
/// `row + c` of the first four reaches rows `row..=row + c` (element by element); the
/// others are whole vectors ([`joseph_lanes`]). Returns one sum of new values per row
/// (four independent chains of additions, kept in a register; finite only if every value
/// is).
#[cfg(any(test, not(target_arch = "arm")))]
#[inline(always)]
fn joseph_row_quad(
    columns: &mut [[f64; STATE_DIMENSION]; STATE_DIMENSION],
    row: usize,
    (n, k): (&[Row; 4], &[Row; 4]),
    gains: &StateRows,
    products: &StateRows,
) -> [f64; 4] {
    let mut sums = [0.0; 4];
    let all = (
        columns.get_mut(row..),
        gains.get(row..),
        products.get(row..),
    );
    let (Some(all_columns), Some(all_gains), Some(all_products)) = all else {
        return sums;
    };
    let terms = (&by_term(n), &by_term(k));
    let mut triples = all_columns.iter_mut().zip(all_gains).zip(all_products);
    // The first four columns reach the diagonal: column `row + c` has rows `row..=row + c`
    // only; its lanes below the diagonal (old lower-triangle values, whatever they are) are
    // computed and discarded, so every column is one vector.
    for c in 0..4 {
        if let Some(((column, kj), mj)) = triples.next() {
            if let Some(values) = quad_of(column, row) {
                let new = joseph_lanes(*values, terms, *kj, *mj);
                *values = on_and_above(c, new, *values);
                sums = add_lanes(sums, on_and_above(c, new, [0.0; 4]));
            }
        }
    }
    for ((column, kj), mj) in triples {
        if let Some(values) = quad_of(column, row) {
            *values = joseph_lanes(*values, terms, *kj, *mj);
            sums = add_lanes(sums, *values);
        }
    }
    sums
}

/// The host's `joseph_upper`: four rows at a time (`joseph_row_quad`), the same values.
#[cfg(any(test, not(target_arch = "arm")))]
#[inline(never)]
fn joseph_upper_by_four(
    columns: &mut [[f64; STATE_DIMENSION]; STATE_DIMENSION],
    gains: &StateRows,
    products: &StateRows,
    s: &Block,
) -> f64 {
    let mut sums = [0.0; 4];
    let quads = gains.chunks_exact(4).zip(products.chunks_exact(4));
    for (quad, (k, m)) in quads.enumerate() {
        if let ([k0, k1, k2, k3], [m0, m1, m2, m3]) = (k, m) {
            let n = [
                n_row(*k0, s, *m0),
                n_row(*k1, s, *m1),
                n_row(*k2, s, *m2),
                n_row(*k3, s, *m3),
            ];
            let rows = (&n, &[*k0, *k1, *k2, *k3]);
            let part = joseph_row_quad(columns, 4 * quad, rows, gains, products);
            for (sum, value) in sums.iter_mut().zip(part) {
                *sum += value;
            }
        }
    }
    let [a, b, c, d] = sums;
    a + b + c + d
}

/// Whether every element of the upper triangle is finite: the exact check when the sum of
/// the new values is not finite (it also overflows when finite values are large).
#[inline(never)]
fn upper_triangle_is_finite(p: &CovarianceMatrix) -> bool {
    let mut check = FiniteCheck::new();
    for (j, column) in p.data.0.iter().enumerate() {
        for value in column.iter().take(j + 1) {
            check.value(*value);
        }
    }
    check.all_finite()
}

/// `N_i = K_i S − M_i` (`s` symmetric, row-major), each element `(0 + K_i·S_r) − M_ir`.
#[inline(always)]
fn n_row(gain: Row, s: &Block, product: Row) -> Row {
    block::row_sub(mul_vector_add([0.0; 3], s, gain), product)
}

/// Joseph form expanded (module docs), in place: `P⁺_ij = (P_ij + N_i·K_j) − K_i·M_j` with
/// `N = K S − M` on the upper triangle (6 multiply-adds per element in one pass, two rows
/// at a time on the Cortex-M7, `joseph_row_pair`, four on the host, each group's `N_i`
/// computed with it), mirrored; `gains` are
/// the rows `K_i`, `observed` holds `M = P Hᵀ`, `s` is symmetric. `false` (and `P`
/// unchanged) if the result is not finite: new values go to the upper triangle only, so
/// the untouched lower triangle and a saved diagonal are the roll-back copy.
pub(crate) fn joseph_update(
    p: &mut CovarianceMatrix,
    gains: &StateRows,
    observed: &ObservedCovariance,
    s: &Matrix3<f64>,
) -> bool {
    let s = block::from_matrix(s);
    let products = &observed.products;
    let diagonal: [f64; STATE_DIMENSION] = core::array::from_fn(|i| block::entry(p, i, i));
    // The same values either way (the kernels' bit-for-bit test).
    #[cfg(target_arch = "arm")]
    let sum = joseph_upper(&mut p.data.0, gains, products, &s);
    #[cfg(not(target_arch = "arm"))]
    let sum = joseph_upper_by_four(&mut p.data.0, gains, products, &s);
    if sum.is_finite() || upper_triangle_is_finite(p) {
        #[cfg(target_arch = "arm")]
        block::mirror_upper_to_lower(p, STATE_DIMENSION);
        #[cfg(not(target_arch = "arm"))]
        block::mirror_upper_to_lower_by_tiles(p);
        true
    } else {
        block::mirror_lower_to_upper(p, STATE_DIMENSION);
        for (index, value) in diagonal.iter().enumerate() {
            block::set_entry(p, index, index, *value);
        }
        false
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::structured::tests::random_covariance;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// The Cortex-M7's two-row Joseph kernel and the host's four-row one give the same
    /// upper triangle and the same verdict, bit for bit (each element's operations are the
    /// same, only the grouping of rows differs), including the diagonal's partial columns.
    #[test]
    fn the_two_row_and_four_row_joseph_kernels_agree_bit_for_bit() {
        let mut rng = ChaCha8Rng::seed_from_u64(17);
        for _ in 0..50 {
            let p = random_covariance(&mut rng);
            let mut row = || -> Row { core::array::from_fn(|_| rng.random_range(-2.0..2.0)) };
            let gains: StateRows = core::array::from_fn(|_| row());
            let products: StateRows = core::array::from_fn(|_| row());
            let s = [row(), row(), row()];
            let (mut two, mut four) = (p, p);
            let sum_two = joseph_upper(&mut two.data.0, &gains, &products, &s);
            let sum_four = joseph_upper_by_four(&mut four.data.0, &gains, &products, &s);
            assert_eq!(two.map(f64::to_bits), four.map(f64::to_bits));
            assert!(sum_two.is_finite() && sum_four.is_finite());
            // The lower triangle is untouched (the roll-back copy).
            for j in 0..STATE_DIMENSION {
                for i in j + 1..STATE_DIMENSION {
                    assert_eq!(two[(i, j)].to_bits(), p[(i, j)].to_bits());
                }
            }
        }
    }
}
