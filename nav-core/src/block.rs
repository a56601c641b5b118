//! 3×3 block arithmetic on plain arrays, and element access to the 24×24 covariance by
//! compile-time block indices: the kernels of [`crate::structured`].
//!
//! Why not nalgebra here: products of `fixed_view`s of a 24×24 matrix compiled, on the
//! Cortex-M7, to several times the instructions of the arithmetic itself (views, strides and
//! temporaries; measured in `qemu/src/bin/checks.rs`). These helpers are written so that,
//! once inlined, every index is a constant: each product is exactly its 27 multiplications
//! and 18 additions plus loads and stores, with no loop, no bounds check and no panic path
//! (element access goes through `get`, whose `None` branch the constant indices remove).
//!
//! Arithmetic is the textbook definition, summed in index order:
//! `(A B)_ij = (A_i0 B_0j + A_i1 B_1j) + A_i2 B_2j`, and `acc + A B` adds the three products
//! to `acc` one after the other.

use nalgebra::{Matrix3, SMatrix, Vector3};

use crate::discretise::CovarianceMatrix;

/// A row of three (or a 3-vector).
pub(crate) type Row = [f64; 3];
/// A 3×3 block, row-major: `block[row][column]`.
pub(crate) type Block = [Row; 3];

/// The zero block.
pub(crate) const ZERO: Block = [[0.0; 3]; 3];
/// The identity block.
pub(crate) const IDENTITY: Block = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

/// `a + b`.
#[inline(always)]
pub(crate) fn row_add(a: Row, b: Row) -> Row {
    let ([a0, a1, a2], [b0, b1, b2]) = (a, b);
    [a0 + b0, a1 + b1, a2 + b2]
}

/// `a − b`.
#[inline(always)]
pub(crate) fn row_sub(a: Row, b: Row) -> Row {
    let ([a0, a1, a2], [b0, b1, b2]) = (a, b);
    [a0 - b0, a1 - b1, a2 - b2]
}

/// `s a`.
#[inline(always)]
pub(crate) fn row_scale(a: Row, s: f64) -> Row {
    let [a0, a1, a2] = a;
    [a0 * s, a1 * s, a2 * s]
}

/// `a + s b`.
#[inline(always)]
pub(crate) fn row_add_scaled(a: Row, b: Row, s: f64) -> Row {
    let ([a0, a1, a2], [b0, b1, b2]) = (a, b);
    [a0 + b0 * s, a1 + b1 * s, a2 + b2 * s]
}

/// `a · b = (a0 b0 + a1 b1) + a2 b2`.
#[inline(always)]
pub(crate) fn dot(a: Row, b: Row) -> f64 {
    let ([a0, a1, a2], [b0, b1, b2]) = (a, b);
    a0 * b0 + a1 * b1 + a2 * b2
}

/// `c + a · b = ((c + a0 b0) + a1 b1) + a2 b2` (each element of [`mul_transpose_add`]).
#[inline(always)]
pub(crate) fn dot_add(c: f64, a: Row, b: Row) -> f64 {
    let ([a0, a1, a2], [b0, b1, b2]) = (a, b);
    c + a0 * b0 + a1 * b1 + a2 * b2
}

/// `acc + A b` (`b` a column vector).
#[inline(always)]
pub(crate) fn mul_vector_add(acc: Row, a: &Block, b: Row) -> Row {
    let ([r0, r1, r2], [a0, a1, a2]) = (acc, *a);
    [r0 + dot(a0, b), r1 + dot(a1, b), r2 + dot(a2, b)]
}

/// `A B`.
#[inline(always)]
pub(crate) fn mul(a: &Block, b: &Block) -> Block {
    let [b0, b1, b2] = *b;
    a.map(|[x, y, z]| row_add_scaled(row_add(row_scale(b0, x), row_scale(b1, y)), b2, z))
}

/// `acc + A B`.
#[inline(always)]
pub(crate) fn mul_add(acc: &Block, a: &Block, b: &Block) -> Block {
    let ([r0, r1, r2], [a0, a1, a2], [b0, b1, b2]) = (*acc, *a, *b);
    let row = |r: Row, [x, y, z]: Row| {
        row_add_scaled(row_add_scaled(row_add_scaled(r, b0, x), b1, y), b2, z)
    };
    [row(r0, a0), row(r1, a1), row(r2, a2)]
}

