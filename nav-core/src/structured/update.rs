//! The measurement update: `P Hᵀ` over the observed blocks, the 3×3 Cholesky factor and the
//! expanded Joseph update (module docs of [`super`]).

use super::{
    Cholesky3, ObservedCovariance, StateRows, ATT, BIAS_A, BIAS_G, INSTALL, POS, SCALE_A, SCALE_G,
    VEL,
};
use nalgebra::{Matrix3, SMatrix, Vector3};

use crate::block::{
    self, add, dot, mul_transpose_add, mul_vector_add, read, transpose, Block, FiniteCheck, Row,
    ZERO,
};
use crate::discretise::CovarianceMatrix;
use crate::measurement::MeasurementJacobian;
use crate::state::{BlockMask, STATE_DIMENSION};

impl ObservedCovariance {
    /// `M = P Hᵀ` and `H P Hᵀ` over the blocks of `H` that are not all zero: for each
    /// observed block `K`, `M_j += H_K P_{K,j}` over the 24 columns `j` (the symmetric `P`
    /// read by columns), then `H P Hᵀ = Σ_K H_K P_{K,·} H_Kᵀ`'s sum `Σ_K (M_K)ᵀ H_Kᵀ`.
    pub(crate) fn new(
        jacobian: &MeasurementJacobian,
        p: &CovarianceMatrix,
        border: Option<(&StateRows, &crate::gnss_error::Border)>,
    ) -> Self {
        // Built in its final place (a local array moved into `Self` would be copied).
        let mut observed = Self {
            products: [[0.0; 3]; STATE_DIMENSION],
            projected: ZERO,
        };
        let blocks = [
            (ATT, read::<0, ATT, 3, 24>(jacobian)),
            (POS, read::<0, POS, 3, 24>(jacobian)),
            (VEL, read::<0, VEL, 3, 24>(jacobian)),
            (BIAS_G, read::<0, BIAS_G, 3, 24>(jacobian)),
            (BIAS_A, read::<0, BIAS_A, 3, 24>(jacobian)),
            (INSTALL, read::<0, INSTALL, 3, 24>(jacobian)),
            (SCALE_G, read::<0, SCALE_G, 3, 24>(jacobian)),
            (SCALE_A, read::<0, SCALE_A, 3, 24>(jacobian)),
        ];
        let observed_blocks = || {
            blocks
                .iter()
                .filter(|(_, h)| !h.iter().flatten().all(|v| *v == 0.0))
        };
        for (offset, h) in observed_blocks() {
            add_observed_block(&mut observed.products, p, *offset, h);
        }
        // H P Hᵀ = Σ_K (H P)_{·,K} H_Kᵀ, with (H P)_{·,K} = [M_K, M_K+1, M_K+2] as columns.
        for (offset, h) in observed_blocks() {
            if let Some([m0, m1, m2]) = observed.products.get(*offset..*offset + 3) {
                observed.projected =
                    mul_transpose_add(&observed.projected, &transpose(&[*m0, *m1, *m2]), h);
            }
        }
        if let Some((cross, border)) = border {
            observed.add_border(cross, border);
        }
        observed
    }

    /// Adds the correlated-GNSS-error border ([`crate::gnss_error`]): `h_ε C_j` to each
    /// `M_j` and the border's terms to `H P Hᵀ`.
    fn add_border(&mut self, cross: &StateRows, border: &crate::gnss_error::Border) {
        for (product, c) in self.products.iter_mut().zip(cross) {
            *product = block::row_add_scaled(*product, *c, border.coefficient);
        }
        self.projected = add(&self.projected, &border.projected);
    }

    /// `M = P Hᵀ`, row `j` for state `j`.
    pub(crate) fn products(&self) -> &StateRows {
        &self.products
    }

    /// `H P Hᵀ`.
    pub(crate) fn projected(&self) -> Matrix3<f64> {
        block::to_matrix(&self.projected)
    }

    /// The gain `K = P Hᵀ S⁻¹`, row `j` = `S⁻¹ M_j`, the rows of the `frozen` blocks zero.
    pub(crate) fn gain(&self, cholesky: &Cholesky3, frozen: &BlockMask) -> StateRows {
        // Built element by element (no zero-fill of the 576-byte array first).
        core::array::from_fn(|state_index| match self.products.get(state_index) {
            Some(product) if !frozen.contains_state(state_index) => cholesky.solve(*product),
            _ => [0.0; 3],
        })
    }
}

