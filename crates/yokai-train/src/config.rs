//! Training configuration: one TOML file per experiment (see `configs/`).
//!
//! Every field has a default (the paper's IPPO on 9c-2p with the paper network), so a file
//! only states what differs. Unknown keys are errors, so a typo never silently trains the
//! default. The resolved configuration (every field written out) is saved with each run.

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

/// How a trained policy turns its action distribution into a move when it plays (`yokai
/// eval`, `play`, `serve`, Python); training's rollouts always sample.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ActConfig {
    /// Decide END instead of drawing it: wherever END is legal, END if its probability
    /// exceeds this threshold, else a move drawn from the other legal actions. With the
    /// target form of `ppo.end_lookahead`, P(END) is trained towards "ending beats playing
    /// on", so it estimates the chance that it does; drawing END from it at every turn ends
    /// many unsure boards on a coin flip (docs/training.md), while 0.5 ends exactly where
    /// the network thinks ending more likely right than wrong. Absent (every preset but
    /// `cpu`): END is drawn like any action.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub end_threshold: Option<f32>,
}

impl ActConfig {
    fn is_default(&self) -> bool {
        *self == ActConfig::default()
    }

    /// `t` as an END threshold, or why it cannot be one: the one check for the config
    /// field, `yokai eval --end` and Python's `end=`.
    pub fn end_threshold_from(t: f64) -> Result<f32, String> {
        if t > 0.0 && t < 1.0 {
            Ok(t as f32)
        } else {
            Err(format!("must lie in (0, 1), a probability of END, not {t}"))
        }
    }
}

/// Off-Belief Learning (docs/training.md): the value target of each of a seat's actions
/// comes from a fictitious continuation in a world drawn from the seat's belief (of the
/// previous level's play), the partners played by `partner`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct OblConfig {
    /// 0: off (IPPO, HE, OP). 1: level 1, whose previous level is uniform random play and
    /// whose belief is exact (uniform over the colourings consistent with the seat's
    /// first-hand colours). 2 and up: the previous level is `previous`, and the belief a
    /// model trained on its self-play when the run starts (`yokai train --levels` also
    /// starts the level from the previous level's weights).
    pub level: u32,
    /// Levels ≥ 2: the previous level's policy (policy file, checkpoint or run directory;
    /// for a directory of `seed-N` runs, seed N uses `seed-N`). A relative path is read
    /// from the directory `yokai train` runs in.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub previous: Option<std::path::PathBuf>,
    /// Levels ≥ 2: updates of the belief model on the previous level's self-play (16 games
    /// × 16 steps each) before PPO starts; redone identically on resume.
    pub belief_updates: u64,
    /// Levels ≥ 2: width of the belief model's memory.
    pub belief_hidden: usize,
    /// A diagnostic, not OBL (level 1 only): every continuation runs in the true colours
    /// instead of a draw from the belief. The continuation is then the real transition, so
    /// this is self-play with OBL's one-step targets: what the learning machinery reaches
    /// when the belief grounds nothing away.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub oracle: bool,
    /// Who plays the partners' turns inside the fictitious continuations.
    pub partner: OblPartner,
    /// How many of the acting seat's own decisions a fictitious continuation covers before
    /// it bootstraps from the learner's value. 1 (the reference implementation's one-step
    /// target): the partners play until the seat is to act again. n > 1: the seat plays
    /// its next n − 1 decisions in the fictitious world too (as the learner, with its memory
    /// of that world), so the target is an n-decision return of the world drawn once from
    /// the belief, as OBL's operator defines the value ("past by π_{ℓ−1}, future by π_ℓ");
    /// the longer return carries credit further per update, as a GAE λ above 0 does for
    /// IPPO. Needs `partner = "learner"`: in the operator, every future move is π_ℓ's.
    pub decisions: u32,
}

