//! What a flight parameter accepts ([`Range`]) and how a parameter's value becomes a number
//! to check and a replay-setup word ([`ParamValue`]).

use nav_core::filter::FilterMode;

use super::{FrameLoad, SecondOrderAttitude};
use crate::calibration_manager::EstimationPolicy;

/// The values a flight parameter accepts: a closed interval `[low, high]` (open at `low` when
/// `low_open`), optionally also 0 (the parameter's term switched off) or `+∞` (no gate); a
/// choice's values are the indices of its `choices`. NaN is never accepted.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Range {
    /// Smallest accepted value.
    pub low: f64,
    /// Largest accepted value.
    pub high: f64,
    /// `low` itself is refused: the range is `(low, high]`.
    pub low_open: bool,
    /// 0 is accepted too: it switches the parameter's term off.
    pub zero_is_off: bool,
    /// `+∞` is accepted too: no gate.
    pub infinity_is_off: bool,
    /// The names of a choice's values (index 0 first); empty for a number.
    pub choices: &'static [&'static str],
}

impl Range {
    /// `[low, high]`.
    pub const fn new(low: f64, high: f64) -> Self {
        Self {
            low,
            high,
            low_open: false,
            zero_is_off: false,
            infinity_is_off: false,
            choices: &[],
        }
    }

    /// `(low, high]`.
    pub const fn above(low: f64, high: f64) -> Self {
        Self {
            low_open: true,
            ..Self::new(low, high)
        }
    }

    /// The same range, or 0 (off).
    pub const fn or_off(self) -> Self {
        Self {
            zero_is_off: true,
            ..self
        }
    }

    /// The same range, or `+∞` (no gate).
    pub const fn or_no_gate(self) -> Self {
        Self {
            infinity_is_off: true,
            ..self
        }
    }

    /// `[low, high]` of a count.
    // `u32` to `f64` is exact (every `u32` is an `f64`); `From` is not `const`.
    #[allow(clippy::as_conversions)]
    pub const fn counts(low: u32, high: u32) -> Self {
        Self::new(low as f64, high as f64)
    }

    /// One of `choices`, by index.
    pub const fn choice(choices: &'static [&'static str]) -> Self {
        // The last index, counted: `From` is not `const` and a choice has a few values.
        let mut last = 0_u32;
        let mut index = 1;
        while index < choices.len() {
            last = last.saturating_add(1);
            index += 1;
        }
        Self {
            choices,
            ..Self::counts(0, last)
        }
    }

    /// `false` or `true` (0 or 1).
    pub const FLAG: Self = Self::choice(&["false", "true"]);

    /// Whether `value` is accepted.
    pub fn contains(&self, value: f64) -> bool {
        let above_low = if self.low_open {
            value > self.low
        } else {
            value >= self.low
        };
        (above_low && value <= self.high)
            || (self.zero_is_off && value == 0.0)
            || (self.infinity_is_off && value == f64::INFINITY)
    }
}

/// A number as the reference and the error messages print it (`write_number`).
#[derive(Debug, Clone, Copy)]
pub struct Number(pub f64);

impl core::fmt::Display for Number {
    fn fmt(&self, formatter: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write_number(formatter, self.0)
    }
}

/// A number as the reference and the error messages print it: plain between 1e-3 and 1e6,
/// else in exponent form (`1e-150`, not a hundred and fifty zeros).
pub(crate) fn write_number(
    formatter: &mut core::fmt::Formatter<'_>,
    value: f64,
) -> core::fmt::Result {
    let magnitude = value.abs();
    if value != 0.0 && magnitude.is_finite() && !(1e-3..1e6).contains(&magnitude) {
        write!(formatter, "{value:e}")
    } else {
        write!(formatter, "{value}")
    }
}

/// [`Range`]'s interval without the off value: `[low, high]` or `(low, high]`, with
/// ` or +inf (no gate)` where that is accepted.
#[derive(Debug, Clone, Copy)]
pub struct Interval(pub Range);

