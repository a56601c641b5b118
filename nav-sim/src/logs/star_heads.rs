//! Which star-tracker heads reach the flight software: the flight software fuses one head,
//! and neither its star port nor its log record carries a head, so only head 0
//! (`[star_sensor]`) is handed over. Every place that hands simulated events to the flight
//! software or writes them to a log passes them through [`FlightStarHeads`], the one place to
//! change when the flight software takes several heads; it counts the measurements of the
//! other heads it holds back, and the runs report that count.

use crate::world::sensors::SensorEvent;

/// The star-tracker heads the flight software takes: heads `0..FLIGHT_SOFTWARE_STAR_HEADS`.
pub const FLIGHT_SOFTWARE_STAR_HEADS: usize = 1;

/// The filter between the simulator's events and the flight software (or a log): passes
/// every IMU and GNSS event and the star events of the heads the flight software takes,
/// counts the star events it holds back.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct FlightStarHeads {
    withheld: u64,
}

impl FlightStarHeads {
    /// Whether `event` goes to the flight software; a star event of another head is counted
    /// as withheld.
    pub fn hands_over(&mut self, event: &SensorEvent) -> bool {
        match event {
            SensorEvent::Star { head, .. } if *head >= FLIGHT_SOFTWARE_STAR_HEADS => {
                self.withheld += 1;
                false
            }
            _ => true,
        }
    }

    /// The star measurements of the other heads held back so far.
    pub fn withheld(&self) -> u64 {
        self.withheld
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Quaternion, Vector3};

    fn star(head: usize) -> SensorEvent {
        SensorEvent::Star {
            head,
            time_tag_s: 600.1,
            attitude_q_gs: Quaternion::new(1.0, 0.0, 0.0, 0.0),
        }
    }

    #[test]
    fn head_zero_imu_and_gnss_pass_and_the_other_heads_are_counted() {
        let imu = SensorEvent::Imu {
            frame_index: 0,
            time_s: 600.002,
            interval_s: 0.002,
            delta_angle_rad: Vector3::zeros(),
            delta_velocity_mps: Vector3::zeros(),
        };
        let mut heads = FlightStarHeads::default();
        assert!(heads.hands_over(&imu));
        assert!(heads.hands_over(&star(0)));
        assert_eq!(heads.withheld(), 0);
        assert!(!heads.hands_over(&star(1)));
        assert!(!heads.hands_over(&star(3)));
        assert_eq!(heads.withheld(), 2);
    }
}
