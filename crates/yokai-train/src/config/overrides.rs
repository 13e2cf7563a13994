//! `FIELD=VALUE` overrides of a training config (`yokai train --set ppo.lr=1e-3`), checked
//! as the file's own fields are: an unknown field or a value of the wrong type is refused
//! with the override named, and the result is validated as a whole.
//!
//! An override edits the file's TOML table before it becomes a [`TrainConfig`], so serde's
//! `deny_unknown_fields` and the types of the fields judge it exactly as they judge the
//! file. A value is read as TOML (`3e-3`, `true`, `"pointer"`, `[1, 2]`); where it does not
//! parse as TOML it is taken as a string, so `--set network.head=pointer` needs no quotes.

use super::{TrainConfig, TrainConfigError};
use std::str::FromStr;

/// One `FIELD=VALUE`: a dotted path to a field (`ppo.lr`, `game`) and its new value.
#[derive(Clone, Debug, PartialEq)]
pub struct Override {
    path: Vec<String>,
    value: toml::Value,
    /// The override as written, for messages.
    text: String,
}

impl Override {
    /// The override as it was written (`ppo.lr=1e-3`).
    pub fn text(&self) -> &str {
        &self.text
    }
}

impl FromStr for Override {
    type Err = TrainConfigError;

    fn from_str(text: &str) -> Result<Override, TrainConfigError> {
        let refuse = |message: &str| TrainConfigError::Override {
            set: text.to_string(),
            message: message.to_string(),
        };
        let (field, raw) = text
            .split_once('=')
            .ok_or_else(|| refuse("is not FIELD=VALUE (for example ppo.lr=1e-3)"))?;
        let path: Vec<String> = field.trim().split('.').map(str::to_string).collect();
        if path.iter().any(|p| p.is_empty()) {
            return Err(refuse(
                "names no field: write a section and a key, as in ppo.lr=1e-3, or a \
                 top-level key, as in game=9c-3p-perfect",
            ));
        }
        let raw = raw.trim();
        let value = toml::from_str::<toml::Table>(&format!("v = {raw}"))
            .ok()
            .and_then(|mut t| t.remove("v"))
            .unwrap_or_else(|| toml::Value::String(raw.to_string()));
        Ok(Override {
            path,
            value,
            text: text.to_string(),
        })
    }
}

impl TrainConfig {
    /// The config in `text` with `overrides` applied in order, then validated. Errors in
    /// the file name `origin`; errors an override brings name the override.
    pub fn from_toml_with(
        text: &str,
        origin: &str,
        overrides: &[Override],
    ) -> Result<TrainConfig, TrainConfigError> {
        if overrides.is_empty() {
            return TrainConfig::from_toml_str(text, origin);
        }
        // The file alone first, so that its own errors are not blamed on an override.
        let file = TrainConfig::from_toml_str(text, origin)?;
        let mut table = toml::Table::try_from(&file).expect("a training config is a table");
        for o in overrides {
            set(&mut table, o)?;
            table
                .clone()
                .try_into::<TrainConfig>()
                .map_err(|e| TrainConfigError::Override {
                    set: o.text.clone(),
                    // toml puts "in `section`" on a line of its own.
                    message: e.to_string().trim_end().replace('\n', " "),
                })?;
        }
        let config: TrainConfig = table.try_into().expect("checked after each override");
        let sets: Vec<&str> = overrides.iter().map(|o| o.text()).collect();
        config.validate(&format!("{origin} with --set {}", sets.join(" --set ")))?;
        Ok(config)
    }
}

