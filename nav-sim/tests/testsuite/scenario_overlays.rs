//! The shipped scenarios as overlays: each resolves to the values recorded for it in
//! `scenarios/resolved.sha256` (`nav-sim scenario --resolved FILE | sha256sum`), so a change
//! to any resolved scenario, through its own file or a base, shows in review; and the
//! command prints what the hash is taken of.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

use nav_sim::scenario::overlay::resolve_file;

/// The bases every other shipped scenario extends, directly or through another overlay.
const BASES: [&str; 2] = ["default.toml", "upper_stage.toml"];

/// Most lines of all shipped scenario files together: the bases carry the comments, the
/// overlays only what differs.
const MAX_SCENARIO_LINES: usize = 4_000;

fn scenarios() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios")
}

/// The shipped scenario files by name.
fn shipped() -> BTreeMap<String, PathBuf> {
    std::fs::read_dir(scenarios())
        .unwrap()
        .map(|entry| entry.unwrap().path())
        .filter(|path| {
            path.extension()
                .is_some_and(|extension| extension == "toml")
        })
        .map(|path| {
            (
                path.file_name().unwrap().to_string_lossy().into_owned(),
                path,
            )
        })
        .collect()
}

/// `scenarios/resolved.sha256`: name -> SHA-256, in `sha256sum`'s format.
fn recorded() -> BTreeMap<String, String> {
    std::fs::read_to_string(scenarios().join("resolved.sha256"))
        .unwrap()
        .lines()
        .map(|line| {
            let (hash, name) = line.split_once("  ").unwrap();
            (name.to_string(), hash.to_string())
        })
        .collect()
}

#[test]
fn every_shipped_scenario_resolves_to_its_recorded_hash() {
    let shipped = shipped();
    let recorded = recorded();
    assert_eq!(
        shipped.keys().collect::<Vec<_>>(),
        recorded.keys().collect::<Vec<_>>(),
        "scenarios/resolved.sha256 lists every shipped scenario, and only those"
    );
    for (name, path) in &shipped {
        let hash = resolve_file(path).unwrap().sha256(name).unwrap();
        assert_eq!(&hash, &recorded[name], "{name} resolves to other values");
    }
}

#[test]
fn every_shipped_scenario_but_the_bases_is_a_short_overlay() {
    let mut lines = 0;
    for (name, path) in shipped() {
        let text = std::fs::read_to_string(&path).unwrap();
        lines += text.lines().count();
        let resolved = resolve_file(&path).unwrap();
        if BASES.contains(&name.as_str()) {
            assert_eq!(resolved.files().len(), 1, "{name}");
        } else {
            assert!(resolved.files().len() >= 2, "{name} extends no base");
            let root = resolved.files().last().unwrap();
            assert!(
                BASES.iter().any(|base| root.ends_with(base)),
                "{name} ends in {}",
                root.display()
            );
        }
    }
    assert!(
        lines <= MAX_SCENARIO_LINES,
        "{lines} lines of scenario TOML"
    );
}

#[test]
fn the_resolved_command_prints_the_text_the_hash_is_taken_of() {
    let path = scenarios().join("star_tracker_two_heads_unmodelled.toml");
    let output = Command::new(env!("CARGO_BIN_EXE_nav-sim"))
        .args(["scenario", "--resolved"])
        .arg(&path)
        .output()
        .unwrap();
    assert!(output.status.success(), "{output:?}");
    let text = String::from_utf8(output.stdout).unwrap();
    let resolved = resolve_file(&path).unwrap();
    assert_eq!(text, resolved.to_toml("test").unwrap());
    assert!(text.contains("star_second_head = false") && !text.contains("extends"));
    let scenario = nav_sim::Scenario::from_toml_str(&text).unwrap();
    assert_eq!(scenario, nav_sim::Scenario::load(&path).unwrap());
    assert_eq!(scenario.star_sensor.additional_heads.len(), 1);
}

#[test]
fn the_resolved_command_fails_on_a_bad_overlay_naming_file_and_key() {
    let directory = tempfile::tempdir().unwrap();
    let path = directory.path().join("stale.toml");
    let base = scenarios().join("default.toml");
    std::fs::write(
        &path,
        format!("extends = '{}'\nremove = [\"gravity\"]\n", base.display()),
    )
    .unwrap();
    let output = Command::new(env!("CARGO_BIN_EXE_nav-sim"))
        .args(["scenario", "--resolved"])
        .arg(&path)
        .output()
        .unwrap();
    assert!(!output.status.success());
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains("stale.toml") && stderr.contains("`remove` names `gravity`"),
        "{stderr}"
    );
}
