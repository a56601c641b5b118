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
use nav_core::arithmetic::FilterArithmetic;
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
        FilterArithmetic,
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
        FilterArithmetic,
    ) -> Result<(), nav_core::NavError>,
    F: Fn(
        &mut nav_core::selftest::FilterPathFixture,
        FilterArithmetic,
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
    for (implementation, cost) in [
        FilterArithmetic::Structured,
        FilterArithmetic::DenseReference,
    ]
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

/// Runs the scheduler scenario ([`nav_qemu::scenario`]) and returns the costs of the worst
/// IMU-only frame, the star frame and the late-GNSS frame; `None` if a measurement was not
/// accepted.
fn run_scheduler(
    counter: &mut InstructionCounter,
    arithmetic: nav_fsw::scheduler::FilterArithmetic,
) -> Option<[u64; 3]> {
    use nav_fsw::telemetry::FrameFusion;
    use nav_qemu::scenario::{SchedulerScenario, GNSS_FRAME, STAR_FRAME};

    let mut scenario = SchedulerScenario::new(arithmetic)?;
    let mut imu_worst = 0;
    let mut star_cost = 0;
    let mut gnss_cost = 0;
    while let Some((frame, mut ports)) = scenario.next_frame() {
        let computer = &mut scenario.computer;
        let (telemetry, cost) = counter.measure(|| ports.run(computer)).ok()?;
        match (frame, telemetry.fusion) {
            (STAR_FRAME, FrameFusion::StarAccepted) => star_cost = cost,
            (GNSS_FRAME, FrameFusion::GnssAccepted) => gnss_cost = cost,
            (STAR_FRAME | GNSS_FRAME, _) => return None,
            (f, _) if f > 2 => imu_worst = imu_worst.max(cost),
            _ => {}
        }
    }
    // A scenario that ended early (its GNSS fix could not be formed) measured nothing.
    (star_cost > 0 && gnss_cost > 0).then_some([imu_worst, star_cost, gnss_cost])
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
