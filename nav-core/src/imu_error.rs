//! Systematic IMU error states beyond the paper's model, as optional state blocks beside the
//! 24: gyro non-orthogonality (3), accelerometer misalignment (6), gyro g-sensitivity (3).
//! This module holds their layout, their continuous error-model columns, the correction the
//! strapdown would apply, their action as equivalent sensor biases, and the map from a truth
//! description into the filter's gauge.
//!
//! ## The filter's sensor model (what the states mean)
//! With the raw measured rate `ω_m` and specific force `f_m` (body axes), the true body rate
//! and specific force are, in the filter's model,
//! `ω = ω_m − diag(ω_m) λg − L_g ω_m − diag(g) f_m − bg − ηg` and
//! `f = f_m − diag(f_m) λa − A_a f_m − ba − ηa`, with
//! * `L_g` the gyro non-orthogonality, strictly lower triangular, three terms in the order
//!   [`GYRO_NON_ORTHOGONALITY_TERMS`] `(a_yx, a_zx, a_zy)`; `a_ij > 0`: axis `i` reads
//!   `+a_ij` of the rate about body axis `j` (the simulator's sign, `docs/guide/model.md`);
//! * `A_a` the accelerometer misalignment, zero diagonal, six terms
//!   [`ACCEL_MISALIGNMENT_TERMS`] `(a_xy, a_xz, a_yx, a_yz, a_zx, a_zy)`, same sign;
//! * `g` the gyro g-sensitivity per axis (rad/s per m/s²).
//!
//! Every term multiplies a raw measurement, as the paper's scale factor does (`Λ ω_m`), so
//! the correction ([`correct_rates`]) is exact in the model and the truth's `(I + A)` acting
//! on the true increment maps into it without approximation ([`to_filter_gauge`]).
//!
//! ## Gauge freedom
//! A rotation `R` common to both triads is indistinguishable from a rotation of the body
//! frame: attitude `q_ib' = q_ib ⊗ q_bb'` and star installation `q_ψ' = q_bs* ⊗ q_b'b ⊗
//! q_bs ⊗ q_ψ` give the same star measurement, and `R ω`, `R f` are the same inertial
//! motion. With both triads' six off-diagonal terms the model has a three-dimensional null
//! space for every motion (`nav-sim`'s `studies::observability::imu_errors` tests it). The
//! body frame is fixed by the **gyro triad**: `x` along the gyro `x` sensing axis, `y` in the
//! plane of its `x` and `y` sensing axes, so `L_g` is lower triangular; the accelerometer
//! keeps all six terms relative to that frame, and the star-sensor installation error and the
//! attitude absorb the rotation. Why the gyro: the frame is pinned only where the triad that
//! defines it is excited. The gyro is excited by the slews, which turn about every axis; the
//! accelerometer only by specific force, which an upper stage has along `x` alone. In the
//! 36-state analysis of an upper stage thrusting along `x` only (slews about `x`, `y`, `z`)
//! the gyro-defined gauge leaves hidden only the terms that multiply the absent `y` and `z`
//! force (`λa,y`, `λa,z`, `g_y`, `g_z`, `a_xy`, `a_xz`, `a_yz`, `a_zy`), which then do not act
//! on the navigation; the accelerometer-defined gauge (accelerometer lower triangular, six
//! gyro terms) would leave the frame's rotations free, hiding attitude, installation and
//! every misalignment term (`docs/guide/observability.md`, "The gauge for the flight").
//!
//! ## Error-model columns ([`system_columns`])
//! With `δ = truth − estimate` and the correction of [`correct_rates`],
//! `δω = −(diag(ω_m) δλg + δbg + Ψ(ω_m) δa_g + diag(f_m) δg + ηg)` and
//! `δf = −(diag(f_m) δλa + δba + Ω(f_m) δa_a + ηa)`, where `L_g ω = Ψ(ω) a_g`,
//! `Ψ(ω) = [[0, 0, 0], [ω_x, 0, 0], [0, ω_x, ω_y]]` and `A_a f = Ω(f) a_a`,
//! `Ω(f) = [[f_y, f_z, 0, 0, 0, 0], [0, 0, f_x, f_z, 0, 0], [0, 0, 0, 0, f_x, f_y]]`. Through
//! `ϑ̇ = −[ω̂×]ϑ + ½ δω` and `δv̇ = … + Ĉ δf` ([`crate::error_model`]):
//! `B_{ϑ,a_g} = −½ Ψ(ω_m)`, `B_{δv,a_a} = −Ĉ Ω(f_m)`, `B_{ϑ,g} = −½ diag(f_m)`; the three
//! blocks are random constants (zero rows).
//!
//! ## Equivalent biases ([`equivalent_bias_terms`])
//! Each state enters `δω` or `δf` on one axis, multiplied by one component of the measured
//! rate or force: it acts on the navigation exactly as a bias on that axis of size
//! `m_k ε_k`, and its column of `A` is that bias's column times `m_k`.

use nalgebra::{Matrix3, Quaternion, SMatrix, SVector, Vector3};

