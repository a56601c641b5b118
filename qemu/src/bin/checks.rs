//! Target checks run on QEMU (`cargo run --release --bin checks`): verifies the
//! instruction-count harness against a loop of known length, runs nav-core's reference
//! workload, the filter path and the observability analysis of the paper's motion states,
//! and prints their results as bit patterns for the host's bit-for-bit comparison.
//! Exit status 0 only if every check passed; a panic or HardFault exits with failure.
//!
//! Output lines the host test parses (decoded defmt):
//! `BITS <workload> <index> <16 hex digits>` and `COST <workload> <instructions>`.
#![no_std]
#![no_main]

use cortex_m_rt::entry;
use nav_core::selftest::Implementation;
use nav_qemu::cost::{known_length_loop, InstructionCounter};
use nav_qemu::{exit_failure, exit_success};

/// Iterations of the known-length loops (2 instructions each).
const CALIBRATION_ITERATIONS: [u32; 2] = [1_000_000, 123_457];
/// Largest accepted relative deviation of the harness from the known loop length (ppm): 1 %.
const CALIBRATION_TOLERANCE_PPM: u64 = 10_000;

#[entry]
fn main() -> ! {
    let Some(peripherals) = cortex_m::Peripherals::take() else {
        defmt::error!("core peripherals already taken");
        exit_failure()
    };
    let mut counter = InstructionCounter::new(peripherals.SYST);
    let mut all_passed = true;

    // 1. The harness against loops of known length (two lengths, one not a multiple of the
    //    tick, so a wrong factor cannot pass by coincidence).
    for iterations in CALIBRATION_ITERATIONS {
        all_passed &= check_known_loop(&mut counter, iterations);
    }

    // 2. The reference workload, bit patterns for the host comparison.
    match counter.measure(nav_core::selftest::reference_workload) {
        Ok((results, instructions)) => {
            print_bits("reference_workload", &results);
            defmt::println!("COST reference_workload {=u64}", instructions);
        }
        Err(error) => {
            all_passed = false;
            defmt::error!("reference workload: {}", error);
        }
    }

    // 3. The whole filter path: per-call costs, then the reference sequence's bits.
    all_passed &= filter_path(&mut counter);

    // 3b. Structured vs dense, operation by operation and for whole frames.
    all_passed &= structured_versus_dense(&mut counter);
    all_passed &= scheduler_frames(&mut counter);

    // 4. The observability analysis of the paper's motion states I, II, III (Table 1):
    //    24 singular values and the rank of each.
    all_passed &= observability(&mut counter);

    if all_passed {
        defmt::println!("target checks: all passed");
        exit_success()
    } else {
        defmt::error!("target checks: FAILED");
        exit_failure()
    }
}

/// Costs one call of each filter step, runs the reference sequence and prints its results.
fn filter_path(counter: &mut InstructionCounter) -> bool {
    use nav_core::selftest::FilterPathFixture;
    let Ok(mut fixture) = FilterPathFixture::new() else {
        defmt::error!("filter path: fixture rejected its configuration");
        return false;
    };
    let mut passed = true;
    let mut cost =
        |name: &str, result: Result<(Result<(), nav_core::NavError>, u64), _>| match result {
            Ok((Ok(()), instructions)) => defmt::println!("COST {=str} {=u64}", name, instructions),
            Ok((Err(error), _)) => {
                defmt::error!("filter path {=str}: {}", name, error);
                passed = false;
            }
            Err(error) => {
                defmt::error!("filter path {=str}: {}", name, error);
                passed = false;
            }
        };
    cost("strapdown_step", counter.measure(|| fixture.navigate()));
    cost("filter_propagate", counter.measure(|| fixture.propagate()));
    cost(
        "propagate_point",
        counter.measure(|| fixture.propagate_part(0)),
    );
    cost(
        "propagate_point_model",
        counter.measure(|| fixture.propagate_part(1)),
    );
    cost(
        "filter_star_update",
        counter.measure(|| fixture.star_update()),
    );
    cost("filter_reset", counter.measure(|| fixture.reset()));
    cost(
        "filter_gnss_update",
        counter.measure(|| fixture.gnss_update()),
    );
    cost(
        "filter_reset_after_gnss",
        counter.measure(|| fixture.reset()),
    );

    let Ok(mut sequence) = FilterPathFixture::new() else {
        return false;
    };
    match counter.measure(|| sequence.run_sequence()) {
        Ok((Ok(()), instructions)) => {
            print_bits("filter_path", &sequence.results());
            defmt::println!("COST filter_path_sequence {=u64}", instructions);
        }
        Ok((Err(error), _)) => {
            defmt::error!("filter path sequence: {}", error);
            passed = false;
        }
        Err(error) => {
            defmt::error!("filter path sequence: {}", error);
            passed = false;
        }
    }
    passed
}

