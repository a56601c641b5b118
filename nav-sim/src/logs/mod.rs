//! The sensor-log formats: the replay log of the sensor-event stream, as CSV and binary
//! ([`sensor_log`], `docs/replay-format.md`).

pub mod sensor_log;
