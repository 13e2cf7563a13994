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
    /// How sharply the other moves are drawn: from softmax(logits / T) over the legal
    /// actions; 0 takes the most likely legal action. Absent means 1, the distribution the
    /// policy was trained to be. A partner in self-play reads every move as a message, and
    /// the moves the network itself rates unlikely are the ones it cannot read; drawing
    /// them less often is how Hanabi agents are evaluated (greedy play). P(END) for
    /// `end_threshold` is always read at temperature 1, where the END term calibrated it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub temperature: Option<f32>,
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

    /// `t` as a temperature for drawing moves, or why it cannot be one: the one check for
    /// the config field, `yokai eval --temperature` and Python's `temperature=`.
    pub fn temperature_from(t: f64) -> Result<f32, String> {
        if t.is_finite() && (0.0..=100.0).contains(&t) {
            Ok(t as f32)
        } else {
            Err(format!(
                "must lie in [0, 100] (1 draws from the trained distribution, 0 takes the most likely move), not {t}"
            ))
        }
    }

    /// The temperature moves are drawn at: the field, or 1.
    pub fn temperature(&self) -> f32 {
        self.temperature.unwrap_or(1.0)
    }
}
