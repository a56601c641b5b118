//! Monte Carlo campaigns split into shards and merged again: `nav-sim monte-carlo --shard K/M`
//! flies its share of the runs and writes one JSON line per run, `nav-sim merge` reads the
//! shard files back and prints the report of the whole campaign, identical to the report of
//! the same campaign flown in one process (`docs/monte-carlo.md`).
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

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::io::Write as _;
use std::path::{Path, PathBuf};

use comfy_table::{presets::UTF8_FULL_CONDENSED, Cell, CellAlignment, Table};
use nalgebra::{SMatrix, SVector};
use serde::{Deserialize, Serialize};
use statrs::distribution::{ChiSquared, ContinuousCDF};

use crate::campaign::monte_carlo::{
    self, MonteCarloError, MonteCarloSummary, RunOutcome, CALIBRATION_STATES,
};
use crate::harness::flight::{FlightError, NisSum};
use crate::output::{OutputError, OutputFile};
use crate::scenario::Scenario;

/// The `format` field of a shard file's header.
pub const FORMAT: &str = "nav-sim monte-carlo shard";

/// The version of the shard file format.
pub const FORMAT_VERSION: u32 = 1;

/// Probability below the NEES bound that marks a run as an outlier: the χ²(15) 99.9 % point.
pub const OUTLIER_NEES_PROBABILITY: f64 = 0.999;

/// A state's |error| beyond this many filter σ marks its run as an outlier.
pub const OUTLIER_SIGMAS: f64 = 3.0;

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

/// The seed of run `run`: the scenario's seed plus the run index (wrapping).
pub fn run_seed(scenario: &Scenario, run: u64) -> u64 {
    scenario.simulation.seed.wrapping_add(run)
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

/// One run of a campaign: its index and what it left for the statistics.
#[derive(Debug, Clone, PartialEq)]
pub struct RunRecord {
    /// The run index `k` (seed = scenario seed + `k`).
    pub run: u64,
    /// The run's outcome.
    pub outcome: RunOutcome,
}

/// Flies the given runs of the campaign of `scenario` in parallel (rayon), in the order given.
///
/// # Errors
/// [`MonteCarloError::Run`] with the seed of a failed flight.
pub fn fly_runs(
    scenario: &Scenario,
    runs: &[u64],
    show_progress: bool,
) -> Result<Vec<RunRecord>, MonteCarloError<FlightError>> {
    let seeds: Vec<u64> = runs.iter().map(|&run| run_seed(scenario, run)).collect();
    let outcomes = monte_carlo::fly_campaign(scenario, &seeds, show_progress)?;
    Ok(runs
        .iter()
        .zip(outcomes)
        .map(|(&run, outcome)| RunRecord { run, outcome })
        .collect())
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
}

/// The first line of a shard file.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq, Eq)]
#[serde(deny_unknown_fields)]
struct Header {
    format: String,
    version: u32,
    /// The scenario file as given on the command line (`null`: the built-in one); only for
    /// the re-run commands of the report, the campaign is identified by the hash.
    scenario: Option<String>,
    scenario_hash: String,
    seed_base: u64,
    runs: u64,
    shard: u64,
    shards: u64,
}

impl Header {
    /// The fields that name the campaign, which every shard file of it shares.
    fn campaign(&self) -> [(&'static str, String); 4] {
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
    /// "error", "sigma", "covariance", "star_nis", "gnss_nis", "position_error_m"}`, floats
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
            },
        })
    }
}

/// Flies `shard` of the campaign of `runs` runs of `scenario` and writes
/// `directory/shard-K-of-M.jsonl` (through [`OutputFile`], so a failed shard leaves no file).
/// `scenario_path` is the scenario file as given (`None`: the built-in scenario); the file is
/// refused as an output. Returns the path written and the number of runs.
///
/// # Errors
/// [`CampaignError::Output`] naming the file, or [`CampaignError::MonteCarlo`] with the seed
/// of a failed flight.
pub fn write_shard(
    scenario: &Scenario,
    scenario_path: Option<&Path>,
    runs: u64,
    shard: Shard,
    directory: &Path,
    show_progress: bool,
) -> Result<(PathBuf, usize), CampaignError> {
    crate::output::prepare_directory(directory)?;
    let path = directory.join(shard.file_name());
    let mut file =
        OutputFile::create_distinct(&path, &scenario_path.into_iter().collect::<Vec<_>>())?;
    let records = fly_runs(scenario, &shard.runs(runs), show_progress)?;
    let header = Header {
        format: FORMAT.to_string(),
        version: FORMAT_VERSION,
        scenario: scenario_path.map(|path| path.display().to_string()),
        scenario_hash: format!("{:016x}", scenario_hash(scenario)),
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
    /// The scenario file the first shard names (`None`: the built-in scenario).
    pub scenario: Option<String>,
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
        scenario: header.scenario,
        records: runs.into_values().map(|(_, record)| record).collect(),
    })
}

