//! Scenario overlays: a scenario file that names a base and holds only what differs from it.
//!
//! ```toml
//! # A star tracker blind above 3 deg/s, otherwise the default flight.
//! extends = "default.toml"
//! remove = ["filter.gravity"]     # optional: keys or tables of the base to drop
//!
//! [star_sensor]
//! max_rate_deg_per_s = 3.0
//! ```
//!
//! Resolution works on TOML values, before the scenario is deserialised: the base (its path
//! relative to the overlay file's directory) is resolved first, then the overlay's `remove`
//! entries are taken out of it, then the overlay's keys are merged in. Tables merge key by
//! key, at every depth; any other value, arrays and arrays of tables (`[[manoeuvre]]`)
//! included, replaces the base's whole. A table and a non-table never replace each other (a
//! removal first makes that explicit). `remove` lists dotted key paths (`"gravity"`,
//! `"filter.gravity"`, `"gnss.velocity_noise_mps"`); a path the base does not have is an
//! error, so a removal cannot go stale silently. A base may itself be an overlay, up to
//! [`MAX_OVERLAY_DEPTH`] files in a chain; a chain that comes back to a file is an error. The
//! resolved scenario is then checked as any scenario file is (`deny_unknown_fields`, ranges).
//!
//! The resolved scenario has one canonical text ([`ResolvedScenario::to_toml`]: keys sorted,
//! no comments, what `nav-sim scenario --resolved FILE` prints) and its SHA-256
//! ([`ResolvedScenario::sha256`]), the hash the outputs name a scenario by: two files that
//! resolve to the same values have the same hash, whatever their comments, layout or chain.

use std::path::{Path, PathBuf};

use sha2::{Digest, Sha256};

use super::ScenarioError;

/// Most files in an overlay chain, the scenario file included: a base of a base of ... is
/// refused beyond it (a real family of scenarios is two or three deep).
pub const MAX_OVERLAY_DEPTH: usize = 8;

/// The top-level key that names an overlay's base.
pub const EXTENDS_KEY: &str = "extends";

/// The top-level key that lists the keys of the base an overlay removes.
pub const REMOVE_KEY: &str = "remove";

/// Why an overlay chain cannot be resolved (the file it concerns is in
/// [`ScenarioError::Overlay`]).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum OverlayError {
    /// `extends` is not a string.
    #[error("`extends` must be the base file's path (a string), not {found}")]
    ExtendsNotAPath {
        /// The TOML type found ("an integer", ...).
        found: &'static str,
    },
    /// `remove` is not a list of strings.
    #[error("`remove` must be a list of dotted key paths (strings), e.g. [\"gravity\", \"filter.gravity\"]")]
    RemoveNotAList,
    /// `remove` without `extends`: there is no base to remove from.
    #[error("`remove` needs `extends`: only an overlay removes keys of its base")]
    RemoveWithoutBase,
    /// `extends` in text given without a file: there is no directory to find the base in.
    #[error(
        "`extends` needs a scenario file (its base is found relative to the file's directory)"
    )]
    NoDirectory,
    /// A `remove` entry names a key the base does not have.
    #[error("`remove` names `{key}`, which its base {base} does not have")]
    RemoveMissing {
        /// The dotted key path.
        key: String,
        /// The base file.
        base: String,
    },
    /// The overlay sets a table where its base has a value, or a value where it has a table.
    #[error(
        "`{key}` is {overlay} here and {base_type} in its base {base}: remove it first \
         (`remove = [\"{key}\"]`) to replace it"
    )]
    TypeMismatch {
        /// The dotted key path.
        key: String,
        /// What the overlay has there ("a table", "an integer", ...).
        overlay: &'static str,
        /// What the base has there.
        base_type: &'static str,
        /// The base file.
        base: String,
    },
    /// The chain of bases comes back to a file already in it.
    #[error("the chain of bases is a cycle: {chain}")]
    Cycle {
        /// The files, scenario first, ` -> ` between them.
        chain: String,
    },
    /// The chain is longer than [`MAX_OVERLAY_DEPTH`] files.
    #[error("the chain of bases is longer than {MAX_OVERLAY_DEPTH} files: {chain}")]
    TooDeep {
        /// The files, scenario first, ` -> ` between them.
        chain: String,
    },
}

