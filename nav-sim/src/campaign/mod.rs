//! Monte Carlo campaigns: runs over seeds with their statistics and the NEES test
//! ([`monte_carlo`], plotted by [`plots`]), the runs of a campaign ([`runs`]), flown in shards
//! ([`shards`]), merged again ([`mod@merge`]) and reported ([`report`]; the optional state
//! blocks' statistics in [`optional_block_report`], the per-state checks with their
//! intervals in [`consistency_checks`]; the consistency flags' false alarms on clean flights
//! in [`false_alarms`]).
//!
//! The campaign functions draw no progress bar: they take a progress callback,
//! `progress: &(dyn Fn() + Sync)`, called once per finished run from the rayon workers
//! (`&|| {}` for none).

pub mod consistency_checks;
pub mod false_alarms;
pub mod merge;
pub mod monte_carlo;
pub mod optional_block_report;
pub mod plots;
pub mod report;
pub mod runs;
pub mod shards;

pub use merge::*;
pub use optional_block_report::{
    GnssErrorCampaign, ImuErrorCampaign, OptionalBlockCampaign, ReportedBlock,
};
pub use report::*;
pub use runs::*;
pub use shards::*;
