//! Fuzz tests of the trainer's parsers of outside input: checkpoint and policy files, and
//! training config TOML. Arbitrary bytes and mutations of valid inputs must never panic, an
//! altered file must never load (a mutated file is either refused or byte-for-byte the
//! original), and an accepted config reads back from its saved form unchanged. `YOKAI_FUZZ_CASES=100000 cargo test --release -p yokai-train --test fuzz` runs
//! a long session (docs/reliability.md).

use proptest::prelude::*;
use std::path::Path;
use yokai_train::Container;
use yokai_train::{MlpEncoder, TrainConfig, Trainer};

fn cases() -> u32 {
    std::env::var("YOKAI_FUZZ_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(256)
}

/// A real policy file of a tiny untrained network.
fn policy_bytes() -> Vec<u8> {
    let config = TrainConfig::from_toml_str(
        "[network]\npreset = \"compact\"\nhidden = 8\n[ppo]\nnum_envs = 2\nrollout_steps = 2\nminibatches = 1\n[run]\nthreads = 1\n",
        "fuzz",
    )
    .unwrap();
    Trainer::<MlpEncoder>::new(config, 0)
        .unwrap()
        .policy()
        .to_bytes()
}

const PRESET: &str = include_str!("../../../configs/cpu.toml");

proptest! {
    #![proptest_config(ProptestConfig { cases: cases(), ..ProptestConfig::default() })]

    #[test]
    fn an_altered_policy_file_never_loads(edits in prop::collection::vec((any::<usize>(), 0u8..3, any::<u8>()), 1..5), junk in prop::collection::vec(any::<u8>(), 0..64)) {
        let original = policy_bytes();
        let mut bytes = original.clone();
        for &(at, kind, value) in &edits {
            let at = at % bytes.len();
            match kind {
                0 => bytes[at] = value,
                1 => bytes.insert(at, value),
                _ => { bytes.remove(at); }
            }
        }
        match Container::from_bytes(&bytes, Path::new("fuzz.ykp")) {
            Ok(c) => prop_assert_eq!(c.to_bytes(), original, "an altered file was accepted"),
            Err(e) => prop_assert!(e.to_string().contains("fuzz.ykp")),
        }
        let _ = Container::from_bytes(&junk, Path::new("junk"));
    }

    #[test]
    fn training_config_toml_never_panics(text in "\\PC{0,200}", at in any::<usize>(), value in any::<char>()) {
        let _ = TrainConfig::from_toml_str(&text, "fuzz");
        let mut chars: Vec<char> = PRESET.chars().collect();
        let at = at % chars.len();
        chars[at] = value;
        let mutated: String = chars.into_iter().collect();
        match TrainConfig::from_toml_str(&mutated, "fuzz.toml") {
            // What is accepted is what a run saves: its resolved TOML reads back the same.
            Ok(config) => prop_assert_eq!(
                TrainConfig::from_toml_str(&config.to_toml(), "resolved").unwrap(),
                config
            ),
            Err(e) => prop_assert!(e.to_string().contains("fuzz.toml")),
        }
    }
}
