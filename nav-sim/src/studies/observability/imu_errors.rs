//! Observability of the systematic IMU error states (nav-core `imu_error`): the paper's 24
//! states and the 12 new ones in the filter's gyro-defined gauge (gyro non-orthogonality 3,
//! accelerometer misalignment 6, gyro g-sensitivity 3) as a 36-state piece-wise constant
//! system, per motion segment.
//!
//! Beside it, for comparison: the same with the gauge free ([`analyse_ungauged`], both triads
//! with six terms, 39 states) and in the accelerometer-defined gauge
//! ([`analyse_accel_gauged`], accelerometer lower triangular, six gyro terms), both built from
//! the ungauged system, whose columns come from nav-core's sensitivities.
//!
//! Method as nav-core's `observability` (which stays at 24): per segment the scaled rows
//! `W H (Aτ)^k S`, `k = 0..35`, `A = [[A_24, B], [0, 0]]` with `A_24` from
//! `error_model::system_matrix` and `B` from `imu_error::system_columns`; the rows of all
//! segments are rotated into a 36×36 triangular factor (Givens), whose SVD gives the rank,
//! the null-space test per state (σ ≤ 1e-12 σ_max is zero; a state is observable when its
//! unit vector's projection on the null space is ≤ 1e-6) and the degree `σ_k/σ_max`
//! (largest-component assignment, as Table 1). `τ = min(1 s, 1 rad / max|ω|)`.

use nalgebra::{Quaternion, SMatrix, SVector, Vector3, SVD};
use nav_core::attitude::{exp_rotation_vector, product, rotation_matrix};
use nav_core::error_model::{system_matrix, LinearisationPoint};
use nav_core::imu_error::{
    accel_misalignment_sensitivity, system_columns, ImuErrorBlock, AUGMENTED_DIMENSION,
};
use nav_core::observability::{
    constant_motion, full_update_measurement_matrix, PaperMotionState, Scaling,
};
use nav_core::state::{StateBlock, ATTITUDE, STATE_DIMENSION, VELOCITY};
use nav_core::NavError;

/// States of the analysis with the gauge left free: the 24, both triads' six off-diagonal
/// terms and the g-sensitivity (24 + 6 + 6 + 3).
pub const UNGAUGED_DIMENSION: usize = STATE_DIMENSION + 15;

/// Typical magnitude of a misalignment term (rad): 20 µrad, the 1σ.
pub const MISALIGNMENT_MAGNITUDE_RAD: f64 = 2.0e-5;
/// Typical g-sensitivity (rad/s per m/s²): 0.5 °/h/g.
pub const G_SENSITIVITY_MAGNITUDE: f64 = 0.5 * core::f64::consts::PI / 180.0 / 3600.0 / 9.80665;

/// One constant motion: body rate and specific force, at an attitude.
#[derive(Debug, Clone)]
pub struct MotionSegment {
    /// Label for the report.
    pub label: String,
    /// The linearisation point (measured = corrected, zero gravity gradient).
    pub point: LinearisationPoint,
    /// `q̂_ib` (for the star-sensor rows).
    pub attitude: Quaternion<f64>,
}

impl MotionSegment {
    /// A segment of rate `rate_deg_s` (°/s) and specific force `force_mps2` at `attitude`.
    pub fn new(
        label: &str,
        rate_deg_s: [f64; 3],
        force_mps2: [f64; 3],
        attitude: Quaternion<f64>,
    ) -> Self {
        let rate = Vector3::from(rate_deg_s).map(f64::to_radians);
        Self {
            label: label.to_string(),
            point: constant_motion(
                &rate,
                &Vector3::from(force_mps2),
                &rotation_matrix(&attitude),
            ),
            attitude,
        }
    }

    /// The same motion after it has run for `duration_s` (the attitude advanced).
    pub fn after(&self, duration_s: f64) -> Quaternion<f64> {
        product(
            &self.attitude,
            &exp_rotation_vector(&(self.point.corrected_rate_rad_s * duration_s)),
        )
    }
}

/// The result for one case (a sequence of segments), over `N` states.
#[derive(Debug, Clone)]
pub struct AugmentedObservability<const N: usize> {
    /// Numerical rank.
    pub rank: usize,
    /// Per state: passes the null-space test.
    pub observable: [bool; N],
    /// Per state: `σ_k/σ_max` (largest-component assignment; 0 if none).
    pub degree: [f64; N],
}

