//! Training configuration: one TOML file per experiment (see `configs/`).
//!
//! Every field has a default (the paper's IPPO on 9c-2p with the paper network), so a file
//! only states what differs. Unknown keys are errors, so a typo never silently trains the
//! default. The resolved configuration (every field written out) is saved with each run.
//!
//! One file per section, each struct beside its defaults and checks: [`ppo`], [`network`],
//! [`algorithm`], [`obl`], [`act`], [`run`]; [`overrides`] applies `FIELD=VALUE` overrides
//! (`yokai train --set`); [`presets`] holds the shipped configs of `configs/`; this module holds the whole config, its file I/O and the rules
//! that tie sections together.

mod act;
mod algorithm;
mod network;
mod obl;
mod overrides;
mod ppo;
mod presets;
mod run;

pub use act::ActConfig;
pub use algorithm::{AlgorithmConfig, SymmetrySet};
pub use network::{
    ActionHead, ColourNames, CriticInput, EncoderKind, GraphReadout, MemoryKind, NetworkConfig,
    NetworkPreset, GRAPH_HEADS,
};
pub use obl::{BeliefOf, OblConfig, OblPartner};
pub use overrides::Override;
pub use ppo::{EndForm, GainBaseline, GainSeats, PpoConfig};
pub use presets::PRESETS;
pub use run::RunConfig;

use serde::{Deserialize, Serialize};
use std::path::Path;
use yokai_engine::Config;

/// Everything that defines a training run except the seed.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct TrainConfig {
    /// The game: a short name such as `9c-2p-perfect` or a path to a game TOML file.
    pub game: String,
    pub algorithm: AlgorithmConfig,
    pub network: NetworkConfig,
    pub ppo: PpoConfig,
    /// Off-Belief Learning (off unless `obl.level` ≥ 1).
    pub obl: OblConfig,
    /// How the trained policy acts outside training (eval, play, serve, Python). Left out
    /// of saved configs when it is the default, so files without a rule read everywhere.
    #[serde(skip_serializing_if = "ActConfig::is_default")]
    pub act: ActConfig,
    pub run: RunConfig,
}

impl Default for TrainConfig {
    fn default() -> Self {
        TrainConfig {
            game: "9c-2p-perfect".into(),
            algorithm: AlgorithmConfig::default(),
            network: NetworkConfig::default(),
            ppo: PpoConfig::default(),
            obl: OblConfig::default(),
            act: ActConfig::default(),
            run: RunConfig::default(),
        }
    }
}

/// A training configuration that cannot be used, with where and why.
#[derive(Debug, thiserror::Error)]
pub enum TrainConfigError {
    #[error("cannot read training config {path}: {message}")]
    Io { path: String, message: String },
    #[error("training config {origin}: {message}")]
    Parse { origin: String, message: String },
    #[error("training config {origin}: field `{field}` {message}")]
    Invalid {
        origin: String,
        field: &'static str,
        message: String,
    },
    /// A `--set FIELD=VALUE` that does not fit the config.
    #[error("--set {set}: {message}")]
    Override { set: String, message: String },
    #[error("training config {origin}: game: {source}")]
    Game {
        origin: String,
        #[source]
        source: yokai_engine::ConfigError,
    },
}

impl TrainConfig {
    pub fn from_toml_str(text: &str, origin: &str) -> Result<TrainConfig, TrainConfigError> {
        let config: TrainConfig = toml::from_str(text).map_err(|e| TrainConfigError::Parse {
            origin: origin.to_string(),
            message: e.to_string().trim_end().to_string(),
        })?;
        config.validate(origin)?;
        Ok(config)
    }

    pub fn from_file(path: &Path) -> Result<TrainConfig, TrainConfigError> {
        TrainConfig::from_file_with(path, &[])
    }

    /// The config file at `path` with `overrides` applied ([`TrainConfig::from_toml_with`]).
    pub fn from_file_with(
        path: &Path,
        overrides: &[Override],
    ) -> Result<TrainConfig, TrainConfigError> {
        let text = std::fs::read_to_string(path).map_err(|e| TrainConfigError::Io {
            path: path.display().to_string(),
            message: e.to_string(),
        })?;
        TrainConfig::from_toml_with(&text, &path.display().to_string(), overrides)
    }

    pub fn to_toml(&self) -> String {
        toml::to_string_pretty(self).expect("a training config always serialises")
    }

