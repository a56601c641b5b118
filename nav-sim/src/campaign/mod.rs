//! Monte Carlo campaigns: runs over seeds with their statistics and the NEES test
//! ([`monte_carlo`]), flown in shards and merged into one report ([`shards`]).

pub mod monte_carlo;
pub mod shards;

pub use shards::*;