/// Who plays the partners inside OBL's fictitious continuations (`obl.partner`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum OblPartner {
    /// The level below (uniformly random play at level 1, `obl.previous` above): the
    /// project's training spec (docs/spec/training.md, row OBL).
    #[default]
    Previous,
    /// The policy being learnt, as the reference implementation plays it (all actors of a
    /// game share the learning network's runner, `pyhanabi/act_group.py`) and as OBL's
    /// operator reads ("future actions will follow π_ℓ", the paper's §4).
    Learner,
}

impl Default for OblConfig {
    fn default() -> Self {
        OblConfig {
            level: 0,
            previous: None,
            belief_updates: 300,
            belief_hidden: 64,
            oracle: false,
            partner: OblPartner::Previous,
            decisions: 1,
        }
    }
}

/// Which of the paper's algorithms; they differ only in these fields.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct AlgorithmConfig {
    /// `ippo`, `he` (high-entropy IPPO) or `op` (Other-Play). A label for tables; HE's
    /// different entropy and λ are set in `[ppo]` by its config file.
    pub name: String,
    /// Other-Play symmetries drawn per seat and episode: `none` (IPPO, HE), `colour`,
    /// `rotation` or `both` (Φ_col × Φ_rot).
    pub symmetries: SymmetrySet,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum SymmetrySet {
    None,
    Colour,
    Rotation,
    Both,
}

impl SymmetrySet {
    pub fn colours(self) -> bool {
        matches!(self, SymmetrySet::Colour | SymmetrySet::Both)
    }
    pub fn rotations(self) -> bool {
        matches!(self, SymmetrySet::Rotation | SymmetrySet::Both)
    }
}

/// Which network: the paper's CNN-GRU, or a small MLP-GRU that learns on a laptop CPU.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum NetworkPreset {
    /// 4 × Conv2d(64, 3×3, valid) over the image observation → Linear → GRU.
    Paper,
    /// Two-layer MLP over the per-card (graph node) features → GRU.
    Compact,
}

/// The observation encoder (`network.encoder`). Unset, it follows the preset: `cnn` for
/// `paper`, `mlp` for `compact`. The graph encoders are the paper's encoder ablations; they
/// read the graph observation (node features; the edges are rebuilt from the features, see
/// `network/graph.rs`) and keep the preset's embedding width and memory.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum EncoderKind {
    /// 4 × Conv2d(filters, 3×3, valid) over the image observation (the paper's).
    Cnn,
    /// One layer shared by every node, then one over all nodes in order (compact).
    Mlp,
    /// Graph convolutions (Kipf & Welling) over the board's 4-neighbourhood.
    Gcn,
    /// GATv2 attention (Brody et al.) over the same edges, 4 heads.
    Gatv2,
    /// Self-attention between every pair of nodes (a relation module), 4 heads.
    Relation,
    /// The paper's CNN twice, over the image's public and private (known-colour) channels:
    /// OBL's public–private architecture (`network/public_private.rs`).
    #[serde(rename = "public-private")]
    PublicPrivate,
}

impl std::fmt::Display for EncoderKind {
    /// The name a config file gives it (`network.encoder`), as serde spells it: the names
    /// are written once, in the attributes above.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match serde_json::to_value(self) {
            Ok(serde_json::Value::String(name)) => f.write_str(&name),
            _ => write!(f, "{self:?}"),
        }
    }
}

impl EncoderKind {
    /// Whether the encoder reads the graph observation (which the pointer head needs too).
    pub fn reads_graph(self) -> bool {
        !matches!(self, EncoderKind::Cnn | EncoderKind::PublicPrivate)
    }
}

/// The recurrent memory (`network.memory`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum MemoryKind {
    /// A GRU of width `network.hidden` (the paper's).
    #[default]
    Gru,
    /// A gated Transformer-XL layer over the last `network.trxl_memory` steps (the paper's
    /// memory ablation; `network/trxl.rs`).
    Trxl,
}