impl core::fmt::Display for Interval {
    fn fmt(&self, formatter: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        let range = &self.0;
        formatter.write_str(if range.low_open { "(" } else { "[" })?;
        write_number(formatter, range.low)?;
        formatter.write_str(", ")?;
        write_number(formatter, range.high)?;
        formatter.write_str("]")?;
        if range.infinity_is_off {
            formatter.write_str(" or +inf (no gate)")?;
        }
        Ok(())
    }
}

/// `[low, high]`, `0 (off) or [low, high]`, `[low, high] or +inf (no gate)`, or a choice's
/// names separated by `, `.
impl core::fmt::Display for Range {
    fn fmt(&self, formatter: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        if !self.choices.is_empty() {
            for (index, name) in self.choices.iter().enumerate() {
                let separator = if index == 0 { "" } else { ", " };
                write!(formatter, "{separator}{name}")?;
            }
            return Ok(());
        }
        if self.zero_is_off {
            formatter.write_str("0 (off) or ")?;
        }
        write!(formatter, "{}", Interval(*self))
    }
}

/// A parameter's type: its value as a number for [`Range::contains`] and as a replay-setup
/// word (an `f64` by its bits, a count or a choice by its value).
pub trait ParamValue: Copy {
    /// The value as a number: a count exactly, a choice or flag as its index.
    fn to_number(self) -> f64;
    /// The replay-setup word.
    fn to_word(self) -> u64;
    /// The value of a replay-setup word; `None` for a count beyond the type or an index that
    /// names no choice.
    fn from_word(word: u64) -> Option<Self>;
    /// The value of a number ([`Self::to_number`]'s inverse); `None` for a number that is no
    /// value of the type (a fraction or a negative number for a count, ...).
    // The cast saturates; comparing back keeps only the whole numbers a word holds.
    #[allow(clippy::as_conversions)]
    fn from_number(number: f64) -> Option<Self> {
        let word = number as u64;
        // Exact: a whole number the word holds, else no value of a count or a choice.
        ((word as f64).to_bits() == number.to_bits())
            .then_some(word)
            .and_then(Self::from_word)
    }
}

impl ParamValue for f64 {
    fn to_number(self) -> f64 {
        self
    }
    fn from_number(number: f64) -> Option<Self> {
        Some(number)
    }
    fn to_word(self) -> u64 {
        self.to_bits()
    }
    fn from_word(word: u64) -> Option<Self> {
        Some(f64::from_bits(word))
    }
}

impl ParamValue for u32 {
    fn to_number(self) -> f64 {
        f64::from(self)
    }
    fn to_word(self) -> u64 {
        u64::from(self)
    }
    fn from_word(word: u64) -> Option<Self> {
        u32::try_from(word).ok()
    }
}

impl ParamValue for u8 {
    fn to_number(self) -> f64 {
        f64::from(self)
    }
    fn to_word(self) -> u64 {
        u64::from(self)
    }
    fn from_word(word: u64) -> Option<Self> {
        u8::try_from(word).ok()
    }
}

/// A choice's values in index order, for [`ParamValue`] by index.
macro_rules! choice_value {
    ($type:ty: $($variant:expr),+) => {
        impl ParamValue for $type {
            fn to_number(self) -> f64 {
                f64::from(u8::try_from(self.to_word()).unwrap_or(u8::MAX))
            }
            fn to_word(self) -> u64 {
                let variants = [$($variant),+];
                let index = variants.iter().position(|variant| *variant == self);
                index.and_then(|index| u64::try_from(index).ok()).unwrap_or(u64::MAX)
            }
            fn from_word(word: u64) -> Option<Self> {
                let variants = [$($variant),+];
                usize::try_from(word).ok().and_then(|index| variants.get(index).copied())
            }
        }
    };
}

choice_value!(bool: false, true);
choice_value!(FilterMode: FilterMode::OpenLoop, FilterMode::ClosedLoop);
choice_value!(FrameLoad: FrameLoad::PropagateThenFuse, FrameLoad::FuseOrPropagate);
choice_value!(SecondOrderAttitude: SecondOrderAttitude::Neglected, SecondOrderAttitude::Bounded);
choice_value!(
    EstimationPolicy: EstimationPolicy::AllBlocks,
    EstimationPolicy::PaperSchedule,
    EstimationPolicy::MotionObservability
);
