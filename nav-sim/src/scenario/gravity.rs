//! The scenario's optional `[gravity]` table: the truth's gravity field (`docs/model.md`,
//! "The truth's gravity field"). Absent, or `model = "j2"`, the truth flies the flight code's
//! point mass + `J2`; `model = "egm2008"` adds the published model's terms up to `degree` and
//! `order` (the world layer's `gravity` module). The flight software's model is unchanged.

use serde::Deserialize;

/// Largest `gravity.degree`: the degree of the model file shipped in `nav-sim/data/`.
pub const MAX_FIELD_DEGREE: u32 = 60;

/// The truth's gravity model.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum GravityModelName {
    /// nav-core's point mass + `J2` (WGS-84), the flight code's own model.
    J2,
    /// EGM2008 (Pavlis et al. 2012), NGA's model for WGS-84, to `degree` and `order`.
    Egm2008,
}

/// The `[gravity]` table.
#[derive(Debug, Clone, PartialEq, Eq, Deserialize)]
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
