//! How the outputs name a scenario: the file as given and the SHA-256 of the resolved
//! scenario (`scenario::overlay`), so two reports of the same values carry the same hash
//! whatever the file's comments, layout or chain of bases.

/// What names a scenario in the outputs: the file as given (`None`: the built-in default)
/// and the SHA-256 of its resolved text (`None` only for a campaign merged from shard files
/// written before they recorded it).
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct ScenarioLabel {
    /// The scenario file as given on the command line.
    pub file: Option<String>,
    /// The resolved scenario's SHA-256 (64 hexadecimal digits).
    pub sha256: Option<String>,
}

/// How the text outputs name the built-in scenario.
const BUILT_IN: &str = "<built-in default>";

impl ScenarioLabel {
    /// One line for the text outputs: `scenario FILE (resolved SHA-256 HEX)`.
    ///
    /// # Examples
    /// ```
    /// use nav_sim::output::scenario_label::ScenarioLabel;
    /// let label = ScenarioLabel { file: Some("a.toml".into()), sha256: Some("ab12".into()) };
    /// assert_eq!(label.line(), "scenario a.toml (resolved SHA-256 ab12)");
    /// assert_eq!(
    ///     ScenarioLabel::default().line(),
    ///     "scenario <built-in default> (resolved SHA-256 not recorded)"
    /// );
    /// ```
    pub fn line(&self) -> String {
        let file = self.file.as_deref().unwrap_or(BUILT_IN);
        let hash = self.sha256.as_deref().unwrap_or("not recorded");
        format!("scenario {file} (resolved SHA-256 {hash})")
    }

    /// `{"file": FILE or null, "sha256": HEX or null}` for the JSON outputs.
    pub fn json(&self) -> serde_json::Value {
        serde_json::json!({ "file": self.file, "sha256": self.sha256 })
    }
}