use crate::attitude::{conjugate, product};
use crate::error_model::LinearisationPoint;
use crate::state::{OptionalBlock, ATTITUDE, STATE_DIMENSION, VELOCITY};
use crate::strapdown::{ImuIncrement, SensorCorrections};
use crate::NavError;

/// A block of the systematic IMU error states, after the paper's 24 (a closed set).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum ImuErrorBlock {
    /// Gyro non-orthogonality `a_g` (rad), three terms in [`GYRO_NON_ORTHOGONALITY_TERMS`].
    GyroNonOrthogonality,
    /// Accelerometer misalignment `a_a` (rad), six off-diagonal terms in
    /// [`ACCEL_MISALIGNMENT_TERMS`].
    AccelMisalignment,
    /// Gyro g-sensitivity `g` (rad/s per m/s²), per axis x, y, z.
    GyroGSensitivity,
}

impl ImuErrorBlock {
    /// All blocks in their order after the 24 states.
    pub const ALL: [ImuErrorBlock; 3] = [
        Self::GyroNonOrthogonality,
        Self::AccelMisalignment,
        Self::GyroGSensitivity,
    ];

    /// The block in the state layout ([`crate::state`]).
    pub const fn layout(self) -> OptionalBlock {
        match self {
            Self::GyroNonOrthogonality => OptionalBlock::GyroNonOrthogonality,
            Self::AccelMisalignment => OptionalBlock::AccelMisalignment,
            Self::GyroGSensitivity => OptionalBlock::GyroGSensitivity,
        }
    }

    /// Index of the block's first state in the 12 systematic-error states.
    pub const fn offset(self) -> usize {
        self.layout().index() - OptionalBlock::GyroNonOrthogonality.index()
    }

    /// Index of the block's first state in the augmented vector (after the 24).
    ///
    /// # Examples
    /// ```
    /// use nav_core::imu_error::ImuErrorBlock;
    /// assert_eq!(ImuErrorBlock::GyroNonOrthogonality.index(), 24);
    /// assert_eq!(ImuErrorBlock::AccelMisalignment.index(), 27);
    /// assert_eq!(ImuErrorBlock::GyroGSensitivity.index(), 33);
    /// ```
    pub const fn index(self) -> usize {
        STATE_DIMENSION + self.offset()
    }

    /// Number of states in the block (3, 6, 3).
    pub const fn dimension(self) -> usize {
        self.layout().dimension()
    }

    /// Short name (tables, telemetry).
    pub const fn name(self) -> &'static str {
        self.layout().name()
    }

    /// Name of the block's `k`-th component (`yx`, `xy`, `x`, …); `"?"` past the block.
    pub fn component_name(self, k: usize) -> &'static str {
        const PAIRS: [&str; 6] = ["xy", "xz", "yx", "yz", "zx", "zy"];
        const LOWER: [&str; 3] = ["yx", "zx", "zy"];
        const AXES: [&str; 3] = ["x", "y", "z"];
        let names: &[&str] = match self {
            Self::GyroNonOrthogonality => &LOWER,
            Self::AccelMisalignment => &PAIRS,
            Self::GyroGSensitivity => &AXES,
        };
        names.get(k).copied().unwrap_or("?")
    }
}

/// Number of systematic IMU error states (3 + 6 + 3): the layout's blocks summed.
pub const IMU_ERROR_DIMENSION: usize = ImuErrorBlock::GyroNonOrthogonality.dimension()
    + ImuErrorBlock::AccelMisalignment.dimension()
    + ImuErrorBlock::GyroGSensitivity.dimension();
/// The paper's 24 states and the 12 systematic IMU error states.
pub const AUGMENTED_DIMENSION: usize = STATE_DIMENSION + IMU_ERROR_DIMENSION;
const _: () = assert!(
    ImuErrorBlock::GyroNonOrthogonality.dimension()
        + ImuErrorBlock::AccelMisalignment.dimension()
        + ImuErrorBlock::GyroGSensitivity.dimension()
        == IMU_ERROR_DIMENSION
);
const _: () = assert!(ImuErrorBlock::GyroNonOrthogonality.offset() == 0);
const _: () = assert!(
    ImuErrorBlock::AccelMisalignment.offset()
        == ImuErrorBlock::GyroNonOrthogonality.offset()
            + ImuErrorBlock::GyroNonOrthogonality.dimension()
);
const _: () = assert!(
    ImuErrorBlock::GyroGSensitivity.offset()
        == ImuErrorBlock::AccelMisalignment.offset() + ImuErrorBlock::AccelMisalignment.dimension()
);
const _: () = assert!(
    ImuErrorBlock::GyroGSensitivity.offset() + ImuErrorBlock::GyroGSensitivity.dimension()
        == IMU_ERROR_DIMENSION
);

/// `(row, column)` of the gyro non-orthogonality terms, in state order.
pub const GYRO_NON_ORTHOGONALITY_TERMS: [(usize, usize); 3] = [(1, 0), (2, 0), (2, 1)];
/// `(row, column)` of the accelerometer misalignment terms, in state order.
pub const ACCEL_MISALIGNMENT_TERMS: [(usize, usize); 6] =
    [(0, 1), (0, 2), (1, 0), (1, 2), (2, 0), (2, 1)];

