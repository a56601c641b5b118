//! The flight's gravity beyond point mass + `J2` and the allowance for the field it omits.

use nav_core::error_model::ProcessNoise;

use super::range::Range;

/// What the parameter table accepts for the field and its allowance, with the reasons. With
/// the feature `gravity-field` the flight's EGM2008 tables (nav-core `gravity::egm2008`) set
/// the degree; without it the build flies point mass + `J2` alone and never evaluates the
/// omitted field that scales and checks an allowance, so it accepts neither the field nor an
/// allowance: a configuration that asks for them is refused, naming the parameter.
#[cfg(feature = "gravity-field")]
pub(super) mod ranges {
    use super::Range;

    pub(in crate::config) const DEGREE: Range = Range::new(2.0, 12.0);
    pub(in crate::config) const DEGREE_WHY: &str =
        "2 is point mass + J2 alone; the flight's EGM2008 tables end at degree 12";
    pub(in crate::config) const ORDER: Range = Range::new(0.0, 12.0);
    pub(in crate::config) const ORDER_WHY: &str = "at most the degree (checked with it)";
    pub(in crate::config) const OMITTED_SIGMA: Range = Range::new(1.0e-12, 1.0e-2).or_off();
    pub(in crate::config) const OMITTED_SIGMA_WHY: &str =
        "the field beyond J2 is a few 1e-3 m/s^2 at most at the surface, less aloft";
    pub(in crate::config) const OMITTED_PSD: Range = Range::new(1.0e-20, 1.0).or_off();
    pub(in crate::config) const OMITTED_PSD_WHY: &str =
        "a velocity noise for that field: 1 m^2/s^3 swamps every accelerometer";
}

/// See the module of the same name above: the build without the feature `gravity-field`.
#[cfg(not(feature = "gravity-field"))]
pub(super) mod ranges {
    use super::Range;

    pub(in crate::config) const DEGREE: Range = Range::new(2.0, 2.0);
    pub(in crate::config) const DEGREE_WHY: &str = "point mass + J2 alone: this build has no \
         field beyond J2 (nav-fsw feature gravity-field off)";
    pub(in crate::config) const ORDER: Range = Range::new(0.0, 0.0);
    pub(in crate::config) const ORDER_WHY: &str = DEGREE_WHY;
    pub(in crate::config) const OMITTED_SIGMA: Range = Range::new(0.0, 0.0);
    pub(in crate::config) const OMITTED_SIGMA_WHY: &str = "no allowance: this build never \
         evaluates the omitted field that scales and checks one (nav-fsw feature \
         gravity-field off)";
    pub(in crate::config) const OMITTED_PSD: Range = OMITTED_SIGMA;
    pub(in crate::config) const OMITTED_PSD_WHY: &str = OMITTED_SIGMA_WHY;
}

/// The flight's gravity beyond the strapdown's point mass + `J2` (nav-core
/// `gravity::harmonics`), and the allowance for the field it leaves out: white velocity noise
/// of spectral density `omitted_field_psd_m2_per_s3` (isotropic, per axis) added to the
/// filter's process noise where the omitted field is `omitted_field_sigma_mps2` per axis, and
/// scaled with the omitted field's power at the vehicle's radius below that: the omitted
/// field's spectral density at zero frequency, scaled to that σ and averaged over ground
/// tracks, is what the constant calibration states see (docs/guide/gravity.md, "The allowance with
/// the altitude"; `nav-sim gravity-omission`). Each evaluation compares the RMS magnitude of
/// the omitted field at the vehicle's radius with `√3 σ`; above it (a model too coarse for
/// its allowance, or a flight lower than designed for), `gravity_allowance_short` counts an
/// episode; with no allowance at all the check is a start-up configuration warning instead
/// (`health::ConfigurationWarnings`).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct GravityConfig {
    /// Degree, order and work per frame of the field beyond `J2`.
    pub field: nav_core::gravity::harmonics::FieldModel,
    /// 1σ per axis of the omitted field the allowance is for (m/s²); 0: no allowance.
    pub omitted_field_sigma_mps2: f64,
    /// Spectral density of the white velocity noise that covers a field of that 1σ (m²/s³),
    /// scaled down with the field's power where it is weaker; 0: none.
    pub omitted_field_psd_m2_per_s3: f64,
}

