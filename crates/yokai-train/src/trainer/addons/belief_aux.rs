//! `ppo.belief_aux`: an auxiliary belief loss (pointer head only). At every choosing state
//! the network predicts each card's true colour from the card's embedding, by
//! cross-entropy: a centralised-training signal that makes the embeddings carry what the
//! seat can infer of the colours, which the END decision needs. Under Other-Play the
//! targets use the seat's colour labels.

use crate::actor::Actor;
use crate::config::PpoConfig;
use burn::prelude::*;
use burn::tensor::activation::log_softmax;
use burn::tensor::TensorData;

#[derive(Clone, Debug)]
pub(in crate::trainer) struct BeliefAux {
    pub weight: f32,
}

/// The rollout's column: per step, row and card, the card's true colour as the row's seat
/// sees colours (`[T × rows × Y]`), written for the acting seats' rows, which are the rows
/// that choose (the waiting seats' stay 0 and are never read).
pub(in crate::trainer) struct Truth {
    colours: Vec<u8>,
    cards: usize,
}

/// A shard's belief loss and its hits (cards whose most likely colour is the true one).
pub(in crate::trainer) struct BeliefLoss {
    pub loss: Tensor<1>,
    pub hits: u64,
}

impl BeliefAux {
    pub fn from_config(c: &PpoConfig) -> Option<BeliefAux> {
        (c.belief_aux > 0.0).then_some(BeliefAux {
            weight: c.belief_aux,
        })
    }

    /// Rollout: an empty column for `t_len` steps of `rows` rows of `cards` cards.
    pub fn column(&self, t_len: usize, rows: usize, cards: usize) -> Truth {
        Truth {
            colours: vec![0; t_len * rows * cards],
            cards,
        }
    }

    /// Gather: choosing row `i` of the rollout, its cards' colours one-hot over `colours`.
    pub fn gather(&self, column: &Truth, i: usize, colours: usize, out: &mut Vec<f32>) {
        let y = column.cards;
        for &colour in &column.colours[i * y..][..y] {
            let at = out.len();
            out.resize(at + colours, 0.0);
            out[at + colour as usize] = 1.0;
        }
    }

    /// Loss: the cross-entropy of the shard's `truth` (`[n, Y, C]` one-hot) under the
    /// colour logits, in nats per card over the minibatch's `choosing` rows.
    pub fn loss(
        &self,
        colour_logits: Tensor<3>,
        truth: Vec<f32>,
        choosing: f32,
        d: &Device,
    ) -> BeliefLoss {
        let [n, y, colours] = colour_logits.dims();
        let truth = Tensor::<3>::from_data(TensorData::new(truth, [n, y, colours]), d);
        let log_p = log_softmax(colour_logits, 2);
        let hits = colour_hits(log_p.clone(), truth.clone());
        BeliefLoss {
            loss: (log_p * truth).sum().neg() / (choosing * y as f32),
            hits,
        }
    }
}

impl Truth {
    /// Rollout: at step `t`, the colours every acting seat's row sees (`acting[i]` the seat
    /// of game `i`).
    pub fn record(&mut self, t: usize, acting: &[u8], actor: &Actor) {
        let (y, rows) = (self.cards, actor.rows());
        let p = rows / acting.len();
        for (i, &seat) in acting.iter().enumerate() {
            let r = i * p + seat as usize;
            actor.view_truth(r, &mut self.colours[(t * rows + r) * y..][..y]);
        }
    }
}

/// Cards among `[n, Y, C]` whose most likely colour under `log_p` is the true one.
fn colour_hits(log_p: Tensor<3>, truth: Tensor<3>) -> u64 {
    let picked = log_p.detach().argmax(2);
    let true_colour = truth.argmax(2);
    picked.equal(true_colour).int().sum().into_scalar::<i64>() as u64
}