/// Prints `COST <name>_structured`, `COST <name>_dense` and `RATIO <name> <dense/structured>`
/// (one decimal) for one operation run on two copies of the same state.
fn compare<F>(counter: &mut InstructionCounter, name: &str, operation: F) -> bool
where
    F: Fn(
        &mut nav_core::selftest::FilterPathFixture,
        Implementation,
    ) -> Result<(), nav_core::NavError>,
{
    compare_after(counter, name, |_, _| Ok(()), operation)
}

/// [`compare`] with an unmeasured `prepare` step on each copy first.
fn compare_after<G, F>(
    counter: &mut InstructionCounter,
    name: &str,
    prepare: G,
    operation: F,
) -> bool
where
    G: Fn(
        &mut nav_core::selftest::FilterPathFixture,
        Implementation,
    ) -> Result<(), nav_core::NavError>,
    F: Fn(
        &mut nav_core::selftest::FilterPathFixture,
        Implementation,
    ) -> Result<(), nav_core::NavError>,
{
    let Ok(mut fixture) = nav_core::selftest::FilterPathFixture::new() else {
        return false;
    };
    // A representative state: a few frames of navigation and propagation first.
    for _ in 0..5 {
        if fixture
            .navigate()
            .and_then(|()| fixture.propagate())
            .is_err()
        {
            return false;
        }
    }
    let mut costs = [0_u64; 2];
    for (implementation, cost) in [Implementation::Structured, Implementation::Dense]
        .into_iter()
        .zip(costs.iter_mut())
    {
        let mut copy = fixture;
        if prepare(&mut copy, implementation).is_err() {
            return false;
        }
        match counter.measure(|| operation(&mut copy, implementation)) {
            Ok((Ok(()), instructions)) => *cost = instructions,
            _ => {
                defmt::error!("{=str}: failed", name);
                return false;
            }
        }
    }
    let [structured, dense] = costs;
    defmt::println!("COST {=str}_structured {=u64}", name, structured);
    defmt::println!("COST {=str}_dense {=u64}", name, dense);
    let tenths = dense * 10 / structured.max(1);
    defmt::println!("RATIO {=str} {=u64}.{=u64}", name, tenths / 10, tenths % 10);
    true
}

/// The filter's operations, structured (flight) vs dense (reference), on the target.
fn structured_versus_dense(counter: &mut InstructionCounter) -> bool {
    let mut passed = true;
    passed &= compare(counter, "propagation", |f, i| f.propagate_with(i));
    passed &= compare(counter, "star_update", |f, i| f.star_update_with(i));
    passed &= compare(counter, "gnss_update", |f, i| f.gnss_update_with(i, 0.0));
    passed &= compare(counter, "gnss_update_late", |f, i| {
        f.gnss_update_with(i, 0.01)
    });
    passed &= compare_after(
        counter,
        "reset",
        |f, i| f.star_update_with(i),
        |f, i| f.reset_with(i),
    );
    passed &= compare(counter, "worst_frame", |f, i| f.worst_frame_with(i));
    passed
}

/// Worst IMU-only frame, a star frame and a frame fusing a GNSS fix 10 ms late, through the
/// flight scheduler (nav-fsw `run_frame`: input checks, strapdown, propagation, protection,
/// fusion with referral, reset, calibration manager, telemetry), structured vs dense.
fn scheduler_frames(counter: &mut InstructionCounter) -> bool {
    use nav_fsw::scheduler::FilterArithmetic;
    let mut costs = [[0_u64; 3]; 2];
    for (arithmetic, slot) in [
        FilterArithmetic::Structured,
        FilterArithmetic::DenseReference,
    ]
    .into_iter()
    .zip(costs.iter_mut())
    {
        match run_scheduler(counter, arithmetic) {
            Some(frame_costs) => *slot = frame_costs,
            None => {
                defmt::error!("scheduler frames: failed");
                return false;
            }
        }
    }
    let [structured, dense] = costs;
    for ((name, s), d) in [
        "scheduler_imu_frame",
        "scheduler_star_frame",
        "scheduler_gnss_frame",
    ]
    .into_iter()
    .zip(structured)
    .zip(dense)
    {
        defmt::println!("COST {=str}_structured {=u64}", name, s);
        defmt::println!("COST {=str}_dense {=u64}", name, d);
        let tenths = d * 10 / s.max(1);
        defmt::println!("RATIO {=str} {=u64}.{=u64}", name, tenths / 10, tenths % 10);
    }
    true
}

