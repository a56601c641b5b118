//! Issue 6: the default scenario replayed through nav-fsw on the host and, from the very same
//! input file, by the firmware on QEMU (500 Hz SysTick frames in virtual time); every output
//! word of every frame must agree bit for bit. Prints the per-frame target cost (instructions)
//! by frame type and writes it to `target/qemu/replay-report.txt`.
//!
//! Ignored by default (needs QEMU and the firmware): `scripts/test.sh` builds the firmware
//! and runs it with `NAV_QEMU_REPLAY_ELF` set; `NAV_REPLAY_SECONDS` (default 300) sets how
//! much of the scenario is replayed (scripts/test.sh: 300 s).

use std::path::PathBuf;
use std::process::Command;

use nav_sim::target_replay::{
    cost_statistics, first_difference, output_file_words, run_on_host, write_input, FRAME_WORDS,
};
use nav_sim::Scenario;

#[test]
#[ignore = "needs qemu-system-arm and the replay firmware; run by scripts/test.sh"]
fn default_scenario_replays_bit_for_bit_on_host_and_target() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..");
    // Relative paths are relative to the workspace root.
    let elf = root.join(
        std::env::var("NAV_QEMU_REPLAY_ELF").expect("NAV_QEMU_REPLAY_ELF: the replay firmware"),
    );
    let seconds: u64 = std::env::var("NAV_REPLAY_SECONDS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(300);
    let directory = root.join("target/qemu/replay");
    std::fs::create_dir_all(&directory).unwrap();
    let scenario = Scenario::default_scenario().unwrap();
    let frames = seconds * 500;
    let input_path = directory.join("replay-in.bin");
    let written = write_input(
        &scenario,
        frames,
        std::io::BufWriter::new(std::fs::File::create(&input_path).unwrap()),
    )
    .unwrap();
    assert_eq!(written, frames.min(scenario.frame_count()));

    let started = std::time::Instant::now();
    let status = Command::new(root.join("qemu/run.sh"))
        .arg(elf.canonicalize().unwrap())
        .current_dir(&directory)
        .status()
        .unwrap();
    println!("QEMU replay of {written} frames: {:.1?}", started.elapsed());
    assert!(status.success(), "firmware replay failed: {status}");

    let target = output_file_words(&std::fs::read(directory.join("replay-out.bin")).unwrap());
    let host = run_on_host(&std::fs::read(&input_path).unwrap()).unwrap();
    assert_eq!(host.len() / FRAME_WORDS, usize::try_from(written).unwrap());
    if let Some(difference) = first_difference(&host, &target) {
        panic!("host and target differ first at {difference:?}");
    }
    let mut report = format!(
        "Replay of the default scenario's first {written} frames ({seconds} s): host and \
         target outputs identical bit for bit ({} words per frame).\n\
         Target cost per frame (instructions, QEMU -icount shift=0):\n",
        FRAME_WORDS - 1
    );
    for (name, statistics) in cost_statistics(&target) {
        report += &format!(
            "  {name:<18} frames {:>7}  min {:>9}  median {:>9}  worst {:>9}\n",
            statistics.frames, statistics.minimum, statistics.median, statistics.worst
        );
    }
    print!("{report}");
    std::fs::write(root.join("target/qemu/replay-report.txt"), report).unwrap();
}