/// A scenario resolved to one TOML table: the overlay chain applied, `extends` and `remove`
/// gone. Not yet deserialised or validated ([`ResolvedScenario::scenario`] does both).
#[derive(Debug, Clone, PartialEq)]
pub struct ResolvedScenario {
    table: toml::Table,
    files: Vec<PathBuf>,
}

impl ResolvedScenario {
    /// The resolved values.
    pub fn table(&self) -> &toml::Table {
        &self.table
    }

    /// The files it was resolved from, the scenario file first and its last base last (empty
    /// for text given without a file).
    pub fn files(&self) -> &[PathBuf] {
        &self.files
    }

    /// The canonical text: every resolved key and value, keys sorted, no comments.
    ///
    /// # Errors
    /// [`ScenarioError::Parse`] naming `origin` if the values cannot be written as TOML.
    pub fn to_toml(&self, origin: &str) -> Result<String, ScenarioError> {
        toml::to_string(&self.table).map_err(|error| ScenarioError::Parse {
            origin: origin.to_string(),
            message: error.to_string(),
        })
    }

    /// SHA-256 of the canonical text, as 64 lower-case hexadecimal digits: the hash the
    /// outputs name the scenario by (`nav-sim scenario --resolved FILE | sha256sum`).
    ///
    /// # Errors
    /// As [`ResolvedScenario::to_toml`].
    pub fn sha256(&self, origin: &str) -> Result<String, ScenarioError> {
        let digest = Sha256::digest(self.to_toml(origin)?.as_bytes());
        Ok(digest.iter().map(|byte| format!("{byte:02x}")).collect())
    }

    /// The scenario: deserialised (unknown keys refused) and validated, errors naming
    /// `origin`.
    ///
    /// # Errors
    /// [`ScenarioError::Parse`] for an unknown or missing key or a wrong type,
    /// [`ScenarioError::Invalid`] for a value out of its range.
    pub fn scenario(&self, origin: &str) -> Result<super::Scenario, ScenarioError> {
        let scenario: super::Scenario =
            self.table
                .clone()
                .try_into()
                .map_err(|error: toml::de::Error| ScenarioError::Parse {
                    origin: format!("{origin} (resolved: nav-sim scenario --resolved shows it)"),
                    message: error.to_string(),
                })?;
        scenario.validate_from(origin)?;
        Ok(scenario)
    }
}

impl super::Scenario {
    /// Reads and resolves the scenario file at `path`, then parses and validates it: the
    /// scenario, and its resolution for the canonical text and the hash.
    ///
    /// # Errors
    /// As [`resolve_file`], then as [`super::Scenario::from_toml_str`] with the file's path
    /// in the message.
    pub fn load_resolved(path: &Path) -> Result<(Self, ResolvedScenario), ScenarioError> {
        let resolved = resolve_file(path)?;
        let origin = path.display().to_string();
        let scenario = if resolved.files.len() == 1 {
            // A file without a base is parsed from its own text, so a parse error names its
            // line.
            let text = std::fs::read_to_string(path).map_err(|source| ScenarioError::Io {
                path: origin.clone(),
                source,
            })?;
            Self::parse(&text, &origin)?
        } else {
            resolved.scenario(&origin)?
        };
        Ok((scenario, resolved))
    }

    /// The built-in default scenario and its resolution.
    ///
    /// # Errors
    /// Only if the embedded file is broken, which the crate's tests rule out.
    pub fn default_resolved() -> Result<(Self, ResolvedScenario), ScenarioError> {
        let origin = DEFAULT_ORIGIN;
        let resolved = resolve_str(super::DEFAULT_SCENARIO_TOML, origin)?;
        Ok((Self::parse(super::DEFAULT_SCENARIO_TOML, origin)?, resolved))
    }
}

