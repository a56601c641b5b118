//! docs/reference/scenario-keys.md is written from the scenario types' JSON Schema (schemars,
//! derived beside `Deserialize`, so it has their doc comments and serde attributes): this test
//! renders it and fails when the committed file differs, and fails when a shipped scenario
//! uses a key the page does not list. `NAV_BLESS=1 cargo test -p nav-sim --test testsuite
//! scenario_keys` writes it.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

use nav_sim::scenario::{overlay, Scenario};
use serde_json::{Map, Value};

/// The page, from the nav-sim crate's directory.
const PAGE: &str = "../docs/reference/scenario-keys.md";

/// How the page is written again.
const BLESS: &str = "NAV_BLESS=1 cargo test -p nav-sim --test testsuite scenario_keys";

/// A key's unit from its name's ending, the longest that matches (the scenario's convention:
/// SI unless the name says otherwise).
const UNITS: [(&str, &str); 18] = [
    ("_deg_per_h_per_sqrt_hz", "(deg/h)/√Hz"),
    ("_rad_per_s_per_sqrt_s", "(rad/s)/√s"),
    ("_mps2_per_sqrt_s", "(m/s²)/√s"),
    ("_rad_s_per_mps2", "(rad/s)/(m/s²)"),
    ("_m2_per_s3", "m²/s³"),
    ("_deg_per_s", "deg/s"),
    ("_rad_per_s", "rad/s"),
    ("_mps2", "m/s²"),
    ("_mps", "m/s"),
    ("_arcsec", "arcsec"),
    ("_percent", "%"),
    ("_frames", "IMU frames"),
    ("_deg", "deg"),
    ("_rad", "rad"),
    ("_hz", "Hz"),
    ("_utc", "UTC"),
    ("_m", "m"),
    ("_s", "s"),
];

/// What a row's key holds.
enum Holds {
    /// A value.
    Value,
    /// Tables with the keys of the section at this path (`star_sensor.additional_heads`).
    TablesOf(String),
    /// A table described once, in the section of this title (a tagged enum: `Distribution`).
    Shared(String),
}

/// One key.
struct Row {
    key: String,
    kind: String,
    unit: String,
    default: String,
    description: String,
    holds: Holds,
}

/// One TOML table (or a shared table type).
struct Section {
    title: String,
    about: String,
    rows: Vec<Row>,
}

/// The page's content.
struct Reference {
    sections: Vec<Section>,
}

/// The first sentence of a doc comment, on one line, rustdoc's link brackets taken out.
fn first_sentence(doc: Option<&Value>) -> String {
    let doc = doc.and_then(Value::as_str).unwrap_or("");
    let paragraph = doc.split("\n\n").next().unwrap_or("");
    let text = paragraph
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ")
        .replace("`[`", "")
        .replace("[`", "`")
        .replace("`]", "`");
    let mut end = text.len();
    for (index, _) in text.match_indices(". ") {
        let before = &text[..index];
        let after = text[index + 2..].chars().next();
        let abbreviation = ["e.g", "i.e", "eq", "cf"]
            .iter()
            .any(|short| before.ends_with(short));
        if after.is_some_and(|c| c.is_uppercase() || c == '`') && !abbreviation {
            end = index + 1;
            break;
        }
    }
    text[..end].replace('|', "\\|")
}

fn unit(key: &str) -> String {
    UNITS
        .iter()
        .filter(|(ending, _)| key.ends_with(ending))
        .max_by_key(|(ending, _)| ending.len())
        .map_or("-", |(_, unit)| unit)
        .to_string()
}

/// A default as TOML writes it.
fn toml_value(value: &Value) -> String {
    match value {
        Value::Array(items) => {
            let items: Vec<String> = items.iter().map(toml_value).collect();
            format!("[{}]", items.join(", "))
        }
        other => other.to_string(),
    }
}

fn definition_name(schema: &Value) -> Option<&str> {
    schema.get("$ref")?.as_str()?.strip_prefix("#/$defs/")
}

/// The schema without its `null` alternative (an `Option`).
fn without_null(schema: &Value) -> &Value {
    let is_null = |schema: &&Value| schema.get("type").and_then(Value::as_str) == Some("null");
    match schema.get("anyOf").and_then(Value::as_array) {
        Some(alternatives) => {
            let rest: Vec<&Value> = alternatives.iter().filter(|s| !is_null(s)).collect();
            match rest[..] {
                [only] => only,
                _ => schema,
            }
        }
        None => schema,
    }
}