    /// The game configuration this run trains on.
    pub fn game_config(&self) -> Result<Config, TrainConfigError> {
        Config::resolve(&self.game).map_err(|source| TrainConfigError::Game {
            origin: self.game.clone(),
            source,
        })
    }

    /// Number of PPO updates the run makes.
    pub fn updates(&self) -> u64 {
        let per = (self.ppo.num_envs * self.ppo.rollout_steps) as u64;
        self.ppo.total_steps.div_ceil(per).max(1)
    }

    /// Check every field a typo or a bad value could break, naming the field.
    pub fn validate(&self, origin: &str) -> Result<(), TrainConfigError> {
        let game = self.game_config().map_err(|e| match e {
            TrainConfigError::Game { source, .. } => TrainConfigError::Game {
                origin: origin.to_string(),
                source,
            },
            other => other,
        })?;
        self.ppo
            .check(game.players())
            .and_then(|()| self.network.check(&game))
            .and_then(|()| self.obl.check())
            .and_then(|()| self.check_combinations())
            .map_err(|(field, message)| TrainConfigError::Invalid {
                origin: origin.to_string(),
                field,
                message,
            })
    }

    /// The rules that tie fields of different sections together.
    fn check_combinations(&self) -> Checked {
        let (p, n) = (&self.ppo, &self.network);
        if let Some(t) = self.act.end_threshold {
            if let Err(why) = ActConfig::end_threshold_from(t.into()) {
                return bad("act.end_threshold", &why);
            }
        }
        if let Some(t) = self.act.temperature {
            if let Err(why) = ActConfig::temperature_from(t.into()) {
                return bad("act.temperature", &why);
            }
        }
        if p.belief_aux > 0.0 && n.head != ActionHead::Pointer {
            return bad(
                "ppo.belief_aux",
                "reads the pointer head's card embeddings: it needs network.head = \"pointer\"",
            );
        }
        if p.belief_gain > 0.0 && p.belief_aux == 0.0 {
            return bad(
                "ppo.belief_gain",
                "reads the colour layer of the belief loss: it needs ppo.belief_aux > 0",
            );
        }
        if self.obl.level >= 1 {
            // Checked at the levels it switches on only: a level below it has had its
            // symmetries taken away (`for_its_level`) and is checked after that.
            if self
                .obl
                .symmetries_from_level
                .is_some_and(|from| self.obl.level >= from)
                && self.algorithm.symmetries == SymmetrySet::None
            {
                return bad(
                    "obl.symmetries_from_level",
                    "switches on algorithm.symmetries from that level, but they are \"none\": \
                     set algorithm.symmetries (\"both\" for Other-Play's)",
                );
            }
            for (field, weight) in [
                ("ppo.cluster_shaping", p.cluster_shaping),
                ("ppo.belief_gain", p.belief_gain),
            ] {
                if weight > 0.0 {
                    return bad(
                        field,
                        "is not paid in OBL's fictitious continuations: set it to 0",
                    );
                }
            }
            if n.critic == CriticInput::Central {
                return bad(
                    "network.critic",
                    "OBL's value targets come from fictitious continuations, whose colours \
                     the seat's belief drew: set it to \"local\"",
                );
            }
            if n.colours != ColourNames::Dealt {
                return bad(
                    "network.colours",
                    "OBL steps its partners from bare game states, which do not keep a \
                     seat's colour names: set it to \"dealt\"",
                );
            }
        }
        if self.run.checkpoint_every == 0 || self.run.log_every == 0 {
            return bad("run.checkpoint_every / run.log_every", "must be at least 1");
        }
        Ok(())
    }
}