/// How `ppo.end_lookahead` turns "what END would pay" into a gradient on the END logit.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum EndForm {
    /// The expected policy gradient of END, −π(END|s)·(R_END(s) − V(s)). Its gradient on the
    /// END logit carries a factor π(END)(1 − π(END)), so it fades once P(END) is tiny.
    #[default]
    Expected,
    /// A cross-entropy pulling P(END) towards σ((R_END(s) − V(s)) / ¼ point): about 1 where
    /// ending pays a point or more beyond playing on, about 0 where it costs as much. Its
    /// gradient on the END log-odds, σ(…) − P(END), does not fade with P(END), and it is at
    /// most 1 per state whatever the size of the advantage, so it never outweighs the rest
    /// of the loss. Under partial observability P(END | history) settles at the mean target
    /// over the boards the history allows: the agent ends when it is likely to pay.
    Target,
}

/// How the actor turns the GRU state into action logits.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ActionHead {
    /// One dense layer `hidden → N_a` (the paper's).
    #[default]
    Dense,
    /// Logits of OBSERVE, MOVE and PLACE scored from per-card and per-hint embeddings
    /// (`network/pointer.rs`); compact network only.
    Pointer,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct NetworkConfig {
    pub preset: NetworkPreset,
    /// The encoder; unset, the preset's ([`NetworkConfig::encoder`]).
    pub encoder: Option<EncoderKind>,
    /// Graph encoders: message-passing layers and their width (4 and 64 in the paper).
    pub graph_layers: usize,
    pub graph_width: usize,
    /// The memory: `gru` (the paper's) or `trxl`.
    pub memory: MemoryKind,
    /// Transformer-XL: model width, attention heads, steps remembered, and the bias that
    /// starts its gates near the identity (64, 8, 32 and 2 in the paper).
    pub trxl_width: usize,
    pub trxl_heads: usize,
    pub trxl_memory: usize,
    pub trxl_gate_bias: f64,
    /// The actor head: `dense` (the paper's) or `pointer`.
    pub head: ActionHead,
    /// Pointer head only: NOOP, END and REVEAL read the mean and maximum of the card
    /// embeddings besides the GRU state, so "is every colour clustered?" — a question about
    /// all cards at once — reaches the END logit directly.
    pub pointer_pool: bool,
    /// Width of the embedding layer and of the GRU state (256 in the paper).
    pub hidden: usize,
    /// Conv filters per layer (paper preset only; 64 in the paper).
    pub filters: usize,
    /// Orthogonal-init gain of the actor head (small, so the first policy is near uniform).
    pub actor_gain: f64,
    /// Orthogonal-init gain of the critic head.
    pub critic_gain: f64,
}