/// Names of the 36 states: the 24's `block.axis`, then `block.component`.
pub fn state_name(k: usize) -> String {
    if let Some(block) = StateBlock::ALL.get(k / 3).filter(|_| k < STATE_DIMENSION) {
        let axis = ["x", "y", "z"].get(k % 3).copied().unwrap_or("?");
        return format!("{}.{axis}", block.name());
    }
    ImuErrorBlock::ALL
        .iter()
        .find(|b| (b.index()..b.index() + b.dimension()).contains(&k))
        .map_or_else(
            || "?".to_string(),
            |b| format!("{}.{}", b.name(), b.component_name(k - b.index())),
        )
}

/// The 36×36 system matrix `[[A_24, B], [0, 0]]`.
fn augmented_system(
    point: &LinearisationPoint,
) -> SMatrix<f64, AUGMENTED_DIMENSION, AUGMENTED_DIMENSION> {
    let mut a = SMatrix::<f64, AUGMENTED_DIMENSION, AUGMENTED_DIMENSION>::zeros();
    a.fixed_view_mut::<STATE_DIMENSION, STATE_DIMENSION>(0, 0)
        .copy_from(&system_matrix(point));
    a.fixed_view_mut::<STATE_DIMENSION, 12>(0, STATE_DIMENSION)
        .copy_from(&system_columns(point));
    a
}

/// The 39×39 system matrix with the gauge free: the 24, the gyro's six off-diagonal terms
/// (`ϑ` rows `−½ Ω(ω_m)`), the accelerometer's six (`δv` rows `−Ĉ Ω(f_m)`), then the
/// g-sensitivity; `Ω` is nav-core's six-term sensitivity, the same for either triad.
fn ungauged_system(
    point: &LinearisationPoint,
) -> SMatrix<f64, UNGAUGED_DIMENSION, UNGAUGED_DIMENSION> {
    let mut a = SMatrix::<f64, UNGAUGED_DIMENSION, UNGAUGED_DIMENSION>::zeros();
    let columns = system_columns(point);
    a.fixed_view_mut::<STATE_DIMENSION, STATE_DIMENSION>(0, 0)
        .copy_from(&system_matrix(point));
    a.fixed_view_mut::<3, 6>(ATTITUDE.index(), UNGAUGED_GYRO)
        .copy_from(&(accel_misalignment_sensitivity(&point.measured_rate_rad_s) * -0.5));
    a.fixed_view_mut::<3, 6>(VELOCITY.index(), UNGAUGED_ACCEL)
        .copy_from(
            &(-point.body_to_inertial
                * accel_misalignment_sensitivity(&point.measured_specific_force_mps2)),
        );
    a.fixed_view_mut::<STATE_DIMENSION, 3>(0, UNGAUGED_G_SENSITIVITY)
        .copy_from(&columns.fixed_columns::<3>(ImuErrorBlock::GyroGSensitivity.offset()));
    a
}

/// First ungauged state of the gyro's six terms.
const UNGAUGED_GYRO: usize = STATE_DIMENSION;
/// First ungauged state of the accelerometer's six terms.
const UNGAUGED_ACCEL: usize = STATE_DIMENSION + 6;
/// First ungauged state of the g-sensitivity.
const UNGAUGED_G_SENSITIVITY: usize = STATE_DIMENSION + 12;
/// Positions of the lower-triangular terms (yx, zx, zy) among the six (xy, xz, yx, yz, zx, zy).
const LOWER_OF_SIX: [usize; 3] = [2, 4, 5];

/// Ungauged states kept by a gauge, in order: the 24, the defining triad's lower-triangular
/// terms (yx, zx, zy, from the six at `lower_from`), the other triad's six (at `full_from`),
/// the g-sensitivity.
const fn gauge_kept(lower_from: usize, full_from: usize) -> [usize; AUGMENTED_DIMENSION] {
    let mut kept = [0; AUGMENTED_DIMENSION];
    let mut k = 0;
    while k < STATE_DIMENSION {
        kept[k] = k;
        k += 1;
    }
    let mut j = 0;
    while j < 3 {
        kept[STATE_DIMENSION + j] = lower_from + LOWER_OF_SIX[j];
        j += 1;
    }
    while j < 9 {
        kept[STATE_DIMENSION + j] = full_from + j - 3;
        j += 1;
    }
    while j < 12 {
        kept[STATE_DIMENSION + j] = UNGAUGED_G_SENSITIVITY + j - 9;
        j += 1;
    }
    kept
}

