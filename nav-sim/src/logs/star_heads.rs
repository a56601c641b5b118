//! Which star-tracker heads reach the flight software or a log: the flight software takes
//! two heads when it is configured with a second (`star.second_head`, nav-fsw
//! `scheduler::heads`), one otherwise; the CSV sensor log carries the heads a tracker port
//! carries (0 and 1), the QEMU replay input the heads the flight software is told of. Every place that hands simulated events to the flight software or
//! writes them to a log passes them through [`FlightStarHeads`]; it counts the measurements of
//! the heads it holds back, and the runs report that count.

use crate::world::sensors::SensorEvent;

/// The filter between the simulator's events and the flight software (or a log): passes
/// every IMU and GNSS event and the star events of heads `0..heads`, counts the star events it
/// holds back. The default takes head 0 only ([`FlightStarHeads::port`]: the heads a port carries).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FlightStarHeads {
    heads: usize,
    withheld: u64,
}

impl Default for FlightStarHeads {
    fn default() -> Self {
        Self::taking(1)
    }
}

impl FlightStarHeads {
    /// Takes the star events of heads `0..heads`.
    pub fn taking(heads: usize) -> Self {
        Self { heads, withheld: 0 }
    }

    /// The heads a tracker port carries (nav-fsw `MAX_STAR_HEADS`: 0 and 1), what a sensor log
    /// holds.
    pub fn port() -> Self {
        Self::taking(nav_fsw::scheduler::MAX_STAR_HEADS)
    }

    /// The heads a tracker port carries for `scenario`: head 0, and head 1 when the scenario
    /// has an additional head (the flight software's `star.second_head`, `setup::fsw`, unless
    /// `[filter] star_second_head = false`).
    pub fn for_scenario(scenario: &crate::scenario::Scenario) -> Self {
        let second = usize::from(!scenario.star_sensor.additional_heads.is_empty());
        Self::taking(1 + second)
    }

    /// Whether `event` goes on; a star event of another head is counted as withheld.
    pub fn hands_over(&mut self, event: &SensorEvent) -> bool {
        match event {
            SensorEvent::Star { head, .. } if *head >= self.heads => {
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
        let mut two = FlightStarHeads::taking(2);
        assert!(two.hands_over(&star(0)) && two.hands_over(&star(1)));
        assert!(!two.hands_over(&star(2)));
        assert_eq!(two.withheld(), 1);
    }
}