/// Walks the schema into sections, tables in the order of their paths.
struct Walker<'a> {
    definitions: &'a Map<String, Value>,
    /// The path each table type was first described at.
    placed: BTreeMap<String, String>,
    /// The tagged enums, described once at the end.
    shared: BTreeSet<String>,
    sections: Vec<Section>,
}

impl Walker<'_> {
    fn resolve<'s>(&'s self, schema: &'s Value) -> &'s Value {
        let schema = without_null(schema);
        definition_name(schema).map_or(schema, |name| &self.definitions[name])
    }

    /// A table type: its definition's name, if `schema` is one.
    fn table_type<'s>(&self, schema: &'s Value) -> Option<&'s str> {
        let name = definition_name(without_null(schema))?;
        self.definitions[name].get("properties").map(|_| name)
    }

    fn kind(&self, schema: &Value) -> String {
        let schema = self.resolve(schema);
        if let Some(variants) = schema.get("oneOf").and_then(Value::as_array) {
            let names: Vec<String> = variants.iter().map(|v| self.kind(v)).collect();
            return names.join(" or ");
        }
        if let Some(constant) = schema.get("const") {
            return format!("`{constant}`");
        }
        let kind = match schema.get("type") {
            Some(Value::Array(kinds)) => kinds.iter().find(|kind| *kind != "null"),
            kind => kind,
        };
        match kind.and_then(Value::as_str) {
            Some("array") => {
                let items = self.kind(&schema["items"]);
                match (schema.get("minItems"), schema.get("maxItems")) {
                    (Some(min), Some(max)) if min == max => format!("{items}[{min}]"),
                    _ => format!("{items}[]"),
                }
            }
            Some(kind) => kind.to_string(),
            None => "?".to_string(),
        }
    }

    fn default_of(required: bool, property: &Value) -> String {
        match property.get("default") {
            _ if required => "required".to_string(),
            Some(Value::Null) | None => "absent".to_string(),
            Some(value) => format!("`{}`", toml_value(value)),
        }
    }

    /// The section of the table at `path` and, after it, those of its tables.
    fn table(&mut self, path: &str, title: String, about: String, schema: &Value) {
        let required: BTreeSet<&str> = schema["required"]
            .as_array()
            .map(|keys| keys.iter().filter_map(Value::as_str).collect())
            .unwrap_or_default();
        let mut rows = Vec::new();
        let mut tables = Vec::new();
        for (key, property) in schema["properties"].as_object().into_iter().flatten() {
            let full = if path.is_empty() {
                key.clone()
            } else {
                format!("{path}.{key}")
            };
            let description = first_sentence(property.get("description"));
            let optional = if required.contains(key.as_str()) {
                ""
            } else {
                " (optional)"
            };
            let resolved = self.resolve(property);
            let (table_type, array) = match self.table_type(property) {
                Some(name) => (Some(name), false),
                None => (resolved.get("items").and_then(|i| self.table_type(i)), true),
            };
            let mut row = Row {
                key: full.clone(),
                kind: self.kind(property),
                unit: unit(key),
                default: Self::default_of(required.contains(key.as_str()), property),
                description,
                holds: Holds::Value,
            };
            if let Some(name) = table_type {
                if let Some(at) = self.placed.get(name) {
                    let many = if array { "tables" } else { "a table" };
                    row.kind = format!("{many} with the keys of `[{at}]`");
                    row.holds = Holds::TablesOf(at.clone());
                } else {
                    let title = if array {
                        format!("`[[{full}]]`{optional}")
                    } else {
                        format!("`[{full}]`{optional}")
                    };
                    tables.push((full, title, row.description, name.to_string()));
                    continue;
                }
            } else if resolved.get("oneOf").is_some() && resolved.get("type").is_none() {
                let name = definition_name(without_null(property)).unwrap_or("?");
                if resolved["oneOf"][0].get("properties").is_some() {
                    self.shared.insert(name.to_string());
                    row.kind = format!("{name} (below)");
                    row.holds = Holds::Shared(name.to_string());
                }
            }
            rows.push(row);
        }
        if !rows.is_empty() {
            self.sections.push(Section { title, about, rows });
        }
        for (full, title, about, name) in tables {
            self.placed.insert(name.clone(), full.clone());
            let definition = self.definitions[&name].clone();
            self.table(&full, title, about, &definition);
        }
    }

    /// A tagged enum's section: the tag, then each variant's keys.
    fn shared(&mut self, name: &str) {
        let definition = &self.definitions[name];
        let variants = definition["oneOf"].as_array().cloned().unwrap_or_default();
        let tag = variants[0]["properties"]
            .as_object()
            .and_then(|keys| keys.iter().find(|(_, p)| p.get("const").is_some()))
            .map(|(key, _)| key.clone())
            .unwrap_or_default();
        let constant = |variant: &Value| format!("`{}`", variant["properties"][&tag]["const"]);
        let mut rows = vec![Row {
            key: tag.clone(),
            kind: variants
                .iter()
                .map(constant)
                .collect::<Vec<_>>()
                .join(" or "),
            unit: "-".to_string(),
            default: "required".to_string(),
            description: variants
                .iter()
                .map(|v| format!("{}: {}", constant(v), first_sentence(v.get("description"))))
                .collect::<Vec<_>>()
                .join(" "),
            holds: Holds::Value,
        }];
        for variant in &variants {
            for (key, property) in variant["properties"].as_object().into_iter().flatten() {
                if *key != tag {
                    rows.push(Row {
                        key: key.clone(),
                        kind: self.kind(property),
                        unit: unit(key),
                        default: format!("required with {tag} = {}", constant(variant)),
                        description: first_sentence(property.get("description")),
                        holds: Holds::Value,
                    });
                }
            }
        }
        let about = first_sentence(definition.get("description"));
        self.sections.push(Section {
            title: name.to_string(),
            about,
            rows,
        });
    }
}