/// Ungauged states of the gyro-defined gauge (nav-core's layout, [`state_name`]).
#[cfg(test)]
const GYRO_GAUGE_KEPT: [usize; AUGMENTED_DIMENSION] = gauge_kept(UNGAUGED_GYRO, UNGAUGED_ACCEL);
/// Ungauged states of the accelerometer-defined gauge ([`accel_gauge_state_name`]).
const ACCEL_GAUGE_KEPT: [usize; AUGMENTED_DIMENSION] = gauge_kept(UNGAUGED_ACCEL, UNGAUGED_GYRO);

/// The rows and columns `kept` of the ungauged system.
fn gauged_system(
    point: &LinearisationPoint,
    kept: &[usize; AUGMENTED_DIMENSION],
) -> SMatrix<f64, AUGMENTED_DIMENSION, AUGMENTED_DIMENSION> {
    let ungauged = ungauged_system(point);
    SMatrix::from_fn(|row, column| match (kept.get(row), kept.get(column)) {
        (Some(r), Some(c)) => ungauged[(*r, *c)],
        _ => 0.0,
    })
}

/// The 36×36 system matrix of the accelerometer-defined gauge: the accelerometer triad
/// lower-triangular (its x axis and xy plane define the body frame), the gyro with all six
/// terms, then the g-sensitivity (the rows and columns [`ACCEL_GAUGE_KEPT`] of the ungauged
/// system).
fn accel_gauged_system(
    point: &LinearisationPoint,
) -> SMatrix<f64, AUGMENTED_DIMENSION, AUGMENTED_DIMENSION> {
    gauged_system(point, &ACCEL_GAUGE_KEPT)
}

/// Names of the accelerometer-defined gauge's 36 states: the 24, the accelerometer's
/// lower-triangular terms (yx, zx, zy), the six gyro terms, the g-sensitivity.
pub fn accel_gauge_state_name(k: usize) -> String {
    const TERMS: [&str; 6] = ["xy", "xz", "yx", "yz", "zx", "zy"];
    let new = k.saturating_sub(STATE_DIMENSION);
    match (k < STATE_DIMENSION, new) {
        (true, _) => state_name(k),
        (false, 0..3) => format!("accel_non_orthogonality.{}", ["yx", "zx", "zy"][new]),
        (false, 3..9) => format!("gyro_misalignment.{}", TERMS[new - 3]),
        (false, 9..12) => format!("gyro_g_sensitivity.{}", ["x", "y", "z"][new - 9]),
        _ => "?".to_string(),
    }
}

/// Typical magnitudes of the `N` states (nav-core's 24, then misalignments, g-sensitivity).
fn state_magnitudes<const N: usize>() -> SVector<f64, N> {
    let typical = Scaling::typical().state_magnitudes;
    SVector::from_fn(|k, _| match typical.get(k) {
        Some(value) => *value,
        None if k + 3 >= N => G_SENSITIVITY_MAGNITUDE,
        None => MISALIGNMENT_MAGNITUDE_RAD,
    })
}

/// Rotates `row` into the lower-triangular `factor` (`Rᵀ`, column `j` = row `j` of `R`).
fn givens_add_row<const N: usize>(factor: &mut SMatrix<f64, N, N>, row: &SVector<f64, N>) {
    let mut x = *row;
    for (j, mut column) in factor.column_iter_mut().enumerate() {
        let (a, b) = (column[j], x[j]);
        if b == 0.0 {
            continue;
        }
        let rho = a.hypot(b);
        let (c, s) = (a / rho, b / rho);
        for (r_k, x_k) in column.iter_mut().zip(x.iter_mut()).skip(j) {
            let (r_old, x_old) = (*r_k, *x_k);
            *r_k = c * r_old + s * x_old;
            *x_k = c * x_old - s * r_old;
        }
    }
}

