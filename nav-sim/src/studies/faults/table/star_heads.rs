//! Fault rows 38–40, a tracker with two heads: a step in either head, with or without the
//! other head blind, and what the flight software then hands the installation block to.
//! Each row flies the default scenario with a second head 90° from the first (the
//! `star_tracker_two_heads.toml` head: its mounting, its own installation error, the same
//! noise), told to the flight software.

use super::*;
use crate::studies::faults::Injector;

/// The step fault of these rows: 120″ about sensor x, seven times the gate's reach at 10″.
const STEP_DEG: f64 = 120.0 / 3600.0;

/// Adds the second head (boresight along body +y, 90° from head 0's) to the scenario.
fn add_second_head(scenario: &mut Scenario) {
    scenario.star_sensor.additional_heads = vec![scenario.star_sensor.head_across()];
}

/// On the frames of `window`, turns head `head`'s measurements by the step, and silences
/// head `silent` over `silent_window`.
fn stepped_and_silent(
    head: u8,
    window: std::ops::Range<i64>,
    silent: u8,
    silent_window: std::ops::Range<i64>,
) -> Injector {
    Box::new(move |relative, ports| {
        if silent_window.contains(&relative) {
            let kept: Vec<_> = ports
                .star
                .0
                .iter()
                .filter(|m| m.head != silent)
                .copied()
                .collect();
            ports.star.0.clear();
            for measurement in kept {
                // The port held these measurements a moment ago: they fit.
                let _ = ports.star.0.push_back(measurement);
            }
        }
        if window.contains(&relative) {
            for measurement in ports.star.0.iter_mut().filter(|m| m.head == head) {
                rotate_star(measurement, 0, STEP_DEG);
            }
        }
    })
}

/// The two-head rows, in row order.
pub(super) fn rows(_frames: FrameSchedule) -> Vec<FaultClass> {
    vec![
        FaultClass {
            name: "star head 0 step 120″, two heads",
            injected: "the fused head's measurements turned 120″ about sensor x for 30 s; the \
                       second head healthy",
            reaction: "head 0 declared faulty, the installation block handed to head 1; head 0 \
                       takes it back once 100 pairs in a row agree again",
            counts: vec![
                (counter!(star_head_handovers), Expected::Exactly(2)),
                (counter!(star_pair_rejections), Expected::AtLeast(250)),
            ],
            injection_s: 45.0,
            declared_faulty: [1, 0],
            criterion: Criterion::CalibrationWithinBound,
            scenario_change: Some(add_second_head),
            injector: |f| stepped_and_silent(0, 0..f.frames(30.0), 1, 0..0),
        },
        FaultClass {
            name: "star head 1 step 120″, head 0 blind 20 s",
            injected: "the second head's measurements turned 120″ for 60 s; the fused head \
                       silent from 30 s to 50 s",
            reaction: "the pairs rejected and their inconsistency counted, no head declared \
                       faulty; the outage hands nothing to the head that disagrees, head 0 is \
                       fused again when it returns",
            counts: vec![
                (counter!(star_pair_rejections), Expected::AtLeast(350)),
                (counter!(star_heads_inconsistent), Expected::AtLeast(1)),
                (counter!(star_outages), Expected::Exactly(1)),
                (counter!(star_head_handovers), Expected::Exactly(0)),
            ],
            injection_s: 60.0,
            declared_faulty: [0, 0],
            criterion: Criterion::CalibrationWithinBound,
            scenario_change: Some(add_second_head),
            injector: |f| {
                stepped_and_silent(1, 0..f.frames(60.0), 0, f.frames(30.0)..f.frames(50.0))
            },
        },
        FaultClass {
            name: "star head 0 blind 60 s, head 1 steps 120″ while it carries",
            injected: "the fused head silent for 60 s; the second head's measurements turned \
                       120″ from 20 s to 60 s",
            reaction: "the block handed to head 1 for the outage; head 1 declared faulty when \
                       it steps; head 0's return hands the block back",
            counts: vec![(counter!(star_head_handovers), Expected::Exactly(2))],
            injection_s: 60.0,
            declared_faulty: [1, 0],
            criterion: Criterion::CalibrationWithinBound,
            scenario_change: Some(add_second_head),
            injector: |f| {
                stepped_and_silent(1, f.frames(20.0)..f.frames(60.0), 0, 0..f.frames(60.0))
            },
        },
    ]
}
