//! The training configs shipped in `configs/`, built into the library so that their names
//! work from any directory and from every front end (`yokai train`, Python's
//! `yokai.torch_train`), and [`TrainConfig::named`]: a config by preset name or path.

use super::{Override, TrainConfig, TrainConfigError};
use std::path::Path;

/// `(name, contents)` of each named file in `configs/`.
macro_rules! presets {
    ($($name:literal),* $(,)?) => {
        &[$(($name, include_str!(concat!("../../../../configs/", $name, ".toml")))),*]
    };
}

/// The configs shipped in `configs/`: `(name, TOML text)`.
pub const PRESETS: &[(&str, &str)] = presets!(
    "quick",
    "quick-op",
    "obl-quick",
    "obl-cpu",
    "obl-cpu-long",
    "obl-cpu-op",
    "obl-9c-2p",
    "cpu",
    "cpu-fast",
    "cpu-op",
    "ippo-9c-2p",
    "he-9c-2p",
    "op-9c-2p",
    "op-col-9c-2p",
    "op-rot-9c-2p",
    "ippo-9c-3p",
    "he-9c-3p",
    "op-9c-3p",
    "ippo-9c-4p",
    "he-9c-4p",
    "op-9c-4p",
    "ippo-16c-2p",
    "ippo-9c-2p-imperfect",
    "op-9c-2p-imperfect",
    "op-trxl-9c-2p-imperfect",
    "ippo-1hl-9c-2p",
    "ippo-2hl-9c-2p",
    "ippo-gcn-9c-2p",
    "ippo-gatv2-9c-2p",
    "ippo-relation-9c-2p",
    "ippo-trxl-9c-2p",
);