/// A section's check: `Err((field, why))` names the first field that is wrong.
pub(super) type Checked = Result<(), (&'static str, String)>;

pub(super) fn bad(field: &'static str, message: &str) -> Checked {
    Err((field, message.to_string()))
}

impl TrainConfig {
    /// For unit tests that need a trainer or a policy file, not learning: the compact
    /// network at width `hidden`, 4 games × 4 steps per update, one minibatch, one thread.
    #[cfg(test)]
    pub(crate) fn tiny_for_tests(hidden: usize) -> TrainConfig {
        let mut c = TrainConfig::from_toml_str(
            "[network]\npreset = \"compact\"\n[ppo]\nnum_envs = 4\nrollout_steps = 4\n\
             minibatches = 1\n[run]\nthreads = 1\n",
            "test",
        )
        .expect("a valid config");
        c.network.hidden = hidden;
        c
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The error message for a config that must be refused.
    fn refused(text: &str, origin: &str) -> String {
        TrainConfig::from_toml_str(text, origin)
            .unwrap_err()
            .to_string()
    }

    #[test]
    fn defaults_are_the_papers_ippo() {
        let c = TrainConfig::from_toml_str("", "test").unwrap();
        assert_eq!(c.ppo.num_envs, 1024);
        assert_eq!(c.ppo.rollout_steps, 128);
        assert_eq!(c.ppo.entropy_coef, 0.05);
        assert_eq!(c.network.hidden, 256);
        assert_eq!(c.algorithm.symmetries, SymmetrySet::None);
        // The levers of issue 21 are opt-in: the paper's head, no extra bonus or shaping.
        assert_eq!(c.network.head, ActionHead::Dense);
        assert!(!c.network.pointer_pool);
        assert_eq!(c.ppo.end_entropy_coef, 0.0);
        assert_eq!(c.ppo.end_lookahead, 0.0);
        assert_eq!(c.ppo.end_lookahead_form, EndForm::Expected);
        assert_eq!(c.ppo.shaping_fraction, 1.0);
        assert_eq!(c.ppo.belief_aux, 0.0);
        assert_eq!(c.ppo.cluster_shaping, 0.0);
        assert!(!c.ppo.entropy_normalized);
        assert_eq!(c.act.end_threshold, None);
    }

    #[test]
    fn the_temperature_is_at_least_zero_and_survives_the_round_trip() {
        assert_eq!(TrainConfig::default().act.temperature(), 1.0);
        let c = TrainConfig::from_toml_str("[act]\ntemperature = 0.0\n", "a.toml").unwrap();
        assert_eq!(c.act.temperature(), 0.0);
        let again = TrainConfig::from_toml_str(&c.to_toml(), "saved").unwrap();
        assert_eq!(again, c);
        for bad in ["-0.5", "nan", "inf", "1000.0"] {
            let e = refused(&format!("[act]\ntemperature = {bad}\n"), "a.toml");
            assert!(
                e.contains("act.temperature") && e.contains("a.toml"),
                "{bad}: {e}"
            );
        }
    }

    #[test]
    fn the_end_threshold_is_a_probability_and_survives_the_round_trip() {
        let c = TrainConfig::from_toml_str("[act]\nend_threshold = 0.5\n", "a.toml").unwrap();
        assert_eq!(c.act.end_threshold, Some(0.5));
        let again = TrainConfig::from_toml_str(&c.to_toml(), "saved").unwrap();
        assert_eq!(again, c);
        // Without it the saved config has no [act] section at all (older readers refuse
        // unknown sections).
        assert!(!TrainConfig::default().to_toml().contains("[act]"));
        for bad in ["0.0", "1.0", "1.5", "-0.1", "nan"] {
            let e = refused(&format!("[act]\nend_threshold = {bad}\n"), "a.toml");
            assert!(
                e.contains("act.end_threshold") && e.contains("a.toml"),
                "{bad}: {e}"
            );
        }
    }

    #[test]
    fn the_pointer_head_needs_the_compact_network() {
        let e = refused("[network]\nhead = \"pointer\"\n", "p.toml");
        assert!(e.contains("network.head") && e.contains("compact"), "{e}");
        let ok = "[network]\nhead = \"pointer\"\npreset = \"compact\"\n";
        assert!(TrainConfig::from_toml_str(ok, "p.toml").is_ok());
        let pooled = format!("{ok}pointer_pool = true\n");
        assert!(TrainConfig::from_toml_str(&pooled, "p.toml").is_ok());
        let e = refused("[network]\npointer_pool = true\n", "p.toml");
        assert!(e.contains("network.pointer_pool"), "{e}");
    }

    /// `network.encoder` defaults to the preset's, takes the graph kinds, and the pointer
    /// head works with every encoder that reads the graph observation (not the CNN).
    #[test]
    fn the_encoder_follows_the_preset_unless_named() {
        let paper = TrainConfig::from_toml_str("", "e.toml").unwrap();
        assert_eq!(paper.network.encoder(), EncoderKind::Cnn);
        let compact = TrainConfig::from_toml_str("[network]\npreset = \"compact\"\n", "e.toml");
        assert_eq!(compact.unwrap().network.encoder(), EncoderKind::Mlp);
        for (name, kind) in [
            ("gcn", EncoderKind::Gcn),
            ("gatv2", EncoderKind::Gatv2),
            ("relation", EncoderKind::Relation),
        ] {
            let text = format!("[network]\nencoder = \"{name}\"\nhead = \"pointer\"\n");
            let c = TrainConfig::from_toml_str(&text, "e.toml").unwrap();
            assert_eq!(c.network.encoder(), kind);
            // It survives the round trip through the run's saved config.
            let again = TrainConfig::from_toml_str(&c.to_toml(), "e.toml").unwrap();
            assert_eq!(again.network.encoder(), kind);
            assert_eq!(kind.to_string(), name, "the name a config gives it");
        }
        // OBL's public–private encoder reads the image, as the paper's CNN does: the dense
        // head, and the name with its hyphen round-trips.
        let c = TrainConfig::from_toml_str("[network]\nencoder = \"public-private\"\n", "e.toml")
            .unwrap();
        assert_eq!(c.network.encoder(), EncoderKind::PublicPrivate);
        assert_eq!(c.network.encoder().to_string(), "public-private");
        let again = TrainConfig::from_toml_str(&c.to_toml(), "e.toml").unwrap();
        assert_eq!(again.network.encoder(), EncoderKind::PublicPrivate);
        let e = refused(
            "[network]\nencoder = \"public-private\"\nhead = \"pointer\"\n",
            "e.toml",
        );
        assert!(e.contains("network.head"), "{e}");
        let e = refused(
            "[network]\nencoder = \"cnn\"\nhead = \"pointer\"\n",
            "e.toml",
        );
        assert!(e.contains("network.head") && e.contains("gcn"), "{e}");
        let e = refused("[network]\nencoder = \"gat\"\n", "e.toml");
        assert!(e.contains("e.toml") && e.contains("gat"), "{e}");
        let e = refused("[network]\nencoder = \"gcn\"\ngraph_width = 30\n", "e.toml");
        assert!(e.contains("network.graph_width"), "{e}");
        let e = refused("[network]\ngraph_readout = \"concat\"\n", "e.toml");
        assert!(
            e.contains("network.graph_readout") && e.contains("graph encoders only"),
            "{e}"
        );
        let e = refused(
            "[network]\nencoder = \"gcn\"\ngraph_readout = \"flat\"\n",
            "e.toml",
        );
        assert!(e.contains("flat"), "{e}");
    }

    #[test]
    fn unknown_keys_and_bad_values_name_the_field() {
        let e = refused("[ppo]\nlearning_rate = 1.0\n", "x.toml");
        assert!(e.contains("x.toml") && e.contains("learning_rate"), "{e}");
        let e = refused("[ppo]\nnum_envs = 0\n", "x.toml");
        assert!(e.contains("ppo.num_envs"), "{e}");
        let e = refused("game = \"7c\"\n", "x.toml");
        assert!(e.contains("game"), "{e}");
        for bad in ["0.0", "1.5", "-0.1", "nan"] {
            let e = refused(&format!("[ppo]\nshaping_fraction = {bad}\n"), "x");
            assert!(e.contains("ppo.shaping_fraction"), "{bad}: {e}");
        }
        let e = refused("[ppo]\nbelief_aux = 0.5\n", "x");
        assert!(e.contains("ppo.belief_aux") && e.contains("pointer"), "{e}");
        let e = refused("[ppo]\nbelief_aux = -1.0\n", "x");
        assert!(e.contains("ppo.belief_aux"), "{e}");
        let e = refused("[ppo]\nbelief_gain = 0.1\n", "x");
        assert!(
            e.contains("ppo.belief_gain") && e.contains("belief_aux"),
            "{e}"
        );
        let e = refused("[ppo]\nbelief_gain = -0.1\n", "x");
        assert!(e.contains("ppo.belief_gain") && e.contains("≥ 0"), "{e}");
        for bad in ["0.0", "1.5", "-0.1"] {
            let e = refused(&format!("[ppo]\nbelief_gain_fraction = {bad}\n"), "x");
            assert!(e.contains("ppo.belief_gain_fraction"), "{bad}: {e}");
        }
        let e = refused("[ppo]\nend_lookahead_form = \"fast\"\n", "x");
        assert!(e.contains("fast") && e.contains("target"), "{e}");
        // Off-Belief Learning: level 1 only for now, without what reads the true colours.
        let e = refused("[obl]\nlevel = 2\n", "x");
        assert!(e.contains("obl.previous") && e.contains("level 2"), "{e}");
        let e = refused("[obl]\nlevel = 1\nprevious = \"runs/x\"\n", "x");
        assert!(e.contains("obl.previous"), "{e}");
        assert!(TrainConfig::from_toml_str("[obl]\nlevel = 3\nprevious = \"r\"\n", "x").is_ok());
        // OBL with Other-Play: each seat sees the fictitious worlds through its symmetry too.
        let both = "[algorithm]\nsymmetries = \"both\"\n[obl]\nlevel = 1\n";
        assert!(TrainConfig::from_toml_str(both, "x").is_ok());
        // Symmetries from a level: an OBL field, from level 1 up.
        let e = refused(
            "[algorithm]\nsymmetries = \"both\"\n[obl]\nsymmetries_from_level = 2\n",
            "x",
        );
        assert!(
            e.contains("obl.symmetries_from_level") && e.contains("obl.level = 0"),
            "{e}"
        );
        let e = refused(
            "[algorithm]\nsymmetries = \"both\"\n[obl]\nlevel = 1\nsymmetries_from_level = 0\n",
            "x",
        );
        assert!(
            e.contains("obl.symmetries_from_level") && e.contains("at least 1"),
            "{e}"
        );
        let e = refused("[obl]\nlevel = 1\nsymmetries_from_level = 1\n", "x");
        assert!(
            e.contains("obl.symmetries_from_level") && e.contains("\"none\""),
            "{e}"
        );
        // The ramp: a fraction of the switch level's steps, read only with the switch.
        let ramp = |from: &str, ramp: &str| {
            format!(
                "[algorithm]\nsymmetries = \"both\"\n[obl]\nlevel = 1\n{from}symmetries_ramp = {ramp}\n"
            )
        };
        let from = "symmetries_from_level = 1\n";
        assert!(TrainConfig::from_toml_str(&ramp(from, "1.0"), "x").is_ok());
        let e = refused(&ramp("", "0.5"), "x");
        assert!(
            e.contains("obl.symmetries_ramp") && e.contains("obl.symmetries_from_level"),
            "{e}"
        );
        for bad_share in ["0.0", "1.5", "nan"] {
            let e = refused(&ramp(from, bad_share), "x");
            assert!(
                e.contains("obl.symmetries_ramp") && e.contains("(0, 1]"),
                "{bad_share}: {e}"
            );
        }
        let e = refused("[network]\ncritic = \"central\"\n[obl]\nlevel = 1\n", "x");
        assert!(e.contains("network.critic") && e.contains("local"), "{e}");
        let e = refused("[network]\ncritic = \"oracle\"\n", "x");
        assert!(e.contains("oracle") && e.contains("central"), "{e}");
        // First-seen colour names: any algorithm but OBL, whose partners step from bare
        // game states; a misspelt value lists the accepted ones.
        let e = refused(
            "[network]\ncolours = \"first-seen\"\n[obl]\nlevel = 1\n",
            "x",
        );
        assert!(e.contains("network.colours") && e.contains("dealt"), "{e}");
        let e = refused("[network]\ncolours = \"first_seen\"\n", "x");
        assert!(e.contains("first_seen") && e.contains("first-seen"), "{e}");
        let c = TrainConfig::from_toml_str(
            "[algorithm]\nsymmetries = \"both\"\n[network]\ncolours = \"first-seen\"\n",
            "x",
        )
        .unwrap();
        assert_eq!(c.network.colours, ColourNames::FirstSeen);
        let e = refused(
            "[network]\ncolours = \"public-first\"\n[obl]\nlevel = 1\n",
            "x",
        );
        assert!(e.contains("network.colours"), "{e}");
        let c = TrainConfig::from_toml_str("[network]\ncolours = \"public-first\"\n", "x").unwrap();
        assert_eq!(c.network.colours, ColourNames::PublicFirst);
        assert_eq!(ColourNames::PublicFirst.to_string(), "public-first");
        assert_eq!(TrainConfig::default().network.colours, ColourNames::Dealt);
        // Under OBL the END term reads the world drawn from the belief (trainer/addons/end.rs).
        assert!(
            TrainConfig::from_toml_str("[ppo]\nend_lookahead = 0.5\n[obl]\nlevel = 1\n", "x")
                .is_ok()
        );
        let e = refused(
            "[obl]\nlevel = 2\nprevious = \"runs/x\"\noracle = true\n",
            "x",
        );
        assert!(e.contains("obl.oracle") && e.contains("level-1"), "{e}");
        let c =
            TrainConfig::from_toml_str("[obl]\nlevel = 1\npartner = \"learner\"\n", "x").unwrap();
        assert_eq!(c.obl.partner, OblPartner::Learner);
        assert_eq!(
            TrainConfig::default().obl.partner,
            OblPartner::Previous,
            "the spec's rule"
        );
        let e = refused("[obl]\nlevel = 1\npartner = \"me\"\n", "x");
        assert!(e.contains("partner"), "{e}");
        // Longer continuations have the learner play on, so its partners must be it too.
        let e = refused("[obl]\nlevel = 1\ndecisions = 3\n", "x");
        assert!(e.contains("obl.decisions") && e.contains("learner"), "{e}");
        let e = refused("[obl]\nlevel = 1\ndecisions = 0\n", "x");
        assert!(
            e.contains("obl.decisions") && e.contains("at least 1"),
            "{e}"
        );
        let c = TrainConfig::from_toml_str(
            "[obl]\nlevel = 1\npartner = \"learner\"\ndecisions = 3\n",
            "x",
        )
        .unwrap();
        assert_eq!(
            (c.obl.decisions, TrainConfig::default().obl.decisions),
            (3, 1)
        );
        let e = refused("[ppo]\ncluster_shaping = 1.0\n[obl]\nlevel = 1\n", "x");
        assert!(e.contains("ppo.cluster_shaping"), "{e}");
        let pointer = "[network]\npreset = \"compact\"\nhead = \"pointer\"\n";
        let e = refused(
            &format!("{pointer}[ppo]\nbelief_aux = 0.5\nbelief_gain = 0.1\n[obl]\nlevel = 1\n"),
            "x",
        );
        assert!(e.contains("ppo.belief_gain") && e.contains("OBL"), "{e}");
        assert!(TrainConfig::from_toml_str("[obl]\nlevel = 1\n", "x").is_ok());
        let e = refused("[obl]\nwarm_lr = 1e-3\n", "x");
        assert!(
            e.contains("obl.warm_lr") && e.contains("obl.level = 0"),
            "{e}"
        );
        let e = refused("[obl]\nlevel = 1\nwarm_lr = 0.0\n", "x");
        assert!(e.contains("obl.warm_lr") && e.contains("positive"), "{e}");
        let e = refused("[obl]\nlevel = 1\nwarm_shaping = -1.0\n", "x");
        assert!(e.contains("obl.warm_shaping") && e.contains("≥ 0"), "{e}");
        // The belief of every seed of the level below: read by levels ≥ 2, allowed at level
        // 1 (whose `--levels` plan makes the levels above), refused without OBL.
        let c = TrainConfig::from_toml_str(
            "[obl]\nlevel = 2\nprevious = \"runs/x\"\nbelief_of = \"all-seeds\"\n",
            "x",
        )
        .unwrap();
        assert_eq!(
            (c.obl.belief_of, TrainConfig::default().obl.belief_of),
            (BeliefOf::AllSeeds, BeliefOf::OwnSeed)
        );
        assert!(
            TrainConfig::from_toml_str("[obl]\nlevel = 1\nbelief_of = \"all-seeds\"\n", "x")
                .is_ok()
        );
        let e = refused("[obl]\nbelief_of = \"all-seeds\"\n", "x");
        assert!(
            e.contains("obl.belief_of") && e.contains("obl.level = 0"),
            "{e}"
        );
        let e = refused(
            "[obl]\nlevel = 2\nprevious = \"runs/x\"\nbelief_of = \"every\"\n",
            "x",
        );
        assert!(e.contains("belief_of"), "{e}");
    }

    #[test]
    fn resolved_config_round_trips() {
        let c = TrainConfig::from_toml_str(
            "game = \"9c-3p-perfect\"\n[algorithm]\nname = \"op\"\nsymmetries = \"both\"\n",
            "t",
        )
        .unwrap();
        let back = TrainConfig::from_toml_str(&c.to_toml(), "t").unwrap();
        assert_eq!(c, back);
    }
}
