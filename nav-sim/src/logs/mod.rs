//! The sensor-log formats: the replay log of the sensor-event stream, as CSV and binary
//! ([`sensor_log`], `docs/guide/replay-format.md`), and the filter of the star-tracker heads that
//! reach the flight software and its logs ([`star_heads`]); the flight's telemetry packets
//! decoded on the ground and the output-record CSV ([`telemetry_packets`]).

pub mod sensor_log;
pub mod star_heads;
pub mod telemetry_packets;