/// The 24×12 columns of the system matrix for the systematic IMU error states.
pub type ImuErrorColumns = SMatrix<f64, STATE_DIMENSION, IMU_ERROR_DIMENSION>;

/// Estimated (or true, in the filter's gauge) systematic IMU errors (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ImuErrorEstimate {
    /// Gyro non-orthogonality `a_g` (rad), order [`GYRO_NON_ORTHOGONALITY_TERMS`].
    pub gyro_non_orthogonality_rad: Vector3<f64>,
    /// Accelerometer misalignment `a_a` (rad), order [`ACCEL_MISALIGNMENT_TERMS`].
    pub accel_misalignment_rad: SVector<f64, 6>,
    /// Gyro g-sensitivity `g` (rad/s per m/s²).
    pub gyro_g_sensitivity_rad_s_per_mps2: Vector3<f64>,
}

/// Writes `values[k]` at `terms[k]` of a zero 3×3 matrix.
fn from_terms(terms: &[(usize, usize)], values: &[f64]) -> Matrix3<f64> {
    let mut matrix = Matrix3::zeros();
    for ((row, column), value) in terms.iter().zip(values.iter()) {
        if let Some(entry) = matrix.get_mut((*row, *column)) {
            *entry = *value;
        }
    }
    matrix
}

impl ImuErrorEstimate {
    /// The gyro non-orthogonality matrix `L_g` (strictly lower triangular).
    ///
    /// # Examples
    /// ```
    /// use nav_core::imu_error::ImuErrorEstimate;
    /// let mut e = ImuErrorEstimate::default();
    /// e.gyro_non_orthogonality_rad[2] = 2e-5; // a_zy
    /// assert_eq!(e.gyro_matrix()[(2, 1)].to_bits(), 2e-5f64.to_bits());
    /// ```
    pub fn gyro_matrix(&self) -> Matrix3<f64> {
        from_terms(
            &GYRO_NON_ORTHOGONALITY_TERMS,
            self.gyro_non_orthogonality_rad.as_slice(),
        )
    }

    /// The accelerometer misalignment matrix `A_a` (zero diagonal).
    ///
    /// # Examples
    /// ```
    /// use nav_core::imu_error::ImuErrorEstimate;
    /// let mut e = ImuErrorEstimate::default();
    /// e.accel_misalignment_rad[0] = 2e-5; // a_xy
    /// assert_eq!(e.accel_matrix()[(0, 1)].to_bits(), 2e-5f64.to_bits());
    /// ```
    pub fn accel_matrix(&self) -> Matrix3<f64> {
        from_terms(
            &ACCEL_MISALIGNMENT_TERMS,
            self.accel_misalignment_rad.as_slice(),
        )
    }

    /// True when every value is finite.
    pub fn is_finite(&self) -> bool {
        self.gyro_non_orthogonality_rad
            .iter()
            .chain(self.accel_misalignment_rad.iter())
            .chain(self.gyro_g_sensitivity_rad_s_per_mps2.iter())
            .all(|v| v.is_finite())
    }
}

/// `Ψ(ω)` with `L_g ω = Ψ(ω) a_g` (module docs).
///
/// # Examples
/// ```
/// use nav_core::imu_error::{gyro_non_orthogonality_sensitivity, ImuErrorEstimate};
/// use nalgebra::Vector3;
/// let mut e = ImuErrorEstimate::default();
/// e.gyro_non_orthogonality_rad[1] = 1e-3; // a_zx
/// let rate = Vector3::new(0.1, 0.2, 0.3);
/// let direct = e.gyro_matrix() * rate;
/// let by_columns = gyro_non_orthogonality_sensitivity(&rate) * e.gyro_non_orthogonality_rad;
/// assert!((direct - by_columns).norm() < 1e-18);
/// assert_eq!(direct.z.to_bits(), (1e-3f64 * 0.1).to_bits()); // z senses ω_x
/// ```
pub fn gyro_non_orthogonality_sensitivity(rate: &Vector3<f64>) -> Matrix3<f64> {
    let mut psi = Matrix3::zeros();
    for (k, (row, column)) in GYRO_NON_ORTHOGONALITY_TERMS.iter().enumerate() {
        if let (Some(entry), Some(value)) = (psi.get_mut((*row, k)), rate.get(*column)) {
            *entry = *value;
        }
    }
    psi
}

/// `Ω(f)` with `A_a f = Ω(f) a_a` (module docs).
///
/// # Examples
/// ```
/// use nav_core::imu_error::accel_misalignment_sensitivity;
/// use nalgebra::Vector3;
/// let omega = accel_misalignment_sensitivity(&Vector3::new(30.0, 1.0, 0.0));
/// assert_eq!(omega[(1, 2)].to_bits(), 30.0f64.to_bits()); // a_yx senses f_x on y
/// assert_eq!(omega[(0, 0)].to_bits(), 1.0f64.to_bits()); // a_xy senses f_y on x
/// ```
pub fn accel_misalignment_sensitivity(force: &Vector3<f64>) -> SMatrix<f64, 3, 6> {
    let mut omega = SMatrix::<f64, 3, 6>::zeros();
    for (k, (row, column)) in ACCEL_MISALIGNMENT_TERMS.iter().enumerate() {
        if let (Some(entry), Some(value)) = (omega.get_mut((*row, k)), force.get(*column)) {
            *entry = *value;
        }
    }
    omega
}

