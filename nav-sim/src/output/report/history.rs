//! The time-history CSVs: one file per estimated block, written and read back.

use std::path::{Path, PathBuf};

use super::{time_history_file, Axis, BlockSample, Parameter, ReportError, TimeHistorySample};
use crate::output::OutputFile;

/// Header of a block's time-history CSV.
fn history_header() -> Vec<String> {
    let mut header = vec!["time_s".to_string()];
    for quantity in ["estimate", "sigma", "truth", "error"] {
        for axis in Axis::ALL {
            header.push(format!("{quantity}_{}", axis.name()));
        }
    }
    header
}

/// Writes one CSV per block into `directory` (`<block name>.csv`: `time_s`, `estimate_{x,y,z}`,
/// `sigma_{x,y,z}`, `truth_{x,y,z}`, `error_{x,y,z}`; floats in shortest round-trip form).
/// Each file is written whole or not at all ([`OutputFile`]). Returns the files written.
///
/// # Errors
/// [`ReportError::Output`] / [`ReportError::Csv`] naming the file.
pub fn write_time_histories(
    directory: &Path,
    history: &[TimeHistorySample],
) -> Result<Vec<PathBuf>, ReportError> {
    let mut buffer = ryu::Buffer::new();
    Parameter::ALL
        .iter()
        .map(|&parameter| {
            let path = time_history_file(directory, parameter);
            let csv_error = |line, source| ReportError::Csv {
                path: path.clone(),
                line,
                source,
            };
            let mut writer = csv::Writer::from_writer(OutputFile::create(&path)?);
            writer
                .write_record(history_header())
                .map_err(|source| csv_error(1, source))?;
            for (line, sample) in (2_u64..).zip(history) {
                let block = sample.block(parameter);
                let values = std::iter::once(sample.time_s)
                    .chain(block.estimate)
                    .chain(block.sigma)
                    .chain(block.truth)
                    .chain(block.error());
                // NaN/inf are written as Rust prints them (`NaN`, `inf`) and read back as such.
                let row: Vec<String> = values
                    .map(|value| {
                        if value.is_finite() {
                            buffer.format_finite(value).to_string()
                        } else {
                            value.to_string()
                        }
                    })
                    .collect();
                writer
                    .write_record(&row)
                    .map_err(|source| csv_error(line, source))?;
            }
            let output = writer.into_inner().map_err(|error| ReportError::Io {
                path: path.clone(),
                source: error.into_error(),
            })?;
            output.commit()?;
            Ok(path)
        })
        .collect()
}

/// Reads the time histories written by [`write_time_histories`] back.
///
/// # Errors
/// [`ReportError`] naming the file, line and column.
pub fn read_time_histories(directory: &Path) -> Result<Vec<TimeHistorySample>, ReportError> {
    let header = history_header();
    let mut history: Vec<TimeHistorySample> = Vec::new();
    for (file_number, parameter) in Parameter::ALL.into_iter().enumerate() {
        let path = directory.join(format!("{}.csv", parameter.name()));
        let csv_error = |line, source| ReportError::Csv {
            path: path.clone(),
            line,
            source,
        };
        let mut reader = csv::Reader::from_path(&path).map_err(|source| csv_error(1, source))?;
        let found = reader.headers().map_err(|source| csv_error(1, source))?;
        if found.iter().ne(header.iter().map(String::as_str)) {
            return Err(ReportError::Header {
                path: path.clone(),
                expected: header.join(","),
                found: found.iter().collect::<Vec<_>>().join(","),
            });
        }
        for (index, row) in reader.records().enumerate() {
            let row = row.map_err(|source| {
                let line = source.position().map_or(0, csv::Position::line);
                csv_error(line, source)
            })?;
            let line = row.position().map_or(0, csv::Position::line);
            let mut values = [0.0; 13];
            for (column, (value, text)) in values.iter_mut().zip(row.iter()).enumerate() {
                *value = text.parse().map_err(|_| ReportError::Invalid {
                    path: path.clone(),
                    line,
                    column: header[column].clone(),
                    value: text.to_string(),
                })?;
            }
            let [time_s, ex, ey, ez, sx, sy, sz, tx, ty, tz, ..] = values;
            if file_number == 0 {
                history.push(TimeHistorySample {
                    time_s,
                    ..TimeHistorySample::default()
                });
            }
            let sample = history
                .get_mut(index)
                .filter(|sample| sample.time_s.to_bits() == time_s.to_bits());
            let Some(sample) = sample else {
                return Err(ReportError::TimeMismatch {
                    path: path.clone(),
                    line,
                    found: time_s,
                    expected: history.get(index).map_or(f64::NAN, |sample| sample.time_s),
                });
            };
            sample.blocks[parameter.index()] = BlockSample {
                estimate: [ex, ey, ez],
                sigma: [sx, sy, sz],
                truth: [tx, ty, tz],
            };
        }
    }
    Ok(history)
}