/// `A Bᵀ` (element `(i, j)` is row `i` of `A` dot row `j` of `B`).
#[inline(always)]
pub(crate) fn mul_transpose(a: &Block, b: &Block) -> Block {
    let [b0, b1, b2] = *b;
    a.map(|row| [dot(row, b0), dot(row, b1), dot(row, b2)])
}

/// `acc + A Bᵀ`.
#[inline(always)]
pub(crate) fn mul_transpose_add(acc: &Block, a: &Block, b: &Block) -> Block {
    let ([r0, r1, r2], [a0, a1, a2], [b0, b1, b2]) = (*acc, *a, *b);
    // ((c + a0 b0) + a1 b1) + a2 b2: three multiply-accumulates per element.
    let row =
        |[c0, c1, c2]: Row, a: Row| [dot_add(c0, a, b0), dot_add(c1, a, b1), dot_add(c2, a, b2)];
    [row(r0, a0), row(r1, a1), row(r2, a2)]
}

/// `A + B`.
#[inline(always)]
pub(crate) fn add(a: &Block, b: &Block) -> Block {
    let ([a0, a1, a2], [b0, b1, b2]) = (*a, *b);
    [row_add(a0, b0), row_add(a1, b1), row_add(a2, b2)]
}

/// `A + s B`.
#[inline(always)]
pub(crate) fn add_scaled(a: &Block, b: &Block, s: f64) -> Block {
    let ([a0, a1, a2], [b0, b1, b2]) = (*a, *b);
    [
        row_add_scaled(a0, b0, s),
        row_add_scaled(a1, b1, s),
        row_add_scaled(a2, b2, s),
    ]
}

/// `s A`.
#[inline(always)]
pub(crate) fn scale(a: &Block, s: f64) -> Block {
    a.map(|row| row_scale(row, s))
}

/// `A + diag(v) B` (the block kernel's and the correlated-error border's; the row kernel
/// folds whole rows).
#[inline(always)]
pub(crate) fn add_scaled_rows(a: &Block, b: &Block, v: Row) -> Block {
    let ([a0, a1, a2], [b0, b1, b2], [v0, v1, v2]) = (*a, *b, v);
    [
        row_add_scaled(a0, b0, v0),
        row_add_scaled(a1, b1, v1),
        row_add_scaled(a2, b2, v2),
    ]
}

/// `A diag(v)` (column `j` times `v_j`).
#[inline(always)]
pub(crate) fn scale_columns(a: &Block, v: Row) -> Block {
    let [v0, v1, v2] = v;
    a.map(|[x, y, z]| [x * v0, y * v1, z * v2])
}

/// `A + B diag(v)`.
#[inline(always)]
pub(crate) fn add_scaled_columns(a: &Block, b: &Block, v: Row) -> Block {
    let ([a0, a1, a2], [b0, b1, b2], [v0, v1, v2]) = (*a, *b, v);
    let row = |[x, y, z]: Row, [p, q, r]: Row| [x + p * v0, y + q * v1, z + r * v2];
    [row(a0, b0), row(a1, b1), row(a2, b2)]
}

/// `Aᵀ`.
#[inline(always)]
pub(crate) fn transpose(a: &Block) -> Block {
    let [[a00, a01, a02], [a10, a11, a12], [a20, a21, a22]] = *a;
    [[a00, a10, a20], [a01, a11, a21], [a02, a12, a22]]
}

/// `[v×]`, the cross-product matrix (`[v×] u = v × u`).
#[inline(always)]
pub(crate) fn skew(v: Row) -> Block {
    let [x, y, z] = v;
    [[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]]
}

/// A nalgebra 3×3 as a block.
#[inline(always)]
pub(crate) fn from_matrix(m: &Matrix3<f64>) -> Block {
    // nalgebra stores columns: data.0[column][row].
    transpose(&m.data.0)
}

/// A block as a nalgebra 3×3.
#[inline(always)]
pub(crate) fn to_matrix(b: &Block) -> Matrix3<f64> {
    Matrix3::from_data(nalgebra::ArrayStorage(transpose(b)))
}

