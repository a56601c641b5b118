//! Monte Carlo campaigns split into shards and merged again: `nav-sim monte-carlo --shard K/M`
//! flies its share of the runs and writes one JSON line per run, `nav-sim merge` reads the
//! shard files back and prints the report of the whole campaign, identical to the report of
//! the same campaign flown in one process (`docs/guide/monte-carlo.md`).
//!
//! Run `k` of a campaign has the seed `scenario seed + k` (wrapping), and its sensor-error
//! truth and sensor noise come from that seed alone
//! ([`crate::setup::prior::with_truth_drawn_from_prior`]), so a run gives the same bits in any shard,
//! in any process and alone (`nav-sim monte-carlo --run K`).
//!
//! Sharding is round robin: run `k` belongs to shard `k mod M` (shards numbered from 0, as
//! Slurm array indices and Kubernetes completion indices are), so the shards get equal shares
//! of the runs whatever `N` and a shard's runs spread over the whole campaign.
//!
//! A shard file `shard-K-of-M.jsonl` is JSON Lines: a header object naming the campaign, then
//! one object per run. Every float that the report uses is written as the 16 hexadecimal
//! digits of its IEEE 754 bits, so it reads back bit for bit whatever the JSON parser.

use std::io::Write as _;
use std::path::{Path, PathBuf};

use nalgebra::{SMatrix, SVector};
use serde::{Deserialize, Serialize};

use crate::campaign::monte_carlo::{self, MonteCarloError, RunOutcome, CALIBRATION_STATES};
use crate::campaign::runs::{fly_runs, RunRecord};
use crate::harness::flight::{FlightError, NisSum};
use crate::harness::optional_blocks::BlockOutcome;
use crate::output::{OutputError, OutputFile};
use crate::scenario::Scenario;

/// The `format` field of a shard file's header.
pub const FORMAT: &str = "nav-sim monte-carlo shard";

/// The version of the shard file format.
pub const FORMAT_VERSION: u32 = 2;

/// Why a campaign, a shard file or a merge failed; an error about a file names it.
#[derive(Debug, thiserror::Error)]
pub enum CampaignError {
    /// `--shard` is not `K/M` with `K < M`.
    #[error("{text:?} is not K/M with whole numbers 0 ≤ K < M (e.g. 0/4)")]
    BadShard {
        /// The text given.
        text: String,
    },
    /// A file could not be read.
    #[error("cannot read {}: {source}", path.display())]
    Read {
        /// The path.
        path: PathBuf,
        /// The I/O error.
        source: std::io::Error,
    },
    /// A line of a shard file is not what the format says.
    #[error("{}:{line}: {message}", path.display())]
    Parse {
        /// The file.
        path: PathBuf,
        /// Line number, from 1.
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// Two shard files belong to different campaigns.
    #[error(
        "{} and {} are not one campaign: {field} {first_value} against {second_value}",
        first.display(),
        second.display()
    )]
    DifferentCampaigns {
        /// The first file read.
        first: PathBuf,
        /// The file that differs from it.
        second: PathBuf,
        /// The header field that differs.
        field: &'static str,
        /// Its value in `first`.
        first_value: String,
        /// Its value in `second`.
        second_value: String,
    },
    /// The same shard is given twice.
    #[error("shard {shard} of {shards} is given twice: {} and {}", first.display(), second.display())]
    DuplicateShard {
        /// The shard index.
        shard: u64,
        /// The number of shards.
        shards: u64,
        /// The first file.
        first: PathBuf,
        /// The second file.
        second: PathBuf,
    },
    /// A run appears twice.
    #[error("run {run} appears twice: in {} and in {}", first.display(), second.display())]
    DuplicateRun {
        /// The run index.
        run: u64,
        /// The file of its first appearance.
        first: PathBuf,
        /// The file of its second appearance.
        second: PathBuf,
    },
    /// A run of the campaign is in no file.
    #[error(
        "run {run} of {runs} is missing: it belongs to shard {shard} of {shards} \
         (shard-{shard}-of-{shards}.jsonl{})",
        if *shard_given { ", which lacks it" } else { ", not given" }
    )]
    MissingRun {
        /// The run index.
        run: u64,
        /// Runs in the campaign.
        runs: u64,
        /// The shard it belongs to.
        shard: u64,
        /// The number of shards.
        shards: u64,
        /// Whether that shard's file was given.
        shard_given: bool,
    },
    /// No shard file among the paths given.
    #[error("no shard files (shard-K-of-M.jsonl) in {paths}")]
    NoShardFiles {
        /// The paths given, comma separated.
        paths: String,
    },
    /// An output file could not be written.
    #[error(transparent)]
    Output(#[from] OutputError),
    /// A run failed or the statistics could not be computed.
    #[error(transparent)]
    MonteCarlo(#[from] MonteCarloError<FlightError>),
}

/// One shard of a campaign, `index` of `count` (`--shard K/M`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    /// The shard's index `K`, from 0.
    pub index: u64,
    /// The number of shards `M`, 1 or more.
    pub count: u64,
}

