//! `nav-sim merge`: the shard files of a campaign read back and checked to form one campaign
//! (the same scenario, seed base, number of runs and of shards, each shard once, every run
//! exactly once).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use crate::campaign::runs::RunRecord;
use crate::campaign::shards::{CampaignError, Header, FORMAT, FORMAT_VERSION};
use crate::output::scenario_label::ScenarioLabel;

/// The shard files among `paths`: a directory stands for its `shard-*-of-*.jsonl` files
/// (sorted by name), a file for itself.
fn shard_files(paths: &[PathBuf]) -> Result<Vec<PathBuf>, CampaignError> {
    let mut files = Vec::new();
    for path in paths {
        if !path.is_dir() {
            files.push(path.clone());
            continue;
        }
        let read_error = |source| CampaignError::Read {
            path: path.clone(),
            source,
        };
        let mut found = Vec::new();
        for entry in std::fs::read_dir(path).map_err(read_error)? {
            let entry = entry.map_err(read_error)?;
            let name = entry.file_name().to_string_lossy().into_owned();
            if name.starts_with("shard-") && name.ends_with(".jsonl") {
                found.push(entry.path());
            }
        }
        found.sort();
        files.extend(found);
    }
    if files.is_empty() {
        return Err(no_shard_files(paths));
    }
    Ok(files)
}

fn no_shard_files(paths: &[PathBuf]) -> CampaignError {
    CampaignError::NoShardFiles {
        paths: paths
            .iter()
            .map(|path| path.display().to_string())
            .collect::<Vec<_>>()
            .join(", "),
    }
}

/// A shard file read back: its header and runs.
fn read_shard(path: &Path) -> Result<(Header, Vec<RunRecord>), CampaignError> {
    let text = std::fs::read_to_string(path).map_err(|source| CampaignError::Read {
        path: path.to_path_buf(),
        source,
    })?;
    let parse_error = |line: usize, message: String| CampaignError::Parse {
        path: path.to_path_buf(),
        line,
        message,
    };
    let mut lines = text
        .lines()
        .enumerate()
        .map(|(index, line)| (index + 1, line));
    let (_, first) = lines
        .next()
        .ok_or_else(|| parse_error(1, "empty file, expected the shard header".into()))?;
    let header: Header = serde_json::from_str(first)
        .map_err(|error| parse_error(1, format!("not a shard header: {error}")))?;
    if header.format != FORMAT || header.version != FORMAT_VERSION {
        return Err(parse_error(
            1,
            format!(
                "format {:?} version {}, expected {FORMAT:?} version {FORMAT_VERSION}",
                header.format, header.version
            ),
        ));
    }
    if header.shard >= header.shards {
        return Err(parse_error(
            1,
            format!("shard {} of {}", header.shard, header.shards),
        ));
    }
    let mut records = Vec::new();
    for (number, line) in lines {
        if line.trim().is_empty() {
            continue;
        }
        let record = RunRecord::parse(line).map_err(|message| parse_error(number, message))?;
        let expected_seed = header.seed_base.wrapping_add(record.run);
        if record.run >= header.runs || record.run % header.shards != header.shard {
            return Err(parse_error(
                number,
                format!(
                    "run {} does not belong to shard {} of {} of a {}-run campaign",
                    record.run, header.shard, header.shards, header.runs
                ),
            ));
        }
        if record.outcome.seed != expected_seed {
            return Err(parse_error(
                number,
                format!(
                    "run {} has seed {}, expected {expected_seed} (seed base {} + run)",
                    record.run, record.outcome.seed, header.seed_base
                ),
            ));
        }
        records.push(record);
    }
    Ok((header, records))
}

/// A campaign read back from its shard files.
#[derive(Debug, Clone, PartialEq)]
pub struct MergedCampaign {
    /// The scenario the first shard names: its file (`None`: the built-in scenario) and
    /// resolved SHA-256.
    pub scenario: ScenarioLabel,
    /// Every run, in run order.
    pub records: Vec<RunRecord>,
}

