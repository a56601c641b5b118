//! The one error type of nav-core: every fallible flight function returns it, nothing panics.

/// Why a nav-core operation refused its input or could not complete.
///
/// `Copy`, no payload beyond small codes, so it can be counted in telemetry and logged with
/// defmt without allocation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum NavError {
    /// An input contained NaN or ±infinity.
    NonFiniteInput,
    /// A quaternion had (near) zero norm and cannot be normalised.
    DegenerateQuaternion,
    /// A time step was not strictly positive (or not finite).
    InvalidTimeStep,
    /// The innovation covariance of an update was not positive definite.
    NonPositiveInnovationCovariance,
    /// A matrix that must be inverted (or factorised) was singular.
    SingularMatrix,
    /// The filter state or covariance became non-finite.
    NonFiniteState,
    /// A configuration value was out of its documented range.
    InvalidConfiguration,
    /// A requested discretisation order is outside 1..=4.
    InvalidDiscretisationOrder,
}

/// One line per variant, as its documentation says.
impl core::fmt::Display for NavError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            Self::NonFiniteInput => "an input contained NaN or infinity",
            Self::DegenerateQuaternion => "a quaternion has (near) zero norm",
            Self::InvalidTimeStep => "a time step is not strictly positive and finite",
            Self::NonPositiveInnovationCovariance => {
                "the innovation covariance is not positive definite"
            }
            Self::SingularMatrix => "a matrix to invert is singular",
            Self::NonFiniteState => "the filter state or covariance became non-finite",
            Self::InvalidConfiguration => "a configuration value is out of its documented range",
            Self::InvalidDiscretisationOrder => "the discretisation order is outside 1..=4",
        })
    }
}

impl core::error::Error for NavError {}
