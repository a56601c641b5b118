//! Fixed-capacity buffer of time-tagged measurements waiting to be fused.
//!
//! Measurements arrive asynchronously and possibly late (up to the configured latency). The
//! buffer keeps them sorted by time tag so the scheduler fuses them in time order once the
//! navigation solution has been propagated to (or past) their time; anything that can't be
//! fused correctly is refused with a reason the scheduler counts.

use heapless::Deque;

/// Why a measurement was refused by the buffer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum BufferRefusal {
    /// Older than `now − max_latency`, or not newer than the last measurement of its kind
    /// already accepted (out of order or duplicated).
    Stale,
    /// Time-tagged after the current navigation time plus one frame.
    Future,
    /// The buffer is full.
    Overflow,
    /// The time tag is not finite.
    NonFinite,
}

impl core::fmt::Display for BufferRefusal {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            Self::Stale => "older than the latency limit, or not newer than the last accepted",
            Self::Future => "time-tagged after the navigation time plus the future tolerance",
            Self::Overflow => "the measurement queue is full",
            Self::NonFinite => "the time tag is not finite",
        })
    }
}

impl core::error::Error for BufferRefusal {}

/// A time-ordered queue of measurements of type `M`, capacity `N`.
#[derive(Debug, Clone)]
pub struct MeasurementBuffer<M, const N: usize> {
    entries: Deque<(f64, M), N>,
    last_accepted_time_s: Option<f64>,
}

impl<M: Copy, const N: usize> Default for MeasurementBuffer<M, N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<M: Copy, const N: usize> MeasurementBuffer<M, N> {
    /// An empty buffer.
    pub const fn new() -> Self {
        Self {
            entries: Deque::new(),
            last_accepted_time_s: None,
        }
    }

    /// Number of buffered measurements.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// True when nothing is buffered.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// Accepts `measurement` time-tagged `time_tag_s` if it can still be fused: not older than
    /// `now_s − max_latency_s`, newer than the last accepted one, not later than
    /// `now_s + future_tolerance_s`.
    ///
    /// # Errors
    /// The [`BufferRefusal`] reason; the buffer is unchanged.
    pub fn push(
        &mut self,
        time_tag_s: f64,
        measurement: M,
        now_s: f64,
        max_latency_s: f64,
        future_tolerance_s: f64,
    ) -> Result<(), BufferRefusal> {
        if !time_tag_s.is_finite() {
            return Err(BufferRefusal::NonFinite);
        }
        if time_tag_s > now_s + future_tolerance_s {
            return Err(BufferRefusal::Future);
        }
        let not_newer = self
            .last_accepted_time_s
            .is_some_and(|last| time_tag_s <= last);
        if time_tag_s < now_s - max_latency_s || not_newer {
            return Err(BufferRefusal::Stale);
        }
        // Accepted tags strictly increase (checked above), so appending keeps the queue sorted.
        self.entries
            .push_back((time_tag_s, measurement))
            .map_err(|_| BufferRefusal::Overflow)?;
        self.last_accepted_time_s = Some(time_tag_s);
        Ok(())
    }

    /// Time tag of the oldest queued measurement.
    pub fn oldest_time_tag(&self) -> Option<f64> {
        self.entries.front().map(|(tag, _)| *tag)
    }

    /// Removes and returns the oldest measurement whose time tag is at or before `up_to_s`.
    pub fn pop_due(&mut self, up_to_s: f64) -> Option<(f64, M)> {
        let due = self.entries.front().is_some_and(|(tag, _)| *tag <= up_to_s);
        if due {
            self.entries.pop_front()
        } else {
            None
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn refuses_stale_future_duplicate_and_overflow_and_pops_in_order() {
        let mut buffer: MeasurementBuffer<u8, 2> = MeasurementBuffer::new();
        assert_eq!(
            buffer.push(9.0, 1, 10.0, 0.5, 0.002),
            Err(BufferRefusal::Stale)
        );
        assert_eq!(
            buffer.push(10.1, 1, 10.0, 0.5, 0.002),
            Err(BufferRefusal::Future)
        );
        assert_eq!(
            buffer.push(f64::NAN, 1, 10.0, 0.5, 0.002),
            Err(BufferRefusal::NonFinite)
        );
        assert_eq!(buffer.push(9.8, 1, 10.0, 0.5, 0.002), Ok(()));
        assert_eq!(
            buffer.push(9.8, 2, 10.0, 0.5, 0.002),
            Err(BufferRefusal::Stale)
        );
        assert_eq!(
            buffer.push(9.7, 2, 10.0, 0.5, 0.002),
            Err(BufferRefusal::Stale)
        );
        assert_eq!(buffer.push(9.9, 2, 10.0, 0.5, 0.002), Ok(()));
        assert_eq!(
            buffer.push(9.95, 3, 10.0, 0.5, 0.002),
            Err(BufferRefusal::Overflow)
        );
        assert_eq!(buffer.pop_due(9.75), None);
        assert_eq!(buffer.pop_due(10.0), Some((9.8, 1)));
        assert_eq!(buffer.pop_due(10.0), Some((9.9, 2)));
        assert!(buffer.is_empty());
    }

    /// The acceptance window is closed at both ends: `<` against `<=` at the edges, and the
    /// sign of the future tolerance.
    #[test]
    fn the_acceptance_window_includes_its_edges_and_reports_the_oldest_tag() {
        let mut buffer: MeasurementBuffer<u8, 4> = MeasurementBuffer::new();
        assert!(buffer.is_empty());
        assert_eq!(buffer.len(), 0);
        assert_eq!(buffer.oldest_time_tag(), None);
        // now 10 s, latency 0.25 s, future tolerance 0.5 s: all exact in binary.
        assert_eq!(buffer.push(9.75, 1, 10.0, 0.25, 0.5), Ok(()));
        assert_eq!(buffer.push(10.25, 2, 10.0, 0.25, 0.5), Ok(()));
        assert_eq!(buffer.push(10.5, 3, 10.0, 0.25, 0.5), Ok(()));
        assert!(!buffer.is_empty());
        assert_eq!(buffer.len(), 3);
        assert_eq!(
            buffer.oldest_time_tag().map(f64::to_bits),
            Some(9.75_f64.to_bits())
        );
        assert_eq!(buffer.pop_due(10.0), Some((9.75, 1)));
        assert_eq!(
            buffer.oldest_time_tag().map(f64::to_bits),
            Some(10.25_f64.to_bits())
        );
        assert_eq!(buffer.len(), 2);
    }
}
