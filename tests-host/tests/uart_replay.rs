//! The replay over serial lines: the default flight's log split into one byte stream per
//! sensor, fed to the QEMU firmware's CMSDK UARTs (`qemu/src/bin/uart_replay.rs`) and run on
//! the host through the same nav-fsw stream readers and merge. Every output word and every
//! line counter must agree bit for bit, for clean lines and for a star-tracker line with
//! corrupt bytes; and the telemetry packets the firmware sends on UART4, decoded by nav-sim's
//! decoder (`nav-sim telemetry decode`), must give the host's output words, word for word,
//! every kind in every frame on the clean lines and at the slower rates the ground sets on
//! the corrupt ones.
//!
//! The QEMU cases are ignored by default: `scripts/test.sh` builds the firmware and runs them
//! with `NAV_QEMU_UART_REPLAY_ELF` set; `NAV_UART_REPLAY_SECONDS` (default 10) sets how much
//! of the flight is replayed.

use std::path::PathBuf;

use nav_fsw::log_record::{LogRecord, RECORD_SIZE};
use nav_fsw::telemetry_packets::{PacketKind, PacketRates};
use nav_sim::harness::target_replay::{run_records_on_host, FRAME_WORDS};
use nav_sim::harness::uart_replay::{replay_lines_on_target, run_lines_on_host, SensorLines};
use nav_sim::setup::fsw::replay_setup;
use nav_sim::Scenario;

fn seconds() -> u64 {
    std::env::var("NAV_UART_REPLAY_SECONDS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(10)
}

fn default_log(frames: u64) -> (Scenario, Vec<LogRecord>) {
    let scenario = Scenario::default_scenario().unwrap();
    let log = nav_sim::logs::sensor_log::simulated_records(&scenario, frames).unwrap();
    (scenario, log)
}

/// The star line with noise: three bytes of garbage after its first record, a record whose
/// tag byte is hit (lost: the reader resynchronises on the next record), and a truncated
/// record at the end of the line.
fn corrupt_star_line(lines: &mut SensorLines) {
    let star = &mut lines.star;
    assert!(
        star.len() >= 4 * RECORD_SIZE,
        "the log has too few star records"
    );
    star[2 * RECORD_SIZE] = 0x7F;
    star.splice(RECORD_SIZE..RECORD_SIZE, [0xA5, 0x02, 0x00]);
    star.extend_from_slice(&[2, 0, 0, 0, 0, 0, 0, 0, 1, 2, 3]);
}

/// Split into lines and merged back, a log gives the host the same frames, word for word,
/// as the log replayed whole: the merge puts records back in an order the frame assembler
/// places identically.
#[test]
fn lines_merged_back_replay_as_the_whole_log() {
    let (scenario, log) = default_log(5_000);
    let setup = replay_setup(&scenario).unwrap();
    let whole = run_records_on_host(&setup, log.clone()).unwrap();
    let lines = run_lines_on_host(&setup, &SensorLines::of_records(&log).unwrap()).unwrap();
    assert_eq!(whole.len() / FRAME_WORDS, 5_000);
    assert!(
        lines.frame_words == whole,
        "the merged lines replay differently"
    );
    let star_records = log
        .iter()
        .filter(|r| matches!(r, LogRecord::Star(_)))
        .count();
    assert_eq!(lines.counters[1].records as usize, star_records);
    assert_eq!(lines.counters.map(|c| c.resync_bytes), [0, 0, 0]);
}

/// Corrupt bytes on the star line cost exactly the record they hit: the reader drops and
/// counts the bytes until records decode again, and every other record arrives.
#[test]
fn a_corrupt_star_line_loses_only_the_record_that_was_hit() {
    let (scenario, log) = default_log(5_000);
    let setup = replay_setup(&scenario).unwrap();
    let mut lines = SensorLines::of_records(&log).unwrap();
    let star_records = lines.star.len() / RECORD_SIZE;
    corrupt_star_line(&mut lines);
    let output = run_lines_on_host(&setup, &lines).unwrap();
    let star = output.counters[1];
    assert_eq!(star.records as usize, star_records - 1);
    // 3 bytes of garbage + the 80 bytes of the record hit; the truncated tail stays unread.
    assert_eq!(star.resync_bytes, 3 + 80);
    assert_eq!(output.frame_words.len() / FRAME_WORDS, 5_000);
}

fn run_on_qemu(name: &str, corrupt: bool) {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..");
    let elf = root.join(
        std::env::var("NAV_QEMU_UART_REPLAY_ELF")
            .expect("NAV_QEMU_UART_REPLAY_ELF: the UART replay firmware"),
    );
    let (scenario, log) = default_log(seconds() * 500);
    let mut lines = SensorLines::of_records(&log).unwrap();
    if corrupt {
        corrupt_star_line(&mut lines);
    }
    // The clean lines with every packet kind in every frame; the corrupt ones with the
    // slower rates the ground sets (navigation every frame, the rest every 10 to 50).
    let rates = if corrupt {
        PacketRates::new([1, 10, 50, 25, 50]).unwrap()
    } else {
        PacketRates::EVERY_FRAME
    };
    let report = replay_lines_on_target(
        &scenario,
        &lines,
        rates,
        &elf,
        &root.join("qemu/run.sh"),
        &root.join("target/qemu").join(name),
    )
    .unwrap();
    print!("{}", report.text());
    if let Some(difference) = &report.difference {
        panic!("host and target differ first at {difference:?}");
    }
    if let Some(difference) = &report.packet_difference {
        panic!("the target's telemetry packets and the host differ first at {difference:?}");
    }
    let due: usize = report
        .host
        .frame_words
        .chunks_exact(FRAME_WORDS)
        .map(|frame| {
            PacketKind::ALL
                .iter()
                .filter(|k| rates.due(**k, frame[0]))
                .count()
        })
        .sum();
    assert_eq!(report.packets, due);
    // Per second (500 frames): 5 × 500, or 500 + 50 + 10 + 20 + 10.
    let packets_per_second = if corrupt { 590 } else { 2_500 };
    assert_eq!(due as u64, packets_per_second * seconds());
    assert_eq!(report.target.counters, report.host.counters);
    assert_eq!(report.frames, seconds() * 500);
    let expected_resync = if corrupt { 83 } else { 0 };
    assert_eq!(report.target.counters[1].resync_bytes, expected_resync);
}

#[test]
#[ignore = "needs qemu-system-arm and the UART replay firmware; run by scripts/test.sh"]
fn sensor_lines_on_the_uarts_replay_bit_for_bit_on_host_and_target() {
    run_on_qemu("uart-replay", false);
}

#[test]
#[ignore = "needs qemu-system-arm and the UART replay firmware; run by scripts/test.sh"]
fn a_corrupt_star_line_replays_bit_for_bit_on_host_and_target() {
    run_on_qemu("uart-replay-corrupt", true);
}
