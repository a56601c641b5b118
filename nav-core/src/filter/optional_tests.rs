//! The optional blocks' protections against the dense 39-state model (24 core states, the 3
//! correlated GNSS error states, the 12 systematic IMU error states, in layout order):
//! freezing is the dense Joseph update with the frozen rows' gain zero, the ceiling is
//! `S P S` with `S` the ceiling's scale on the crossed state, the floor raises one diagonal
//! entry.
#![cfg(all(feature = "gnss-error-states", feature = "imu-error-states"))]

use nalgebra::{Cholesky, SMatrix};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::{ErrorStateFilter, FilterMode, OptionalVarianceBounds};
use crate::gnss_error::GnssErrorModel;
use crate::imu_error_states::ImuErrorModel;
use crate::state::{BlockMask, OptionalBlock, LAYOUT_DIMENSION, OPTIONAL_DIMENSION};
use crate::structured::tests::{
    filter_with, install_both_borders, random_covariance, random_mask, random_measurement,
    whole_covariance, whole_state, Bordered, BORDERED,
};
use crate::NavError;

const RECEIVER: GnssErrorModel = GnssErrorModel {
    sigma_m: 8.0,
    correlation_time_s: 300.0,
};

const IMU: ImuErrorModel = ImuErrorModel {
    gyro_misalignment_sigma_rad: 2e-5,
    accel_misalignment_sigma_rad: 2e-5,
    gyro_g_sensitivity_sigma_rad_s_per_mps2: 2.5e-7,
};

// The test model's states are the layout's.
const _: () = assert!(BORDERED == LAYOUT_DIMENSION);

fn filter_with_both_borders(rng: &mut ChaCha8Rng) -> ErrorStateFilter {
    let mut filter = filter_with(FilterMode::ClosedLoop, &random_covariance(rng));
    install_both_borders(&mut filter, rng, RECEIVER, IMU);
    filter
}

/// `max |A_ij − B_ij| / √(S_ii S_jj)`.
fn relative(a: &Bordered, b: &Bordered, scale: &Bordered) -> f64 {
    let mut worst = 0.0f64;
    for i in 0..BORDERED {
        for j in 0..BORDERED {
            let s = (scale[(i, i)] * scale[(j, j)]).sqrt();
            worst = worst.max((a[(i, j)] - b[(i, j)]).abs() / s);
        }
    }
    worst
}

/// The layout states of `block`.
fn states(block: OptionalBlock) -> core::ops::Range<usize> {
    block.index()..block.index() + block.dimension()
}

/// Frozen optional blocks (any subset, beside frozen core blocks or none): the structured
/// update equals the dense 39-state Joseph update with every frozen row's gain zero, for
/// star, GNSS and referred GNSS measurements; a frozen block's estimate keeps its value
/// exactly, and the blocks not frozen move.
#[test]
fn frozen_optional_blocks_keep_their_estimates_and_the_covariance_is_the_dense_joseph_form() {
    let mut rng = ChaCha8Rng::seed_from_u64(71);
    let mut worst = 0.0f64;
    for case in 0..96 {
        let mut prior = filter_with_both_borders(&mut rng);
        // Every subset of the four blocks, six times over.
        let frozen_blocks = OptionalBlock::ALL.map(|block| (case >> block.position()) & 1 == 1);
        for (block, frozen) in OptionalBlock::ALL.iter().zip(frozen_blocks) {
            prior.set_optional_block_frozen(*block, frozen).unwrap();
            assert_eq!(prior.optional_block_frozen(*block), frozen);
        }
        let core_frozen = if case % 3 == 0 {
            random_mask(&mut rng)
        } else {
            BlockMask::NONE
        };
        let star = case % 3 == 1;
        let mut measurement = random_measurement(&mut rng, star, case % 2 == 1);
        if !star {
            measurement.border_coefficient =
                RECEIVER.position_coefficient(rng.random_range(0.0..0.1));
        }
        let mut h = SMatrix::<f64, 3, BORDERED>::zeros();
        h.fixed_view_mut::<3, 24>(0, 0)
            .copy_from(&measurement.jacobian);
        for k in 0..3 {
            h[(k, 24 + k)] = measurement.border_coefficient;
        }
        let p = whole_covariance(&prior);
        let x = whole_state(&prior);
        let s = h * p * h.transpose() + measurement.noise_covariance;
        let mut gain: SMatrix<f64, BORDERED, 3> =
            Cholesky::new(s).unwrap().solve(&(h * p)).transpose();
        for (i, mut row) in gain.row_iter_mut().enumerate() {
            let optional_frozen = OptionalBlock::ALL
                .iter()
                .zip(frozen_blocks)
                .any(|(block, frozen)| frozen && states(*block).contains(&i));
            if (i < 24 && core_frozen.contains_state(i)) || optional_frozen {
                row.fill(0.0);
            }
        }
        let i_kh = Bordered::identity() - gain * h;
        let expected =
            i_kh * p * i_kh.transpose() + gain * measurement.noise_covariance * gain.transpose();
        let expected = (expected + expected.transpose()) * 0.5;
        let expected_x = x + gain * (measurement.residual - h * x);
        let mut updated = prior;
        updated
            .update_structured(&measurement, f64::INFINITY, &core_frozen)
            .unwrap();
        let error = relative(&whole_covariance(&updated), &expected, &p);
        assert!(error < 1e-11, "case {case}: P {error:e}");
        let got = whole_state(&updated);
        for i in 0..BORDERED {
            assert!(
                (got[i] - expected_x[i]).abs() < 1e-11 * p[(i, i)].sqrt(),
                "case {case}: x {i}"
            );
        }
        for (block, frozen) in OptionalBlock::ALL.iter().zip(frozen_blocks) {
            let moved = states(*block).any(|i| got[i].to_bits() != x[i].to_bits());
            // A star update does not see the GNSS error states, but moves them through
            // their correlation with the attitude all the same.
            assert_eq!(moved, !frozen, "case {case}: {}", block.name());
        }
        let border = updated.imu_error().covariance();
        assert_eq!(border, border.transpose(), "case {case}: P_εε symmetric");
        worst = worst.max(error);
    }
    println!("frozen optional blocks vs dense 39-state update: worst {worst:.2e}");
}