/// The reference, from the scenario's schema.
fn reference() -> Reference {
    let schema = serde_json::to_value(schemars::schema_for!(Scenario)).unwrap();
    let definitions = schema["$defs"].as_object().unwrap();
    let mut walker = Walker {
        definitions,
        placed: BTreeMap::new(),
        shared: BTreeSet::new(),
        sections: Vec::new(),
    };
    let overlay_keys = Section {
        title: "Overlay keys (top level)".to_string(),
        about: "Taken out before the scenario is read ([scenario-overlays.md](../guide/scenario-overlays.md))."
            .to_string(),
        rows: [
            (overlay::EXTENDS_KEY, "string", "The base file's path, relative to this file."),
            (overlay::REMOVE_KEY, "string[]", "Dotted paths of the base's keys or tables to drop; needs `extends`."),
        ]
        .map(|(key, kind, description)| Row {
            key: key.to_string(),
            kind: kind.to_string(),
            unit: "-".to_string(),
            default: "absent".to_string(),
            description: description.to_string(),
            holds: Holds::Value,
        })
        .into(),
    };
    walker.sections.push(overlay_keys);
    walker.table("", String::new(), String::new(), &schema);
    for name in walker.shared.clone() {
        walker.shared(&name);
    }
    Reference {
        sections: walker.sections,
    }
}

impl Reference {
    fn render(&self) -> String {
        let mut page = format!(
            "# Scenario keys\n\n\
             Generated from the scenario types (`nav-sim/src/scenario/`, their JSON Schema \
             derived with `schemars`) by `{BLESS}`; the test fails when this file differs from \
             the types or misses a key of a shipped scenario. Do not edit it by hand.\n\n\
             Every key a scenario file accepts (any other is refused), a table per TOML table. \
             type: `number[3]` is an array of three numbers; unit: from the key's name (`-`: \
             none there); default: `required`, `absent` (an optional key with no value), or \
             the value a left-out key takes; description: the first sentence of the field's doc \
             comment. `Scenario::validate` checks the ranges, naming the key. The `[filter]` \
             keys configure the flight software, whose rules are in \
             [flight-parameters.md](flight-parameters.md).\n"
        );
        for section in &self.sections {
            page.push_str(&format!("\n## {}\n\n", section.title));
            if !section.about.is_empty() {
                page.push_str(&format!("{}\n\n", section.about));
            }
            page.push_str("| key | type | unit | default | description |\n|---|---|---|---|---|\n");
            for row in &section.rows {
                page.push_str(&format!(
                    "| `{}` | {} | {} | {} | {} |\n",
                    row.key, row.kind, row.unit, row.default, row.description
                ));
            }
        }
        page
    }

