//! `[network]`: the encoder, memory and heads.

use super::{bad, Checked};
use serde::{Deserialize, Serialize};
use yokai_engine::Config;

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct NetworkConfig {
    pub preset: NetworkPreset,
    /// The encoder; unset, the preset's ([`NetworkConfig::encoder`]).
    pub encoder: Option<EncoderKind>,
    /// Graph encoders: message-passing layers and their width (4 and 64 in the paper).
    pub graph_layers: usize,
    pub graph_width: usize,
    /// Graph encoders: embed each node-feature modality (colour, hint colours, position,
    /// locks, seen, id, turn, substep) with its own dense layer before message passing, as
    /// the paper's appendix (after Bortoletto et al.). Off: one input layer reads them all.
    pub graph_preembed: bool,
    /// Graph encoders: what the rest of the network reads of the nodes: `pooled` (the
    /// virtual node and the mean of the others: the same whatever the order of cards and
    /// slots) or `concat` (every node's embedding side by side, the paper's appendix).
    pub graph_readout: GraphReadout,
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
    /// Hidden layers (width `hidden`, ReLU) between the memory and the actor and critic
    /// heads: 0 in the paper's network, 1 and 2 its "+1HL" and "+2HL" ablations (Table 5).
    pub head_layers: usize,
    /// Conv filters per layer (paper preset only; 64 in the paper).
    pub filters: usize,
    /// Orthogonal-init gain of the actor head (small, so the first policy is near uniform).
    pub actor_gain: f64,
    /// Orthogonal-init gain of the critic head.
    pub critic_gain: f64,
    /// What the critic reads: `local` (the seat's memory, as the actor; the paper's) or
    /// `central` (also every card's true colour, in training only).
    pub critic: CriticInput,
    /// How the network names the colours: `dealt` (as the deal names them, the paper's),
    /// `first-seen` (by the order in which the seat first saw them, so that no convention
    /// can hang on a colour's name) or `public-first` (the colours hint tiles have shown
    /// first, in the order shown, names both seats share): [`ColourNames`].
    pub colours: ColourNames,
}

impl Default for NetworkConfig {
    fn default() -> Self {
        NetworkConfig {
            preset: NetworkPreset::Paper,
            encoder: None,
            graph_layers: 4,
            graph_width: 64,
            graph_preembed: false,
            graph_readout: GraphReadout::Pooled,
            memory: MemoryKind::Gru,
            trxl_width: 64,
            trxl_heads: 8,
            trxl_memory: 32,
            trxl_gate_bias: 2.0,
            head: ActionHead::Dense,
            pointer_pool: false,
            hidden: 256,
            head_layers: 0,
            filters: 64,
            actor_gain: 0.01,
            critic_gain: 1.0,
            critic: CriticInput::Local,
            colours: ColourNames::Dealt,
        }
    }
}

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

impl NetworkConfig {
    /// The network section on its own, for `game` (the CNN needs a large enough grid).
    pub(super) fn check(&self, game: &Config) -> Checked {
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
        let graph = matches!(
            encoder,
            EncoderKind::Gcn | EncoderKind::Gatv2 | EncoderKind::Relation
        );
        if (n.graph_preembed || n.graph_readout != GraphReadout::Pooled) && !graph {
            return bad(
                "network.graph_preembed / network.graph_readout",
                "apply to the graph encoders only (network.encoder = \"gcn\", \"gatv2\" or \"relation\")",
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
        if n.head_layers > 4 {
            return bad(
                "network.head_layers",
                "must be between 0 and 4 (the paper tries 0, 1 and 2)",
            );
        }
        if n.pointer_pool && n.head != ActionHead::Pointer {
            return bad("network.pointer_pool", "needs network.head = \"pointer\"");
        }
        Ok(())
    }
}

/// How a graph encoder hands its nodes on: pooled (order-free) or concatenated.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum GraphReadout {
    Pooled,
    Concat,
}

/// Attention heads of the GATv2 and relation encoders (the paper's 4).
pub const GRAPH_HEADS: usize = 4;

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

/// A config value's name as serde spells it in a config file: the names are written once,
/// in the enums' serde attributes, and `Display` reads them from there.
fn write_config_name<T: Serialize + std::fmt::Debug>(
    value: &T,
    f: &mut std::fmt::Formatter<'_>,
) -> std::fmt::Result {
    match serde_json::to_value(value) {
        Ok(serde_json::Value::String(name)) => f.write_str(&name),
        _ => write!(f, "{value:?}"),
    }
}

impl std::fmt::Display for EncoderKind {
    /// The name a config file gives it (`network.encoder`).
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write_config_name(self, f)
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

/// What the critic reads (`network.critic`). The critic only ever serves training (a
/// policy acts with the actor alone), so it may read what no seat sees: a centralised
/// critic, as in MAPPO. Why: a seat's return hangs on colours it has not seen, so a critic
/// that reads the seat's memory alone explains little of it (explained variance 0.03-0.09
/// after the shaping is annealed in `cpu-fast`), and advantages measured against it are
/// mostly noise. A baseline that also depends on the true colours (fixed for the whole
/// deal, never on the seat's action) leaves the policy gradient unbiased.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum CriticInput {
    /// The seat's memory state (the paper's).
    #[default]
    Local,
    /// The memory state and every card's true colour (one-hot, in the seat's colour
    /// labels), through one more layer of the memory's width with a ReLU.
    Central,
}

/// How the network names the colours (`network.colours`). Why: Yōkai's colours are
/// interchangeable, so a convention tied to a colour's name is one a partner trained apart
/// has no reason to share. With `first-seen` (or `public-first`), each seat sees its
/// colours named by the order in which it first saw them (or tiles first showed them;
/// `yokai_engine::ColourLabels`): permuting the deal's colours changes nothing the network
/// reads, so every policy is invariant under colour permutations by construction, which
/// Other-Play's colour permutations only train for.
/// The names follow each seat's history, so the trainer and every front end that plays the
/// policy keep them per seat; the probes and OBL, which step seats from bare game states,
/// do not support them yet.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ColourNames {
    /// The deal's colour indices (the paper's).
    #[default]
    Dealt,
    /// The order of the seat's first sight of each colour.
    FirstSeen,
    /// The colours revealed hint tiles have shown, in the order they showed them (names
    /// both seats share), then those the seat has seen only on cards, by first sight
    /// (`yokai_engine::ColourNaming::PublicFirst`).
    PublicFirst,
}

impl std::fmt::Display for ColourNames {
    /// The name a config file gives it (`network.colours`).
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write_config_name(self, f)
    }
}

impl ColourNames {
    /// The engine's naming rule, `None` for the deal's own names.
    pub fn naming(self) -> Option<yokai_engine::ColourNaming> {
        match self {
            ColourNames::Dealt => None,
            ColourNames::FirstSeen => Some(yokai_engine::ColourNaming::FirstSeen),
            ColourNames::PublicFirst => Some(yokai_engine::ColourNaming::PublicFirst),
        }
    }
}