/// The GNSS border frozen through the dense 27-state reference (`update_with_frozen_blocks`)
/// and the structured update: equal, and `ε̂` keeps its value.
#[test]
fn a_frozen_gnss_border_is_frozen_in_the_dense_reference_too() {
    let mut rng = ChaCha8Rng::seed_from_u64(73);
    for case in 0..24 {
        let mut prior = filter_with_both_borders(&mut rng);
        *prior.imu_error_mut() = crate::imu_error_states::ImuErrorStates::EMPTY;
        prior
            .set_optional_block_frozen(OptionalBlock::GnssError, true)
            .unwrap();
        let mut measurement = random_measurement(&mut rng, case % 2 == 0, false);
        measurement.border_coefficient = 1.0;
        let mut dense = prior;
        dense
            .update_with_frozen_blocks(&measurement, f64::INFINITY, &BlockMask::NONE)
            .unwrap();
        let mut structured = prior;
        structured
            .update_structured(&measurement, f64::INFINITY, &BlockMask::NONE)
            .unwrap();
        let scale = whole_covariance(&prior);
        let error = relative(
            &whole_covariance(&structured),
            &whole_covariance(&dense),
            &scale,
        );
        assert!(error < 1e-11, "case {case}: {error:e}");
        for filter in [&dense, &structured] {
            assert_eq!(
                filter.gnss_error().estimate_m(),
                prior.gnss_error().estimate_m()
            );
            assert_eq!(
                filter.gnss_error().covariance(),
                prior.gnss_error().covariance()
            );
        }
    }
}

/// Bounds that never bind (floor 0, ceiling far above every variance), with `changes`
/// applied.
fn wide_bounds(changes: &[(usize, f64, f64)]) -> OptionalVarianceBounds {
    let mut bounds = OptionalVarianceBounds {
        floor: [0.0; OPTIONAL_DIMENSION],
        ceiling: [1e30; OPTIONAL_DIMENSION],
    };
    for (state, floor, ceiling) in changes {
        bounds.floor[state - 24] = *floor;
        bounds.ceiling[state - 24] = *ceiling;
    }
    bounds
}

