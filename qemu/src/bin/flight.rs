//! The panic-free flight build (`--no-default-features --features panic-never` and the
//! optional state blocks the mission flies, e.g. `state-blocks`; release
//! profile): the flight scheduler only, without the reference workloads, the dense
//! reference arithmetic or the ground analysis (none of them is compiled).
//!
//! Its panic handler calls a function that exists nowhere, so if the optimiser leaves any
//! panic path reachable from the flight code, the link fails with an undefined reference to
//! `panic_path_reachable_in_flight_build` (the "panic-never" technique). Inputs come through
//! `black_box`, so the optimiser cannot fold the flight code away and hide a panic path.
#![no_std]
#![no_main]

use core::hint::black_box;

use cortex_m_rt::entry;
use nav_qemu::exit_success;

#[entry]
fn main() -> ! {
    // The computer's size with this build's state blocks (scripts/test.sh checks its bound).
    defmt::println!(
        "NavigationComputer: {=usize} bytes",
        core::mem::size_of::<nav_fsw::scheduler::NavigationComputer>()
    );
    scheduler_frames();
    #[cfg(feature = "demo-panic-path")]
    demo_panic_path();
    exit_success()
}

/// The flight scheduler (input checks, strapdown, propagation, delayed fusion, calibration
/// manager, telemetry, the replay output record and its telemetry packets) over a few frames with a star
/// measurement and a GNSS fix, inputs through `black_box`: all of it must be panic-free.
fn scheduler_frames() {
    use core::mem::MaybeUninit;

    use nalgebra::{Quaternion, Vector3};
    use nav_core::frames::LaunchSite;
    use nav_core::strapdown::NavigationState;
    use nav_fsw::config::FswConfig;
    use nav_fsw::ports::{GnssFix, ImuSample, StarMeasurement};
    use nav_fsw::replay::{output_words, AssemblyCounts, FramePorts};
    use nav_fsw::scheduler::NavigationComputer;
    use nav_fsw::telemetry_packets::{PacketEncoder, PacketRates, MAX_FRAME_PACKET_BYTES};

    let site = black_box(LaunchSite {
        latitude_rad: 0.715,
        longitude_rad: 1.750,
        height_m: 1000.0,
        azimuth_rad: 3.316,
        earth_axis_ecef: [0.0, 0.0, 1.0],
    });
    let initial = black_box(NavigationState {
        attitude: Quaternion::new(1.0, 0.0, 0.0, 0.0),
        position_m: Vector3::new(1.0e5, 5.0e5, 2.0e5),
        velocity_mps: Vector3::new(7.5e3, 10.0, -20.0),
        time_s: 600.0,
    });
    // In place in a static slot, as a flight image keeps it.
    let Some(slot) =
        cortex_m::singleton!(: MaybeUninit<NavigationComputer> = MaybeUninit::uninit())
    else {
        return;
    };
    let Ok(computer) = NavigationComputer::init_in_place(
        slot,
        // PLACEHOLDER ground constants (this image has no star tracker or receiver): a flight
        // image uses its launch's, from `nav-sim ground-constants --format rust`.
        FswConfig::paper_defaults(site, nav_fsw::sensor_frames::SensorFrames::ALIGNED),
        initial,
    ) else {
        defmt::error!("flight scheduler: configuration refused");
        return;
    };
    // Rates and buffer through `black_box`: the encoder's refusals are in the build too.
    let mut packets = PacketEncoder::new(black_box(PacketRates::EVERY_FRAME));
    let mut packet_buffer = [0_u8; MAX_FRAME_PACKET_BYTES];
    for frame in 1..=10_u32 {
        let time_s = 600.0 + 0.002 * f64::from(frame);
        let mut ports = FramePorts::default();
        ports.imu.0 = Some(black_box(ImuSample::new(
            frame,
            time_s,
            [1e-5, -2e-5, 3e-3],
            [0.0, 1e-4, -2e-5],
        )));
        if frame == 5 {
            let _ = ports.star.0.push_back(black_box(StarMeasurement::new(
                time_s,
                [1.0, 1e-5, 0.0, 0.0],
                0,
            )));
        }
        if frame == 10 {
            // 4 ms late: the referral to the current error state runs too. The aligned sensor
            // frames: navigation time is GPS seconds of week 1000.
            let _ = ports.gnss.0.push_back(black_box(GnssFix::new(
                1_000,
                time_s - 0.004,
                [-1.1e6, 5.0e6, 4.2e6],
            )));
        }
        let telemetry = ports.run(computer);
        // A ground command between frames, through `black_box`: every command's path is in
        // the panic-free build.
        if let Some(command) = COMMANDS.get(usize::from(frame % 8 == 3)) {
            let _ = computer.command(black_box(*command));
        }
        let words = black_box(output_words(
            &telemetry,
            computer,
            &AssemblyCounts {
                measurements_dropped: ports.dropped,
                ..AssemblyCounts::default()
            },
        ));
        let buffer_bytes = black_box(MAX_FRAME_PACKET_BYTES);
        let packet_bytes = packet_buffer
            .get_mut(..buffer_bytes)
            .map_or(Ok(0), |buffer| packets.encode_frame(&words, buffer));
        let _ = black_box((packet_bytes, &packet_buffer));
        if frame == 10 {
            // The calibration kept across a reboot: exported, then loaded back through
            // `black_box`, so the record's code is in the panic-free build too.
            if let Ok(record) = computer.export_calibration() {
                let _ = computer.load_calibration(&black_box(record.to_bytes()));
            }
            defmt::println!(
                "flight scheduler: frame {=u32}, {=usize} output words, fusion {}",
                telemetry.frame,
                words.len(),
                telemetry.fusion
            );
        }
    }
}

/// The commands the flight loop passes through `black_box` (the optimiser cannot tell
/// which, so it keeps every command's code).
const COMMANDS: [nav_fsw::scheduler::Command; 2] = [
    nav_fsw::scheduler::Command::ClearSensorFaults,
    nav_fsw::scheduler::Command::ResetFilter {
        keep_calibration: true,
    },
];

/// A deliberately panicking slice index (enabled only by the `demo-panic-path` feature) that
/// the panic-never build must reject.
#[cfg(feature = "demo-panic-path")]
fn demo_panic_path() {
    let table = [1.0_f64, 2.0, 3.0];
    let index: usize = black_box(7);
    #[allow(clippy::indexing_slicing)]
    let value = table[index];
    defmt::println!("unreachable in a correct flight build: {=f64}", value);
}

#[panic_handler]
fn panic(_info: &core::panic::PanicInfo) -> ! {
    extern "Rust" {
        /// Deliberately never defined: referencing it makes a reachable panic a link error.
        fn panic_path_reachable_in_flight_build() -> !;
    }
    // SAFETY: never executed; the symbol does not exist, so a build that keeps this call fails
    // to link.
    unsafe { panic_path_reachable_in_flight_build() }
}
