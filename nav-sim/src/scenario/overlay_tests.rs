//! Overlay resolution: merge, removal, chains and their errors, on files in a temporary
//! directory.

use std::path::{Path, PathBuf};

use super::overlay::{resolve_file, resolve_str, OverlayError, MAX_OVERLAY_DEPTH};
use super::{Scenario, ScenarioError, DEFAULT_SCENARIO_TOML};

fn write(directory: &Path, name: &str, text: &str) -> PathBuf {
    let path = directory.join(name);
    if let Some(parent) = path.parent() {
        std::fs::create_dir_all(parent).unwrap();
    }
    std::fs::write(&path, text).unwrap();
    path
}

/// A directory holding the default scenario as `default.toml`.
fn with_default() -> tempfile::TempDir {
    let directory = tempfile::tempdir().unwrap();
    write(directory.path(), "default.toml", DEFAULT_SCENARIO_TOML);
    directory
}

fn overlay_error(result: Result<impl std::fmt::Debug, ScenarioError>) -> (String, OverlayError) {
    match result.unwrap_err() {
        ScenarioError::Overlay { file, error } => (file, error),
        other => panic!("expected an overlay error, got {other:?}"),
    }
}

#[test]
fn an_overlay_changes_only_its_keys_and_replaces_arrays_whole() {
    let directory = with_default();
    let path = write(
        directory.path(),
        "blind.toml",
        "extends = \"default.toml\"\n[star_sensor]\nmax_rate_deg_per_s = 3.0\n\
         [[manoeuvre]]\nlabel = \"coast\"\nduration_s = 10.0\nramp_s = 0.0\n\
         body_rate_deg_per_s = [0.0, 0.0, 0.0]\nspecific_force_mps2 = [0.0, 0.0, 0.0]\n",
    );
    let (scenario, resolved) = Scenario::load_resolved(&path).unwrap();
    let default = Scenario::default_scenario().unwrap();
    assert_eq!(
        scenario.star_sensor.max_rate_deg_per_s.to_bits(),
        3.0_f64.to_bits()
    );
    assert_eq!(
        scenario.star_sensor.noise_arcsec.to_bits(),
        default.star_sensor.noise_arcsec.to_bits()
    );
    assert_eq!(scenario.manoeuvres.len(), 1);
    assert_eq!(
        scenario.manoeuvres[0].duration_s.to_bits(),
        10.0_f64.to_bits()
    );
    assert_eq!(scenario.gnss, default.gnss);
    assert_eq!(resolved.files().len(), 2);
    assert!(!resolved.table().contains_key("extends"));
}

#[test]
fn a_removal_drops_the_base_key_and_a_missing_one_is_refused() {
    let directory = with_default();
    write(
        directory.path(),
        "field.toml",
        "extends = \"default.toml\"\n[gravity]\nmodel = \"egm2008\"\ndegree = 8\norder = 8\n",
    );
    let path = write(
        directory.path(),
        "j2.toml",
        "extends = \"field.toml\"\nremove = [\"gravity\", \"gnss.velocity_noise_mps\"]\n",
    );
    let (file, error) = overlay_error(resolve_file(&path));
    assert!(file.ends_with("j2.toml"), "{file}");
    assert!(
        matches!(&error, OverlayError::RemoveMissing { key, base }
            if key == "gnss.velocity_noise_mps" && base.ends_with("field.toml")),
        "{error}"
    );
    let path = write(
        directory.path(),
        "j2.toml",
        "extends = \"field.toml\"\nremove = [\"gravity\"]\n",
    );
    let (scenario, resolved) = Scenario::load_resolved(&path).unwrap();
    assert!(scenario.gravity.is_none());
    assert_eq!(
        resolved.table(),
        resolve_str(DEFAULT_SCENARIO_TOML, "default")
            .unwrap()
            .table()
    );
}

#[test]
fn the_base_is_found_beside_the_overlay_and_a_chain_names_every_file() {
    let directory = with_default();
    write(
        directory.path(),
        "family/seed.toml",
        "extends = \"../default.toml\"\n[simulation]\nseed = 7\n",
    );
    let path = write(
        directory.path(),
        "family/deeper/noisy.toml",
        "extends = \"../seed.toml\"\n[gnss]\nnoise_m = 12.0\n",
    );
    let (scenario, resolved) = Scenario::load_resolved(&path).unwrap();
    assert_eq!(scenario.simulation.seed, 7);
    assert_eq!(scenario.gnss.noise_m.to_bits(), 12.0_f64.to_bits());
    assert_eq!(resolved.files().len(), 3);
    assert!(resolved.files()[2].ends_with("default.toml"));
}

