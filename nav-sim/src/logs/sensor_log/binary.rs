//! The binary log form (nav-fsw's `log_record`): a CSV log converted to it, and a binary log
//! read back.

use std::io::{Read, Write};

use nav_fsw::log_record::{self, LogRecord, LogRecordError, HEADER_SIZE, RECORD_SIZE};

use super::{SensorLogError, SensorLogReader};

/// Converts a CSV log into the binary form (header, then one record per row). Returns the
/// number of records written.
///
/// # Errors
/// Any CSV reading error (naming line and column), or an I/O error writing.
pub fn convert_csv_to_binary<R: Read, W: Write>(
    csv: R,
    mut binary: W,
) -> Result<u64, SensorLogError> {
    binary.write_all(&log_record::encode_header())?;
    let mut count = 0_u64;
    for record in SensorLogReader::new(csv)? {
        let bytes = record?.encode().map_err(|error| SensorLogError::Binary {
            record: Some(count),
            error,
        })?;
        binary.write_all(&bytes)?;
        count += 1;
    }
    binary.flush()?;
    Ok(count)
}

/// Reads a binary log (the host side of what the firmware streams).
///
/// # Errors
/// [`SensorLogError::Binary`] naming the header or the record index (a trailing partial record
/// is [`LogRecordError::Truncated`]), or [`SensorLogError::Io`].
pub fn read_binary<R: Read>(mut reader: R) -> Result<Vec<LogRecord>, SensorLogError> {
    let mut header = [0_u8; HEADER_SIZE];
    let available = read_up_to(&mut reader, &mut header)?;
    if available < HEADER_SIZE {
        return Err(SensorLogError::Binary {
            record: None,
            error: LogRecordError::Truncated {
                needed: HEADER_SIZE,
                available,
            },
        });
    }
    log_record::decode_header(&header).map_err(|error| SensorLogError::Binary {
        record: None,
        error,
    })?;
    let mut records = Vec::new();
    let mut buffer = [0_u8; RECORD_SIZE];
    loop {
        let index = u64::try_from(records.len()).unwrap_or(u64::MAX);
        let binary_error = |error| SensorLogError::Binary {
            record: Some(index),
            error,
        };
        match read_up_to(&mut reader, &mut buffer)? {
            0 => return Ok(records),
            RECORD_SIZE => records.push(LogRecord::decode(&buffer).map_err(binary_error)?),
            available => {
                return Err(binary_error(LogRecordError::Truncated {
                    needed: RECORD_SIZE,
                    available,
                }))
            }
        }
    }
}

/// Reads until `buffer` is full or the stream ends; returns the bytes read.
fn read_up_to<R: Read>(reader: &mut R, buffer: &mut [u8]) -> std::io::Result<usize> {
    let mut filled = 0;
    while filled < buffer.len() {
        match reader.read(&mut buffer[filled..]) {
            Ok(0) => break,
            Ok(count) => filled += count,
            Err(error) if error.kind() == std::io::ErrorKind::Interrupted => {}
            Err(error) => return Err(error),
        }
    }
    Ok(filled)
}