/// The columns of `A` for the 12 systematic IMU error states at `point` (module docs):
/// rows `ϑ`: `[−½ Ψ(ω_m), 0, −½ diag(f_m)]`; rows `δv`: `[0, −Ĉ Ω(f_m), 0]`; zero elsewhere.
///
/// # Examples
/// ```
/// use nav_core::imu_error::{system_columns, ImuErrorBlock};
/// use nav_core::observability::constant_motion;
/// use nalgebra::{Matrix3, Vector3};
/// let point = constant_motion(&Vector3::new(0.0, 0.0, 0.1), &Vector3::new(30.0, 0.0, 0.0),
///     &Matrix3::identity());
/// let b = system_columns(&point);
/// // g-sensitivity x under 30 m/s² along x: ϑ̇_x = −15 δg_x.
/// let g_x = ImuErrorBlock::GyroGSensitivity.offset();
/// assert!((b[(0, g_x)] + 15.0).abs() < 1e-15);
/// // Accelerometer misalignment yx under the same force: δv̇_y = −30 δa_yx (Ĉ = I).
/// let a_yx = ImuErrorBlock::AccelMisalignment.offset() + 2;
/// assert!((b[(nav_core::state::VELOCITY.index() + 1, a_yx)] + 30.0).abs() < 1e-15);
/// ```
pub fn system_columns(point: &LinearisationPoint) -> ImuErrorColumns {
    let mut b = ImuErrorColumns::zeros();
    let rate = &point.measured_rate_rad_s;
    let force = &point.measured_specific_force_mps2;
    b.fixed_view_mut::<3, 3>(
        ATTITUDE.index(),
        ImuErrorBlock::GyroNonOrthogonality.offset(),
    )
    .copy_from(&(gyro_non_orthogonality_sensitivity(rate) * -0.5));
    b.fixed_view_mut::<3, 6>(VELOCITY.index(), ImuErrorBlock::AccelMisalignment.offset())
        .copy_from(&(-point.body_to_inertial * accel_misalignment_sensitivity(force)));
    b.fixed_view_mut::<3, 3>(ATTITUDE.index(), ImuErrorBlock::GyroGSensitivity.offset())
        .copy_from(&(Matrix3::from_diagonal(force) * -0.5));
    b
}

/// The sensor whose bias a systematic state acts as ([`equivalent_bias_terms`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum BiasSensor {
    /// The gyro: the state enters `δω`.
    Gyro,
    /// The accelerometer: the state enters `δf`.
    Accel,
}

/// One systematic state as an equivalent sensor bias: it enters the sensor's error on `axis`
/// as `multiplier` times its value ([`equivalent_bias_terms`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EquivalentBias {
    /// The sensor whose error the state enters.
    pub sensor: BiasSensor,
    /// The axis (0 x, 1 y, 2 z) of that sensor.
    pub axis: usize,
    /// `m_k`: the measured rate (rad/s) or specific force (m/s²) component that multiplies it.
    pub multiplier: f64,
}

