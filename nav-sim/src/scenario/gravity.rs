//! The scenario's optional `[gravity]` table: the truth's gravity field (`docs/guide/model.md`,
//! "The truth's gravity field"). Absent, or `model = "j2"`, the truth flies the flight code's
//! point mass + `J2`; `model = "egm2008"` adds the published model's terms up to `degree` and
//! `order` (the world layer's `gravity` module). The flight software's model is unchanged.

use schemars::JsonSchema;
use serde::Deserialize;

/// Largest `gravity.degree`: the degree of the model file shipped in `nav-sim/data/`.
pub const MAX_FIELD_DEGREE: u32 = 60;

/// The truth's gravity model.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum GravityModelName {
    /// nav-core's point mass + `J2` (WGS-84), the flight code's own model.
    J2,
    /// EGM2008 (Pavlis et al. 2012), NGA's model for WGS-84, to `degree` and `order`.
    Egm2008,
}

/// The `[gravity]` table.
#[derive(Debug, Clone, PartialEq, Eq, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct GravitySettings {
    /// The truth's model.
    pub model: GravityModelName,
    /// Largest degree `N` of a published model, in `2..=`[`MAX_FIELD_DEGREE`]; absent for
    /// `"j2"`.
    #[serde(default)]
    pub degree: Option<u32>,
    /// Largest order `M`, in `0..=degree`; absent for `"j2"`.
    #[serde(default)]
    pub order: Option<u32>,
}

impl GravitySettings {
    /// The first key that breaks its rule, with the rule: `(key, requirement)`.
    pub fn violation(&self) -> Option<(&'static str, String)> {
        match self.model {
            GravityModelName::J2 => {
                if self.degree.is_some() {
                    Some((
                        "gravity.degree",
                        "must be absent with model = \"j2\"".into(),
                    ))
                } else if self.order.is_some() {
                    Some(("gravity.order", "must be absent with model = \"j2\"".into()))
                } else {
                    None
                }
            }
            GravityModelName::Egm2008 => match (self.degree, self.order) {
                (None, _) => Some((
                    "gravity.degree",
                    "is required with a published model".into(),
                )),
                (_, None) => Some(("gravity.order", "is required with a published model".into())),
                (Some(degree), Some(order)) => {
                    if !(2..=MAX_FIELD_DEGREE).contains(&degree) {
                        Some((
                            "gravity.degree",
                            format!(
                                "= {degree} must be in 2..={MAX_FIELD_DEGREE} (the degree of \
                                 the model file in nav-sim/data/)"
                            ),
                        ))
                    } else if order > degree {
                        Some((
                            "gravity.order",
                            format!("= {order} must be in 0..=gravity.degree ({degree})"),
                        ))
                    } else {
                        None
                    }
                }
            },
        }
    }
}

/// The truth's field as `(degree, order)`: a published model's `degree` and `order`; point
/// mass + `J2` (no `[gravity]` table, or `model = "j2"`) is `(2, 0)`.
pub fn truth_degree_order(truth: Option<&GravitySettings>) -> (u32, u32) {
    match truth {
        Some(settings) if settings.model == GravityModelName::Egm2008 => {
            (settings.degree.unwrap_or(2), settings.order.unwrap_or(0))
        }
        _ => (2, 0),
    }
}

/// The first `[filter.gravity]` key above the truth's field, with the rule: a flight model
/// with terms the simulated truth does not have models a field the vehicle does not fly in,
/// and its filter is inconsistent with it.
pub fn flight_above_truth(
    flight: &FilterGravity,
    truth: Option<&GravitySettings>,
) -> Option<(&'static str, String)> {
    let (truth_degree, truth_order) = truth_degree_order(truth);
    let truth_keys = match truth {
        Some(settings) if settings.model == GravityModelName::Egm2008 => {
            ("gravity.degree", "gravity.order")
        }
        _ => (
            "gravity.degree (point mass + J2: no [gravity] table or model = \"j2\")",
            "gravity.order (point mass + J2: no [gravity] table or model = \"j2\")",
        ),
    };
    let rule = |key: &str, value: u8, truth_key: &str, truth_value: u32| {
        format!(
            "= {value} is above the simulated truth's {truth_key} = {truth_value}: the flight \
             model must not have terms the truth lacks (lower {key} to at most {truth_value} \
             or raise {truth_key})"
        )
    };
    if u32::from(flight.degree) > truth_degree {
        let key = "filter.gravity.degree";
        return Some((key, rule(key, flight.degree, truth_keys.0, truth_degree)));
    }
    if u32::from(flight.order) > truth_order {
        let key = "filter.gravity.order";
        return Some((key, rule(key, flight.order, truth_keys.1, truth_order)));
    }
    None
}

/// The flight software's gravity beyond point mass + `J2` (`[filter.gravity]`, nav-fsw
/// `GravityConfig`, docs/guide/gravity.md): EGM2008 to `degree` and `order` (at most 12), evaluated
/// `terms_per_frame` work items a frame, and the allowance for the field it omits: white
/// velocity noise of a spectral density (from `nav-sim gravity-omission`), and the 1σ per
/// axis of the omitted field it is for (checked in flight). Absent: point mass + `J2` and no
/// allowance, the paper's model.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct FilterGravity {
    /// Largest degree, 2..=12 (2 with order 0: point mass + `J2` alone).
    #[serde(default = "FilterGravity::default_degree")]
    pub degree: u8,
    /// Largest order, 0..=degree.
    #[serde(default)]
    pub order: u8,
    /// Work items of the evaluation per frame, ≥ 1 (nav-core `gravity::harmonics`).
    #[serde(default = "FilterGravity::default_terms_per_frame")]
    pub terms_per_frame: u8,
    /// 1σ per axis of the field the model omits, at the flight's lowest altitude (m/s²);
    /// 0 = no allowance.
    #[serde(default)]
    pub omitted_field_sigma_mps2: f64,
    /// Spectral density of the white velocity noise that covers a field of that 1σ (m²/s³),
    /// scaled in flight with the omitted field's power at the vehicle's radius; > 0 when the
    /// 1σ is.
    #[serde(default)]
    pub omitted_field_psd_m2_per_s3: f64,
}

impl Default for FilterGravity {
    fn default() -> Self {
        Self {
            degree: Self::default_degree(),
            order: 0,
            terms_per_frame: Self::default_terms_per_frame(),
            omitted_field_sigma_mps2: 0.0,
            omitted_field_psd_m2_per_s3: 0.0,
        }
    }
}

impl FilterGravity {
    fn default_degree() -> u8 {
        2
    }

    fn default_terms_per_frame() -> u8 {
        nav_core::gravity::harmonics::DEFAULT_TERMS_PER_FRAME
    }

    /// Whether the table differs from its absence (it renders in `Debug` only then).
    pub fn is_on(&self) -> bool {
        *self != Self::default()
    }

    /// The flight software's configuration.
    pub fn config(&self) -> nav_fsw::config::GravityConfig {
        nav_fsw::config::GravityConfig {
            field: nav_core::gravity::harmonics::FieldModel {
                degree: self.degree,
                order: self.order,
                terms_per_frame: self.terms_per_frame,
            },
            omitted_field_sigma_mps2: self.omitted_field_sigma_mps2,
            omitted_field_psd_m2_per_s3: self.omitted_field_psd_m2_per_s3,
        }
    }
}