impl std::str::FromStr for Shard {
    type Err = CampaignError;

    fn from_str(text: &str) -> Result<Self, Self::Err> {
        let bad = || CampaignError::BadShard {
            text: text.to_string(),
        };
        let (index, count) = text.split_once('/').ok_or_else(bad)?;
        let index: u64 = index.trim().parse().map_err(|_| bad())?;
        let count: u64 = count.trim().parse().map_err(|_| bad())?;
        if index < count {
            Ok(Self { index, count })
        } else {
            Err(bad())
        }
    }
}

impl Shard {
    /// The runs of a campaign of `runs` runs that belong to this shard: `k` with
    /// `k mod M = K`, in increasing order.
    pub fn runs(self, runs: u64) -> Vec<u64> {
        (self.index..runs)
            .step_by(usize::try_from(self.count).unwrap_or(usize::MAX))
            .collect()
    }

    /// The shard's file name, `shard-K-of-M.jsonl`.
    pub fn file_name(self) -> String {
        format!("shard-{}-of-{}.jsonl", self.index, self.count)
    }
}

/// FNV-1a (64 bit) of the scenario as parsed (its `Debug` rendering, which writes every float
/// in its shortest round-trip form): shards flown from the same scenario, whatever its file's
/// comments or layout, agree; a changed setting changes it.
pub fn scenario_hash(scenario: &Scenario) -> u64 {
    format!("{scenario:?}")
        .bytes()
        .fold(0xcbf2_9ce4_8422_2325, |hash, byte| {
            (hash ^ u64::from(byte)).wrapping_mul(0x0100_0000_01b3)
        })
}

fn hex(value: f64) -> String {
    format!("{:016x}", value.to_bits())
}

fn from_hex(text: &str) -> Result<f64, String> {
    if text.len() != 16 {
        return Err(format!("{text:?} is not 16 hexadecimal digits"));
    }
    u64::from_str_radix(text, 16)
        .map(f64::from_bits)
        .map_err(|_| format!("{text:?} is not 16 hexadecimal digits"))
}

/// A NIS sum on a line: the sum's bits and the update count.
#[derive(Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct NisLine {
    sum: String,
    updates: u64,
}

/// One instant of a run's consistency over time on a line (`monte_carlo::OverTimeSample`):
/// time and NEES as bits (`null`: no NEES), the NIS since the previous instant.
#[derive(Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct OverTimeLine {
    time_s: String,
    nees: Option<String>,
    star_nis: NisLine,
    gnss_nis: NisLine,
}