/// The triangular factor `R` (`RᵀR = QᵀQ`) of the segments' scaled stripped observability
/// matrix, `system` giving each segment's `N×N` matrix.
fn stripped_factor<const N: usize>(
    segments: &[MotionSegment],
    mounting: &Quaternion<f64>,
    system: impl Fn(&LinearisationPoint) -> SMatrix<f64, N, N>,
) -> Result<SMatrix<f64, N, N>, NavError> {
    let fastest = segments
        .iter()
        .map(|s| s.point.corrected_rate_rad_s.norm())
        .fold(0.0_f64, f64::max);
    let tau = if fastest > 1.0 { 1.0 / fastest } else { 1.0 };
    let magnitudes = state_magnitudes::<N>();
    let rows = [Scaling::STAR_ROW_MAGNITUDE, Scaling::GNSS_ROW_MAGNITUDE];
    let mut factor = SMatrix::<f64, N, N>::zeros();
    for segment in segments {
        let h24 = full_update_measurement_matrix(&segment.attitude, mounting)?;
        let mut h = SMatrix::<f64, 6, N>::zeros();
        h.fixed_view_mut::<6, STATE_DIMENSION>(0, 0).copy_from(&h24);
        for (i, mut row) in h.row_iter_mut().enumerate() {
            row /= rows[i / 3];
        }
        let mut step = system(&segment.point) * tau;
        for (i, mut row) in step.row_iter_mut().enumerate() {
            row /= magnitudes[i];
        }
        let mut block = h;
        for (mut column, magnitude) in block.column_iter_mut().zip(magnitudes.iter()) {
            column *= *magnitude;
        }
        for (mut column, magnitude) in step.column_iter_mut().zip(magnitudes.iter()) {
            column *= *magnitude;
        }
        for _ in 0..N {
            for row in block.row_iter() {
                givens_add_row(&mut factor, &row.transpose());
            }
            block *= step;
        }
    }
    Ok(factor.transpose())
}

/// Rank, null-space test and degree from the SVD of the factor.
fn verdicts<const N: usize>(
    sigma: &SVector<f64, N>,
    v_t: &SMatrix<f64, N, N>,
) -> AugmentedObservability<N> {
    let sigma_max = sigma.max();
    let zero = 1e-12 * sigma_max;
    let mut null_square = [0.0; N];
    let mut degree = [0.0; N];
    let mut assigned = [false; N];
    for (value, vector) in sigma.iter().zip(v_t.row_iter()) {
        let best = vector.transpose().iamax();
        if !assigned[best] {
            assigned[best] = true;
            degree[best] = value / sigma_max;
        }
        if *value <= zero {
            for (square, component) in null_square.iter_mut().zip(vector.iter()) {
                *square += component * component;
            }
        }
    }
    AugmentedObservability {
        rank: sigma.iter().filter(|s| **s > zero).count(),
        observable: null_square.map(|s: f64| s.sqrt() <= 1e-6),
        degree,
    }
}

/// The 36-state analysis of `segments` in the filter's gyro-defined gauge (module docs; names
/// by [`state_name`]).
///
/// # Errors
/// nav-core's error for non-finite input or an SVD failure.
pub fn analyse(
    segments: &[MotionSegment],
    mounting: &Quaternion<f64>,
) -> Result<AugmentedObservability<AUGMENTED_DIMENSION>, NavError> {
    let factor = stripped_factor(segments, mounting, augmented_system)?;
    let svd = SVD::try_new(factor, false, true, 1e-15, 10_000).ok_or(NavError::SingularMatrix)?;
    let v_t = svd.v_t.ok_or(NavError::SingularMatrix)?;
    Ok(verdicts(&svd.singular_values, &v_t))
}

/// The same with the gauge free (both triads with six terms, 39 states): its rank stays three
/// short of the states' count for every motion (the common rotation of the triads).
///
/// # Errors
/// As [`analyse`].
pub fn analyse_ungauged(
    segments: &[MotionSegment],
    mounting: &Quaternion<f64>,
) -> Result<AugmentedObservability<UNGAUGED_DIMENSION>, NavError> {
    let factor = stripped_factor(segments, mounting, ungauged_system)?;
    let svd = SVD::try_new(factor, false, true, 1e-15, 10_000).ok_or(NavError::SingularMatrix)?;
    let v_t = svd.v_t.ok_or(NavError::SingularMatrix)?;
    Ok(verdicts(&svd.singular_values, &v_t))
}

