//! Training OBL levels one after another, each on the level below: level L ≥ 2 has level
//! L−1's runs as its previous level (the partner its belief models) and, as in the
//! reference implementation, as its starting weights. Level 1's previous level is random
//! play, and it starts where the config says (`run.init_from`). A level that starts from
//! the level below's weights takes `obl.warm_lr` and `obl.warm_shaping`, when given, in
//! place of `ppo.lr` and `ppo.shaping` ([`TrainConfig::for_its_level`]), so the
//! already-trained policy is not jolted by a restarted rate and shaping reward; level 1
//! keeps the config's. A level below `obl.symmetries_from_level` trains without
//! `algorithm.symmetries` (the same function).

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
            let c = c.for_its_level();
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
            assert_eq!(level.config.clone().for_its_level(), level.config);
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
    fn symmetries_switch_on_at_their_level_and_stay_on() {
        use crate::config::SymmetrySet;
        let c = TrainConfig::from_toml_str(
            "[algorithm]\nsymmetries = \"both\"\n[obl]\nlevel = 1\nsymmetries_from_level = 3\n",
            "obl",
        )
        .unwrap();
        let plan = plan(&c, &[1, 2, 3, 4], Path::new("runs/obl")).unwrap();
        let got: Vec<_> = plan
            .iter()
            .map(|l| (l.level, l.config.algorithm.symmetries))
            .collect();
        let (none, both) = (SymmetrySet::None, SymmetrySet::Both);
        assert_eq!(got, [(1, none), (2, none), (3, both), (4, both)]);
        // Applied again when a level starts (and by a resume), it changes nothing.
        for level in &plan {
            assert_eq!(level.config.clone().for_its_level(), level.config);
        }
        // Absent, every level keeps the config's symmetries.
        let mut every = c.clone();
        every.obl.symmetries_from_level = None;
        let plan = super::plan(&every, &[1, 2], Path::new("runs/obl")).unwrap();
        assert!(plan.iter().all(|l| l.config.algorithm.symmetries == both));
        // Nothing to switch on: refused where it would switch, naming the field.
        let mut nothing = c;
        nothing.algorithm.symmetries = none;
        let e = super::plan(&nothing, &[2, 3], Path::new("x")).unwrap_err();
        let e = format!("{e}: {}", std::error::Error::source(&e).unwrap());
        assert!(
            e.contains("level 3") && e.contains("obl.symmetries_from_level"),
            "{e}"
        );
    }

    /// `obl-cpu-op` is the chain measured in docs/results/obl-op-ramp.md: each level below
    /// 4 trains as `obl-cpu-long` does, each level from 4 as `obl-cpu-long` with
    /// `--set algorithm.symmetries=both`, brought in over level 4's first half (the ramp acts
    /// at level 4 only), so those measurements are the preset's.
    #[test]
    fn obl_cpu_op_is_obl_cpu_long_with_the_symmetries_ramped_in_at_level_4() {
        let both: crate::config::Override = "algorithm.symmetries=both".parse().unwrap();
        let (long, _) = TrainConfig::named("obl-cpu-long", &[]).unwrap();
        let (with_both, _) = TrainConfig::named("obl-cpu-long", &[both]).unwrap();
        let (op, _) = TrainConfig::named("obl-cpu-op", &[]).unwrap();
        let out = Path::new("runs/x");
        let plan = |c: &TrainConfig| super::plan(c, &[1, 2, 3, 4, 5, 7], out).unwrap();
        for ((op, long), with_both) in plan(&op).iter().zip(plan(&long)).zip(plan(&with_both)) {
            let mut c = op.config.clone();
            assert_eq!(c.obl.symmetries_from_level, Some(4));
            assert_eq!(c.obl.symmetries_ramp, Some(0.5));
            // Half of each game's steps at level 4 (the actor counts steps per game).
            let ramp_steps =
                (op.level == 4).then_some(c.updates() * c.ppo.rollout_steps as u64 / 2);
            assert_eq!(c.symmetry_ramp_steps(), ramp_steps, "level {}", op.level);
            c.obl.symmetries_from_level = None;
            c.obl.symmetries_ramp = None;
            let measured = if op.level < 4 { &long } else { &with_both };
            assert_eq!(c, measured.config, "level {}", op.level);
        }
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