/// Runs 40 frames and returns the costs of the worst IMU-only frame, the star frame and the
/// late-GNSS frame; `None` if a measurement was not accepted.
fn run_scheduler(
    counter: &mut InstructionCounter,
    arithmetic: nav_fsw::scheduler::FilterArithmetic,
) -> Option<[u64; 3]> {
    use nalgebra::{Quaternion, Vector3};
    use nav_core::frames::LaunchSite;
    use nav_core::strapdown::NavigationState;
    use nav_fsw::config::FswConfig;
    use nav_fsw::ports::{GnssFix, ImuSample, StarMeasurement};
    use nav_fsw::replay::FramePorts;
    use nav_fsw::scheduler::NavigationComputer;
    use nav_fsw::telemetry::FrameFusion;

    let site = LaunchSite {
        latitude_rad: 0.715,
        longitude_rad: 1.750,
        height_m: 1000.0,
        azimuth_rad: 3.316,
        epoch_s: 0.0,
    };
    let initial = NavigationState {
        attitude: Quaternion::new(1.0, 0.0, 0.0, 0.0),
        position_m: Vector3::new(1.0e5, 5.0e5, 2.0e5),
        velocity_mps: Vector3::new(7.5e3, 10.0, -20.0),
        time_s: 600.0,
    };
    let mut computer = NavigationComputer::new(FswConfig::paper_defaults(site), initial).ok()?;
    computer.set_arithmetic(arithmetic);
    let mut imu_worst = 0;
    let mut star_cost = 0;
    let mut gnss_cost = 0;
    let mut gnss_time_s = 0.0;
    let mut gnss_position = Vector3::zeros();
    for frame in 1..=40_u32 {
        let time_s = 600.0 + 0.002 * f64::from(frame);
        let mut ports = FramePorts::default();
        ports.imu.0 = Some(ImuSample {
            sequence: frame,
            time_s,
            delta_angle_rad: [1e-4, -2e-4, 3e-3],
            delta_velocity_mps: [0.01, 0.04, -0.02],
        });
        let navigation = computer.navigation();
        if frame == 20 {
            let q = navigation.attitude;
            let _ = ports.star.0.push_back(StarMeasurement {
                time_tag_s: navigation.time_s,
                attitude_wxyz: [q.w, q.i, q.j, q.k],
            });
        }
        if frame == 30 {
            // The antenna position of frame 25 (10 ms late), 12 m off.
            let ecef = computer
                .launch_frame()
                .launch_inertial_to_ecef(
                    &(gnss_position + Vector3::new(12.0, -5.0, 3.0)),
                    gnss_time_s,
                )
                .ok()?;
            let _ = ports.gnss.0.push_back(GnssFix {
                time_tag_s: gnss_time_s,
                position_ecef_m: [ecef.x, ecef.y, ecef.z],
            });
        }
        if frame == 25 {
            gnss_time_s = navigation.time_s;
            gnss_position = navigation.position_m;
        }
        let (telemetry, cost) = counter.measure(|| ports.run(&mut computer)).ok()?;
        match (frame, telemetry.fusion) {
            (20, FrameFusion::StarAccepted) => star_cost = cost,
            (30, FrameFusion::GnssAccepted) => gnss_cost = cost,
            (20 | 30, _) => return None,
            (f, _) if f > 2 => imu_worst = imu_worst.max(cost),
            _ => {}
        }
    }
    Some([imu_worst, star_cost, gnss_cost])
}

/// Prints `values` as `BITS <workload> <index> <hex>` lines for the host comparison.
fn print_bits(workload: &str, values: &[f64]) {
    for (index, value) in values.iter().enumerate() {
        defmt::println!(
            "BITS {=str} {=usize} {=u64:016x}",
            workload,
            index,
            value.to_bits()
        );
    }
}

/// Runs the Table 1 observability workload and prints its singular values and ranks.
fn observability(counter: &mut InstructionCounter) -> bool {
    match counter.measure(nav_core::selftest::observability_workload) {
        Ok((Ok(results), instructions)) => {
            print_bits("observability", &results);
            defmt::println!("COST observability {=u64}", instructions);
            true
        }
        Ok((Err(error), _)) => {
            defmt::error!("observability: {}", error);
            false
        }
        Err(error) => {
            defmt::error!("observability: {}", error);
            false
        }
    }
}

/// Measures `known_length_loop(iterations)` and reports whether the harness agrees with the
/// known instruction count within [`CALIBRATION_TOLERANCE_PPM`].
fn check_known_loop(counter: &mut InstructionCounter, iterations: u32) -> bool {
    let expected = 2 * u64::from(iterations);
    match counter.measure(|| known_length_loop(iterations)) {
        Ok(((), measured)) => {
            let deviation_ppm = measured.abs_diff(expected) * 1_000_000 / expected;
            let passed = deviation_ppm <= CALIBRATION_TOLERANCE_PPM;
            defmt::println!(
                "ICOUNT known loop: expected {=u64} instructions, measured {=u64} (deviation {=u64} ppm, overhead {=u32} ticks) {=str}",
                expected,
                measured,
                deviation_ppm,
                counter.overhead_ticks(),
                if passed { "PASS" } else { "FAIL" }
            );
            passed
        }
        Err(error) => {
            defmt::error!("ICOUNT known loop: {}", error);
            false
        }
    }
}

#[panic_handler]
fn panic(_info: &core::panic::PanicInfo) -> ! {
    defmt::error!("panic on target");
    exit_failure()
}