/// A run on a line. `nees` and `max_error_over_sigma` are for people and tools reading the
/// file (decimal); the merge recomputes them from the bits.
#[derive(Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct RunLine {
    run: u64,
    seed: u64,
    nees: Option<f64>,
    max_error_over_sigma: f64,
    /// Final error, estimate − truth, of the 15 states.
    error: Vec<String>,
    /// Final filter 1σ of the 15 states (the covariance diagonal's square roots).
    sigma: Vec<String>,
    /// Final covariance of the 15 states, column by column.
    covariance: Vec<String>,
    star_nis: NisLine,
    gnss_nis: NisLine,
    position_error_m: String,
    /// The run's consistency over time (absent in files that do not carry it).
    #[serde(default)]
    over_time: Vec<OverTimeLine>,
    /// The flight software's non-zero health counters at the end of the run, by name.
    health: std::collections::BTreeMap<String, u32>,
    /// The systematic IMU error states' final error and covariance (absent when the filter
    /// does not estimate them, so such lines read as before the field existed).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    imu_error: Option<BlockLine>,
    /// The correlated GNSS error states' final error and covariance (absent when the filter
    /// does not estimate them).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    gnss_error: Option<BlockLine>,
}

/// An optional state block of a run, as hexadecimal bits.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct BlockLine {
    /// Final error, truth − estimate (the systematic IMU errors' truth in the filter's gauge).
    error: Vec<String>,
    /// Final covariance, column by column.
    covariance: Vec<String>,
}

impl BlockLine {
    fn of<const N: usize>(outcome: &BlockOutcome<N>) -> Self {
        Self {
            error: outcome.error.iter().copied().map(hex).collect(),
            covariance: outcome.covariance.iter().copied().map(hex).collect(),
        }
    }

    /// The block's outcome; `name` (the line's key) names it in a message.
    fn outcome<const N: usize>(&self, name: &str) -> Result<BlockOutcome<N>, String> {
        let floats = |field: &str, texts: &[String], count: usize| {
            if texts.len() != count {
                return Err(format!(
                    "{name}.{field}: {} values, expected {count}",
                    texts.len()
                ));
            }
            texts
                .iter()
                .map(|text| from_hex(text).map_err(|message| format!("{name}.{field}: {message}")))
                .collect::<Result<Vec<f64>, String>>()
        };
        Ok(BlockOutcome {
            error: SVector::from_iterator(floats("error", &self.error, N)?),
            covariance: SMatrix::from_iterator(floats("covariance", &self.covariance, N * N)?),
        })
    }
}

/// The first line of a shard file.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq, Eq)]
#[serde(deny_unknown_fields)]
pub(crate) struct Header {
    pub(crate) format: String,
    pub(crate) version: u32,
    /// The scenario file as given on the command line (`null`: the built-in one); only for
    /// the re-run commands of the report, the campaign is identified by the hash.
    pub(crate) scenario: Option<String>,
    pub(crate) scenario_hash: String,
    /// The SHA-256 of the resolved scenario, which the report names (absent in shard files
    /// written before it was recorded).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(crate) scenario_sha256: Option<String>,
    pub(crate) seed_base: u64,
    pub(crate) runs: u64,
    pub(crate) shard: u64,
    pub(crate) shards: u64,
}

