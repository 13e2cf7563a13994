//! The END add-ons. PPO alone stops trying END within its first updates (an early END
//! forfeits what the board would still earn), so two terms keep it in play, each averaged
//! over the choosing rows where END is legal:
//!
//! - `ppo.end_entropy_coef`: a bonus on the entropy of the binary choice END-or-not;
//! - `ppo.end_lookahead`: the END term. Wherever END is legal the rollout records what
//!   ending would pay (`R_END`, in the world OBL draws where OBL is on), and the loss uses
//!   `R_END − V` as the exact advantage of END: in its `expected` form the expected policy
//!   gradient π(END|s)·(R_END − V), in its `target` form a cross-entropy pulling P(END)
//!   towards σ((R_END − V) / ¼ point).

use crate::config::{EndForm, PpoConfig};
use crate::distribution::binary_entropy;
use crate::tensor::tensor1;
use burn::prelude::*;
use yokai_engine::Game;

#[derive(Clone, Debug)]
pub(in crate::trainer) struct EndAddOn {
    entropy_coef: f32,
    lookahead: f32,
    form: EndForm,
}

/// The rollout's column of the END term: per step and row, what END would pay in the row's
/// game at that step (`[T × rows]`; written where the acting seat's mask allows END).
pub(in crate::trainer) struct EndRewards(Vec<f32>);

/// A shard's rows: per choosing row, 1 where END is legal, and with the END term
/// R_END − V (0 where END is illegal).
#[derive(Default)]
pub(in crate::trainer) struct EndRows {
    pub legal: Vec<f32>,
    adv: Vec<f32>,
}

impl EndAddOn {
    pub fn from_config(c: &PpoConfig) -> Option<EndAddOn> {
        (c.end_entropy_coef > 0.0 || c.end_lookahead > 0.0).then_some(EndAddOn {
            entropy_coef: c.end_entropy_coef,
            lookahead: c.end_lookahead,
            form: c.end_lookahead_form,
        })
    }

    /// Rollout: an empty column for `t_len` steps of `rows` rows (none without the END
    /// term).
    pub fn column(&self, t_len: usize, rows: usize) -> Option<EndRewards> {
        (self.lookahead > 0.0).then(|| EndRewards(vec![0.0; t_len * rows]))
    }

    /// Gather: choosing row `i` of the rollout, whose END mask entry is `end_mask` and
    /// value `value`.
    pub fn gather(
        &self,
        column: Option<&EndRewards>,
        i: usize,
        end_mask: f32,
        value: f32,
        rows: &mut EndRows,
    ) {
        rows.legal.push(end_mask);
        if let Some(EndRewards(paid)) = column {
            rows.adv.push((paid[i] - value) * end_mask);
        }
    }

    /// Loss: the END bonus of a shard's choosing rows from their log-probabilities of END
    /// `[rows]`, divided by the minibatch's rows where END is legal.
    pub fn bonus(
        &self,
        log_p_end: Tensor<1>,
        rows: EndRows,
        rows_with_end: f32,
        d: &Device,
    ) -> Tensor<1> {
        let legal = tensor1(rows.legal, d);
        let mut bonus = Tensor::<1>::zeros([1], d).sum();
        if self.entropy_coef > 0.0 {
            let h = binary_entropy(log_p_end.clone()) * legal.clone();
            bonus = bonus + h.sum() / rows_with_end * self.entropy_coef;
        }
        if self.lookahead > 0.0 {
            let end_adv = tensor1(rows.adv, d);
            let gain = match self.form {
                EndForm::Expected => log_p_end.exp() * end_adv,
                EndForm::Target => end_target_gain(log_p_end, end_adv, legal),
            };
            bonus = bonus + gain.sum() / rows_with_end * self.lookahead;
        }
        bonus
    }
}

impl EndRewards {
    /// The column as recorded.
    #[cfg(test)]
    pub fn paid(&self) -> &[f32] {
        &self.0
    }

