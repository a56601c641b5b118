//! Reading the decoded defmt log of a firmware run on QEMU.
//!
//! The firmware prints `BITS <workload> <index> <16 hex digits>` for every f64 result it wants
//! compared with the host, and `COST <workload> <instructions>` for its costs.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Where `scripts/test.sh` saves the decoded log of the `checks` firmware run.
pub fn default_checks_log() -> PathBuf {
    std::env::var_os("NAV_QEMU_CHECKS_LOG")
        .map(PathBuf::from)
        .unwrap_or_else(|| crate::project_root().join("target/qemu/checks.log"))
}

/// The parsed content of a firmware log.
#[derive(Debug, Default)]
pub struct TargetLog {
    /// f64 results by workload name, in index order, as raw bits.
    pub bits: BTreeMap<String, Vec<u64>>,
    /// Instruction counts by workload name.
    pub costs: BTreeMap<String, u64>,
    /// Every line of the log.
    pub lines: Vec<String>,
}

impl TargetLog {
    /// Reads and parses the log at `path`.
    pub fn read(path: &Path) -> Result<Self, String> {
        let text = std::fs::read_to_string(path).map_err(|error| {
            format!(
                "cannot read the QEMU log {}: {error} (run scripts/test.sh, which runs the firmware first)",
                path.display()
            )
        })?;
        Self::parse(&text)
    }

    /// Parses a decoded defmt log.
    pub fn parse(text: &str) -> Result<Self, String> {
        let mut log = TargetLog::default();
        for line in text.lines() {
            log.lines.push(line.to_string());
            let fields: Vec<&str> = line.split_whitespace().collect();
            match fields.as_slice() {
                ["BITS", workload, index, hex] => {
                    let index: usize = index.parse().map_err(|e| format!("{line}: {e}"))?;
                    let bits = u64::from_str_radix(hex, 16).map_err(|e| format!("{line}: {e}"))?;
                    let values = log.bits.entry((*workload).to_string()).or_default();
                    if index != values.len() {
                        return Err(format!("{line}: index {index} out of order"));
                    }
                    values.push(bits);
                }
                ["COST", workload, instructions] => {
                    let instructions = instructions.parse().map_err(|e| format!("{line}: {e}"))?;
                    log.costs.insert((*workload).to_string(), instructions);
                }
                _ => {}
            }
        }
        Ok(log)
    }

    /// Compares the target's bits of `workload` with host values; returns a description of
    /// the first mismatch.
    pub fn compare(&self, workload: &str, host: &[f64]) -> Result<(), String> {
        let target = self
            .bits
            .get(workload)
            .ok_or_else(|| format!("the target log has no BITS for {workload}"))?;
        if target.len() != host.len() {
            return Err(format!(
                "{workload}: target printed {} values, host computed {}",
                target.len(),
                host.len()
            ));
        }
        for (index, (target_bits, host_value)) in target.iter().zip(host).enumerate() {
            if *target_bits != host_value.to_bits() {
                return Err(format!(
                    "{workload}[{index}]: target {:016x} ({}) != host {:016x} ({})",
                    target_bits,
                    f64::from_bits(*target_bits),
                    host_value.to_bits(),
                    host_value
                ));
            }
        }
        Ok(())
    }
}