/// A variance above its ceiling, in each optional block: it becomes the ceiling and the
/// whole 39-state covariance is `S P S` (`S` = `√(ceiling/variance)` on the crossed states,
/// 1 elsewhere), so every correlation coefficient is kept; within the bounds, nothing
/// changes.
#[test]
fn optional_protection_puts_a_variance_at_its_ceiling_and_keeps_correlations() {
    let mut rng = ChaCha8Rng::seed_from_u64(79);
    for case in 0..16 {
        let mut filter = filter_with_both_borders(&mut rng);
        let p = whole_covariance(&filter);
        let gnss_state = 24 + case % 3;
        let imu_state = 27 + case % 12;
        let crossed = [gnss_state, imu_state];
        let bounds = wide_bounds(&crossed.map(|i| (i, 0.0, 0.25 * p[(i, i)])));
        assert!(filter.protect_optional_variances(&bounds));
        let got = whole_covariance(&filter);
        let s = Bordered::from_fn(|i, j| match (i == j, crossed.contains(&i)) {
            (false, _) => 0.0,
            (true, true) => 0.5,
            (true, false) => 1.0,
        });
        let expected = s * p * s;
        assert!(relative(&got, &expected, &p) < 1e-15, "case {case}");
        for i in crossed {
            assert_eq!(got[(i, i)].to_bits(), (0.25 * p[(i, i)]).to_bits());
        }
        let correlation =
            |m: &Bordered, i: usize, j: usize| m[(i, j)] / (m[(i, i)] * m[(j, j)]).sqrt();
        for j in 0..BORDERED {
            for i in crossed {
                assert!((correlation(&got, i, j) - correlation(&p, i, j)).abs() < 1e-14);
            }
        }
        assert!(got.cholesky().is_some());
        assert!(!filter.protect_optional_variances(&bounds));
        assert_eq!(whole_covariance(&filter), got);
    }
}

/// A variance below its floor, in each optional block: raised to it, nothing else changes
/// (bit for bit); at the floor it is inside the bounds.
#[test]
fn optional_protection_raises_a_variance_to_its_floor() {
    let mut rng = ChaCha8Rng::seed_from_u64(83);
    for case in 0..16 {
        let mut filter = filter_with_both_borders(&mut rng);
        let p = whole_covariance(&filter);
        let raised = [24 + case % 3, 27 + case % 12];
        let bounds = wide_bounds(&raised.map(|i| (i, 4.0 * p[(i, i)], 1e30)));
        assert!(filter.protect_optional_variances(&bounds));
        let got = whole_covariance(&filter);
        for i in 0..BORDERED {
            for j in 0..BORDERED {
                let expected = if i == j && raised.contains(&i) {
                    4.0 * p[(i, i)]
                } else {
                    p[(i, j)]
                };
                assert_eq!(got[(i, j)].to_bits(), expected.to_bits(), "case {case}");
            }
        }
        assert!(!filter.protect_optional_variances(&bounds));
    }
}

/// A block not in use cannot be frozen, and its bounds are not read; the bounds follow the
/// configuration (floor², prior × factor²).
#[test]
fn freezing_needs_the_block_in_use_and_the_bounds_follow_the_configuration() {
    let mut rng = ChaCha8Rng::seed_from_u64(89);
    let mut filter = filter_with(FilterMode::ClosedLoop, &random_covariance(&mut rng));
    for block in OptionalBlock::ALL {
        assert_eq!(
            filter.set_optional_block_frozen(block, true),
            Err(NavError::InvalidConfiguration)
        );
        assert!(!filter.optional_block_frozen(block));
    }
    let p = *filter.covariance();
    let nowhere = OptionalVarianceBounds {
        floor: [1e30; OPTIONAL_DIMENSION],
        ceiling: [0.0; OPTIONAL_DIMENSION],
    };
    assert!(!filter.protect_optional_variances(&nowhere));
    assert_eq!(filter.covariance(), &p);
    let mut config = super::tests::config(FilterMode::ClosedLoop);
    config.gnss_error = RECEIVER;
    config.imu_error = IMU;
    let floors = [1e-3, 1e-9, 2e-9, 1e-12];
    let bounds = OptionalVarianceBounds::new(&floors, 10.0, &config).unwrap();
    let prior = IMU.prior_variances();
    for (block, floor) in OptionalBlock::ALL.iter().zip(floors) {
        for k in OptionalVarianceBounds::states(*block) {
            assert_eq!(bounds.floor[k].to_bits(), (floor * floor).to_bits());
            let prior = if k < 3 { 64.0 } else { prior[k - 3] };
            assert_eq!(bounds.ceiling[k].to_bits(), (prior * 100.0).to_bits());
        }
    }
    assert!(OptionalVarianceBounds::new(&floors, 0.5, &config).is_err());
    assert!(OptionalVarianceBounds::new(&[f64::NAN; 4], 10.0, &config).is_err());
}