/// `√3`: the RMS magnitude of a vector of three independent axes of unit 1σ.
const SQRT_3: f64 = 1.732_050_807_568_877_2;

impl GravityConfig {
    /// Point mass + `J2` and no allowance: the paper's model.
    pub const J2_ONLY: Self = Self {
        field: nav_core::gravity::harmonics::FieldModel::J2_ONLY,
        omitted_field_sigma_mps2: 0.0,
        omitted_field_psd_m2_per_s3: 0.0,
    };

    /// The RMS magnitude of the omitted field the allowance covers (m/s²): `σ` per axis is
    /// `√3 σ` in magnitude, the figure the flight software's omitted RMS is checked against.
    pub fn covered_rms_mps2(&self) -> f64 {
        SQRT_3 * self.omitted_field_sigma_mps2
    }

    /// `base` with the allowance added where the omitted field has the RMS magnitude
    /// `omitted_rms_mps2`: the allowance `q` (m²/s³) is for a field of `σ` per axis (RMS
    /// magnitude `√3 σ`), and its density scales with the field's power,
    /// `q_r = q · min(1, (rms / √3 σ)²)`: the omitted degrees' field falls with the radius as
    /// `(a/r)^(n+2)`, and a flight that climbs from its parking orbit leaves the field behind
    /// (docs/guide/gravity.md, "The allowance with the altitude"). Above `√3 σ` the allowance stays
    /// `q`; an RMS that is not a number counts as above. In launch-inertial axes the
    /// accelerometer's white noise enters the velocity as `C (σ_a² I) Cᵀ = σ_a² I`, so an
    /// isotropic white velocity noise of density `q_r` is the same as an accelerometer
    /// density `√(σ_a² + q_r)`. Without an allowance `base`, bit for bit.
    ///
    /// # Examples
    /// ```
    /// use nav_core::error_model::ProcessNoise;
    /// use nav_fsw::config::GravityConfig;
    /// let gravity = GravityConfig {
    ///     omitted_field_sigma_mps2: 2.0e-5,
    ///     omitted_field_psd_m2_per_s3: 1.0e-7,
    ///     ..GravityConfig::J2_ONLY
    /// };
    /// let base = ProcessNoise::PAPER;
    /// // Half the covered RMS: a quarter of the allowance.
    /// let half = gravity.process_noise_at(&base, 0.5 * gravity.covered_rms_mps2());
    /// let density = base.accel_noise_density_mps2_per_sqrt_hz;
    /// let expected = (density * density + 0.25e-7).sqrt();
    /// assert!((half.accel_noise_density_mps2_per_sqrt_hz - expected).abs() < 1e-18);
    /// assert_eq!(GravityConfig::J2_ONLY.process_noise_at(&base, 1.0), base);
    /// ```
    pub fn process_noise_at(&self, base: &ProcessNoise, omitted_rms_mps2: f64) -> ProcessNoise {
        let mut noise = *base;
        let allowance = self.omitted_field_psd_m2_per_s3;
        if allowance > 0.0 {
            // σ > 0 whenever an allowance is configured (the parameter table's companions).
            let ratio = omitted_rms_mps2 / self.covered_rms_mps2();
            let share = if ratio < 1.0 { ratio * ratio } else { 1.0 };
            let density = noise.accel_noise_density_mps2_per_sqrt_hz;
            noise.accel_noise_density_mps2_per_sqrt_hz =
                nav_core::float::sqrt(density * density + allowance * share);
        }
        noise
    }
}
