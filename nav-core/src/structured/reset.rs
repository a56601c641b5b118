//! The covariance reset `P ← J P Jᵀ` by block rows and columns (module docs of [`super`]).

use super::{ATT, BIAS_A, BIAS_G, INSTALL, POS, SCALE_A, SCALE_G, VEL};
use nalgebra::Matrix3;

use crate::block::{
    self, mul, mul_transpose, read, write_diagonal_symmetric, write_symmetric, Block,
};
use crate::discretise::CovarianceMatrix;

/// Block (`R`, `C`), `R < C`, of `J P Jᵀ` in place, with `J_R = left` and `J_C = right`
/// (`None`: identity), and its mirror.
#[inline(always)]
fn reset_pair<const R: usize, const C: usize>(
    p: &mut CovarianceMatrix,
    left: Option<&Block>,
    right: Option<&Block>,
) {
    let old = read::<R, C, 24, 24>(p);
    let value = match (left, right) {
        (Some(l), Some(r)) => mul_transpose(&mul(l, &old), r),
        (Some(l), None) => mul(l, &old),
        (None, Some(r)) => mul_transpose(&old, r),
        (None, None) => old,
    };
    write_symmetric::<R, C>(p, &value);
}

/// Diagonal block `D` of `J P Jᵀ` in place: `J_D P_DD J_Dᵀ`, upper triangle mirrored.
#[inline(always)]
fn reset_diagonal<const D: usize>(p: &mut CovarianceMatrix, jacobian: &Block) {
    let old = read::<D, D, 24, 24>(p);
    write_diagonal_symmetric::<D>(p, &mul_transpose(&mul(jacobian, &old), jacobian));
}

/// `P ← J P Jᵀ` in place for the reset Jacobian `J` = identity except `J_ϑϑ = I − [ϑ̂×]` and
/// `J_ψψ = I − [ψ̂×]`: only the attitude and installation block rows and columns change;
/// each new block depends only on the same old block, so they are overwritten one by one.
/// Inlined at its two call sites (the reset and the star heads' hand-over): out of line, its
/// general form costs every update frame's reset (docs/guide/performance.md).
#[inline(always)]
pub(crate) fn reset_covariance(
    p: &mut CovarianceMatrix,
    attitude: &Matrix3<f64>,
    installation: &Matrix3<f64>,
) {
    let (attitude, installation) = (
        block::from_matrix(attitude),
        block::from_matrix(installation),
    );
    let (a, i) = (Some(&attitude), Some(&installation));
    reset_diagonal::<ATT>(p, &attitude);
    reset_pair::<ATT, POS>(p, a, None);
    reset_pair::<ATT, VEL>(p, a, None);
    reset_pair::<ATT, BIAS_G>(p, a, None);
    reset_pair::<ATT, BIAS_A>(p, a, None);
    reset_pair::<ATT, INSTALL>(p, a, i);
    reset_pair::<ATT, SCALE_G>(p, a, None);
    reset_pair::<ATT, SCALE_A>(p, a, None);
    reset_pair::<POS, INSTALL>(p, None, i);
    reset_pair::<VEL, INSTALL>(p, None, i);
    reset_pair::<BIAS_G, INSTALL>(p, None, i);
    reset_pair::<BIAS_A, INSTALL>(p, None, i);
    reset_diagonal::<INSTALL>(p, &installation);
    reset_pair::<INSTALL, SCALE_G>(p, i, None);
    reset_pair::<INSTALL, SCALE_A>(p, i, None);
}