/// How messages name the built-in default scenario.
pub const DEFAULT_ORIGIN: &str = "<built-in default>";

/// Resolves TOML text that has no file (a string, the built-in default): it may not extend a
/// base.
///
/// # Errors
/// [`ScenarioError::Parse`] for bad TOML; [`ScenarioError::Overlay`] with
/// [`OverlayError::NoDirectory`] if it names a base, [`OverlayError::RemoveWithoutBase`] if
/// it removes keys.
pub fn resolve_str(text: &str, origin: &str) -> Result<ResolvedScenario, ScenarioError> {
    let mut table = parse_table(text, origin)?;
    let overlay = |error| ScenarioError::Overlay {
        file: origin.to_string(),
        error,
    };
    if take_directives(&mut table).map_err(overlay)?.0.is_some() {
        return Err(overlay(OverlayError::NoDirectory));
    }
    Ok(ResolvedScenario {
        table,
        files: Vec::new(),
    })
}

/// One file of a chain: its table without the directives, and the directives.
struct Layer {
    file: PathBuf,
    table: toml::Table,
    remove: Vec<String>,
}

/// Resolves the scenario file at `path` and its chain of bases.
///
/// # Errors
/// [`ScenarioError::Io`] for a file that cannot be read, [`ScenarioError::Parse`] for bad
/// TOML, [`ScenarioError::Overlay`] for a bad `extends` / `remove`, a removal of a key the
/// base does not have, a table replaced by a value, a cycle or a chain longer than
/// [`MAX_OVERLAY_DEPTH`]; each names the file (and the key) concerned.
pub fn resolve_file(path: &Path) -> Result<ResolvedScenario, ScenarioError> {
    let mut layers = read_chain(path)?;
    let files: Vec<PathBuf> = layers.iter().map(|layer| layer.file.clone()).collect();
    // `read_chain` returns at least the file itself; its last layer is the root base.
    let Some(root) = layers.pop() else {
        return Err(ScenarioError::Io {
            path: path.display().to_string(),
            source: std::io::Error::from(std::io::ErrorKind::NotFound),
        });
    };
    let mut table = root.table;
    let mut base_file = root.file;
    for layer in layers.into_iter().rev() {
        let overlay = |error| ScenarioError::Overlay {
            file: layer.file.display().to_string(),
            error,
        };
        let base = base_file.display().to_string();
        for key in &layer.remove {
            remove_path(&mut table, key, &base).map_err(overlay)?;
        }
        merge(&mut table, layer.table, "", &base).map_err(overlay)?;
        base_file = layer.file;
    }
    Ok(ResolvedScenario { table, files })
}

/// The files of the chain from `path`, each parsed, the scenario file first.
fn read_chain(path: &Path) -> Result<Vec<Layer>, ScenarioError> {
    let mut layers: Vec<Layer> = Vec::new();
    let mut seen: Vec<PathBuf> = Vec::new();
    let mut next = Some(path.to_path_buf());
    while let Some(file) = next.take() {
        let io_error = |source| ScenarioError::Io {
            path: file.display().to_string(),
            source,
        };
        let identity = std::fs::canonicalize(&file).map_err(io_error)?;
        let chain_with = |file: &Path| {
            let mut names: Vec<String> = layers
                .iter()
                .map(|layer| layer.file.display().to_string())
                .collect();
            names.push(file.display().to_string());
            names.join(" -> ")
        };
        let first = path.display().to_string();
        if seen.contains(&identity) {
            let error = OverlayError::Cycle {
                chain: chain_with(&file),
            };
            return Err(ScenarioError::Overlay { file: first, error });
        }
        if layers.len() == MAX_OVERLAY_DEPTH {
            let error = OverlayError::TooDeep {
                chain: chain_with(&file),
            };
            return Err(ScenarioError::Overlay { file: first, error });
        }
        let text = std::fs::read_to_string(&file).map_err(io_error)?;
        let origin = file.display().to_string();
        let mut table = parse_table(&text, &origin)?;
        let (extends, remove) =
            take_directives(&mut table).map_err(|error| ScenarioError::Overlay {
                file: origin.clone(),
                error,
            })?;
        let directory = file.parent().unwrap_or_else(|| Path::new(""));
        next = extends.map(|base| directory.join(base));
        seen.push(identity);
        layers.push(Layer {
            file,
            table,
            remove,
        });
    }
    Ok(layers)
}