/// A nalgebra 3-vector as a row.
#[inline(always)]
pub(crate) fn from_vector(v: &Vector3<f64>) -> Row {
    let [column] = v.data.0;
    column
}

/// Accumulates whether values are finite with one multiply-add each: `x · 0` is `0` for
/// every finite `x` and NaN for ±∞ and NaN, so the sum stays `0` exactly while every value
/// added is finite.
#[derive(Debug, Clone, Copy)]
pub(crate) struct FiniteCheck(f64);

impl FiniteCheck {
    /// Nothing checked yet.
    #[inline(always)]
    pub(crate) fn new() -> Self {
        Self(0.0)
    }

    /// Adds one value.
    #[inline(always)]
    pub(crate) fn value(&mut self, x: f64) {
        self.0 += x * 0.0;
    }

    /// Adds the nine values of a block: summed among themselves first, so the running sum
    /// is one addition per block (the same count of operations as value by value, but a
    /// chain of dependent additions a ninth as long: on an out-of-order host each would
    /// wait for the previous one).
    #[inline(always)]
    pub(crate) fn block(&mut self, b: &Block) {
        let [r0, r1, r2] = b.map(|[x, y, z]| (x * 0.0 + y * 0.0) + z * 0.0);
        self.0 += (r0 + r1) + r2;
    }

    /// Adds the three values of a row.
    #[inline(always)]
    pub(crate) fn row(&mut self, r: &Row) {
        let [x, y, z] = *r;
        self.0 += (x * 0.0 + y * 0.0) + z * 0.0;
    }

    /// Adds the values another check has seen.
    #[cfg(any(test, target_arch = "arm"))]
    #[inline(always)]
    pub(crate) fn merge(&mut self, other: FiniteCheck) {
        self.0 += other.0;
    }

    /// True while every value added was finite.
    #[inline(always)]
    pub(crate) fn all_finite(&self) -> bool {
        !self.0.is_nan()
    }
}

/// Whether every value is finite ([`FiniteCheck`]: one multiply-add per value, no branch;
/// nalgebra's `iter().all(is_finite)` branches on every value and costs several times as
/// much on the target). Four running checks over interleaved values, merged at the end: the
/// same operations as one, but four independent chains of additions, so an out-of-order host
/// does not wait on one long chain of a measurement's values.
#[inline(always)]
pub(crate) fn all_finite(values: &[f64]) -> bool {
    let mut checks = [FiniteCheck::new(); 4];
    let chunks = values.chunks_exact(4);
    let rest = chunks.remainder();
    for chunk in chunks {
        for (check, value) in checks.iter_mut().zip(chunk) {
            check.value(*value);
        }
    }
    let [first, ..] = &mut checks;
    for value in rest {
        first.value(*value);
    }
    let [a, b, c, d] = checks.map(|check| check.0);
    !((a + b) + (c + d)).is_nan()
}

/// Row `i` of a block (NaN outside, which in-range indices never reach: the branch is
/// removed at compile time).
#[inline(always)]
pub(crate) fn row_at(b: &Block, i: usize) -> Row {
    b.get(i).copied().unwrap_or([f64::NAN; 3])
}

/// Element (`row`, `column`) of a column-major matrix (NaN outside, which constant in-range
/// indices never reach: the branch is removed at compile time).
#[inline(always)]
pub(crate) fn entry<const R: usize, const C: usize>(
    matrix: &SMatrix<f64, R, C>,
    row: usize,
    column: usize,
) -> f64 {
    matrix
        .data
        .0
        .get(column)
        .and_then(|c| c.get(row))
        .copied()
        .unwrap_or(f64::NAN)
}

/// Sets element (`row`, `column`) of a column-major matrix (ignored outside).
#[inline(always)]
pub(crate) fn set_entry<const R: usize, const C: usize>(
    matrix: &mut SMatrix<f64, R, C>,
    row: usize,
    column: usize,
    value: f64,
) {
    if let Some(slot) = matrix.data.0.get_mut(column).and_then(|c| c.get_mut(row)) {
        *slot = value;
    }
}