/// The 50th, 95th and 99th percentiles of a set of values (nearest rank: the smallest value
/// with at least p % of the values at or below it).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Percentiles {
    /// Median.
    pub p50: f64,
    /// 95th percentile.
    pub p95: f64,
    /// 99th percentile.
    pub p99: f64,
}

impl Percentiles {
    /// The percentiles of `values` (NaN for none).
    pub fn of(mut values: Vec<f64>) -> Self {
        values.sort_by(f64::total_cmp);
        let rank = |percent: usize| {
            // Nearest rank ⌈p n / 100⌉, from 1.
            let rank = (percent * values.len()).div_ceil(100).max(1);
            values.get(rank - 1).copied().unwrap_or(f64::NAN)
        };
        Self {
            p50: rank(50),
            p95: rank(95),
            p99: rank(99),
        }
    }

    fn json(&self, scale: f64) -> serde_json::Value {
        serde_json::json!({
            "p50": scale * self.p50,
            "p95": scale * self.p95,
            "p99": scale * self.p99,
        })
    }
}

/// A run outside 3σ: a state's |error| above [`OUTLIER_SIGMAS`] filter σ, or a NEES above the
/// χ²(15) [`OUTLIER_NEES_PROBABILITY`] point.
#[derive(Debug, Clone, PartialEq)]
pub struct Outlier {
    /// The run index.
    pub run: u64,
    /// Its seed.
    pub seed: u64,
    /// Its NEES.
    pub nees: f64,
    /// The states beyond 3σ: (state index, |error| / σ).
    pub states: Vec<(usize, f64)>,
    /// The command that re-runs it alone.
    pub command: String,
}

/// The report of a campaign: the Monte Carlo summary, percentiles of the final errors and the
/// runs outside 3σ.
#[derive(Debug, Clone, PartialEq)]
pub struct CampaignReport {
    /// RMS error, mean 1σ, NEES and NIS tests.
    pub summary: MonteCarloSummary,
    /// Per calibration state, percentiles of the final |error| (state units).
    pub error_percentiles: [Percentiles; CALIBRATION_STATES],
    /// Percentiles of the norm of the final navigation position error (m).
    pub position_error_percentiles: Percentiles,
    /// The NEES above which a run is an outlier.
    pub outlier_nees_bound: f64,
    /// The runs outside 3σ, in run order.
    pub outliers: Vec<Outlier>,
}

/// A path for a shell command line: as is if it needs no quoting, else in single quotes.
fn shell_word(text: &str) -> String {
    let plain = !text.is_empty()
        && text
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || "/._-+=:,@".contains(c));
    if plain {
        text.to_string()
    } else {
        format!("'{}'", text.replace('\'', r"'\''"))
    }
}

/// The command that re-runs run `run` of a campaign of `scenario` alone.
pub fn rerun_command(scenario: Option<&str>, run: u64) -> String {
    match scenario {
        Some(path) => format!("nav-sim monte-carlo {} --run {run}", shell_word(path)),
        None => format!("nav-sim monte-carlo --run {run}"),
    }
}