/// The 36-state analysis of `segments` in the accelerometer-defined gauge (accelerometer
/// lower triangular, all six gyro terms; names by [`accel_gauge_state_name`]), for comparison
/// with the filter's gyro-defined one ([`analyse`]).
///
/// # Errors
/// As [`analyse`].
pub fn analyse_accel_gauged(
    segments: &[MotionSegment],
    mounting: &Quaternion<f64>,
) -> Result<AugmentedObservability<AUGMENTED_DIMENSION>, NavError> {
    let factor = stripped_factor(segments, mounting, accel_gauged_system)?;
    let svd = SVD::try_new(factor, false, true, 1e-15, 10_000).ok_or(NavError::SingularMatrix)?;
    let v_t = svd.v_t.ok_or(NavError::SingularMatrix)?;
    Ok(verdicts(&svd.singular_values, &v_t))
}

/// The cases of the study: the paper's motion states I, II, III after a coast, and an upper
/// stage's manoeuvres flown in sequence (coast, thrust along x, slews about x, y, z at 3 °/s,
/// a 1 °/s pitch during thrust), each case the sequence up to it (PWCS).
pub fn study_cases(initial_attitude: &Quaternion<f64>) -> Vec<(String, Vec<MotionSegment>)> {
    let c0 = rotation_matrix(initial_attitude);
    let paper = |state: PaperMotionState| MotionSegment {
        label: state.label().to_string(),
        point: state.linearisation_point(&c0),
        attitude: *initial_attitude,
    };
    let [coast, rotation, acceleration] = PaperMotionState::ALL.map(paper);
    let mut cases = vec![
        ("I".to_string(), vec![coast.clone()]),
        ("II".to_string(), vec![rotation.clone()]),
        ("III".to_string(), vec![acceleration.clone()]),
        ("I→II".to_string(), vec![coast.clone(), rotation]),
        ("I→III".to_string(), vec![coast, acceleration]),
    ];
    let plan: [(&str, [f64; 3], [f64; 3], f64); 6] = [
        ("coast", [0.0; 3], [0.0; 3], 60.0),
        ("thrust +x", [0.0; 3], [20.0, 0.0, 0.0], 60.0),
        ("slew x", [3.0, 0.0, 0.0], [0.0; 3], 30.0),
        ("slew y", [0.0, 3.0, 0.0], [0.0; 3], 30.0),
        ("slew z", [0.0, 0.0, 3.0], [0.0; 3], 30.0),
        (
            "pitch during thrust",
            [0.0, 1.0, 0.0],
            [20.0, 0.0, 0.0],
            60.0,
        ),
    ];
    let mut attitude = *initial_attitude;
    let mut sequence: Vec<MotionSegment> = Vec::new();
    for (label, rate, force, duration) in plan {
        let segment = MotionSegment::new(label, rate, force, attitude);
        attitude = segment.after(duration);
        cases.push((format!("{label} alone (after coast)"), {
            let coast = MotionSegment::new("coast", [0.0; 3], [0.0; 3], segment.attitude);
            vec![coast, segment.clone()]
        }));
        sequence.push(segment);
        cases.push((format!("upper stage to {label}"), sequence.clone()));
    }
    cases
}

