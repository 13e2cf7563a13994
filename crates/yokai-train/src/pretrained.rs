//! Pretrained agents built into the library, so that `pretrained:quick/0` seats a trained
//! partner anywhere a policy is taken (`yokai eval`, `play`, `serve`,
//! `yokai.Agent.pretrained`) without a training run first.
//!
//! The policy files live in `crates/yokai-train/pretrained/PRESET/seed-N.ykp`, beside
//! `pretrained.toml`, which says for each preset how it was trained and what it scores in
//! self-play (a test plays each file and checks that score). They are compiled into the
//! binary, so the names work from any directory and in the Python wheel.

use crate::error::TrainError;
use crate::policy::TrainedPolicy;
use serde::Deserialize;

/// The prefix that names a pretrained agent: `pretrained:PRESET/SEED`.
pub const PREFIX: &str = "pretrained:";

/// `(preset, seed, policy file)` of every agent shipped.
macro_rules! shipped {
    ($(($preset:literal, $seed:literal)),* $(,)?) => {
        &[$(($preset, $seed, include_bytes!(
            concat!("../pretrained/", $preset, "/seed-", $seed, ".ykp")
        ))),*]
    };
}

const SHIPPED: &[(&str, u64, &[u8])] = shipped!(
    ("quick", 0),
    ("quick", 1),
    ("quick", 2),
    ("quick-op", 0),
    ("quick-op", 1),
    ("quick-op", 2),
    ("cpu-op", 0),
    ("cpu-op", 1),
    ("cpu-op", 2),
    ("cpu-fast", 0),
    ("cpu-fast", 1),
    ("cpu-fast", 2),
    ("obl-cpu", 0),
    ("obl-cpu", 1),
    ("obl-cpu", 2),
    ("obl-cpu-level-4", 0),
    ("obl-cpu-level-4", 1),
    ("obl-cpu-level-4", 2),
    ("obl-cpu-level-5", 0),
    ("obl-cpu-level-5", 1),
    ("obl-cpu-level-5", 2),
    ("obl-cpu-op-level-7", 0),
    ("obl-cpu-op-level-7", 1),
    ("obl-cpu-op-level-7", 2),
);

/// `pretrained.toml`: how each preset's agents were made and what they score.
pub const MANIFEST: &str = include_str!("../pretrained/pretrained.toml");

/// One preset's entry in [`MANIFEST`].
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Entry {
    pub preset: String,
    /// What the agents are, in a line.
    pub about: String,
    /// The command that trained them.
    pub command: String,
    pub steps: u64,
    pub seeds: Vec<u64>,
    /// Self-play R of each seed with itself (its file's END rule), and its standard error,
    /// over `games` games of `yokai eval`.
    pub sp_r: Vec<f64>,
    pub sp_se: Vec<f64>,
    pub games: u64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Manifest {
    agent: Vec<Entry>,
}

/// Every entry of [`MANIFEST`], in its order.
pub fn entries() -> Vec<Entry> {
    toml::from_str::<Manifest>(MANIFEST)
        .expect("pretrained.toml parses (tested)")
        .agent
}

/// The names of every agent shipped: `pretrained:quick/0`, ….
pub fn names() -> Vec<String> {
    SHIPPED
        .iter()
        .map(|(preset, seed, _)| format!("{PREFIX}{preset}/{seed}"))
        .collect()
}

/// Why a pretrained name was refused.
#[derive(Debug, thiserror::Error)]
pub enum PretrainedError {
    #[error("no pretrained agent `{asked}`; the ones built in: {}", available.join(", "))]
    Unknown {
        asked: String,
        available: Vec<String>,
    },
    #[error(transparent)]
    File(#[from] TrainError),
}

/// The agent `text` names, which starts with [`PREFIX`]: `pretrained:PRESET/SEED`, or
/// `pretrained:PRESET` for seed 0.
pub fn load(text: &str) -> Result<TrainedPolicy, PretrainedError> {
    let unknown = || PretrainedError::Unknown {
        asked: text.to_string(),
        available: names(),
    };
    let rest = text.strip_prefix(PREFIX).ok_or_else(unknown)?;
    let (preset, seed) = match rest.split_once('/') {
        Some((preset, seed)) => (preset, seed.parse::<u64>().map_err(|_| unknown())?),
        None => (rest, 0),
    };
    let (_, _, bytes) = SHIPPED
        .iter()
        .find(|(p, s, _)| *p == preset && *s == seed)
        .ok_or_else(unknown)?;
    Ok(TrainedPolicy::load_bytes(
        bytes,
        &format!("{PREFIX}{preset}/{seed}"),
    )?)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_manifest_lists_exactly_the_files_shipped() {
        let mut listed: Vec<String> = entries()
            .iter()
            .flat_map(|e| {
                assert_eq!(e.seeds.len(), e.sp_r.len(), "{}", e.preset);
                assert_eq!(e.seeds.len(), e.sp_se.len(), "{}", e.preset);
                // Python's manifest test holds the same: the command a user can rerun.
                assert!(e.command.starts_with("yokai train "), "{}", e.preset);
                e.seeds
                    .iter()
                    .map(|s| format!("{PREFIX}{}/{s}", e.preset))
                    .collect::<Vec<_>>()
            })
            .collect();
        let mut shipped = names();
        listed.sort();
        shipped.sort();
        assert_eq!(listed, shipped);
    }

    #[test]
    fn every_agent_loads_with_its_presets_config() {
        for e in entries() {
            for &seed in &e.seeds {
                let p = load(&format!("{PREFIX}{}/{seed}", e.preset)).unwrap();
                assert_eq!(
                    p.path().display().to_string(),
                    format!("pretrained:{}/{seed}", e.preset)
                );
                assert_eq!(p.header().seed, seed, "{}", e.preset);
                assert_eq!(p.header().env_steps, e.steps, "{}", e.preset);
            }
        }
        // A preset alone is its seed 0.
        assert_eq!(load("pretrained:quick").unwrap().header().seed, 0);
    }

    #[test]
    fn unknown_names_list_the_agents_built_in() {
        for bad in [
            "pretrained:nope/0",
            "pretrained:quick/9",
            "pretrained:quick/x",
            "quick/0",
        ] {
            let e = load(bad).unwrap_err().to_string();
            assert!(e.contains(&format!("`{bad}`")), "{e}");
            assert!(e.contains("pretrained:quick/0, pretrained:quick/1"), "{e}");
        }
    }
}