    /// Rollout: at step `t`, what END pays for every acting seat's row (`acting[i]` the seat
    /// of game `i`, `rows` rows per step) whose mask (`masks`, this step's, `na` actions,
    /// END at `end`) allows it; `game(i)` is the game it would end.
    pub fn record<'g>(
        &mut self,
        t: usize,
        acting: &[u8],
        (masks, na, end): (&[f32], usize, usize),
        game: impl Fn(usize) -> &'g Game,
    ) {
        let rows = masks.len() / na;
        let p = rows / acting.len();
        for (i, &seat) in acting.iter().enumerate() {
            let r = i * p + seat as usize;
            if masks[r * na + end] > 0.5 {
                self.0[t * rows + r] = game(i).end_reward() as f32;
            }
        }
    }
}

/// Temperature of the target form, in points of reward: σ(advantage / 0.25) is 0.98 where
/// ending pays one point more than playing on and 6·10⁻⁶ where it costs three (a typical
/// unwon board), so the target is close to "1 if ending pays" and adds no floor to P(END)
/// where it does not (at one point, σ(−3) would keep P(END) at 5 % there).
const END_TARGET_TEMPERATURE: f32 = 0.25;

/// The target form's gain per row, t·log P(END) + (1 − t)·log(1 − P(END)) with
/// t = σ((R_END − V) / `END_TARGET_TEMPERATURE`); `end_legal` (1 or 0 per row) keeps rows
/// where END is illegal out.
fn end_target_gain(log_p_end: Tensor<1>, end_adv: Tensor<1>, end_legal: Tensor<1>) -> Tensor<1> {
    let target = burn::tensor::activation::sigmoid(end_adv / END_TARGET_TEMPERATURE);
    // log(1 − p), with p kept below 1 so it stays finite.
    let log_rest = log_p_end.clone().exp().clamp_max(1.0 - 1e-6).neg().log1p();
    (target.clone() * log_p_end + (target.neg() + 1.0) * log_rest) * end_legal
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The target END term's gradient on the END log-odds is σ(advantage / T) − P(END): it does
    /// not fade where P(END) is tiny, never exceeds 1 whatever the advantage, and rows where
    /// END is illegal get none.
    #[test]
    fn the_end_target_pulls_the_log_odds_towards_sigmoid_of_the_advantage() {
        let sig = |x: f32| 1.0 / (1.0 + (-x).exp());
        // (log-odds of END, advantage)
        let cases: [(f32, f32); 7] = [
            (-9.0, -3.0), // ending loses, P(END) tiny already: almost no push
            (-9.0, 12.0), // a won board with P(END) tiny: a full push up
            (-4.0, -3.0),
            (0.0, -3.0),
            (0.0, 5.0),
            (3.0, 0.5),
            (9.0, 15.0),
        ];
        let dev = Device::flex().autodiff();
        let p: Vec<f32> = cases.iter().map(|c| sig(c.0)).collect();
        let log_p: Vec<f32> = p.iter().map(|p| p.ln()).collect();
        let mut adv: Vec<f32> = cases.iter().map(|c| c.1).collect();
        let mut log_p = log_p;
        let mut legal = vec![1.0; cases.len()];
        // One row where END is illegal: no gradient at all.
        adv.push(4.0);
        log_p.push(sig(0.0).ln());
        legal.push(0.0);
        let log_p_end = tensor1(log_p, &dev).require_grad();
        let gain =
            end_target_gain(log_p_end.clone(), tensor1(adv, &dev), tensor1(legal, &dev)).sum();
        let grads = gain.backward();
        let g: Vec<f32> = log_p_end
            .grad(&grads)
            .unwrap()
            .into_data()
            .convert::<f32>()
            .try_into_vec()
            .unwrap();
        for (i, &(x, a)) in cases.iter().enumerate() {
            // d log-odds / d log p = 1 / (1 − p): undo it to read the log-odds' gradient.
            let on_log_odds = g[i] * (1.0 - p[i]);
            let want = sig(a / END_TARGET_TEMPERATURE) - p[i];
            assert!(
                (on_log_odds - want).abs() < 1e-3,
                "log-odds {x}, advantage {a}: gradient {on_log_odds}, want {want}"
            );
            assert!(on_log_odds.abs() <= 1.0);
        }
        assert!(g[1] * (1.0 - p[1]) > 0.99, "full push at a won board");
        assert_eq!(g[cases.len()], 0.0, "END illegal: no gradient");
    }
}
