//! `[act]`: how a trained policy plays outside training.

use serde::{Deserialize, Serialize};

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
    pub(super) fn is_default(&self) -> bool {
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