/// Put `o`'s value at its path in `table`, making the sections it names where the file
/// left them out (every section has defaults).
fn set(table: &mut toml::Table, o: &Override) -> Result<(), TrainConfigError> {
    let (key, sections) = o.path.split_last().expect("a path has a field");
    let mut at = table;
    for (depth, section) in sections.iter().enumerate() {
        let entry = at
            .entry(section.clone())
            .or_insert_with(|| toml::Value::Table(toml::Table::new()));
        at = entry
            .as_table_mut()
            .ok_or_else(|| TrainConfigError::Override {
                set: o.text.clone(),
                message: format!("`{}` is a field, not a section", o.path[..=depth].join(".")),
            })?;
    }
    at.insert(key.clone(), o.value.clone());
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn with(text: &str, sets: &[&str]) -> Result<TrainConfig, String> {
        let overrides: Vec<Override> = sets
            .iter()
            .map(|s| s.parse())
            .collect::<Result<_, _>>()
            .map_err(|e: TrainConfigError| e.to_string())?;
        TrainConfig::from_toml_with(text, "test.toml", &overrides).map_err(|e| e.to_string())
    }

    const FILE: &str = "game = \"9c-2p-perfect\"\n[ppo]\nlr = 3e-3\n";

    #[test]
    fn an_override_changes_its_field_and_nothing_else() {
        let base = with(FILE, &[]).unwrap();
        let sets = [
            "ppo.lr=1e-4",
            "network.preset=compact",
            "network.head=pointer",
            "game=9c-3p-perfect",
        ];
        let c = with(FILE, &sets).unwrap();
        assert_eq!(c.ppo.lr, 1e-4);
        assert_eq!(c.network.head, crate::config::ActionHead::Pointer);
        assert_eq!(c.game, "9c-3p-perfect");
        let mut expected = base.clone();
        expected.ppo.lr = 1e-4;
        expected.network.preset = crate::config::NetworkPreset::Compact;
        expected.network.head = crate::config::ActionHead::Pointer;
        expected.game = "9c-3p-perfect".into();
        assert_eq!(c, expected);
        // The saved config shows the override.
        assert!(c.to_toml().contains("lr = 0.0001"), "{}", c.to_toml());
    }

    #[test]
    fn later_overrides_win_and_sections_absent_from_the_file_are_made() {
        let c = with(
            FILE,
            &["ppo.epochs=3", "ppo.epochs=2", "act.end_threshold=0.25"],
        )
        .unwrap();
        assert_eq!(c.ppo.epochs, 2);
        assert_eq!(c.act.end_threshold, Some(0.25));
    }

    #[test]
    fn a_bad_override_is_refused_naming_it_and_what_is_accepted() {
        let e = with(FILE, &["ppo.lrr=1"]).unwrap_err();
        assert!(e.contains("--set ppo.lrr=1"), "{e}");
        assert!(
            e.contains("unknown field `lrr`") && e.contains("`lr`"),
            "{e}"
        );
        let e = with(FILE, &["ppx.lr=1"]).unwrap_err();
        assert!(
            e.contains("unknown field `ppx`") && e.contains("`ppo`"),
            "{e}"
        );
        let e = with(FILE, &["ppo.lr=fast"]).unwrap_err();
        assert!(
            e.contains("--set ppo.lr=fast") && e.contains("string"),
            "{e}"
        );
        let e = with(FILE, &["network.head=dense3"]).unwrap_err();
        assert!(e.contains("dense3") && e.contains("pointer"), "{e}");
        let e = with(FILE, &["ppo.lr.x=1"]).unwrap_err();
        assert!(e.contains("`ppo.lr` is a field, not a section"), "{e}");
        let e = with(FILE, &["ppo.lr"]).unwrap_err();
        assert!(e.contains("FIELD=VALUE"), "{e}");
        let e = with(FILE, &[".lr=1"]).unwrap_err();
        assert!(e.contains("names no field"), "{e}");
    }

    #[test]
    fn an_override_is_validated_with_the_whole_config() {
        let e = with(FILE, &["ppo.num_envs=0"]).unwrap_err();
        assert!(e.contains("test.toml with --set ppo.num_envs=0"), "{e}");
        assert!(e.contains("num_envs"), "{e}");
    }

    #[test]
    fn the_files_own_errors_name_the_file() {
        let e = with("[ppo]\nlrr = 1\n", &["ppo.lr=1e-3"]).unwrap_err();
        assert!(e.starts_with("training config test.toml"), "{e}");
        assert!(!e.contains("--set"), "{e}");
    }
}
