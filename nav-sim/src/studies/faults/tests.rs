//! Unit tests of the campaign's frame schedule: every row injects at the same times in
//! seconds whatever the scenario's IMU rate, and the default 500 Hz schedule is the one the
//! rows were written for.

use nav_fsw::ports::{ImuSample, StarMeasurement};
use nav_fsw::replay::FramePorts;

use super::*;

fn scenario_at(rate_hz: f64) -> Scenario {
    let mut scenario = Scenario::default_scenario().unwrap();
    scenario.imu.rate_hz = rate_hz;
    scenario
}

fn row<'a>(classes: &'a [FaultClass], name: &str) -> &'a FaultClass {
    classes.iter().find(|class| class.name == name).unwrap()
}

/// The frames (from the fault start, over its first `seconds`) on which the row's injector
/// changes the IMU sample or the star measurement of a frame that carries both.
fn injected_frames(class: &FaultClass, frames: FrameSchedule, seconds: f64) -> Vec<i64> {
    let mut inject = (class.injector)(frames);
    (-2..frames.frames(seconds))
        .filter(|&relative| {
            let t = relative as f64 * frames.period_s();
            let sample = ImuSample::new(relative as u32, t, [1e-6 * t, 0.0, 0.0], [0.0; 3]);
            let measurement = StarMeasurement::new(t, [1.0, 0.0, 0.0, 0.0], 0);
            let mut ports = FramePorts::default();
            ports.imu.0 = Some(sample);
            ports.star.0.push_back(measurement).unwrap();
            inject(relative, &mut ports);
            ports.imu.0 != Some(sample) || ports.star.0.front() != Some(&measurement)
        })
        .collect()
}

/// `frames` as runs of consecutive frames: (start, length).
fn runs(frames: &[i64]) -> Vec<(i64, i64)> {
    let mut runs: Vec<(i64, i64)> = Vec::new();
    for &frame in frames {
        match runs.last_mut() {
            Some((start, length)) if *start + *length == frame => *length += 1,
            _ => runs.push((frame, 1)),
        }
    }
    runs
}

#[test]
fn the_default_schedule_is_500_hz_and_every_row_is_built() {
    let scenario = Scenario::default_scenario().unwrap();
    let frames = FrameSchedule::of(&scenario);
    assert_eq!(frames.rate_hz().to_bits(), 500.0_f64.to_bits());
    assert_eq!(frames.frames(1.0), 500);
    assert_eq!(frames.frames(0.5), 250);
    assert_eq!(frames.frames(600.0), 300_000);
    let classes = campaign_for(&scenario);
    assert_eq!(classes.len(), 40);
    assert_eq!(classes.len(), campaign().len());
    let saturation = row(&classes, "IMU saturation held 1 s");
    assert_eq!(saturation.counts[0].1, Expected::Exactly(1000));
}

#[test]
fn the_rows_inject_at_the_same_times_in_seconds_at_any_imu_rate() {
    for rate_hz in [250.0, 500.0, 1000.0] {
        let scenario = scenario_at(rate_hz);
        let frames = FrameSchedule::of(&scenario);
        let classes = campaign_for(&scenario);
        let hz = frames.frames(1.0);
        assert_eq!(hz, rate_hz as i64);
        let seconds = |runs: Vec<(i64, i64)>| -> Vec<(f64, f64)> {
            runs.into_iter()
                .map(|(start, length)| (start as f64 / rate_hz, length as f64 / rate_hz))
                .collect()
        };

        // Dropouts of 1, 10, 100 and 500 frames at 0, 1, 2 and 4 s.
        let dropouts = injected_frames(row(&classes, "IMU dropouts 1-500 frames"), frames, 6.0);
        assert_eq!(
            runs(&dropouts),
            [(0, 1), (hz, 10), (2 * hz, 100), (4 * hz, 500)],
            "{rate_hz} Hz"
        );

        // Ten single-sample spikes every 0.5 s.
        let spikes = injected_frames(row(&classes, "IMU spikes"), frames, 6.0);
        let spike_times: Vec<f64> = spikes.iter().map(|&f| f as f64 / rate_hz).collect();
        assert_eq!(
            spike_times,
            (0..10).map(|k| 0.5 * k as f64).collect::<Vec<_>>()
        );

        // Δθ saturated over [0, 1) s, Δv over [2, 3) s: every sample counted.
        let saturation = row(&classes, "IMU saturation held 1 s");
        let saturated = injected_frames(saturation, frames, 4.0);
        assert_eq!(seconds(runs(&saturated)), [(0.0, 1.0), (2.0, 1.0)]);
        assert_eq!(saturation.counts[0].1, Expected::Exactly(2 * hz as u32));

        // Star outages of 0.5 s at 0 s, 5 s at 2 s, 60 s at 10 s.
        let outages = injected_frames(row(&classes, "star outages 0.5 s, 5 s, 60 s"), frames, 75.0);
        assert_eq!(
            seconds(runs(&outages)),
            [(0.0, 0.5), (2.0, 5.0), (10.0, 60.0)]
        );

        // Clock steps at 0, 1 and 2 s, the wrap from 3 s on.
        let jumps = injected_frames(row(&classes, "IMU clock jumps"), frames, 4.0);
        assert_eq!(
            seconds(runs(&jumps)),
            [
                (0.0, 1.0 / rate_hz),
                (1.0, 1.0 / rate_hz),
                (2.0, 1.0 / rate_hz),
                (3.0, 1.0)
            ]
        );
    }
}