    fn section(&self, title: &str) -> Option<&Section> {
        self.sections.iter().find(|section| section.title == title)
    }

    /// Whether the dotted `key` of a scenario file (array indices left out) has its row.
    fn covers(&self, key: &str) -> bool {
        self.sections.iter().flat_map(|s| &s.rows).any(|row| {
            if row.key == key {
                return matches!(row.holds, Holds::Value);
            }
            let Some(rest) = key.strip_prefix(&format!("{}.", row.key)) else {
                return false;
            };
            match &row.holds {
                Holds::Value => false,
                Holds::TablesOf(at) => self.covers(&format!("{at}.{rest}")),
                Holds::Shared(title) => self
                    .section(title)
                    .is_some_and(|section| section.rows.iter().any(|row| row.key == rest)),
            }
        })
    }
}

/// The dotted paths of every value in `table`, tables in arrays entered without an index.
fn keys(table: &toml::Table, prefix: &str, found: &mut BTreeSet<String>) {
    for (key, value) in table {
        let path = if prefix.is_empty() {
            key.clone()
        } else {
            format!("{prefix}.{key}")
        };
        match value {
            toml::Value::Table(inner) => keys(inner, &path, found),
            toml::Value::Array(items)
                if items.iter().all(toml::Value::is_table) && !items.is_empty() =>
            {
                for item in items.iter().filter_map(toml::Value::as_table) {
                    keys(item, &path, found);
                }
            }
            _ => {
                found.insert(path);
            }
        }
    }
}

fn shipped_scenarios() -> Vec<PathBuf> {
    let directory = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios");
    let mut files: Vec<PathBuf> = std::fs::read_dir(directory)
        .unwrap()
        .map(|entry| entry.unwrap().path())
        .filter(|path| {
            path.extension()
                .is_some_and(|extension| extension == "toml")
        })
        .collect();
    files.sort();
    files
}

#[test]
fn the_scenario_key_reference_is_the_types() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(PAGE);
    let reference = reference();
    // A schema construct the renderer does not know shows as `?`: teach it, do not bless.
    for row in reference.sections.iter().flat_map(|section| &section.rows) {
        assert!(!row.kind.contains('?'), "`{}`: type unknown", row.key);
    }
    let page = reference.render();
    if std::env::var_os("NAV_BLESS").is_some() {
        std::fs::write(&path, &page).unwrap();
    }
    let committed = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        committed == page,
        "{} differs from the scenario types: run {BLESS}",
        path.display()
    );
}

#[test]
fn every_key_of_every_shipped_scenario_is_in_the_reference() {
    let reference = reference();
    let files = shipped_scenarios();
    assert!(files.len() >= 2, "only {} scenario files", files.len());
    let mut used = BTreeSet::new();
    let mut missing = Vec::new();
    for file in &files {
        let resolved = overlay::resolve_file(file).unwrap();
        let mut found = BTreeSet::new();
        keys(resolved.table(), "", &mut found);
        for key in found {
            if !reference.covers(&key) {
                missing.push(format!("{}: {key}", file.display()));
            }
            used.insert(key);
        }
    }
    assert!(
        missing.is_empty(),
        "keys of shipped scenarios the reference does not list (run {BLESS}):\n{}",
        missing.join("\n")
    );
    // The check looks through every kind of key, and refuses one the types do not have.
    for key in [
        "launch_site.earth_orientation.ut1_minus_utc_s",
        "manoeuvre.label",
        "star_sensor.additional_heads.rate_hz",
        "filter.gravity.degree",
    ] {
        assert!(used.contains(key), "no shipped scenario uses {key}");
    }
    for key in [
        "dispersion.gyro_noise_percent.kind",
        "dispersion.gyro_noise_percent.sigma",
        "star_sensor.additional_heads.outages",
        "gravity.model",
    ] {
        assert!(reference.covers(key), "{key}");
    }
    for key in [
        "launch_site.latitude",
        "launch_site",
        "dispersion.gyro_noise_percent.mean",
        "star_sensor.additional_heads.bogus",
    ] {
        assert!(!reference.covers(key), "{key}");
    }
}