impl TrainConfig {
    /// The config `name` names, a preset of `configs/` or a path to a TOML file, with
    /// `overrides` applied; and a short name for it (the preset's, or the file's stem), which
    /// run directories are named after.
    pub fn named(
        name: &str,
        overrides: &[Override],
    ) -> Result<(TrainConfig, String), TrainConfigError> {
        if let Some((preset, text)) = PRESETS.iter().find(|(n, _)| *n == name) {
            let origin = format!("configs/{preset}.toml");
            let config = TrainConfig::from_toml_with(text, &origin, overrides)?;
            return Ok((config, preset.to_string()));
        }
        let path = Path::new(name);
        if !path.exists() {
            let names: Vec<&str> = PRESETS.iter().map(|(n, _)| *n).collect();
            return Err(TrainConfigError::Io {
                path: name.to_string(),
                message: format!("not a preset ({}) and no such file", names.join(", ")),
            });
        }
        let config = TrainConfig::from_file_with(path, overrides)?;
        let stem = path
            .file_stem()
            .map_or("run".into(), |s| s.to_string_lossy().to_string());
        Ok((config, stem))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_shipped_config_is_valid_and_every_file_of_configs_is_shipped() {
        for (name, text) in PRESETS {
            TrainConfig::from_toml_str(text, name).unwrap_or_else(|e| panic!("{name}: {e}"));
        }
        let dir = format!("{}/../../configs", env!("CARGO_MANIFEST_DIR"));
        let mut files: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .filter_map(|e| {
                let name = e.unwrap().file_name().into_string().unwrap();
                name.strip_suffix(".toml").map(String::from)
            })
            .collect();
        files.sort();
        let mut names: Vec<String> = PRESETS.iter().map(|(n, _)| n.to_string()).collect();
        names.sort();
        assert_eq!(files, names);
    }

    #[test]
    fn a_name_is_a_preset_or_a_file_and_anything_else_is_refused_with_the_presets() {
        let set: Override = "ppo.lr=0.01".parse().unwrap();
        let (config, name) = TrainConfig::named("quick", &[set]).unwrap();
        assert_eq!((config.ppo.lr, name.as_str()), (0.01, "quick"));
        let path = format!("{}/../../configs/cpu-fast.toml", env!("CARGO_MANIFEST_DIR"));
        let (from_file, stem) = TrainConfig::named(&path, &[]).unwrap();
        assert_eq!(stem, "cpu-fast");
        assert_eq!(from_file, TrainConfig::named("cpu-fast", &[]).unwrap().0);
        let e = TrainConfig::named("qiuck", &[]).unwrap_err().to_string();
        assert!(
            e.contains("qiuck") && e.contains("not a preset (quick, "),
            "{e}"
        );
    }

    /// `obl-cpu-long` is the recipe measured on `obl-cpu` by overrides (the chains of
    /// docs/results/obl-belief-all-seeds.md and obl-held-out-seeds.md): nothing else differs,
    /// so those measurements are the preset's.
    #[test]
    fn obl_cpu_long_is_obl_cpu_with_the_measured_overrides() {
        let overrides: Vec<Override> = [
            "ppo.total_steps=12000000",
            "ppo.lr=1e-3",
            "obl.belief_of=all-seeds",
        ]
        .iter()
        .map(|o| o.parse().unwrap())
        .collect();
        let (measured, _) = TrainConfig::named("obl-cpu", &overrides).unwrap();
        let (long, _) = TrainConfig::named("obl-cpu-long", &[]).unwrap();
        assert_eq!(long, measured);
    }

    /// The paper presets (every preset on the paper's network) train with the paper's PPO
    /// settings (docs/spec/training.md, "PPO settings" and the algorithms' table) and play
    /// by the trained distribution: the CPU levers stay in presets of their own. Written
    /// out field by field rather than from `PpoConfig::default()`, so that a changed
    /// default shows here too and a new field has to be placed.
    #[test]
    fn the_paper_presets_keep_the_papers_ppo_settings() {
        use crate::config::{ActConfig, EndForm, NetworkPreset, PpoConfig};
        let mut checked = Vec::new();
        for (name, text) in PRESETS {
            let c = TrainConfig::from_toml_str(text, name).unwrap();
            if c.network.preset != NetworkPreset::Paper {
                continue;
            }
            let players = c.game_config().unwrap().players();
            // HE: α 0.07 and λ 0.85; IPPO and OP: α 0.05 with 2 players, 0.01 with 3 or 4.
            let (entropy_coef, gae_lambda) = match (c.algorithm.name.as_str(), players) {
                ("he", _) => (0.07, 0.85),
                (_, 2) => (0.05, 0.95),
                _ => (0.01, 0.95),
            };
            // 256 games for OBL; the paper ran HE with 4 players on 512.
            let num_envs = match (c.algorithm.name.as_str(), *name) {
                ("obl", _) => 256,
                (_, "he-9c-4p") => 512,
                _ => 1024,
            };
            let paper = PpoConfig {
                num_envs,
                rollout_steps: 128,
                total_steps: 1_000_000_000,
                lr: 3e-4,
                anneal_lr: true,
                lr_hold: 0.0,
                adam_eps: 1e-5,
                gamma: 0.99,
                gae_lambda,
                clip: 0.2,
                value_clip: 0.2,
                value_coef: 0.5,
                entropy_coef,
                entropy_final: None,
                entropy_normalized: false,
                end_entropy_coef: 0.0,
                end_lookahead: 0.0,
                end_lookahead_form: EndForm::Expected,
                belief_aux: 0.0,
                max_grad_norm: 0.5,
                epochs: 4,
                minibatches: 4,
                shaping: 1.0,
                shaping_fraction: 1.0,
                normalize_advantages: true,
                cluster_shaping: 0.0,
                belief_gain: 0.0,
                belief_gain_fraction: 1.0,
                belief_gain_baseline: crate::config::GainBaseline::None,
                belief_gain_seats: crate::config::GainSeats::All,
            };
            assert_eq!(c.ppo, paper, "{name}");
            assert_eq!(c.act, ActConfig::default(), "{name}");
            checked.push(*name);
        }
        // The main table's presets are among them (none left the paper's network).
        for name in [
            "ippo-9c-2p",
            "he-9c-2p",
            "op-9c-2p",
            "obl-9c-2p",
            "he-9c-4p",
        ] {
            assert!(
                checked.contains(&name),
                "{name} is not on the paper's network"
            );
        }
    }
}