/// Each systematic state acts on the navigation exactly as an equivalent sensor bias: `δω`,
/// `δf` gain `−m_k ε_k` on one axis. Returns, for the 12 states in order, the sensor, the axis
/// and the multiplier `m_k` at the measured rate/force: gyro non-orthogonality yx → (gyro, y,
/// `ω_x`), zx → (gyro, z, `ω_x`), zy → (gyro, z, `ω_y`); accelerometer misalignment ij →
/// (accel, i, `f_j`); g-sensitivity i → (gyro, i, `f_i`). Column `k` of [`system_columns`] is
/// the column of that bias in [`crate::error_model::system_matrix`] times `m_k`.
///
/// # Examples
/// ```
/// use nav_core::imu_error::{equivalent_bias_terms, BiasSensor, ImuErrorBlock};
/// use nalgebra::Vector3;
/// let terms = equivalent_bias_terms(&Vector3::new(0.1, 0.0, 0.0), &Vector3::new(30.0, 0.0, 0.0));
/// // Accelerometer misalignment yx under thrust along x: an accelerometer y bias of 30 a_yx.
/// let a_yx = terms[ImuErrorBlock::AccelMisalignment.offset() + 2];
/// assert_eq!((a_yx.sensor, a_yx.axis), (BiasSensor::Accel, 1));
/// assert_eq!(a_yx.multiplier.to_bits(), 30.0f64.to_bits());
/// // Gyro non-orthogonality zx during a roll: a gyro z bias of 0.1 a_zx.
/// let g_zx = terms[ImuErrorBlock::GyroNonOrthogonality.offset() + 1];
/// assert_eq!((g_zx.sensor, g_zx.axis), (BiasSensor::Gyro, 2));
/// assert_eq!(g_zx.multiplier.to_bits(), 0.1f64.to_bits());
/// ```
pub fn equivalent_bias_terms(
    measured_rate_rad_s: &Vector3<f64>,
    measured_specific_force_mps2: &Vector3<f64>,
) -> [EquivalentBias; IMU_ERROR_DIMENSION] {
    let component = |v: &Vector3<f64>, axis: usize| v.get(axis).copied().unwrap_or(0.0);
    let term = |sensor: BiasSensor, axis: usize, multiplier: f64| EquivalentBias {
        sensor,
        axis,
        multiplier,
    };
    let gyro_non_orthogonality = GYRO_NON_ORTHOGONALITY_TERMS.iter().map(|(row, column)| {
        term(
            BiasSensor::Gyro,
            *row,
            component(measured_rate_rad_s, *column),
        )
    });
    let accel_misalignment = ACCEL_MISALIGNMENT_TERMS.iter().map(|(row, column)| {
        term(
            BiasSensor::Accel,
            *row,
            component(measured_specific_force_mps2, *column),
        )
    });
    let g_sensitivity = (0..3).map(|axis| {
        term(
            BiasSensor::Gyro,
            axis,
            component(measured_specific_force_mps2, axis),
        )
    });
    let mut terms = [term(BiasSensor::Gyro, 0, 0.0); IMU_ERROR_DIMENSION];
    for (slot, value) in terms.iter_mut().zip(
        gyro_non_orthogonality
            .chain(accel_misalignment)
            .chain(g_sensitivity),
    ) {
        *slot = value;
    }
    terms
}

/// Corrects raw rates for the paper's errors and the systematic ones (module docs):
/// `ω̂ = ω_m − λ̂g∘ω_m − b̂g − L̂_g ω_m − ĝ∘f_m`, `f̂ = f_m − λ̂a∘f_m − b̂a − Â_a f_m`. With
/// `imu` zero the first three terms are the strapdown's correction, bit for bit.
///
/// # Examples
/// ```
/// use nav_core::imu_error::{correct_rates, ImuErrorEstimate};
/// use nav_core::strapdown::SensorCorrections;
/// use nalgebra::Vector3;
/// let mut imu = ImuErrorEstimate::default();
/// imu.gyro_g_sensitivity_rad_s_per_mps2 = Vector3::new(1e-6, 0.0, 0.0);
/// let (rate, _) = correct_rates(&Vector3::zeros(), &Vector3::new(30.0, 0.0, 0.0),
///     &SensorCorrections::default(), &imu);
/// assert!((rate.x + 3e-5).abs() < 1e-18);
/// ```
pub fn correct_rates(
    measured_rate_rad_s: &Vector3<f64>,
    measured_specific_force_mps2: &Vector3<f64>,
    corrections: &SensorCorrections,
    imu: &ImuErrorEstimate,
) -> (Vector3<f64>, Vector3<f64>) {
    let rate = measured_rate_rad_s
        - corrections
            .gyro_scale_factor
            .component_mul(measured_rate_rad_s)
        - corrections.gyro_bias_rad_s
        - imu.gyro_matrix() * measured_rate_rad_s
        - imu
            .gyro_g_sensitivity_rad_s_per_mps2
            .component_mul(measured_specific_force_mps2);
    let force = measured_specific_force_mps2
        - corrections
            .accel_scale_factor
            .component_mul(measured_specific_force_mps2)
        - corrections.accel_bias_mps2
        - imu.accel_matrix() * measured_specific_force_mps2;
    (rate, force)
}

/// [`correct_rates`] on one frame's increments (what the strapdown would apply before
/// coning and sculling): `Δθ = Δθ_m − λ̂g∘Δθ_m − b̂g T − L̂_g Δθ_m − ĝ∘Δv_m`,
/// `Δv = Δv_m − λ̂a∘Δv_m − b̂a T − Â_a Δv_m` (`∫ g∘f_m dt = g∘Δv_m` exactly).
///
/// # Errors
/// [`NavError::InvalidTimeStep`] for a non-positive or non-finite interval,
/// [`NavError::NonFiniteInput`] for NaN/Inf in the increments or corrections.
///
/// # Examples
/// ```
/// use nav_core::imu_error::{correct_increment, ImuErrorEstimate};
/// use nav_core::strapdown::{ImuIncrement, SensorCorrections};
/// use nalgebra::Vector3;
/// let raw = ImuIncrement::from_rates(&Vector3::new(0.1, 0.0, 0.0), &Vector3::zeros(), 0.002);
/// let mut imu = ImuErrorEstimate::default();
/// imu.gyro_non_orthogonality_rad[0] = 1e-3; // a_yx: y reads 1e-3 of the rate about x
/// let corrected = correct_increment(&raw, &SensorCorrections::default(), &imu).unwrap();
/// assert!((corrected.delta_angle_rad.y + 1e-3 * 0.1 * 0.002).abs() < 1e-18);
/// ```
pub fn correct_increment(
    raw: &ImuIncrement,
    corrections: &SensorCorrections,
    imu: &ImuErrorEstimate,
) -> Result<ImuIncrement, NavError> {
    let interval = raw.interval_s;
    if !interval.is_finite() || interval <= 0.0 {
        return Err(NavError::InvalidTimeStep);
    }
    let scaled = SensorCorrections {
        gyro_bias_rad_s: corrections.gyro_bias_rad_s * interval,
        accel_bias_mps2: corrections.accel_bias_mps2 * interval,
        ..*corrections
    };
    let (delta_angle_rad, delta_velocity_mps) =
        correct_rates(&raw.delta_angle_rad, &raw.delta_velocity_mps, &scaled, imu);
    let finite = |v: &Vector3<f64>| v.iter().all(|x| x.is_finite());
    if !(finite(&delta_angle_rad) && finite(&delta_velocity_mps)) {
        return Err(NavError::NonFiniteInput);
    }
    Ok(ImuIncrement {
        delta_angle_rad,
        delta_velocity_mps,
        interval_s: interval,
    })
}

