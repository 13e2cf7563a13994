//! The config table of docs/training.md against the code: every field it names exists,
//! with the default it states, and every field of the config is in it. A default changed
//! in the code, or a field added without its row, fails here with the row to mend.

use std::collections::BTreeMap;
use yokai_train::TrainConfig;

/// Every leaf of the default config as `section.field` → TOML value.
fn defaults() -> BTreeMap<String, toml::Value> {
    let table: toml::Table = toml::from_str(&TrainConfig::default().to_toml()).unwrap();
    let mut out = BTreeMap::new();
    for (key, value) in table {
        match value {
            toml::Value::Table(section) => {
                for (field, v) in section {
                    out.insert(format!("{key}.{field}"), v);
                }
            }
            v => {
                out.insert(key, v);
            }
        }
    }
    out
}

/// The rows of the table under "| field | default | meaning |": (fields, defaults), a row
/// naming several fields of one section (`ppo.lr`, `anneal_lr`, `adam_eps`) expanded.
fn documented() -> Vec<(String, String)> {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../docs/training.md"
    ))
    .unwrap();
    let table = text
        .split("| field | default | meaning |")
        .nth(1)
        .expect("the config table");
    let mut out = Vec::new();
    for row in table.lines().skip(2).take_while(|l| l.starts_with('|')) {
        let cells: Vec<&str> = row.trim_matches('|').split(" | ").map(str::trim).collect();
        let fields: Vec<&str> = cells[0].split(", ").map(|f| f.trim_matches('`')).collect();
        let section = fields[0].split_once('.').map(|(s, _)| s);
        let values: Vec<&str> = if fields.len() > 1 {
            cells[1].split(", ").collect()
        } else {
            vec![cells[1]]
        };
        assert_eq!(
            values.len(),
            fields.len(),
            "docs row `{row}`: one default per field"
        );
        for (k, (field, value)) in fields.iter().zip(values).enumerate() {
            // Later fields of a row name their section once, in the first.
            let name = match section {
                Some(s) if k > 0 && !field.contains('.') => format!("{s}.{field}"),
                _ => field.to_string(),
            };
            out.push((name, value.trim_matches('`').to_string()));
        }
    }
    out
}

/// Whether the docs' `text` states `value`.
fn states(text: &str, value: Option<&toml::Value>) -> bool {
    let number = |t: &str| t.replace("10⁹", "1e9").parse::<f64>().ok();
    match value {
        None => matches!(text, "none" | "–"),
        Some(toml::Value::String(s)) => s == text,
        Some(toml::Value::Boolean(b)) => text == b.to_string(),
        Some(toml::Value::Integer(i)) => number(text) == Some(*i as f64),
        Some(toml::Value::Float(f)) => {
            number(text).is_some_and(|x| ((x - f) / f.abs().max(1e-12)).abs() < 1e-6)
        }
        Some(other) => text == other.to_string(),
    }
}

/// Whether a config file may set `field` (one the defaults leave out when serialised, as an
/// unset option): setting it to a string is refused for its type, never as unknown.
fn accepted(field: &str) -> bool {
    let (section, key) = field.split_once('.').unwrap_or(("", field));
    let text = format!("[{section}]\n{key} = \"?\"\n");
    match TrainConfig::from_toml_str(&text, "probe") {
        Ok(_) => true,
        Err(e) => !e.to_string().contains("unknown field"),
    }
}

/// Whether a config file that sets `field` to the docs' `text` is the default config: for
/// fields the serialised defaults leave out (an option unset, a flag off).
fn sets_default(field: &str, text: &str) -> bool {
    let (section, key) = field.split_once('.').unwrap_or(("", field));
    let default = TrainConfig::default().to_toml();
    [text.to_string(), format!("{text:?}")]
        .iter()
        .any(|literal| {
            let toml = format!("[{section}]\n{key} = {literal}\n");
            TrainConfig::from_toml_str(&toml, "probe").is_ok_and(|c| c.to_toml() == default)
        })
}

#[test]
fn every_documented_default_is_the_codes_and_every_field_is_documented() {
    let code = defaults();
    let docs = documented();
    let mut wrong = Vec::new();
    for (field, text) in &docs {
        // Defaults that depend on another field are described, not stated.
        if text.contains("preset's") {
            continue;
        }
        if !code.contains_key(field) && !accepted(field) {
            wrong.push(format!(
                "{field}: documented, but the config has no such field"
            ));
        } else if !states(text, code.get(field)) && !sets_default(field, text) {
            wrong.push(format!(
                "{field}: documented default {text}, the code's {:?}",
                code.get(field)
            ));
        }
    }
    for field in code.keys() {
        if !docs.iter().any(|(f, _)| f == field) {
            wrong.push(format!(
                "{field}: in the config, not in docs/training.md's table"
            ));
        }
    }
    assert!(
        wrong.is_empty(),
        "docs/training.md's config table:\n  {}",
        wrong.join("\n  ")
    );
    // The check read the table: the paper's learning rate among its rows.
    assert!(docs.iter().any(|(f, v)| f == "ppo.lr" && v == "3e-4"));
}