/// Reads the shard files in `paths` (directories stand for their `shard-*-of-*.jsonl` files)
/// and checks that they form one campaign: the same format, scenario hash, seed base, number
/// of runs and of shards, each shard once, every run exactly once.
///
/// # Errors
/// [`CampaignError`] naming the file and, for a duplicate or missing run, the run.
pub fn merge(paths: &[PathBuf]) -> Result<MergedCampaign, CampaignError> {
    let mut first: Option<(PathBuf, Header)> = None;
    let mut shards: BTreeMap<u64, PathBuf> = BTreeMap::new();
    let mut runs: BTreeMap<u64, (PathBuf, RunRecord)> = BTreeMap::new();
    for path in shard_files(paths)? {
        let (header, records) = read_shard(&path)?;
        if let Some((first_path, first_header)) = &first {
            if let Some(((field, first_value), (_, second_value))) = first_header
                .campaign()
                .into_iter()
                .zip(header.campaign())
                .find(|((_, first), (_, second))| first != second)
            {
                return Err(CampaignError::DifferentCampaigns {
                    first: first_path.clone(),
                    second: path,
                    field,
                    first_value,
                    second_value,
                });
            }
        }
        if let Some(earlier) = shards.insert(header.shard, path.clone()) {
            return Err(CampaignError::DuplicateShard {
                shard: header.shard,
                shards: header.shards,
                first: earlier,
                second: path,
            });
        }
        for record in records {
            if let Some((earlier, _)) = runs.get(&record.run) {
                return Err(CampaignError::DuplicateRun {
                    run: record.run,
                    first: earlier.clone(),
                    second: path,
                });
            }
            runs.insert(record.run, (path.clone(), record));
        }
        if first.is_none() {
            first = Some((path, header));
        }
    }
    let Some((_, header)) = first else {
        return Err(no_shard_files(paths));
    };
    if let Some(run) = (0..header.runs).find(|run| !runs.contains_key(run)) {
        let shard = run % header.shards;
        return Err(CampaignError::MissingRun {
            run,
            runs: header.runs,
            shard,
            shards: header.shards,
            shard_given: shards.contains_key(&shard),
        });
    }
    Ok(MergedCampaign {
        scenario: ScenarioLabel {
            file: header.scenario,
            sha256: header.scenario_sha256,
        },
        records: runs.into_values().map(|(_, record)| record).collect(),
    })
}
#[cfg(test)]
mod tests {
    use super::*;
    use crate::campaign::report::CampaignReport;
    use crate::campaign::shards::tests::record;
    use crate::campaign::shards::Shard;

    fn write_shards(directory: &Path, runs: u64, shards: u64, skip: Option<u64>) {
        for index in 0..shards {
            let header = Header {
                format: FORMAT.into(),
                version: FORMAT_VERSION,
                scenario: Some("my scenario.toml".into()),
                scenario_hash: "0123456789abcdef".into(),
                scenario_sha256: None,
                seed_base: 100,
                runs,
                shard: index,
                shards,
            };
            let mut text = serde_json::to_string(&header).unwrap() + "\n";
            for run in (Shard {
                index,
                count: shards,
            })
            .runs(runs)
            {
                if Some(run) != skip {
                    text += &(record(run).json_line().unwrap() + "\n");
                }
            }
            let name = Shard {
                index,
                count: shards,
            }
            .file_name();
            std::fs::write(directory.join(name), text).unwrap();
        }
    }

    #[test]
    fn merge_checks_the_campaign_and_names_the_run() {
        let directory = tempfile::tempdir().unwrap();
        write_shards(directory.path(), 7, 3, None);
        let merged = merge(&[directory.path().to_path_buf()]).unwrap();
        assert_eq!(
            merged.records.iter().map(|r| r.run).collect::<Vec<_>>(),
            (0..7).collect::<Vec<_>>()
        );
        assert_eq!(merged.scenario.file.as_deref(), Some("my scenario.toml"));
        assert_eq!(merged.scenario.sha256, None);
        // Run 4 with its first state 10σ off.
        let mut records = merged.records.clone();
        records[4].outcome.error[0] = 1.0e-2;
        let report = CampaignReport::new(&records, &merged.scenario).unwrap();
        assert_eq!(report.outliers.len(), 1);
        assert!(report
            .json()
            .unwrap()
            .contains("\"error_over_sigma\": 10.0"));
        let text = report.text();
        assert!(
            text.contains("  run 4 (seed 104): NEES ")
                && text.contains(
                    "gyro_bias x 10.00σ; re-run: nav-sim monte-carlo 'my scenario.toml' --run 4"
                ),
            "{text}"
        );

        // The same directory twice: every shard twice.
        let twice = merge(&[
            directory.path().to_path_buf(),
            directory.path().to_path_buf(),
        ])
        .unwrap_err()
        .to_string();
        assert!(twice.contains("shard 0 of 3 is given twice"), "{twice}");

        let gap = tempfile::tempdir().unwrap();
        write_shards(gap.path(), 7, 3, Some(4));
        let error = merge(&[gap.path().to_path_buf()]).unwrap_err().to_string();
        assert!(
            error.contains("run 4 of 7 is missing: it belongs to shard 1 of 3"),
            "{error}"
        );
        std::fs::remove_file(gap.path().join("shard-2-of-3.jsonl")).unwrap();
        let error = merge(&[gap.path().to_path_buf()]).unwrap_err().to_string();
        assert!(
            error.contains("run 2 of 7 is missing") && error.contains("not given"),
            "{error}"
        );

        let other = tempfile::tempdir().unwrap();
        write_shards(other.path(), 8, 3, None);
        let mixed = merge(&[
            directory.path().join("shard-0-of-3.jsonl"),
            other.path().join("shard-1-of-3.jsonl"),
        ])
        .unwrap_err()
        .to_string();
        assert!(
            mixed.contains("not one campaign: runs 7 against 8"),
            "{mixed}"
        );

        let duplicate = directory.path().join("shard-1-of-3.jsonl");
        let copy = other.path().join("copy.jsonl");
        let mut text = std::fs::read_to_string(&duplicate).unwrap();
        text = text.replace("\"shard\":1", "\"shard\":2");
        std::fs::write(&copy, text).unwrap();
        let error = merge(std::slice::from_ref(&copy)).unwrap_err().to_string();
        assert!(
            error.contains("copy.jsonl:2: run 1 does not belong to shard 2"),
            "{error}"
        );
    }
}