/// A truth description of the IMU and star sensor in the simulator's convention
/// (`docs/guide/model.md`): `Δθ_m = (I − Λg)⁻¹ ((I + A_g) Δθ + G Δv + bg T + …)`,
/// `Δv_m = (I − Λa)⁻¹ ((I + A_a) Δv + ba T + …)`, `q_is = q_ib ⊗ q_bs ⊗ q_ψ`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImuTruth {
    /// Full gyro misalignment `A_g` (rad, zero diagonal).
    pub gyro_misalignment_rad: Matrix3<f64>,
    /// Full accelerometer misalignment `A_a` (rad, zero diagonal).
    pub accel_misalignment_rad: Matrix3<f64>,
    /// Gyro g-sensitivity `G = diag(g)` (rad/s per m/s²).
    pub gyro_g_sensitivity_rad_s_per_mps2: Vector3<f64>,
    /// Gyro bias `bg` (rad/s; the total at the epoch of interest).
    pub gyro_bias_rad_s: Vector3<f64>,
    /// Accelerometer bias `ba` (m/s²).
    pub accel_bias_mps2: Vector3<f64>,
    /// Gyro scale factors `λg`.
    pub gyro_scale_factor: Vector3<f64>,
    /// Accelerometer scale factors `λa`.
    pub accel_scale_factor: Vector3<f64>,
    /// Star-sensor nominal mounting `q_bs`.
    pub star_mounting: Quaternion<f64>,
    /// Star-sensor installation error `q_ψ`.
    pub star_installation: Quaternion<f64>,
}

/// An [`ImuTruth`] in the filter's gauge: the values the filter's states converge to.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GaugeTruth {
    /// `q_bb'`: the filter's body frame `b'` (gyro-defined) into the truth's `b`;
    /// the filter's attitude truth is `q_ib ⊗ q_bb'` ([`GaugeTruth::attitude`]).
    pub body_rotation: Quaternion<f64>,
    /// The systematic error states.
    pub imu: ImuErrorEstimate,
    /// Gyro bias (rad/s) in `b'`: `R (I + A_g)⁻¹ (bg − G (I + A_a)⁻¹ ba)`.
    pub gyro_bias_rad_s: Vector3<f64>,
    /// Accelerometer bias (m/s²) in `b'`: `R (I + A_a)⁻¹ ba`.
    pub accel_bias_mps2: Vector3<f64>,
    /// Gyro scale factors: `1 − diag(K_g)`.
    pub gyro_scale_factor: Vector3<f64>,
    /// Accelerometer scale factors: `1 − diag(K_a)`.
    pub accel_scale_factor: Vector3<f64>,
    /// Star installation `q_ψ' = q_bs* ⊗ q_b'b ⊗ q_bs ⊗ q_ψ`.
    pub star_installation: Quaternion<f64>,
    /// The part of the truth the model cannot hold: the off-diagonal of the g-sensitivity
    /// map `N = R (I + A_g)⁻¹ G K_a` (second order, `g a`), rad/s per m/s².
    pub unmodelled_g_sensitivity: Matrix3<f64>,
}

impl GaugeTruth {
    /// The filter's attitude truth `q_ib' = q_ib ⊗ q_bb'` for a true attitude `q_ib`.
    pub fn attitude(&self, true_attitude: &Quaternion<f64>) -> Quaternion<f64> {
        product(true_attitude, &self.body_rotation)
    }
}