/// The 3×3 block of `matrix` at rows `R..R+3`, columns `C..C+3`.
#[inline(always)]
pub(crate) fn read<const R: usize, const C: usize, const ROWS: usize, const COLUMNS: usize>(
    matrix: &SMatrix<f64, ROWS, COLUMNS>,
) -> Block {
    [0, 1, 2].map(|i| [0, 1, 2].map(|j| entry(matrix, R + i, C + j)))
}

/// Writes `value` into rows `R..R+3`, columns `C..C+3` of a 24×24 matrix (the dense `F`).
#[cfg(any(test, feature = "dense-reference"))]
#[inline(always)]
pub(crate) fn write<const R: usize, const C: usize>(matrix: &mut CovarianceMatrix, value: &Block) {
    for (i, row) in value.iter().enumerate() {
        for (j, x) in row.iter().enumerate() {
            set_entry(matrix, R + i, C + j, *x);
        }
    }
}

/// Writes `value` into rows `R..R+3`, columns `C..C+3` (`R < C`) and `valueᵀ` into rows
/// `C..C+3`, columns `R..R+3`.
#[inline(always)]
pub(crate) fn write_symmetric<const R: usize, const C: usize>(
    matrix: &mut CovarianceMatrix,
    value: &Block,
) {
    for (i, row) in value.iter().enumerate() {
        for (j, x) in row.iter().enumerate() {
            set_entry(matrix, R + i, C + j, *x);
            set_entry(matrix, C + j, R + i, *x);
        }
    }
}

/// Writes the diagonal block at `D..D+3` from the upper triangle of `value`, mirrored.
#[inline(always)]
pub(crate) fn write_diagonal_symmetric<const D: usize>(
    matrix: &mut CovarianceMatrix,
    value: &Block,
) {
    for (i, row) in value.iter().enumerate() {
        for (j, x) in row.iter().enumerate().skip(i) {
            set_entry(matrix, D + i, D + j, *x);
            set_entry(matrix, D + j, D + i, *x);
        }
    }
}

/// Copies the strict upper triangle of the first `rows` rows into the lower triangle:
/// `P(j, i) = P(i, j)` for `i < j`, `i < rows`.
#[cfg(any(test, target_arch = "arm"))]
pub(crate) fn mirror_upper_to_lower(matrix: &mut CovarianceMatrix, rows: usize) {
    let columns = &mut matrix.data.0;
    for j in 1..columns.len() {
        let (left, right) = columns.split_at_mut(j);
        let Some(column_j) = right.first() else {
            continue;
        };
        for (column_i, value) in left.iter_mut().zip(column_j.iter()).take(rows) {
            if let Some(target) = column_i.get_mut(j) {
                *target = *value;
            }
        }
    }
}

/// Tiles of 4×4 along a side of the 24×24 covariance.
#[cfg(any(test, not(target_arch = "arm")))]
const TILES: usize = 6;
#[cfg(any(test, not(target_arch = "arm")))]
const _: () = assert!(4 * TILES == crate::state::STATE_DIMENSION);

/// Rows `row..row + 4` of column `column` (NaN outside, which in-range tiles never reach).
#[cfg(any(test, not(target_arch = "arm")))]
#[inline(always)]
fn tile_column(columns: &[[f64; 24]; 24], column: usize, row: usize) -> [f64; 4] {
    columns
        .get(column)
        .and_then(|values| values.get(row..row + 4))
        .and_then(|values| <[f64; 4]>::try_from(values).ok())
        .unwrap_or([f64::NAN; 4])
}

/// `mirror_upper_to_lower(matrix, 24)` by 4×4 tiles, for hosts with 256-bit vectors
/// (x86-64-v3): each tile above the diagonal is four column vectors, transposed in
/// registers and stored as four column vectors below it (the element-by-element copy
/// reads one column's values and stores them a whole column apart, one scalar at a time); the
/// six diagonal tiles are copied element by element. The same copies, so the same bits.
#[cfg(any(test, not(target_arch = "arm")))]
pub(crate) fn mirror_upper_to_lower_by_tiles(matrix: &mut CovarianceMatrix) {
    let columns = &mut matrix.data.0;
    for tile_column_index in 1..TILES {
        let column = 4 * tile_column_index;
        for row in (0..column).step_by(4) {
            let [[a00, a01, a02, a03], [a10, a11, a12, a13], [a20, a21, a22, a23], [a30, a31, a32, a33]] =
                [0, 1, 2, 3].map(|c| tile_column(columns, column + c, row));
            let transposed = [
                [a00, a10, a20, a30],
                [a01, a11, a21, a31],
                [a02, a12, a22, a32],
                [a03, a13, a23, a33],
            ];
            for (offset, values) in transposed.iter().enumerate() {
                let target = columns
                    .get_mut(row + offset)
                    .and_then(|values| values.get_mut(column..column + 4));
                if let Some(target) = target {
                    target.copy_from_slice(values);
                }
            }
        }
    }
    for corner in (0..4 * TILES).step_by(4) {
        for j in corner + 1..corner + 4 {
            for i in corner..j {
                set_entry(matrix, j, i, entry(matrix, i, j));
            }
        }
    }
}