impl Header {
    /// The fields that name the campaign, which every shard file of it shares.
    pub(crate) fn campaign(&self) -> [(&'static str, String); 4] {
        [
            ("scenario hash", self.scenario_hash.clone()),
            ("seed base", self.seed_base.to_string()),
            ("runs", self.runs.to_string()),
            ("shards", self.shards.to_string()),
        ]
    }
}

/// The largest |error| / 1σ over the states of a run.
fn max_error_over_sigma(outcome: &RunOutcome) -> f64 {
    (0..CALIBRATION_STATES)
        .map(|state| outcome.error[state].abs() / outcome.covariance[(state, state)].sqrt())
        .fold(0.0, f64::max)
}

impl RunRecord {
    /// The run as one JSON line (no newline): `{"run", "seed", "nees", "max_error_over_sigma",
    /// "error", "sigma", "covariance", "star_nis", "gnss_nis", "position_error_m", "over_time",
    /// "health"}`, floats
    /// except `nees` and `max_error_over_sigma` as the hexadecimal digits of their bits.
    ///
    /// # Errors
    /// A serialisation error (none expected).
    pub fn json_line(&self) -> Result<String, serde_json::Error> {
        let outcome = &self.outcome;
        let nis = |sum: &NisSum| NisLine {
            sum: hex(sum.sum),
            updates: sum.updates,
        };
        serde_json::to_string(&RunLine {
            run: self.run,
            seed: outcome.seed,
            nees: monte_carlo::run_nees(outcome),
            max_error_over_sigma: max_error_over_sigma(outcome),
            error: outcome.error.iter().copied().map(hex).collect(),
            sigma: outcome
                .covariance
                .diagonal()
                .iter()
                .map(|variance| hex(variance.sqrt()))
                .collect(),
            covariance: outcome.covariance.iter().copied().map(hex).collect(),
            star_nis: nis(&outcome.star_nis),
            gnss_nis: nis(&outcome.gnss_nis),
            position_error_m: hex(outcome.position_error_m),
            over_time: outcome
                .over_time
                .iter()
                .map(|sample| OverTimeLine {
                    time_s: hex(sample.time_s),
                    nees: sample.nees.map(hex),
                    star_nis: nis(&sample.star_nis),
                    gnss_nis: nis(&sample.gnss_nis),
                })
                .collect(),
            health: outcome.health.clone(),
            imu_error: outcome.imu_error.as_ref().map(BlockLine::of),
            gnss_error: outcome.gnss_error.as_ref().map(BlockLine::of),
        })
    }