/// PPO hyper-parameters (the paper's Table of training details).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct PpoConfig {
    /// Parallel games per rollout.
    pub num_envs: usize,
    /// Steps per rollout (and BPTT length: every game's sequence is kept whole).
    pub rollout_steps: usize,
    /// Total environment steps (one step = one action in each of `num_envs` games).
    pub total_steps: u64,
    /// Adam learning rate at the start; annealed linearly to 0 when `anneal_lr`.
    pub lr: f64,
    pub anneal_lr: bool,
    pub adam_eps: f64,
    pub gamma: f32,
    pub gae_lambda: f32,
    /// Policy-ratio clip ε.
    pub clip: f32,
    /// Clip of the value change from the rollout's value (the clipped value loss).
    pub value_clip: f32,
    pub value_coef: f32,
    /// Entropy bonus α.
    pub entropy_coef: f32,
    /// Divide each row's entropy by the log of its number of legal actions before the
    /// bonus, so a turn with 700 legal moves and one with 10 pull towards uniform with the
    /// same strength (the raw masked entropy of a 700-way choice swamps the policy gradient;
    /// docs/training.md). Off in the paper's presets.
    pub entropy_normalized: bool,
    /// Bonus on the entropy of the binary choice "END or not" wherever END is legal (the
    /// first substep of a turn): keeps ending explored without pulling the hundreds of
    /// MOVE logits towards uniform as `entropy_coef` does. END pays only when the board is
    /// won, so PPO otherwise stops trying it in the first updates (docs/training.md).
    /// 0 (the paper's presets) turns it off.
    pub end_entropy_coef: f32,
    /// Weight of an exact END term: wherever END is legal, the simulator knows what ending
    /// now would pay (R of the true board, `Game::end_reward`), so the loss adds the
    /// expected policy gradient of END, −π(END|s)·(R_END(s) − V(s)), at every such state,
    /// not only where END was drawn. A centralised-training signal (the policy still acts
    /// on its own view); 0 (the paper's presets) turns it off. Under OBL the board is the
    /// fictitious one, recoloured by a draw from the acting seat's belief, so the term
    /// values END as OBL's own target does and never reads the true colours.
    pub end_lookahead: f32,
    /// Which gradient `end_lookahead` adds (see [`EndForm`]); the paper's presets leave
    /// `end_lookahead` at 0, where this does nothing.
    pub end_lookahead_form: EndForm,
    /// Weight of an auxiliary belief loss (pointer head only): from each card's embedding
    /// the network predicts the card's true colour, by cross-entropy, at every state where
    /// a seat chooses. The agent has to represent what it knows and what it can infer about
    /// every card, which END (is every colour clustered?) and clustering moves depend on.
    /// A centralised-training signal; 0 (every preset but `cpu`) turns it off and leaves
    /// the network without the colour layer.
    pub belief_aux: f32,
    /// Global gradient-norm clip.
    pub max_grad_norm: f32,
    pub epochs: usize,
    pub minibatches: usize,
    /// Weight of the shaping reward at the start; annealed linearly to 0 over the first
    /// `shaping_fraction` of the run.
    pub shaping: f32,
    /// Share of the run, in (0, 1], over which the shaping weight falls to 0 (1 = the whole
    /// run, the paper's). The shaping pays for observing and hinting, so while it lasts
    /// every value V(s) counts future shaping that ending forfeits, and END looks worse
    /// than it is; a shorter anneal lets the late run value END by the game's reward alone.
    pub shaping_fraction: f32,
    /// Normalise advantages inside each minibatch (as JaxMARL's IPPO does).
    pub normalize_advantages: bool,
    /// Weight of a clustering shaping reward, annealed with `shaping`: each step that is
    /// not an episode's last adds the change in the number of clustered colours (a
    /// potential-based term, so it does not change which policies are optimal). The game's
    /// own reward counts clustered colours only at the end, 32 steps later; this gives the
    /// moves that cluster a signal of their own. 0 (the paper's presets) turns it off.
    pub cluster_shaping: f32,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct RunConfig {
    /// Write a checkpoint every this many updates (and always after the last one).
    pub checkpoint_every: u64,
    /// Append a metrics line every this many updates.
    pub log_every: u64,
    /// Worker threads for the environments and the CPU backend; 0 = one per core.
    pub threads: usize,
    /// Start the network from the parameters of this policy file, checkpoint or run
    /// directory (fine-tuning, curricula) instead of a fresh initialisation; the network
    /// settings and the game must match it. Only the weights are taken: the optimiser, the
    /// step count and the schedules start anew. A relative path is read from the directory
    /// `yokai train` runs in.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub init_from: Option<std::path::PathBuf>,
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

impl Default for AlgorithmConfig {
    fn default() -> Self {
        AlgorithmConfig {
            name: "ippo".into(),
            symmetries: SymmetrySet::None,
        }
    }
}

/// Attention heads of the GATv2 and relation encoders (the paper's 4).
pub const GRAPH_HEADS: usize = 4;

impl NetworkConfig {
    /// The encoder: `network.encoder`, else the preset's (`cnn` for `paper`, `mlp` for
    /// `compact`).
    pub fn encoder(&self) -> EncoderKind {
        self.encoder.unwrap_or(match self.preset {
            NetworkPreset::Paper => EncoderKind::Cnn,
            NetworkPreset::Compact => EncoderKind::Mlp,
        })
    }
}

impl Default for NetworkConfig {
    fn default() -> Self {
        NetworkConfig {
            preset: NetworkPreset::Paper,
            encoder: None,
            graph_layers: 4,
            graph_width: 64,
            memory: MemoryKind::Gru,
            trxl_width: 64,
            trxl_heads: 8,
            trxl_memory: 32,
            trxl_gate_bias: 2.0,
            head: ActionHead::Dense,
            pointer_pool: false,
            hidden: 256,
            filters: 64,
            actor_gain: 0.01,
            critic_gain: 1.0,
        }
    }
}

impl Default for PpoConfig {
    fn default() -> Self {
        PpoConfig {
            num_envs: 1024,
            rollout_steps: 128,
            total_steps: 1_000_000_000,
            lr: 3e-4,
            anneal_lr: true,
            adam_eps: 1e-5,
            gamma: 0.99,
            gae_lambda: 0.95,
            clip: 0.2,
            value_clip: 0.2,
            value_coef: 0.5,
            entropy_coef: 0.05,
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
        }
    }
}

impl Default for RunConfig {
    fn default() -> Self {
        RunConfig {
            checkpoint_every: 50,
            log_every: 1,
            threads: 0,
            init_from: None,
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
        let text = std::fs::read_to_string(path).map_err(|e| TrainConfigError::Io {
            path: path.display().to_string(),
            message: e.to_string(),
        })?;
        TrainConfig::from_toml_str(&text, &path.display().to_string())
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
        if p.belief_aux > 0.0 && n.head != ActionHead::Pointer {
            return bad(
                "ppo.belief_aux",
                "reads the pointer head's card embeddings: it needs network.head = \"pointer\"",
            );
        }
        if self.obl.level >= 1 {
            if self.algorithm.symmetries != SymmetrySet::None {
                return bad(
                    "obl.level",
                    "OBL trains without Other-Play symmetries: set algorithm.symmetries = \"none\"",
                );
            }
            if p.cluster_shaping > 0.0 {
                return bad(
                    "ppo.cluster_shaping",
                    "is not paid in OBL's fictitious continuations: set it to 0",
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
type Checked = Result<(), (&'static str, String)>;

fn bad(field: &'static str, message: &str) -> Checked {
    Err((field, message.to_string()))
}

impl PpoConfig {
    /// The PPO section on its own, for a game of `players` seats.
    fn check(&self, players: usize) -> Checked {
        let p = self;
        if p.num_envs == 0 {
            return bad("ppo.num_envs", "must be at least 1");
        }
        if p.rollout_steps == 0 {
            return bad("ppo.rollout_steps", "must be at least 1");
        }
        if p.minibatches == 0 || p.minibatches > p.num_envs * players {
            return bad(
                "ppo.minibatches",
                "must be between 1 and num_envs × players (minibatches split whole sequences)",
            );
        }
        if p.epochs == 0 {
            return bad("ppo.epochs", "must be at least 1");
        }
        if !(p.lr > 0.0 && p.lr.is_finite()) {
            return bad("ppo.lr", "must be a positive number");
        }
        if !(0.0..=1.0).contains(&p.gamma) || !(0.0..=1.0).contains(&p.gae_lambda) {
            return bad("ppo.gamma / ppo.gae_lambda", "must lie in [0, 1]");
        }
        if p.clip <= 0.0 || p.value_clip <= 0.0 || p.max_grad_norm <= 0.0 {
            return bad(
                "ppo.clip / ppo.value_clip / ppo.max_grad_norm",
                "must be positive",
            );
        }
        if !(p.shaping_fraction > 0.0 && p.shaping_fraction <= 1.0) {
            return bad("ppo.shaping_fraction", "must lie in (0, 1]");
        }
        // Weights of optional terms: 0 turns a term off, and none may be negative.
        for (field, weight) in [
            ("ppo.end_lookahead", p.end_lookahead),
            ("ppo.end_entropy_coef", p.end_entropy_coef),
            ("ppo.cluster_shaping", p.cluster_shaping),
            ("ppo.belief_aux", p.belief_aux),
        ] {
            if !(weight >= 0.0 && weight.is_finite()) {
                return bad(field, "must be a number ≥ 0");
            }
        }
        Ok(())
    }
}

impl NetworkConfig {
    /// The network section on its own, for `game` (the CNN needs a large enough grid).
    fn check(&self, game: &Config) -> Checked {
        let n = self;
        if n.hidden == 0 || n.filters == 0 {
            return bad("network.hidden / network.filters", "must be at least 1");
        }
        let encoder = n.encoder();
        if !encoder.reads_graph() && game.grid() < 9 {
            return bad(
                "network.encoder",
                "cnn (the paper preset's) and public-private need a grid of at least 9×9 (four \
                 valid 3×3 convolutions)",
            );
        }
        if n.head == ActionHead::Pointer && !encoder.reads_graph() {
            return bad(
                "network.head",
                "pointer reads the graph node features: it needs network.preset = \"compact\" \
                 or a graph encoder (network.encoder = \"mlp\", \"gcn\", \"gatv2\" or \"relation\")",
            );
        }
        if n.graph_layers == 0 || n.graph_width == 0 || n.graph_width % GRAPH_HEADS != 0 {
            return bad(
                "network.graph_layers / network.graph_width",
                "need at least 1 layer and a width that is a positive multiple of 4 (the heads)",
            );
        }
        if n.trxl_heads == 0 || n.trxl_width == 0 || n.trxl_width % n.trxl_heads != 0 {
            return bad(
                "network.trxl_width / network.trxl_heads",
                "need at least 1 head and a width that is a multiple of the heads",
            );
        }
        if n.trxl_memory == 0 || !n.trxl_gate_bias.is_finite() {
            return bad(
                "network.trxl_memory / network.trxl_gate_bias",
                "need at least 1 remembered step and a finite gate bias",
            );
        }
        if n.pointer_pool && n.head != ActionHead::Pointer {
            return bad("network.pointer_pool", "needs network.head = \"pointer\"");
        }
        Ok(())
    }
}

impl OblConfig {
    /// The OBL section on its own.
    fn check(&self) -> Checked {
        let o = self;
        if o.level >= 2 && o.previous.is_none() {
            return bad(
                "obl.previous",
                "is needed from level 2 on: the previous level's policy (its run directory)",
            );
        }
        if o.oracle && o.level != 1 {
            return bad(
                "obl.oracle",
                "is a level-1 diagnostic (the true colours in place of the exact belief)",
            );
        }
        if o.level < 2 && o.previous.is_some() {
            return bad(
                "obl.previous",
                "is read from level 2 on only (level 1's previous level is random play)",
            );
        }
        if o.level >= 2 && (o.belief_updates == 0 || o.belief_hidden == 0) {
            return bad(
                "obl.belief_updates / obl.belief_hidden",
                "must be at least 1",
            );
        }
        if o.decisions == 0 {
            return bad(
                "obl.decisions",
                "must be at least 1 (1: bootstrap where the seat acts again)",
            );
        }
        if o.decisions > 1 && o.partner != OblPartner::Learner {
            return bad(
                "obl.decisions",
                "above 1 has the learner play on after the seat's next decision, so the \
                 partners must be the learner too: set obl.partner = \"learner\"",
            );
        }
        Ok(())
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
        let e = refused("[ppo]\nend_lookahead_form = \"fast\"\n", "x");
        assert!(e.contains("fast") && e.contains("target"), "{e}");
        // Off-Belief Learning: level 1 only for now, without what reads the true colours.
        let e = refused("[obl]\nlevel = 2\n", "x");
        assert!(e.contains("obl.previous") && e.contains("level 2"), "{e}");
        let e = refused("[obl]\nlevel = 1\nprevious = \"runs/x\"\n", "x");
        assert!(e.contains("obl.previous"), "{e}");
        assert!(TrainConfig::from_toml_str("[obl]\nlevel = 3\nprevious = \"r\"\n", "x").is_ok());
        let e = refused(
            "[algorithm]\nsymmetries = \"colour\"\n[obl]\nlevel = 1\n",
            "x",
        );
        assert!(e.contains("obl.level") && e.contains("symmetries"), "{e}");
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
        assert!(TrainConfig::from_toml_str("[obl]\nlevel = 1\n", "x").is_ok());
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