/// `M_j += H_K P_{K,j}` for all 24 columns `j` (`offset` = `K`'s first state). Not inlined:
/// `H_K` stays in nine registers over the loop.
#[inline(never)]
fn add_observed_block(products: &mut StateRows, p: &CovarianceMatrix, offset: usize, h: &Block) {
    let [h0, h1, h2] = *h;
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

impl Cholesky3 {
    /// `None` if `s` is not positive definite (or not finite).
    pub(crate) fn new(s: &Matrix3<f64>) -> Option<Self> {
        let [[s00, _, _], [s10, s11, _], [s20, s21, s22]] = block::from_matrix(s);
        let pivot = |value: f64| (value.is_finite() && value > 0.0).then(|| libm::sqrt(value));
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

/// One rank-3 pass of the expanded Joseph update over rows `row..row + 3`, upper triangle:
/// `P_ij ← ((P_ij ± l_i0 r_j0) ± l_i1 r_j1) ± l_i2 r_j2` (`+` unless `SUBTRACT`), with the
/// rows' vectors `left` and the columns' vectors `right`. The nine row coefficients stay in
/// registers while the columns stream past; each column's three rows (contiguous in the
/// column-major `P`) and its `r_j` are loaded once. Column `row` reaches only row `row`,
/// column `row + 1` rows `row` and `row + 1`. The subtracting pass also checks every new
/// value (the returned check; a local accumulator stays in a register).
#[inline(never)]
fn joseph_pass<const SUBTRACT: bool>(
    columns: &mut [[f64; STATE_DIMENSION]; STATE_DIMENSION],
    row: usize,
    left: &[Row; 3],
    right: &StateRows,
) -> FiniteCheck {
    let mut check = FiniteCheck::new();
    let [l0, l1, l2] = *left;
    let term = |value: f64, [a0, a1, a2]: Row, [b0, b1, b2]: Row| {
        if SUBTRACT {
            value - a0 * b0 - a1 * b1 - a2 * b2
        } else {
            value + a0 * b0 + a1 * b1 + a2 * b2
        }
    };
    let mut update = |value: &mut f64, l: Row, r: Row| {
        *value = term(*value, l, r);
        if SUBTRACT {
            check.value(*value);
        }
    };
    if let (Some(column), Some(r)) = (columns.get_mut(row), right.get(row)) {
        if let Some(p0) = column.get_mut(row) {
            update(p0, l0, *r);
        }
    }
    if let (Some(column), Some(r)) = (columns.get_mut(row + 1), right.get(row + 1)) {
        if let Some([p0, p1]) = column.get_mut(row..row + 2) {
            update(p0, l0, *r);
            update(p1, l1, *r);
        }
    }
    // Plain slice zips (no iterator state kept in memory across iterations).
    let (Some(full_columns), Some(full_right)) = (columns.get_mut(row + 2..), right.get(row + 2..))
    else {
        return check;
    };
    for (column, r) in full_columns.iter_mut().zip(full_right) {
        if let Some([p0, p1, p2]) = column.get_mut(row..row + 3) {
            update(p0, l0, *r);
            update(p1, l1, *r);
            update(p2, l2, *r);
        }
    }
    check
}

/// Joseph form expanded (module docs), in place: `P⁺_ij = (P_ij + N_i·K_j) − K_i·M_j` with
/// `N = K S − M` on the upper triangle (6 multiply-adds per element, in two rank-3 passes
/// per triple of rows, [`joseph_pass`]), mirrored; `gains` are the rows `K_i`, `observed`
/// holds `M = P Hᵀ`, `s` is symmetric. `false` (and `P` unchanged) if the result is not
/// finite: new values go to the upper triangle only, so the untouched lower triangle and a
/// saved diagonal are the roll-back copy.
pub(crate) fn joseph_update(
    p: &mut CovarianceMatrix,
    gains: &StateRows,
    observed: &ObservedCovariance,
    s: &Matrix3<f64>,
) -> bool {
    let s = block::from_matrix(s);
    // N_i = K_i S − M_i (built element by element: no zero-fill first).
    let n_rows: StateRows = core::array::from_fn(|i| {
        let gain = gains.get(i).copied().unwrap_or([0.0; 3]);
        let product = observed.products.get(i).copied().unwrap_or([0.0; 3]);
        block::row_sub(mul_vector_add([0.0; 3], &s, gain), product)
    });
    let diagonal: [f64; STATE_DIMENSION] = core::array::from_fn(|i| block::entry(p, i, i));
    let mut check = FiniteCheck::new();
    let triples = n_rows
        .chunks_exact(3)
        .zip(gains.chunks_exact(3))
        .enumerate();
    for (triple, (n, k)) in triples {
        let row = 3 * triple;
        if let ([n0, n1, n2], [k0, k1, k2]) = (n, k) {
            joseph_pass::<false>(&mut p.data.0, row, &[*n0, *n1, *n2], gains);
            let products = &observed.products;
            check.merge(joseph_pass::<true>(
                &mut p.data.0,
                row,
                &[*k0, *k1, *k2],
                products,
            ));
        }
    }
    if check.all_finite() {
        block::mirror_upper_to_lower(p, STATE_DIMENSION);
        true
    } else {
        block::mirror_lower_to_upper(p, STATE_DIMENSION);
        for (index, value) in diagonal.iter().enumerate() {
            block::set_entry(p, index, index, *value);
        }
        false
    }
}