/// `R = C_b'b` of the gyro-defined frame: rows `x' ∥ s_x`, `z' ∥ s_x × s_y`,
/// `y' = z' × x'`, with `s_i` row `i` of `I + A_g` (gyro axis `i`'s sensing direction in `b`).
fn gyro_frame(gyro_misalignment: &Matrix3<f64>) -> Result<Matrix3<f64>, NavError> {
    let sensing = Matrix3::identity() + gyro_misalignment;
    let s_x: Vector3<f64> = sensing.row(0).transpose();
    let s_y: Vector3<f64> = sensing.row(1).transpose();
    let z = s_x.cross(&s_y);
    let (x_norm, z_norm) = (
        crate::float::sqrt(s_x.dot(&s_x)),
        crate::float::sqrt(z.dot(&z)),
    );
    if !(x_norm > 0.0 && z_norm > 0.0 && x_norm.is_finite() && z_norm.is_finite()) {
        return Err(NavError::InvalidConfiguration);
    }
    let (x, z) = (s_x / x_norm, z / z_norm);
    let y = z.cross(&x);
    Ok(Matrix3::from_rows(&[
        x.transpose(),
        y.transpose(),
        z.transpose(),
    ]))
}

/// Unit quaternion of a rotation matrix (Shepperd's method: the largest of `w², x², y², z²`
/// is taken from the diagonal, the others from the off-diagonal sums and differences).
fn quaternion_of(c: &Matrix3<f64>) -> Quaternion<f64> {
    let trace = c.m11 + c.m22 + c.m33;
    let candidates = [trace, c.m11, c.m22, c.m33];
    let mut largest = 0;
    for (k, value) in candidates.iter().enumerate() {
        if candidates.get(largest).is_some_and(|best| value > best) {
            largest = k;
        }
    }
    let (w, x, y, z) = match largest {
        0 => {
            let s = 2.0 * crate::float::sqrt(1.0 + trace);
            (
                0.25 * s,
                (c.m32 - c.m23) / s,
                (c.m13 - c.m31) / s,
                (c.m21 - c.m12) / s,
            )
        }
        1 => {
            let s = 2.0 * crate::float::sqrt(1.0 + c.m11 - c.m22 - c.m33);
            (
                (c.m32 - c.m23) / s,
                0.25 * s,
                (c.m12 + c.m21) / s,
                (c.m13 + c.m31) / s,
            )
        }
        2 => {
            let s = 2.0 * crate::float::sqrt(1.0 - c.m11 + c.m22 - c.m33);
            (
                (c.m13 - c.m31) / s,
                (c.m12 + c.m21) / s,
                0.25 * s,
                (c.m23 + c.m32) / s,
            )
        }
        _ => {
            let s = 2.0 * crate::float::sqrt(1.0 - c.m11 - c.m22 + c.m33);
            (
                (c.m21 - c.m12) / s,
                (c.m13 + c.m31) / s,
                (c.m23 + c.m32) / s,
                0.25 * s,
            )
        }
    };
    crate::attitude::canonical(&Quaternion::new(w, x, y, z))
}

/// Values of the off-diagonal `terms` of `-k` (the correction matrix `K = I − Λ − A`).
fn negated_terms<const N: usize>(k: &Matrix3<f64>, terms: &[(usize, usize); N]) -> [f64; N] {
    let mut values = [0.0; N];
    for (value, index) in values.iter_mut().zip(terms.iter()) {
        *value = -k.get(*index).copied().unwrap_or(0.0);
    }
    values
}