#[test]
fn cycles_and_long_chains_are_refused_naming_the_chain() {
    let directory = with_default();
    write(directory.path(), "a.toml", "extends = \"b.toml\"\n");
    let path = write(directory.path(), "b.toml", "extends = \"a.toml\"\n");
    let (_, error) = overlay_error(resolve_file(&path));
    let OverlayError::Cycle { chain } = &error else {
        panic!("{error}");
    };
    assert_eq!(chain.matches(" -> ").count(), 2, "{chain}");
    assert!(chain.ends_with("b.toml"), "{chain}");

    let mut base = "default.toml".to_string();
    for level in 0..MAX_OVERLAY_DEPTH {
        let name = format!("level{level}.toml");
        write(directory.path(), &name, &format!("extends = \"{base}\"\n"));
        base = name;
    }
    let deepest = directory.path().join(&base);
    let (_, error) = overlay_error(resolve_file(&deepest));
    assert!(matches!(error, OverlayError::TooDeep { .. }), "{error}");
    let within = directory
        .path()
        .join(format!("level{}.toml", MAX_OVERLAY_DEPTH - 2));
    assert_eq!(
        resolve_file(&within).unwrap().files().len(),
        MAX_OVERLAY_DEPTH
    );
}

#[test]
fn bad_directives_and_type_changes_are_refused_naming_the_key() {
    let directory = with_default();
    for (text, expected) in [
        ("extends = 3\n", "`extends` must be the base file's path"),
        (
            "extends = \"default.toml\"\nremove = \"gravity\"\n",
            "list of dotted key paths",
        ),
        ("remove = [\"gravity\"]\n", "`remove` needs `extends`"),
        (
            "extends = \"default.toml\"\ngnss = 3\n",
            "`gnss` is an integer here and a table",
        ),
        (
            "extends = \"default.toml\"\n[imu.rate_hz]\nvalue = 1\n",
            "`imu.rate_hz` is a table here and a float",
        ),
    ] {
        let path = write(directory.path(), "bad.toml", text);
        let error = resolve_file(&path).unwrap_err().to_string();
        assert!(error.contains(expected), "{text}: {error}");
        assert!(error.contains("bad.toml"), "{error}");
    }
    let path = write(
        directory.path(),
        "missing.toml",
        "extends = \"nowhere.toml\"\n",
    );
    let error = resolve_file(&path).unwrap_err();
    assert!(matches!(&error, ScenarioError::Io { path, .. } if path.ends_with("nowhere.toml")));
}

#[test]
fn the_resolved_scenario_keeps_unknown_keys_refused() {
    let directory = with_default();
    let path = write(
        directory.path(),
        "typo.toml",
        "extends = \"default.toml\"\n[gnss]\nnoise_mm = 1.0\n",
    );
    let error = Scenario::load(&path).unwrap_err().to_string();
    assert!(
        error.contains("noise_mm") && error.contains("typo.toml"),
        "{error}"
    );
    let path = write(
        directory.path(),
        "range.toml",
        "extends = \"default.toml\"\n[imu]\nrate_hz = -1.0\n",
    );
    let error = Scenario::load(&path).unwrap_err();
    assert!(matches!(&error, ScenarioError::Invalid { key, .. } if key == "imu.rate_hz"));
}

#[test]
fn text_without_a_file_cannot_extend() {
    let error = Scenario::from_toml_str("extends = \"default.toml\"\n").unwrap_err();
    assert!(
        matches!(
            &error,
            ScenarioError::Overlay {
                error: OverlayError::NoDirectory,
                ..
            }
        ),
        "{error}"
    );
}

#[test]
fn the_hash_is_of_the_values_not_of_the_comments_or_the_chain() {
    let directory = with_default();
    let copy = write(
        directory.path(),
        "copy.toml",
        &format!("# a comment of its own\n{DEFAULT_SCENARIO_TOML}"),
    );
    let overlay = write(
        directory.path(),
        "same.toml",
        "extends = \"default.toml\"\n[simulation]\nseed = 20170415\n",
    );
    let other = write(
        directory.path(),
        "other.toml",
        "extends = \"default.toml\"\n[simulation]\nseed = 1\n",
    );
    let (_, builtin) = Scenario::default_resolved().unwrap();
    let hash = |path: &Path| resolve_file(path).unwrap().sha256("test").unwrap();
    let builtin = builtin.sha256("test").unwrap();
    assert_eq!(builtin.len(), 64);
    assert_eq!(hash(&copy), builtin);
    assert_eq!(hash(&overlay), builtin);
    assert_ne!(hash(&other), builtin);
    let text = resolve_file(&copy).unwrap().to_toml("test").unwrap();
    assert!(!text.contains('#'));
    assert_eq!(
        Scenario::from_toml_str(&text).unwrap(),
        Scenario::default_scenario().unwrap()
    );
}