impl CampaignReport {
    /// The report of `records` (in run order); `scenario` is the scenario file as given, for
    /// the re-run commands (`None`: the built-in scenario).
    ///
    /// # Errors
    /// [`MonteCarloError`] from the statistics (no runs, a covariance not positive definite,
    /// χ² quantiles refused).
    pub fn new(
        records: &[RunRecord],
        scenario: Option<&str>,
    ) -> Result<Self, MonteCarloError<FlightError>> {
        let outcomes: Vec<RunOutcome> = records
            .iter()
            .map(|record| record.outcome.clone())
            .collect();
        let summary = monte_carlo::summarise::<CALIBRATION_STATES, FlightError>(&outcomes)?;
        let dof = CALIBRATION_STATES as f64;
        let outlier_nees_bound = ChiSquared::new(dof)
            .map_err(|error| MonteCarloError::ChiSquared {
                degrees_of_freedom: dof,
                message: error.to_string(),
            })?
            .inverse_cdf(OUTLIER_NEES_PROBABILITY);
        let error_percentiles = std::array::from_fn(|state| {
            Percentiles::of(
                outcomes
                    .iter()
                    .map(|outcome| outcome.error[state].abs())
                    .collect(),
            )
        });
        let position_error_percentiles = Percentiles::of(
            outcomes
                .iter()
                .map(|outcome| outcome.position_error_m)
                .collect(),
        );
        let outliers = records
            .iter()
            .zip(&summary.nees.per_run)
            .filter_map(|(record, &nees)| {
                let outcome = &record.outcome;
                let states: Vec<(usize, f64)> = (0..CALIBRATION_STATES)
                    .map(|state| {
                        let sigma = outcome.covariance[(state, state)].sqrt();
                        (state, outcome.error[state].abs() / sigma)
                    })
                    .filter(|(_, ratio)| *ratio > OUTLIER_SIGMAS)
                    .collect();
                (nees > outlier_nees_bound || !states.is_empty()).then(|| Outlier {
                    run: record.run,
                    seed: outcome.seed,
                    nees,
                    states,
                    command: rerun_command(scenario, record.run),
                })
            })
            .collect();
        Ok(Self {
            summary,
            error_percentiles,
            position_error_percentiles,
            outlier_nees_bound,
            outliers,
        })
    }

    /// The text report: the RMS / 1σ table, the percentile table, the NEES and NIS lines and
    /// the runs outside 3σ with their re-run commands.
    pub fn text(&self) -> String {
        let labels = monte_carlo::calibration_labels();
        let mut text = format!("{}\n", self.summary.table(&labels));
        let mut table = Table::new();
        table.load_preset(UTF8_FULL_CONDENSED).set_header([
            "parameter",
            "axis",
            "|error| p50",
            "p95",
            "p99",
        ]);
        let right =
            |value: f64| Cell::new(format!("{value:.3e}")).set_alignment(CellAlignment::Right);
        for ((parameter, axis), percentiles) in labels.iter().zip(&self.error_percentiles) {
            let scale = parameter.state_to_report_scale();
            table.add_row([
                Cell::new(format!("{} ({})", parameter.name(), parameter.unit())),
                Cell::new(axis.name()),
                right(scale * percentiles.p50),
                right(scale * percentiles.p95),
                right(scale * percentiles.p99),
            ]);
        }
        let position = &self.position_error_percentiles;
        table.add_row([
            Cell::new("navigation position (m)"),
            Cell::new("norm"),
            right(position.p50),
            right(position.p95),
            right(position.p99),
        ]);
        let _ = writeln!(
            text,
            "final |error| percentiles over {} runs (nearest rank):\n{table}",
            self.summary.runs
        );
        let _ = writeln!(text, "{}", self.summary.nees_line());
        for (sensor, test) in [
            ("star sensor", &self.summary.star_nis),
            ("GNSS", &self.summary.gnss_nis),
        ] {
            if let Some(test) = test {
                let _ = writeln!(text, "{}", test.line(sensor));
            }
        }
        let _ = writeln!(
            text,
            "runs outside 3σ (a state's |error| > {OUTLIER_SIGMAS}σ or NEES > {:.2}, the χ²({}) \
             {} % point): {} of {}",
            self.outlier_nees_bound,
            CALIBRATION_STATES,
            OUTLIER_NEES_PROBABILITY * 100.0,
            self.outliers.len(),
            self.summary.runs
        );
        for outlier in &self.outliers {
            let states: Vec<String> = outlier
                .states
                .iter()
                .map(|&(state, ratio)| {
                    let (parameter, axis) = labels[state];
                    format!("{} {} {ratio:.2}σ", parameter.name(), axis.name())
                })
                .collect();
            let _ = writeln!(
                text,
                "  run {} (seed {}): NEES {:.2}{}; re-run: {}",
                outlier.run,
                outlier.seed,
                outlier.nees,
                if states.is_empty() {
                    String::new()
                } else {
                    format!(", {}", states.join(", "))
                },
                outlier.command
            );
        }
        text
    }

