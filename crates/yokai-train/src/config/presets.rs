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
}