/// Maps a truth description into the filter's gauge (module docs), exactly.
///
/// Derivation. The truth gives `ω = K_g ω_m − (I + A_g)⁻¹ (bg + G f)` with
/// `K_g = (I + A_g)⁻¹ (I − Λg)`, and `f = K_a f_m − (I + A_a)⁻¹ ba`,
/// `K_a = (I + A_a)⁻¹ (I − Λa)`. The gyro's sensing directions `s_i` are the rows of
/// `I + A_g` (`s_iᵀ (I + A_g)⁻¹ = e_iᵀ`). The frame `b'` has `C_b'b = R` with rows
/// `x' ∥ s_x`, `z' ∥ s_x × s_y`, `y' = z' × x'`: `x'` is orthogonal to column `j ≠ 0` of
/// `(I + A_g)⁻¹` and `y'`, in the plane of `s_x` and `s_y`, to column 2, so `R K_g` is lower
/// triangular. In `b'` the filter's model
/// `ω' = (I − Λ'g − L'_g) ω_m − b'g − diag(g') f_m` matches `R ω` with
/// `I − Λ'g − L'_g = R K_g` (the gyro non-orthogonality is its negated strictly lower part),
/// `g' = diag(N)`, `N = R (I + A_g)⁻¹ G K_a`, `b'g = R (I + A_g)⁻¹ (bg − G (I + A_a)⁻¹ ba)`,
/// and `f' = (I − Λ'a − A'_a) f_m − b'a` matches `R f` with `I − Λ'a − A'_a = R K_a` (full:
/// the six accelerometer misalignment terms are its negated off-diagonal),
/// `b'a = R (I + A_a)⁻¹ ba`; the scale factors are `1 − diag(R K_g)`, `1 − diag(R K_a)`. The
/// star measurement `q_ib ⊗ q_bs ⊗ q_ψ` is `q_ib' ⊗ q_bs ⊗ q_ψ'` with
/// `q_ib' = q_ib ⊗ q_bb'`, `q_bb' = q_b'b*` and `q_ψ' = q_bs* ⊗ q_b'b ⊗ q_bs ⊗ q_ψ`. Only the
/// off-diagonal of `N` is left out (reported).
///
/// # Errors
/// [`NavError::NonFiniteInput`] for NaN/Inf, [`NavError::SingularMatrix`] if `I + A` is
/// singular, [`NavError::InvalidConfiguration`] for degenerate gyro axes.
///
/// # Examples
/// ```
/// use nav_core::imu_error::{to_filter_gauge, ImuTruth};
/// use nalgebra::{Matrix3, Quaternion, Vector3};
/// // Gyro x sensing axis tilted towards body y by 2e-5 rad (a_xy).
/// let mut gyro = Matrix3::zeros();
/// gyro[(0, 1)] = 2e-5;
/// let truth = ImuTruth {
///     gyro_misalignment_rad: gyro, accel_misalignment_rad: Matrix3::zeros(),
///     gyro_g_sensitivity_rad_s_per_mps2: Vector3::zeros(),
///     gyro_bias_rad_s: Vector3::zeros(), accel_bias_mps2: Vector3::zeros(),
///     gyro_scale_factor: Vector3::zeros(), accel_scale_factor: Vector3::zeros(),
///     star_mounting: Quaternion::identity(), star_installation: Quaternion::identity(),
/// };
/// let gauge = to_filter_gauge(&truth).unwrap();
/// // Body x' follows the gyro x axis: the frame turns by 2e-5 about z. The gyro keeps it as
/// // its non-orthogonality yx, the accelerometer (aligned with the old frame) as a rotation.
/// assert!((gauge.imu.gyro_non_orthogonality_rad[0] - 2e-5).abs() < 1e-12); // a_yx
/// assert!((gauge.imu.accel_misalignment_rad[0] + 2e-5).abs() < 1e-12); // a_xy
/// assert!((gauge.imu.accel_misalignment_rad[2] - 2e-5).abs() < 1e-12); // a_yx
/// assert!(gauge.imu.accel_misalignment_rad.iter().skip(3).all(|a| a.abs() < 1e-12));
/// // q_bb' turns about +z by 2e-5 rad (half-angle 1e-5).
/// assert!((gauge.body_rotation.k - 1e-5).abs() < 1e-12);
/// ```
pub fn to_filter_gauge(truth: &ImuTruth) -> Result<GaugeTruth, NavError> {
    let identity = Matrix3::<f64>::identity();
    let inverse_g = (identity + truth.gyro_misalignment_rad)
        .try_inverse()
        .ok_or(NavError::SingularMatrix)?;
    let inverse_a = (identity + truth.accel_misalignment_rad)
        .try_inverse()
        .ok_or(NavError::SingularMatrix)?;
    let r = gyro_frame(&truth.gyro_misalignment_rad)?;
    let k_g =
        r * inverse_g * Matrix3::from_diagonal(&(Vector3::repeat(1.0) - truth.gyro_scale_factor));
    let k_a_body =
        inverse_a * Matrix3::from_diagonal(&(Vector3::repeat(1.0) - truth.accel_scale_factor));
    let k_a = r * k_a_body;
    let g = Matrix3::from_diagonal(&truth.gyro_g_sensitivity_rad_s_per_mps2);
    let n = r * inverse_g * g * k_a_body;
    let accel_bias_body = inverse_a * truth.accel_bias_mps2;
    let imu = ImuErrorEstimate {
        gyro_non_orthogonality_rad: Vector3::from(negated_terms(
            &k_g,
            &GYRO_NON_ORTHOGONALITY_TERMS,
        )),
        accel_misalignment_rad: SVector::from(negated_terms(&k_a, &ACCEL_MISALIGNMENT_TERMS)),
        gyro_g_sensitivity_rad_s_per_mps2: n.diagonal(),
    };
    let q_b_prime_b = quaternion_of(&r);
    let mounting = &truth.star_mounting;
    let star_installation = product(
        &product(&product(&conjugate(mounting), &q_b_prime_b), mounting),
        &truth.star_installation,
    );
    let gauge = GaugeTruth {
        body_rotation: conjugate(&q_b_prime_b),
        imu,
        gyro_bias_rad_s: r * inverse_g * (truth.gyro_bias_rad_s - g * accel_bias_body),
        accel_bias_mps2: r * accel_bias_body,
        gyro_scale_factor: Vector3::repeat(1.0) - k_g.diagonal(),
        accel_scale_factor: Vector3::repeat(1.0) - k_a.diagonal(),
        star_installation,
        unmodelled_g_sensitivity: n - Matrix3::from_diagonal(&n.diagonal()),
    };
    let finite = gauge.imu.is_finite()
        && gauge
            .gyro_bias_rad_s
            .iter()
            .chain(gauge.accel_bias_mps2.iter())
            .all(|v| v.is_finite())
        && [gauge.star_installation, gauge.body_rotation]
            .iter()
            .all(|q| q.coords.iter().all(|v| v.is_finite()));
    if finite {
        Ok(gauge)
    } else {
        Err(NavError::NonFiniteInput)
    }
}

#[cfg(test)]
#[path = "imu_error_tests.rs"]
mod tests;
