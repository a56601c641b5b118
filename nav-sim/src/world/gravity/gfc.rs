//! Reader of the ICGEM gravity-field format (`.gfc`), the format in which the International
//! Centre for Global Earth Models distributes the published Earth models (Barthelmes &
//! Förste, *The ICGEM-format*, GFZ Potsdam, 2011).
//!
//! A file is a free-text header closed by a line starting with `end_of_head`, then one line
//! per coefficient: `gfc L M C S [sigma_C sigma_S]`, the fully normalised Stokes coefficients
//! `C̄_LM`, `S̄_LM` (Fortran `d` exponents accepted). The header's keys read here are
//! `earth_gravity_constant` (m³/s²), `radius` (m), `max_degree` and `norm` (which must be
//! `fully_normalized`); `modelname` names the model in messages.

use std::collections::HashMap;

/// Why a gravity-field file could not be read.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GfcError {
    /// A header key the evaluation needs is missing or not a number.
    #[error("gravity model file: header key {key} is missing or unreadable")]
    Header {
        /// The key.
        key: &'static str,
    },
    /// The file's normalisation is not the fully normalised one.
    #[error("gravity model file: norm is {norm:?}, only fully_normalized is supported")]
    Normalisation {
        /// The file's `norm` value.
        norm: String,
    },
    /// A coefficient line cannot be read.
    #[error("gravity model file, line {line}: {reason}")]
    Line {
        /// 1-based line number.
        line: usize,
        /// What is wrong with it.
        reason: String,
    },
    /// The file does not reach the requested degree.
    #[error("gravity model {model}: degree {requested} requested, the file stops at {available}")]
    Degree {
        /// Model name from the header.
        model: String,
        /// Requested degree.
        requested: usize,
        /// The file's `max_degree`.
        available: usize,
    },
    /// A coefficient up to the requested degree is absent.
    #[error("gravity model {model}: coefficient degree {degree} order {order} is missing")]
    Missing {
        /// Model name from the header.
        model: String,
        /// Its degree.
        degree: usize,
        /// Its order.
        order: usize,
    },
}

/// Fully normalised Stokes coefficients of a model up to degree `N`, order `M ≤ N`.
#[derive(Debug, Clone, PartialEq)]
pub struct GravityCoefficients {
    /// The header's `modelname` (or `"unnamed"`).
    pub model: String,
    /// The model's gravitational constant `GM` (m³/s²).
    pub gm_m3_s2: f64,
    /// The model's reference radius `a` (m).
    pub radius_m: f64,
    /// Largest degree `N` kept.
    pub degree: usize,
    /// Largest order `M` kept (`M ≤ N`; coefficients of higher order are zero).
    pub order: usize,
    /// `C̄_nm` at [`triangle_index`]`(n, m)`, `n ≤ N`.
    pub c: Vec<f64>,
    /// `S̄_nm`, same layout.
    pub s: Vec<f64>,
}

/// Index of `(n, m)`, `m ≤ n`, in a lower-triangular array stored degree by degree.
pub fn triangle_index(degree: usize, order: usize) -> usize {
    degree * (degree + 1) / 2 + order
}

fn parse_number(text: &str) -> Option<f64> {
    text.replace(['d', 'D'], "e")
        .parse::<f64>()
        .ok()
        .filter(|value| value.is_finite())
}

/// The header's values: the keys it defines and the line after `end_of_head` (0-based).
fn read_header(text: &str) -> Result<(HashMap<&str, &str>, usize), GfcError> {
    let mut keys = HashMap::new();
    for (index, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        match (words.next(), words.next()) {
            (Some("end_of_head"), _) => return Ok((keys, index + 1)),
            (Some(key), Some(value)) => {
                keys.insert(key, value);
            }
            _ => {}
        }
    }
    Err(GfcError::Header { key: "end_of_head" })
}

fn header_number(keys: &HashMap<&str, &str>, key: &'static str) -> Result<f64, GfcError> {
    keys.get(key)
        .and_then(|text| parse_number(text))
        .ok_or(GfcError::Header { key })
}

/// One `gfc` line: `(n, m, C̄, S̄)`.
fn coefficient_line(line: &str) -> Option<(usize, usize, f64, f64)> {
    let words: Vec<&str> = line.split_whitespace().collect();
    if words.len() < 5 {
        return None;
    }
    let degree = words[1].parse().ok()?;
    let order = words[2].parse().ok()?;
    (order <= degree).then_some(())?;
    Some((
        degree,
        order,
        parse_number(words[3])?,
        parse_number(words[4])?,
    ))
}

/// Reads `text` (an ICGEM `.gfc` file) up to degree `degree` and order `order` (`order` is
/// clamped to `degree`); degree-0 and degree-1 lines are optional (0 when absent: degree 1
/// vanishes in a geocentric frame), every other coefficient up to `degree` must be present.
///
/// # Errors
/// [`GfcError`] naming the header key, line or coefficient that is wrong or missing.
pub fn parse_gfc(text: &str, degree: usize, order: usize) -> Result<GravityCoefficients, GfcError> {
    let (keys, first_data_line) = read_header(text)?;
    let model = keys.get("modelname").unwrap_or(&"unnamed").to_string();
    let norm = keys.get("norm").copied().unwrap_or("");
    if norm != "fully_normalized" {
        return Err(GfcError::Normalisation {
            norm: norm.to_string(),
        });
    }
    let gm_m3_s2 = header_number(&keys, "earth_gravity_constant")?;
    let radius_m = header_number(&keys, "radius")?;
    if gm_m3_s2 <= 0.0 || radius_m <= 0.0 {
        return Err(GfcError::Header {
            key: "earth_gravity_constant/radius (must be > 0)",
        });
    }
    let available = keys
        .get("max_degree")
        .and_then(|text| text.parse::<usize>().ok())
        .ok_or(GfcError::Header { key: "max_degree" })?;
    if degree > available {
        return Err(GfcError::Degree {
            model,
            requested: degree,
            available,
        });
    }
    let order = order.min(degree);
    let size = triangle_index(degree, degree) + 1;
    let (mut c, mut s, mut seen) = (vec![0.0; size], vec![0.0; size], vec![false; size]);
    for (index, line) in text.lines().enumerate().skip(first_data_line) {
        if !line.trim_start().starts_with("gfc") {
            continue;
        }
        let (n, m, c_nm, s_nm) = coefficient_line(line).ok_or_else(|| GfcError::Line {
            line: index + 1,
            reason: format!("expected `gfc L M C S`, found {:?}", line.trim()),
        })?;
        if n > degree || m > order {
            continue;
        }
        let at = triangle_index(n, m);
        c[at] = c_nm;
        s[at] = s_nm;
        seen[at] = true;
    }
    for n in 2..=degree {
        for m in 0..=n.min(order) {
            if !seen[triangle_index(n, m)] {
                return Err(GfcError::Missing {
                    model,
                    degree: n,
                    order: m,
                });
            }
        }
    }
    Ok(GravityCoefficients {
        model,
        gm_m3_s2,
        radius_m,
        degree,
        order,
        c,
        s,
    })
}