/// Copies the strict lower triangle back into the upper for the first `rows` rows:
/// `P(i, j) = P(j, i)` for `i < j`, `i < rows` (the roll-back of [`mirror_upper_to_lower`]'s
/// users, whose untouched lower triangle is the copy of the old values).
pub(crate) fn mirror_lower_to_upper(matrix: &mut CovarianceMatrix, rows: usize) {
    let columns = &mut matrix.data.0;
    for j in 1..columns.len() {
        let (left, right) = columns.split_at_mut(j);
        let Some(column_j) = right.first_mut() else {
            continue;
        };
        for (column_i, value) in left.iter().zip(column_j.iter_mut()).take(rows) {
            if let Some(source) = column_i.get(j) {
                *value = *source;
            }
        }
    }
}

/// The variance floor on the diagonal of a square covariance block `P` (an optional state
/// block's `P_εε`, the rule of `ErrorStateFilter::protect_variances`): a variance below its
/// `floor` is raised to it; one above its `ceiling` is only marked, for
/// [`scale_to_ceilings`] (out of line: it never runs in a nominal flight). Returns whether
/// a floor was applied and the marks (bit `a`: state `a`). Only the diagonal is read.
#[inline(always)]
pub(crate) fn floor_and_mark_ceilings<const N: usize>(
    covariance: &mut [[f64; N]; N],
    floor: &[f64; N],
    ceiling: &[f64; N],
) -> (bool, u16) {
    const { assert!(N <= 16, "one bit per state in a u16") };
    let mut clamped = false;
    let mut crossing = 0u16;
    let bounds = floor.iter().zip(ceiling);
    for (a, (row, (floor, ceiling))) in covariance.iter_mut().zip(bounds).enumerate() {
        let Some(variance) = row.get_mut(a) else {
            continue;
        };
        if *variance < *floor {
            *variance = *floor;
            clamped = true;
        } else if *variance > *ceiling {
            crossing |= 1 << a;
        }
    }
    (clamped, crossing)
}

/// `P' = S P S` on a square covariance block for the states marked in `crossing` (bit `a`:
/// state `a`, from [`floor_and_mark_ceilings`]), each with `s = √(ceiling/variance)` (1
/// for a state not marked), which keeps every correlation coefficient and positive
/// definiteness; each marked diagonal then exactly its ceiling. Returns the scales, for
/// the block's covariances with other states.
#[inline(always)]
pub(crate) fn scale_to_ceilings<const N: usize>(
    covariance: &mut [[f64; N]; N],
    crossing: u16,
    ceiling: &[f64; N],
) -> [f64; N] {
    let crossed = |a: usize| crossing & (1 << a) != 0;
    let scales: [f64; N] = core::array::from_fn(|a| {
        match (crossed(a), covariance.get(a).and_then(|row| row.get(a))) {
            (true, Some(variance)) => {
                crate::float::sqrt(ceiling.get(a).copied().unwrap_or(f64::NAN) / variance)
            }
            _ => 1.0,
        }
    });
    for (a, (row, s_a)) in covariance.iter_mut().zip(scales).enumerate() {
        for (value, s_b) in row.iter_mut().zip(scales) {
            *value = *value * s_a * s_b;
        }
        if let (true, Some(variance), Some(ceiling)) = (crossed(a), row.get_mut(a), ceiling.get(a))
        {
            *variance = *ceiling;
        }
    }
    scales
}

