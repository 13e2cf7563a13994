//! Training OBL levels one after another, each on the level below: level L ≥ 2 has level
//! L−1's runs as its previous level (the partner its belief models) and, as in the
//! reference implementation, as its starting weights. Level 1's previous level is random
//! play, and it starts where the config says (`run.init_from`). A level that starts from
//! the level below's weights takes `obl.warm_lr` and `obl.warm_shaping`, when given, in
//! place of `ppo.lr` and `ppo.shaping` ([`TrainConfig::warm_started`]), so the
//! already-trained policy is not jolted by a restarted rate and shaping reward; level 1
//! keeps the config's.

use crate::config::{TrainConfig, TrainConfigError};
use std::path::{Path, PathBuf};

/// One level of a chain: its config and the directory its seeds' runs go to.
#[derive(Clone, Debug)]
pub struct Level {
    pub level: u32,
    pub config: TrainConfig,
    pub dir: PathBuf,
}

/// Why a chain of levels cannot be planned.
#[derive(Debug, thiserror::Error)]
pub enum LevelsError {
    #[error(
        "the config trains no Off-Belief Learning level (its obl.level is 0): chaining levels \
         needs an OBL config such as obl-cpu or obl-quick"
    )]
    NotObl,
    #[error("levels count from 1 (level 0 is random play)")]
    LevelZero,
    #[error("level {level}: {source}")]
    Config {
        level: u32,
        #[source]
        source: TrainConfigError,
    },
}

/// Where level `level`'s runs go under `out`: `out/level-L`, one `seed-N` run per seed.
pub fn level_dir(out: &Path, level: u32) -> PathBuf {
    out.join(format!("level-{level}"))
}

/// The levels `levels` of the OBL config `config`, trained into `out`, each checked: level
/// L ≥ 2 reads level L−1 from [`level_dir`]`(out, L−1)`, so levels train in the order
/// given and a level's runs must exist before the level above starts.
pub fn plan(config: &TrainConfig, levels: &[u32], out: &Path) -> Result<Vec<Level>, LevelsError> {
    if config.obl.level == 0 {
        return Err(LevelsError::NotObl);
    }
    levels
        .iter()
        .map(|&level| {
            if level == 0 {
                return Err(LevelsError::LevelZero);
            }
            let mut c = config.clone();
            c.obl.level = level;
            if level >= 2 {
                let below = level_dir(out, level - 1);
                c.obl.previous = Some(below.clone());
                c.run.init_from = Some(below);
            }
            // The trainer applies the same rule when the run starts; applied here too so
            // that the planned config is the one each level trains with.
            let c = c.warm_started();
            c.validate("config")
                .map_err(|source| LevelsError::Config { level, source })?;
            Ok(Level {
                level,
                config: c,
                dir: level_dir(out, level),
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn obl() -> TrainConfig {
        TrainConfig::from_toml_str("[obl]\nlevel = 1\n", "obl").unwrap()
    }

    #[test]
    fn each_level_reads_and_starts_from_the_one_below() {
        let out = Path::new("runs/obl");
        let plan = plan(&obl(), &[1, 2, 3], out).unwrap();
        let got: Vec<_> = plan
            .iter()
            .map(|l| {
                let c = &l.config;
                (
                    l.level,
                    c.obl.level,
                    c.obl.previous.clone(),
                    c.run.init_from.clone(),
                )
            })
            .collect();
        let below = |l: u32| Some(out.join(format!("level-{l}")));
        assert_eq!(
            got,
            [
                (1, 1, None, None),
                (2, 2, below(1), below(1)),
                (3, 3, below(2), below(2))
            ]
        );
        assert_eq!(plan[2].dir, out.join("level-3"));
    }

    #[test]
    fn warm_levels_take_the_warm_rate_and_shaping_and_level_1_keeps_its_own() {
        let c = TrainConfig::from_toml_str(
            "[ppo]\nlr = 3e-3\nshaping = 1.0\n[obl]\nlevel = 1\nwarm_lr = 1e-3\nwarm_shaping = 0.0\n",
            "obl",
        )
        .unwrap();
        let plan = plan(&c, &[1, 2, 3], Path::new("runs/obl")).unwrap();
        let got: Vec<_> = plan
            .iter()
            .map(|l| (l.level, l.config.ppo.lr, l.config.ppo.shaping))
            .collect();
        assert_eq!(got, [(1, 3e-3, 1.0), (2, 1e-3, 0.0), (3, 1e-3, 0.0)]);
        // The trainer applies the rule again when the level starts: it changes nothing.
        for level in &plan {
            assert_eq!(level.config.clone().warm_started(), level.config);
        }
        // Absent, every level trains at the config's rate and shaping (the reference's rule).
        let plan = super::plan(&obl(), &[1, 2], Path::new("runs/obl")).unwrap();
        assert_eq!(plan[0].config.ppo, plan[1].config.ppo);
        // Only one of the two given: the other stays the config's.
        let c =
            TrainConfig::from_toml_str("[obl]\nlevel = 1\nwarm_shaping = 0.0\n", "obl").unwrap();
        let plan = super::plan(&c, &[2], Path::new("runs/obl")).unwrap();
        assert_eq!(
            (plan[0].config.ppo.lr, plan[0].config.ppo.shaping),
            (c.ppo.lr, 0.0)
        );
    }

    #[test]
    fn a_chain_needs_an_obl_config_and_levels_from_1() {
        let ippo = TrainConfig::from_toml_str("", "ippo").unwrap();
        let e = plan(&ippo, &[1], Path::new("x")).unwrap_err();
        assert!(e.to_string().contains("obl.level is 0"), "{e}");
        let e = plan(&obl(), &[0, 1], Path::new("x")).unwrap_err();
        assert!(matches!(e, LevelsError::LevelZero), "{e}");
    }
}