    /// Reads a line written by [`json_line`](Self::json_line).
    ///
    /// # Errors
    /// A message saying what is wrong with the line.
    pub fn parse(line: &str) -> Result<Self, String> {
        let parsed: RunLine = serde_json::from_str(line).map_err(|error| error.to_string())?;
        let floats = |name: &str, texts: &[String], count: usize| {
            if texts.len() != count {
                return Err(format!("{name}: {} values, expected {count}", texts.len()));
            }
            texts
                .iter()
                .map(|text| from_hex(text).map_err(|message| format!("{name}: {message}")))
                .collect::<Result<Vec<f64>, String>>()
        };
        let nis = |name: &str, line: &NisLine| {
            Ok::<_, String>(NisSum {
                sum: from_hex(&line.sum).map_err(|message| format!("{name}: {message}"))?,
                updates: line.updates,
            })
        };
        let error = floats("error", &parsed.error, CALIBRATION_STATES)?;
        let covariance = floats(
            "covariance",
            &parsed.covariance,
            CALIBRATION_STATES * CALIBRATION_STATES,
        )?;
        Ok(Self {
            run: parsed.run,
            outcome: RunOutcome {
                seed: parsed.seed,
                error: SVector::from_iterator(error),
                covariance: SMatrix::from_iterator(covariance),
                star_nis: nis("star_nis", &parsed.star_nis)?,
                gnss_nis: nis("gnss_nis", &parsed.gnss_nis)?,
                position_error_m: from_hex(&parsed.position_error_m)
                    .map_err(|message| format!("position_error_m: {message}"))?,
                over_time: parsed
                    .over_time
                    .iter()
                    .map(|sample| {
                        Ok(monte_carlo::OverTimeSample {
                            time_s: from_hex(&sample.time_s)
                                .map_err(|message| format!("over_time.time_s: {message}"))?,
                            nees: sample
                                .nees
                                .as_deref()
                                .map(from_hex)
                                .transpose()
                                .map_err(|message| format!("over_time.nees: {message}"))?,
                            star_nis: nis("over_time.star_nis", &sample.star_nis)?,
                            gnss_nis: nis("over_time.gnss_nis", &sample.gnss_nis)?,
                        })
                    })
                    .collect::<Result<Vec<_>, String>>()?,
                health: parsed.health,
                imu_error: parsed
                    .imu_error
                    .as_ref()
                    .map(|line| line.outcome("imu_error"))
                    .transpose()?,
                gnss_error: parsed
                    .gnss_error
                    .as_ref()
                    .map(|line| line.outcome("gnss_error"))
                    .transpose()?,
            },
        })
    }
}

/// Flies `shard` of the campaign of `runs` runs of `scenario` and writes
/// `directory/shard-K-of-M.jsonl` (through [`OutputFile`], so a failed shard leaves no file).
/// `scenario_path` is the scenario file as given (`None`: the built-in scenario); the file is
/// refused as an output. `progress` is called once per finished run (from the rayon workers).
/// Returns the path written and the number of runs.
///
/// # Errors
/// [`CampaignError::Output`] naming the file, or [`CampaignError::MonteCarlo`] with the seed
/// of a failed flight.
pub fn write_shard(
    scenario: &Scenario,
    scenario_path: Option<&Path>,
    scenario_sha256: &str,
    runs: u64,
    shard: Shard,
    directory: &Path,
    progress: &(dyn Fn() + Sync),
) -> Result<(PathBuf, usize), CampaignError> {
    crate::output::prepare_directory(directory)?;
    let path = directory.join(shard.file_name());
    let mut file =
        OutputFile::create_distinct(&path, &scenario_path.into_iter().collect::<Vec<_>>())?;
    let records = fly_runs(scenario, &shard.runs(runs), progress)?;
    let header = Header {
        format: FORMAT.to_string(),
        version: FORMAT_VERSION,
        scenario: scenario_path.map(|path| path.display().to_string()),
        scenario_hash: format!("{:016x}", scenario_hash(scenario)),
        scenario_sha256: Some(scenario_sha256.to_string()),
        seed_base: scenario.simulation.seed,
        runs,
        shard: shard.index,
        shards: shard.count,
    };
    let write_error = |source: std::io::Error| OutputError::Io {
        action: "write",
        path: path.clone(),
        source,
    };
    let serialisation = |error: serde_json::Error| std::io::Error::other(error);
    let mut text = serde_json::to_string(&header)
        .map_err(serialisation)
        .map_err(write_error)?;
    text.push('\n');
    for record in &records {
        text += &record
            .json_line()
            .map_err(serialisation)
            .map_err(write_error)?;
        text.push('\n');
    }
    file.write_all(text.as_bytes()).map_err(write_error)?;
    file.commit()?;
    Ok((path, records.len()))
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;

    pub(in crate::campaign) fn record(run: u64) -> RunRecord {
        let covariance =
            SMatrix::<f64, CALIBRATION_STATES, CALIBRATION_STATES>::from_fn(|row, column| {
                if row == column {
                    1e-6 * (row as f64 + 1.0)
                } else {
                    1e-9 / (1.0 + row as f64 + column as f64)
                }
            });
        RunRecord {
            run,
            outcome: RunOutcome {
                seed: 100 + run,
                error: SVector::from_fn(|state, _| (state as f64 - 7.0) * 1.0e-4 / 3.0),
                covariance,
                star_nis: NisSum {
                    sum: 0.1 + run as f64,
                    updates: 7,
                },
                gnss_nis: NisSum::default(),
                position_error_m: std::f64::consts::PI,
                over_time: vec![monte_carlo::OverTimeSample {
                    time_s: 600.25,
                    nees: Some(14.0 + 1.0 / 3.0),
                    star_nis: NisSum {
                        sum: 2.0 / 3.0,
                        updates: 2,
                    },
                    gnss_nis: NisSum::default(),
                }],
                health: [("star_gate_rejections".to_string(), 3 + run as u32)]
                    .into_iter()
                    .collect(),
                imu_error: (run % 2 == 1).then(|| {
                    crate::harness::optional_blocks::ImuErrorOutcome {
                        error: SVector::from_fn(|state, _| (state as f64 - 5.0) * 1.0e-6 / 7.0),
                        covariance: SMatrix::from_fn(|row, column| {
                            if row == column {
                                1e-10 * (row as f64 + 1.0)
                            } else {
                                1e-13 / (3.0 + row as f64 + column as f64)
                            }
                        }),
                    }
                }),
                gnss_error: (run % 3 == 2).then(|| BlockOutcome {
                    error: SVector::from_fn(|state, _| (state as f64 - 1.0) / 3.0),
                    covariance: SMatrix::from_fn(|row, column| {
                        if row == column {
                            64.0 + row as f64
                        } else {
                            1.0 / (5.0 + row as f64 + column as f64)
                        }
                    }),
                }),
            },
        }
    }

    #[test]
    fn shards_partition_the_runs_round_robin() {
        let shards: Vec<Shard> = (0..3).map(|index| Shard { index, count: 3 }).collect();
        assert_eq!(shards[1].runs(8), vec![1, 4, 7]);
        let mut all: Vec<u64> = shards.iter().flat_map(|shard| shard.runs(8)).collect();
        all.sort_unstable();
        assert_eq!(all, (0..8).collect::<Vec<_>>());
        assert_eq!(Shard { index: 4, count: 5 }.runs(3), Vec::<u64>::new());
        assert_eq!("2/3".parse::<Shard>().unwrap(), shards[2]);
        for bad in ["3/3", "1", "-1/3", "a/b", "0/0"] {
            assert!(bad.parse::<Shard>().is_err(), "{bad}");
        }
        assert_eq!(shards[0].file_name(), "shard-0-of-3.jsonl");
    }

    #[test]
    fn a_run_line_reads_back_bit_for_bit() {
        let original = record(5);
        let line = original.json_line().unwrap();
        assert!(!line.contains('\n'));
        let parsed = RunRecord::parse(&line).unwrap();
        assert_eq!(parsed.run, 5);
        let bits = |record: &RunRecord| {
            let outcome = &record.outcome;
            let mut bits: Vec<u64> = outcome
                .error
                .iter()
                .chain(outcome.covariance.iter())
                .map(|value| value.to_bits())
                .collect();
            bits.extend([
                outcome.star_nis.sum.to_bits(),
                outcome.gnss_nis.sum.to_bits(),
                outcome.position_error_m.to_bits(),
                outcome.seed,
                outcome.star_nis.updates,
            ]);
            for sample in &outcome.over_time {
                bits.extend([
                    sample.time_s.to_bits(),
                    sample.nees.map_or(0, f64::to_bits),
                    sample.star_nis.sum.to_bits(),
                    sample.star_nis.updates,
                ]);
            }
            if let Some(imu) = &outcome.imu_error {
                bits.extend(
                    imu.error
                        .iter()
                        .chain(imu.covariance.iter())
                        .map(|v| v.to_bits()),
                );
            }
            if let Some(gnss) = &outcome.gnss_error {
                bits.extend(
                    gnss.error
                        .iter()
                        .chain(gnss.covariance.iter())
                        .map(|v| v.to_bits()),
                );
            }
            bits
        };
        assert!(original.outcome.imu_error.is_some());
        assert!(original.outcome.gnss_error.is_some());
        assert_eq!(bits(&parsed), bits(&original));
        assert!(parsed.outcome.imu_error.is_some());
        assert_eq!(parsed.outcome.gnss_error, original.outcome.gnss_error);
        assert_eq!(parsed.json_line().unwrap(), line);
        // Without the optional blocks the line has no such fields.
        let without = record(4);
        let without_line = without.json_line().unwrap();
        assert!(!without_line.contains("imu_error") && !without_line.contains("gnss_error"));
        let parsed_without = RunRecord::parse(&without_line).unwrap().outcome;
        assert_eq!(
            (parsed_without.imu_error, parsed_without.gnss_error),
            (None, None)
        );
        // A block of the wrong size is refused, naming it.
        let short = line.replacen(
            "\"gnss_error\":{\"error\":[",
            "\"gnss_error\":{\"error\":[\"0\",",
            1,
        );
        let refused = RunRecord::parse(&short).unwrap_err();
        assert!(
            refused.contains("gnss_error.error: 4 values, expected 3"),
            "{refused}"
        );
        assert!(RunRecord::parse(&line.replace("\"run\":5", "\"run\":5,\"x\":1")).is_err());
    }
}
