//! Bit-for-bit agreement of the Cortex-M7 build (run on QEMU) with the host build.
//!
//! These tests need the decoded log of the `checks` firmware, which `scripts/test.sh` produces
//! before running them; they are `#[ignore]`d so a plain `cargo test` without QEMU stays
//! green, and the script runs them with `--ignored`. Without the log they fail.

use tests_host::target_log::{default_checks_log, TargetLog};

fn checks_log() -> TargetLog {
    TargetLog::read(&default_checks_log()).unwrap_or_else(|error| panic!("{error}"))
}

#[test]
#[ignore = "needs the QEMU log: run scripts/test.sh"]
fn reference_workload_is_bit_identical_on_host_and_target() {
    let log = checks_log();
    let host = nav_core::selftest::reference_workload();
    log.compare("reference_workload", &host)
        .unwrap_or_else(|mismatch| panic!("host and Cortex-M7 differ: {mismatch}"));
    println!(
        "reference_workload: {} f64 results bit-identical on host and Cortex-M7 ({} instructions on target)",
        host.len(),
        log.costs.get("reference_workload").copied().unwrap_or(0)
    );
}

#[test]
#[ignore = "needs the QEMU log: run scripts/test.sh"]
fn instruction_counter_matches_a_loop_of_known_length_within_one_percent() {
    let log = checks_log();
    let lines: Vec<&String> = log
        .lines
        .iter()
        .filter(|line| line.starts_with("ICOUNT known loop"))
        .collect();
    assert_eq!(lines.len(), 2, "the firmware checks two loop lengths");
    for line in lines {
        assert!(line.ends_with("PASS"), "{line}");
    }
}

/// The cost of each workload on the target (instructions under `-icount`, deterministic for
/// one firmware binary) and the structured / dense ratios, as the committed
/// `docs/results/qemu-checks.md` holds them (`NAV_RESULTS_BLESS=1` rewrites it).
#[test]
#[ignore = "needs the QEMU log: run scripts/test.sh"]
fn target_costs_are_the_committed_results() {
    let log = checks_log();
    assert!(
        log.costs.len() >= 6,
        "only {} costs logged",
        log.costs.len()
    );
    let mut text = String::from("workload                                   instructions\n");
    for (name, instructions) in &log.costs {
        text += &format!("{name:<42} {instructions:>12}\n");
    }
    for line in log.lines.iter().filter(|line| line.starts_with("RATIO ")) {
        text += &format!("{line}\n");
    }
    tests_host::docs::check_results("qemu-checks.md", "scripts/results.sh qemu", &text);
}

#[test]
fn a_changed_bit_is_reported_with_its_index() {
    let log = TargetLog::parse("BITS w 0 3ff0000000000000\nBITS w 1 4000000000000000\n").unwrap();
    assert!(log.compare("w", &[1.0, 2.0]).is_ok());
    let mismatch = log
        .compare("w", &[1.0, f64::from_bits(2.0f64.to_bits() + 1)])
        .unwrap_err();
    assert!(mismatch.starts_with("w[1]"), "{mismatch}");
    assert!(log.compare("absent", &[1.0]).is_err());
}

#[test]
#[ignore = "needs the QEMU log: run scripts/test.sh"]
fn filter_path_is_bit_identical_on_host_and_target() {
    let log = checks_log();
    let mut fixture = nav_core::selftest::FilterPathFixture::new().expect("valid fixture");
    fixture.run_sequence().expect("the reference sequence runs");
    let host = fixture.results();
    log.compare("filter_path", &host)
        .unwrap_or_else(|mismatch| panic!("host and Cortex-M7 differ: {mismatch}"));
    println!(
        "filter_path (100 strapdown steps and propagations, 4 star and 2 GNSS updates, 6 resets): {} results bit-identical",
        host.len()
    );
    for step in [
        "strapdown_step",
        "filter_propagate",
        "filter_star_update",
        "filter_gnss_update",
        "filter_reset",
        "filter_path_sequence",
    ] {
        let instructions = log
            .costs
            .get(step)
            .unwrap_or_else(|| panic!("the target reports the cost of {step}"));
        println!("target cost {step}: {instructions} instructions");
    }
}

#[test]
#[ignore = "needs the QEMU log: run scripts/test.sh"]
fn observability_singular_values_are_bit_identical_on_host_and_target() {
    let log = checks_log();
    let host = nav_core::selftest::observability_workload().expect("fixed input is valid");
    log.compare("observability", &host)
        .unwrap_or_else(|mismatch| panic!("host and Cortex-M7 differ: {mismatch}"));
    // Each state's rank (the 25th value of its block) is 15 on both.
    for (label, block) in ["I", "II", "III"].iter().zip(host.chunks_exact(25)) {
        let rank = block.last().copied().unwrap_or(f64::NAN);
        assert!((rank - 15.0).abs() < 1e-12, "state {label}: rank {rank}");
        println!(
            "observability state {label}: rank {rank}, σ_max {:.6e}, σ_15 {:.6e}, σ_16 {:.3e}",
            block[0], block[14], block[15]
        );
    }
    println!(
        "observability: {} results (3 × 24 singular values + 3 ranks) bit-identical ({} instructions on target)",
        host.len(),
        log.costs.get("observability").copied().unwrap_or(0)
    );
}