/// The report as text: per case the rank and, for the 12 new states, observable (degree) or
/// "-".
///
/// # Errors
/// As [`analyse`].
pub fn render_text(
    initial_attitude: &Quaternion<f64>,
    mounting: &Quaternion<f64>,
) -> Result<String, NavError> {
    let mut text = String::from(
        "case; rank of 36; new states: observable with degree σ_k/σ_max, - not observable\n",
    );
    for (label, segments) in study_cases(initial_attitude) {
        let result = analyse(&segments, mounting)?;
        text.push_str(&format!("{label}: rank {}\n", result.rank));
        for k in STATE_DIMENSION..AUGMENTED_DIMENSION {
            let verdict = if result.observable[k] {
                format!("{:.1e}", result.degree[k])
            } else {
                "-".to_string()
            };
            text.push_str(&format!("  {:30} {verdict}\n", state_name(k)));
        }
    }
    Ok(text)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn attitude() -> Quaternion<f64> {
        exp_rotation_vector(&Vector3::new(0.3, -0.7, 1.1))
    }

    fn mounting() -> Quaternion<f64> {
        exp_rotation_vector(&Vector3::new(0.2, 1.3, -0.4))
    }

    fn observable_new(result: &AugmentedObservability<AUGMENTED_DIMENSION>) -> Vec<String> {
        (STATE_DIMENSION..AUGMENTED_DIMENSION)
            .filter(|k| result.observable[*k])
            .map(state_name)
            .collect()
    }

    #[test]
    fn print_the_study() {
        println!("{}", render_text(&attitude(), &mounting()).unwrap());
    }

    /// nav-core's columns (the filter's gyro-defined gauge) are the ungauged system's rows and
    /// columns of the gyro's lower-triangular terms, the accelerometer's six and the
    /// g-sensitivity: the two gauges compared below come from one system.
    #[test]
    fn the_gyro_defined_gauge_is_the_ungauged_system_restricted() {
        for (rate, force) in [
            ([3.0, -1.0, 2.0], [20.0, 4.0, -7.0]),
            ([0.0, 1.0, 0.0], [20.0, 0.0, 0.0]),
        ] {
            let segment = MotionSegment::new("test", rate, force, attitude());
            let gauged = augmented_system(&segment.point);
            let restricted = gauged_system(&segment.point, &GYRO_GAUGE_KEPT);
            assert!(gauged.amax() > 1.0);
            assert_eq!(gauged, restricted);
        }
        let names: Vec<String> = (STATE_DIMENSION..AUGMENTED_DIMENSION)
            .map(accel_gauge_state_name)
            .collect();
        assert_eq!(
            names.first().map(String::as_str),
            Some("accel_non_orthogonality.yx")
        );
        assert_eq!(
            names.get(3).map(String::as_str),
            Some("gyro_misalignment.xy")
        );
        assert_eq!(
            names.last().map(String::as_str),
            Some("gyro_g_sensitivity.z")
        );
        assert_eq!(accel_gauge_state_name(AUGMENTED_DIMENSION), "?");
    }

    fn hidden(
        result: &AugmentedObservability<AUGMENTED_DIMENSION>,
        name: fn(usize) -> String,
    ) -> Vec<String> {
        (0..AUGMENTED_DIMENSION)
            .filter(|k| !result.observable[*k])
            .map(name)
            .collect()
    }

    #[test]
    fn the_common_rotation_of_both_triads_is_never_observable_and_the_gyro_gauge_hides_only_the_z_force_terms(
    ) {
        let all: Vec<MotionSegment> = study_cases(&attitude())
            .into_iter()
            .flat_map(|(_, segments)| segments)
            .collect();
        let ungauged = analyse_ungauged(&all, &mounting()).unwrap();
        let gyro = analyse(&all, &mounting()).unwrap();
        let accel = analyse_accel_gauged(&all, &mounting()).unwrap();
        println!(
            "ungauged rank {} of {UNGAUGED_DIMENSION}, gyro-defined gauge {} and \
             accelerometer-defined gauge {} of {AUGMENTED_DIMENSION}",
            ungauged.rank, gyro.rank, accel.rank
        );
        let (hidden_gyro, hidden_accel) = (
            hidden(&gyro, state_name),
            hidden(&accel, accel_gauge_state_name),
        );
        println!("not observable over every case, gyro-defined gauge: {hidden_gyro:?}");
        println!("accelerometer-defined gauge: {hidden_accel:?}");
        // Fixing the gauge removes exactly the three directions of the common rotation, in
        // either gauge.
        assert_eq!(
            ungauged.rank + 3,
            gyro.rank + (UNGAUGED_DIMENSION - AUGMENTED_DIMENSION)
        );
        assert_eq!(accel.rank, gyro.rank);
        // No case has a specific force along z. In the gyro-defined gauge the frame is pinned
        // by the gyro, which the slews about x, y and z excite: attitude, installation and
        // every gyro term are observable, and the four null directions are the four states
        // that multiply f_z, each alone (it never acts on the navigation of these motions).
        assert_eq!(gyro.rank, AUGMENTED_DIMENSION - 4);
        assert_eq!(
            hidden_gyro,
            [
                "accel_scale_factor.z",
                "accel_misalignment.xz",
                "accel_misalignment.yz",
                "gyro_g_sensitivity.z",
            ]
        );
        // In the accelerometer-defined gauge the same four directions hold the frame's
        // rotations about x and y (not pinned: they move only accelerometer terms that
        // multiply f_z), mixed into attitude, installation and gyro misalignment.
        for state in [
            "accel_scale_factor.z",
            "gyro_g_sensitivity.z",
            "attitude.x",
            "star_installation.z",
            "gyro_misalignment.zx",
        ] {
            assert!(hidden_accel.contains(&state.to_string()), "{state}");
        }
        for state in [
            "gyro_misalignment.xy",
            "gyro_misalignment.yx",
            "accel_non_orthogonality.yx",
            "gyro_g_sensitivity.x",
            "gyro_g_sensitivity.y",
        ] {
            assert!(!hidden_accel.contains(&state.to_string()), "{state}");
        }
    }

    /// The gauge for a vehicle whose specific force is along body x only (the upper-stage
    /// sequence: coast, +x thrust, slews about x, y, z, a pitch during thrust). In the
    /// accelerometer-defined gauge the frame itself is not pinned (attitude, installation
    /// and every gyro term are hidden); in the gyro-defined one, the filter's, the slews pin
    /// it, and the eight hidden states are exactly those that multiply the absent y and z
    /// force (which then do not act on the navigation).
    #[test]
    fn for_thrust_along_x_only_the_gyro_defined_gauge_hides_only_what_multiplies_no_force() {
        let cases = study_cases(&attitude());
        let (_, upper_stage) = cases
            .iter()
            .find(|(label, _)| label == "upper stage to pitch during thrust")
            .unwrap();
        let gyro = analyse(upper_stage, &mounting()).unwrap();
        let accelerometer = analyse_accel_gauged(upper_stage, &mounting()).unwrap();
        let (hidden_gyro, hidden_accelerometer) = (
            hidden(&gyro, state_name),
            hidden(&accelerometer, accel_gauge_state_name),
        );
        println!("gyro gauge rank {}: hidden {hidden_gyro:?}", gyro.rank);
        println!(
            "accelerometer gauge rank {}: hidden {hidden_accelerometer:?}",
            accelerometer.rank
        );
        for state in ["attitude.x", "star_installation.y", "gyro_misalignment.yx"] {
            assert!(hidden_accelerometer.contains(&state.to_string()), "{state}");
        }
        let multiplies_no_force = |name: &String| {
            [
                "accel_scale_factor.y",
                "accel_scale_factor.z",
                "accel_misalignment.xy",
                "accel_misalignment.xz",
                "accel_misalignment.yz",
                "accel_misalignment.zy",
                "gyro_g_sensitivity.y",
                "gyro_g_sensitivity.z",
            ]
            .contains(&name.as_str())
        };
        // The same eight null directions either way (a gauge is a reparametrisation); only
        // what they hold differs.
        assert_eq!(gyro.rank, accelerometer.rank);
        assert_eq!(gyro.rank, AUGMENTED_DIMENSION - 8);
        assert_eq!(hidden_gyro.len(), 8, "{hidden_gyro:?}");
        assert!(
            hidden_gyro.iter().all(multiplies_no_force),
            "{hidden_gyro:?}"
        );
    }

    #[test]
    fn coast_shows_none_of_the_new_states_and_thrust_alone_not_the_gyro() {
        let cases = study_cases(&attitude());
        let case = |label: &str| {
            let (_, segments) = cases.iter().find(|(l, _)| l == label).unwrap();
            analyse(segments, &mounting()).unwrap()
        };
        assert!(observable_new(&case("I")).is_empty());
        let thrust = observable_new(&case("thrust +x alone (after coast)"));
        assert!(!thrust.is_empty());
        assert!(
            thrust
                .iter()
                .all(|s| !s.starts_with("gyro_non_orthogonality")),
            "{thrust:?}"
        );
    }
}