    /// The report as one JSON object: the summary's (`runs`, `nees_mean`,
    /// `nees_interval_95`, `states` with `rms_error` and `mean_sigma`), each state with
    /// `abs_error_percentiles` `{p50, p95, p99}` (report units), `position_error_m_percentiles`,
    /// `star_nis` and `gnss_nis` (`{average, interval_95, updates}` or null),
    /// `outlier_nees_bound` and `outliers` (`[{run, seed, nees, states: [{parameter, axis,
    /// error_over_sigma}], command}]`).
    ///
    /// # Errors
    /// A serialisation error (none expected).
    pub fn json(&self) -> Result<String, serde_json::Error> {
        let labels = monte_carlo::calibration_labels();
        let mut value = self.summary.json_value(&labels);
        if let Some(states) = value
            .get_mut("states")
            .and_then(serde_json::Value::as_array_mut)
        {
            for ((state, percentiles), (parameter, _)) in
                states.iter_mut().zip(&self.error_percentiles).zip(&labels)
            {
                if let Some(object) = state.as_object_mut() {
                    object.insert(
                        "abs_error_percentiles".into(),
                        percentiles.json(parameter.state_to_report_scale()),
                    );
                }
            }
        }
        let nis = |test: &Option<monte_carlo::NisTest>| {
            test.as_ref().map(|test| {
                serde_json::json!({
                    "average": test.average,
                    "interval_95": [test.lower_bound, test.upper_bound],
                    "updates": test.updates,
                })
            })
        };
        let outliers: Vec<serde_json::Value> = self
            .outliers
            .iter()
            .map(|outlier| {
                let states: Vec<serde_json::Value> = outlier
                    .states
                    .iter()
                    .map(|&(state, ratio)| {
                        let (parameter, axis) = labels[state];
                        serde_json::json!({
                            "parameter": parameter.name(),
                            "axis": axis.name(),
                            "error_over_sigma": ratio,
                        })
                    })
                    .collect();
                serde_json::json!({
                    "run": outlier.run,
                    "seed": outlier.seed,
                    "nees": outlier.nees,
                    "states": states,
                    "command": outlier.command,
                })
            })
            .collect();
        if let Some(object) = value.as_object_mut() {
            object.insert(
                "position_error_m_percentiles".into(),
                self.position_error_percentiles.json(1.0),
            );
            object.insert("star_nis".into(), nis(&self.summary.star_nis).into());
            object.insert("gnss_nis".into(), nis(&self.summary.gnss_nis).into());
            object.insert("outlier_nees_bound".into(), self.outlier_nees_bound.into());
            object.insert("outliers".into(), outliers.into());
        }
        serde_json::to_string_pretty(&value)
    }

    /// What `--check` refuses: the average NEES outside its 95 % interval (`None` if inside).
    pub fn check_failure(&self) -> Option<String> {
        let nees = &self.summary.nees;
        (!nees.consistent()).then(|| {
            format!(
                "the average NEES {:.3} over {} runs is outside its 95 % interval [{:.3}, {:.3}]",
                nees.average, self.summary.runs, nees.lower_bound, nees.upper_bound
            )
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(run: u64) -> RunRecord {
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
            bits
        };
        assert_eq!(bits(&parsed), bits(&original));
        assert_eq!(parsed.json_line().unwrap(), line);
        assert!(RunRecord::parse(&line.replace("\"run\":5", "\"run\":5,\"x\":1")).is_err());
    }

    #[test]
    fn percentiles_are_nearest_rank() {
        let values: Vec<f64> = (1..=200).map(f64::from).rev().collect();
        let percentiles = Percentiles::of(values);
        assert_eq!(percentiles.p50.to_bits(), 100.0_f64.to_bits());
        assert_eq!(percentiles.p95.to_bits(), 190.0_f64.to_bits());
        assert_eq!(percentiles.p99.to_bits(), 198.0_f64.to_bits());
        let one = Percentiles::of(vec![2.5]);
        assert_eq!(one.p99.to_bits(), 2.5_f64.to_bits());
        assert!(Percentiles::of(Vec::new()).p50.is_nan());
    }

    fn write_shards(directory: &Path, runs: u64, shards: u64, skip: Option<u64>) {
        for index in 0..shards {
            let header = Header {
                format: FORMAT.into(),
                version: FORMAT_VERSION,
                scenario: Some("my scenario.toml".into()),
                scenario_hash: "0123456789abcdef".into(),
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
        assert_eq!(merged.scenario.as_deref(), Some("my scenario.toml"));
        // Run 4 with its first state 10σ off.
        let mut records = merged.records.clone();
        records[4].outcome.error[0] = 1.0e-2;
        let report = CampaignReport::new(&records, merged.scenario.as_deref()).unwrap();
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
