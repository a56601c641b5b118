//! Monte Carlo campaigns: runs over seeds with their statistics and the NEES test
//! ([`monte_carlo`], plotted by [`plots`]), the runs of a campaign ([`runs`]), flown in shards
//! ([`shards`]), merged again ([`mod@merge`]) and reported ([`report`]).
//!
//! The campaign functions draw no progress bar: they take a progress callback,
//! `progress: &(dyn Fn() + Sync)`, called once per finished run from the rayon workers
//! (`&|| {}` for none).

pub mod imu_error_report;
pub mod merge;
pub mod monte_carlo;
pub mod plots;
pub mod report;
pub mod runs;
pub mod shards;

pub use imu_error_report::ImuErrorCampaign;
pub use merge::*;
pub use report::*;
pub use runs::*;
pub use shards::*;
