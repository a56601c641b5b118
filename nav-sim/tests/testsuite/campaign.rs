//! A sharded Monte Carlo campaign through the built `nav-sim` binary: the 42 s short scenario
//! flown as 3 shards in 3 processes and merged gives exactly the report of the campaign flown
//! in one process (text and `--json`, string for string), one run flown alone gives its shard
//! line bit for bit, and a merge with a shard missing names the first missing run.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Runs in the campaign: 7 over 3 shards gives shards of 3, 2 and 2 runs.
const RUNS: &str = "7";
const SHARDS: u64 = 3;

fn nav_sim(directory: &Path, arguments: &[&str]) -> Command {
    let mut command = Command::new(env!("CARGO_BIN_EXE_nav-sim"));
    command.args(arguments).current_dir(directory);
    command
}

/// Runs the command and returns its standard output, failing the test with its standard
/// error if it fails.
fn succeeded(output: Output) -> String {
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    String::from_utf8(output.stdout).unwrap()
}

/// The 42 s scenario of `tests/common` (10 s coast, 12 s rotation about z at 100 °/s, 20 s
/// coast) as TOML: the built-in scenario with its manoeuvre list replaced.
fn short_scenario(directory: &Path) -> PathBuf {
    let default = succeeded(nav_sim(directory, &["scenario"]).output().unwrap());
    let first = default.find("[[manoeuvre]]").unwrap();
    let filter = default.find("[filter]").unwrap();
    let segment = |label: &str, duration: &str, ramp: &str, rate: &str| {
        format!(
            "[[manoeuvre]]\nlabel = \"{label}\"\nduration_s = {duration}\nramp_s = {ramp}\n\
             body_rate_deg_per_s = {rate}\nspecific_force_mps2 = [0.0, 0.0, 0.0]\n\n"
        )
    };
    let quiet = "[2.4e-4, 2.4e-4, 2.4e-4]";
    let text = default[..first].to_string()
        + &segment("coast", "10.0", "0.0", quiet)
        + &segment("rotate z", "12.0", "1.0", "[0.0, 0.0, 100.0]")
        + &segment("coast", "20.0", "0.0", quiet)
        + &default[filter..];
    let path = directory.join("short.toml");
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn three_shards_merged_give_the_unsharded_campaign_and_a_run_alone_its_line() {
    let directory = tempfile::tempdir().unwrap();
    let directory = directory.path();
    short_scenario(directory);

    // The shards in three processes at once, as a job array would run them.
    let shards: Vec<_> = (0..SHARDS)
        .map(|index| {
            let shard = format!("{index}/{SHARDS}");
            nav_sim(
                directory,
                &[
                    "monte-carlo",
                    "short.toml",
                    "--runs",
                    RUNS,
                    "--shard",
                    &shard,
                    "--out",
                    "shards",
                ],
            )
            .spawn()
            .unwrap()
        })
        .collect();
    for shard in shards {
        succeeded(shard.wait_with_output().unwrap());
    }
    let whole = |json: bool| {
        let mut arguments = vec!["monte-carlo", "short.toml", "--runs", RUNS];
        arguments.extend(json.then_some("--json"));
        succeeded(nav_sim(directory, &arguments).output().unwrap())
    };
    let merged = |json: bool| {
        let mut arguments = vec!["merge", "shards"];
        arguments.extend(json.then_some("--json"));
        succeeded(nav_sim(directory, &arguments).output().unwrap())
    };
    let (whole_json, merged_json) = (whole(true), merged(true));
    assert_eq!(merged_json, whole_json);
    assert_eq!(merged(false), whole(false));
    let report: serde_json::Value = serde_json::from_str(&merged_json).unwrap();
    assert_eq!(report["runs"], 7);
    assert_eq!(report["states"].as_array().unwrap().len(), 15);
    assert!(report["states"][0]["abs_error_percentiles"]["p99"].is_number());
    assert!(
        report["position_error_m_percentiles"]["p50"]
            .as_f64()
            .unwrap()
            > 0.0
    );
    assert!(report["outliers"].is_array());
    // The health counters the runs raised, merged as flown.
    for entry in report["health"].as_array().unwrap() {
        let runs = entry["runs"].as_u64().unwrap();
        assert!((1..=7).contains(&runs), "{entry}");
        assert!(entry["total"].as_u64().unwrap() >= entry["max"].as_u64().unwrap());
    }

    // The shard lines carry each run's consistency over time: the merge draws the same plots
    // as the one-process campaign, bit for bit.
    succeeded(
        nav_sim(directory, &["merge", "shards", "--out", "merged-plots"])
            .output()
            .unwrap(),
    );
    succeeded(
        nav_sim(
            directory,
            &[
                "monte-carlo",
                "short.toml",
                "--runs",
                RUNS,
                "--out",
                "whole-plots",
            ],
        )
        .output()
        .unwrap(),
    );
    for plot in ["monte_carlo.png", "nees_over_time.png"] {
        let merged = std::fs::read(directory.join("merged-plots").join(plot)).unwrap();
        let whole = std::fs::read(directory.join("whole-plots").join(plot)).unwrap();
        assert!(!merged.is_empty() && merged == whole, "{plot}");
    }

    // Run 4 belongs to shard 1 (4 mod 3); flown alone it gives its line bit for bit.
    let shard_file = std::fs::read_to_string(directory.join("shards/shard-1-of-3.jsonl")).unwrap();
    let line = shard_file
        .lines()
        .find(|line| line.starts_with("{\"run\":4,"))
        .unwrap();
    let alone = succeeded(
        nav_sim(directory, &["monte-carlo", "short.toml", "--run", "4"])
            .output()
            .unwrap(),
    );
    assert_eq!(alone, format!("{line}\n"));

    // Without shard 2, the merge names its first run.
    std::fs::remove_file(directory.join("shards/shard-2-of-3.jsonl")).unwrap();
    let output = nav_sim(directory, &["merge", "shards"]).output().unwrap();
    let message = String::from_utf8_lossy(&output.stderr);
    assert!(!output.status.success());
    assert!(
        message.contains("run 2 of 7 is missing: it belongs to shard 2 of 3"),
        "{message}"
    );
}
