//! The setup layer: what a run needs, computed from its scenario: where and when it starts,
//! once per run ([`launch::Launch`]: the launch epoch and ground constants, the launch site and
//! frame, the truth's initial state), the flight software's and the filter's configuration and
//! the initial navigation solution ([`fsw`]), the ground constants a flight image carries
//! ([`ground`]), and every random draw of a run through one
//! registry of streams ([`streams`]): the prior's draw of the sensor-error truth ([`prior`])
//! and the `[dispersion]` table's draws ([`dispersion`]).

#[cfg(test)]
mod datasheet_tests;
pub mod dispersion;
pub mod fsw;
pub mod ground;
pub mod launch;
pub mod prior;
pub mod streams;

use nav_fsw::FswError;

/// Why a run could not be set up from its scenario.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SetupError {
    /// The frame conversions for the initial state failed.
    #[error("initial state: {0}")]
    InitialState(String),
    /// The scenario's launch site was refused.
    #[error("launch site refused: {0}")]
    LaunchSite(String),
    /// A scenario setting the flight software cannot take.
    #[error("scenario setting: {0}")]
    Setting(String),
    /// The flight software refused its configuration ([`fsw::configuration_error`]).
    #[error("flight software configuration refused: {message}")]
    Configuration {
        /// The flight software's error.
        error: FswError,
        /// The scenario key that sets the refused field, with its value and limit where the
        /// scenario gives them, and the flight software's rule.
        message: String,
    },
}