fn parse_table(text: &str, origin: &str) -> Result<toml::Table, ScenarioError> {
    text.parse::<toml::Table>()
        .map_err(|error| ScenarioError::Parse {
            origin: origin.to_string(),
            message: error.to_string(),
        })
}

/// Takes `extends` and `remove` out of a file's top level.
fn take_directives(table: &mut toml::Table) -> Result<(Option<String>, Vec<String>), OverlayError> {
    let extends = match table.remove(EXTENDS_KEY) {
        None => None,
        Some(toml::Value::String(base)) => Some(base),
        Some(other) => {
            return Err(OverlayError::ExtendsNotAPath {
                found: with_article(&other),
            })
        }
    };
    let remove = match table.remove(REMOVE_KEY) {
        None => Vec::new(),
        Some(toml::Value::Array(entries)) => entries
            .into_iter()
            .map(|entry| match entry {
                toml::Value::String(key) => Ok(key),
                _ => Err(OverlayError::RemoveNotAList),
            })
            .collect::<Result<_, _>>()?,
        Some(_) => return Err(OverlayError::RemoveNotAList),
    };
    if extends.is_none() && !remove.is_empty() {
        return Err(OverlayError::RemoveWithoutBase);
    }
    Ok((extends, remove))
}

/// Removes the dotted key path `key` from `table` (the resolved base, file `base`).
fn remove_path(table: &mut toml::Table, key: &str, base: &str) -> Result<(), OverlayError> {
    let missing = || OverlayError::RemoveMissing {
        key: key.to_string(),
        base: base.to_string(),
    };
    let mut parts: Vec<&str> = key.split('.').collect();
    let last = parts.pop().ok_or_else(missing)?;
    let mut current = table;
    for part in parts {
        current = match current.get_mut(part) {
            Some(toml::Value::Table(inner)) => inner,
            _ => return Err(missing()),
        };
    }
    current.remove(last).map(|_| ()).ok_or_else(missing)
}

/// Merges `overlay` into `base`: tables key by key, any other value replacing the base's.
/// `prefix` is the dotted path of `base` (empty at the top level).
fn merge(
    base: &mut toml::Table,
    overlay: toml::Table,
    prefix: &str,
    base_file: &str,
) -> Result<(), OverlayError> {
    for (key, value) in overlay {
        let path = if prefix.is_empty() {
            key.clone()
        } else {
            format!("{prefix}.{key}")
        };
        match (base.get_mut(&key), value) {
            (Some(toml::Value::Table(inner)), toml::Value::Table(value)) => {
                merge(inner, value, &path, base_file)?;
            }
            (Some(existing), value) if existing.is_table() != value.is_table() => {
                return Err(OverlayError::TypeMismatch {
                    key: path,
                    overlay: with_article(&value),
                    base_type: with_article(existing),
                    base: base_file.to_string(),
                });
            }
            (_, value) => {
                base.insert(key, value);
            }
        }
    }
    Ok(())
}

/// A TOML value's type as a message names it: "a table", "an integer", ...
fn with_article(value: &toml::Value) -> &'static str {
    match value {
        toml::Value::String(_) => "a string",
        toml::Value::Integer(_) => "an integer",
        toml::Value::Float(_) => "a float",
        toml::Value::Boolean(_) => "a boolean",
        toml::Value::Datetime(_) => "a date-time",
        toml::Value::Array(_) => "an array",
        toml::Value::Table(_) => "a table",
    }
}