#[cfg(test)]
mod tests {
    use super::*;

    const A: Block = [[1.0, 2.0, -3.0], [0.5, -1.5, 4.0], [2.5, 0.25, -0.75]];
    const B: Block = [[-2.0, 1.0, 0.5], [3.0, -0.5, 1.25], [0.75, 2.0, -1.0]];

    #[test]
    fn block_products_equal_nalgebra() {
        let (a, b) = (to_matrix(&A), to_matrix(&B));
        assert_eq!(to_matrix(&mul(&A, &B)), a * b);
        assert_eq!(to_matrix(&mul_transpose(&A, &B)), a * b.transpose());
        assert_eq!(to_matrix(&mul_add(&B, &A, &B)), b + a * b);
        assert_eq!(
            to_matrix(&mul_transpose_add(&A, &A, &B)),
            a + a * b.transpose()
        );
        assert_eq!(from_matrix(&a), A);
        let v = Vector3::new(1.0, -2.0, 0.5);
        assert_eq!(to_matrix(&skew(from_vector(&v))), crate::attitude::skew(&v));
        assert_eq!(
            to_matrix(&add_scaled_rows(&ZERO, &A, [1.0, 2.0, 3.0])),
            Matrix3::from_diagonal(&Vector3::new(1.0, 2.0, 3.0)) * a
        );
        assert_eq!(
            to_matrix(&scale_columns(&A, [1.0, 2.0, 3.0])),
            a * Matrix3::from_diagonal(&Vector3::new(1.0, 2.0, 3.0))
        );
    }

    #[test]
    fn finite_check_flags_infinity_and_nan_only() {
        let mut check = FiniteCheck::new();
        check.block(&A);
        check.value(-1e308);
        assert!(check.all_finite());
        check.value(f64::INFINITY);
        assert!(!check.all_finite());
        let mut check = FiniteCheck::new();
        check.value(f64::NAN);
        assert!(!check.all_finite());
    }

    /// A block with ±∞ or NaN at any one of its nine places is flagged; finite blocks of
    /// the largest magnitudes are not.
    #[test]
    fn a_block_check_flags_a_non_finite_value_at_every_place() {
        for bad in [f64::INFINITY, f64::NEG_INFINITY, f64::NAN] {
            for place in 0..9 {
                let mut block = A;
                block[place / 3][place % 3] = bad;
                let mut check = FiniteCheck::new();
                check.block(&B);
                check.block(&block);
                assert!(!check.all_finite(), "{bad} at {place} not flagged");
            }
        }
        let mut check = FiniteCheck::new();
        check.block(&[[f64::MAX; 3]; 3]);
        check.block(&[[-f64::MAX; 3]; 3]);
        assert!(check.all_finite());
    }

    #[test]
    fn the_tiled_mirror_equals_the_element_by_element_one() {
        let mut by_elements = CovarianceMatrix::from_fn(|i, j| (i * 24 + j) as f64 - 0.5);
        let mut by_tiles = by_elements;
        mirror_upper_to_lower(&mut by_elements, 24);
        mirror_upper_to_lower_by_tiles(&mut by_tiles);
        assert_eq!(by_elements.map(f64::to_bits), by_tiles.map(f64::to_bits));
        assert_eq!(by_tiles[(23, 0)].to_bits(), 22.5f64.to_bits());
    }

    #[test]
    fn mirrors_copy_one_triangle_onto_the_other() {
        let mut p = CovarianceMatrix::from_fn(|i, j| (i * 24 + j) as f64);
        mirror_upper_to_lower(&mut p, 24);
        assert_eq!(p, p.transpose());
        assert_eq!(p[(20, 3)].to_bits(), ((3 * 24 + 20) as f64).to_bits());
        let mut q = CovarianceMatrix::from_fn(|i, j| (i * 24 + j) as f64);
        mirror_lower_to_upper(&mut q, 9);
        assert_eq!(
            q[(3, 20)].to_bits(),
            ((20 * 24 + 3) as f64).to_bits(),
            "row < 9: copied"
        );
        assert_eq!(
            q[(12, 20)].to_bits(),
            ((12 * 24 + 20) as f64).to_bits(),
            "row ≥ 9: untouched"
        );
    }
}
