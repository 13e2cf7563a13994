//! A minibatch's rows gathered from the rollout, cut into shards that learn side by side.
//!
//! On the CPU one minibatch's forward and backward pass mostly runs on one core: its
//! matrices are small (a GRU step is 32 sequences wide), so burn's kernels do not split
//! them. Sharding the minibatch's sequences over the worker threads, each shard with its
//! own autodiff graph, and adding the shards' gradients uses the other cores. The losses
//! divide by the whole minibatch's counts ([`Totals`]), so the shards' losses, and their
//! gradients, add up to the minibatch's: the same gradient step up to float rounding.

use super::rollout::Rollout;
use crate::config::PpoConfig;
use yokai_engine::{Action, Config};

/// The rows of some whole sequences of a minibatch, laid out as the loss reads them.
#[derive(Default)]
pub(super) struct Shard {
    /// Sequences in this shard.
    pub sequences: usize,
    pub obs: Vec<f32>,
    pub keep: Vec<f32>,
    pub old_v: Vec<f32>,
    pub ret: Vec<f32>,
    /// With OBL, 1 on the rows that carry a value target (empty: all do).
    pub value_weight: Vec<f32>,
    pub h0: Vec<f32>,
    /// Rows with one legal action (seats waiting for their turn, or a forced NOOP) carry
    /// no policy gradient: the actor head, the policy loss and the entropy skip them, so
    /// their masks and one-hot actions are not even gathered. Indices `j·T + t`.
    pub choosing: Vec<i64>,
    pub masks: Vec<f32>,
    pub one_hot: Vec<f32>,
    pub old_logp: Vec<f32>,
    pub adv: Vec<f32>,
    /// Per choosing row, with `entropy_normalized`: 1 / ln(its legal actions).
    pub ent_weight: Vec<f32>,
    /// Per choosing row, with `end_entropy_coef` or `end_lookahead`: 1 where END is legal.
    pub end_legal: Vec<f32>,
    /// Per choosing row, with `end_lookahead`: R_END(s) − V(s) (0 where END is illegal).
    pub end_adv: Vec<f32>,
    /// Per choosing row and card, with `belief_aux`: the card's true colour, one-hot.
    pub truth: Vec<f32>,
}

/// What every shard's losses divide by: the whole minibatch's counts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Totals {
    /// Rows that learn their value (all rows, or with OBL the weighted ones; at least 1).
    pub value_rows: f32,
    /// Rows that choose among several actions.
    pub choosing: usize,
    /// Choosing rows where END is legal (at least 1).
    pub rows_with_end: f32,
}

/// The rows of the rollout's sequences `batch`, cut into `shards` shards of whole
/// sequences (as equal as can be, in order), with advantages normalised over the whole
/// minibatch when `normalize_advantages` asks for it, and the minibatch's totals.
pub(super) fn gather(
    ro: &Rollout,
    batch: &[usize],
    shards: usize,
    c: &PpoConfig,
    game: &Config,
    (rows, l, hsz): (usize, usize, usize),
) -> (Vec<Shard>, Totals) {
    let shards = shards.clamp(1, batch.len().max(1));
    let per = batch.len().div_ceil(shards);
    let mut out: Vec<Shard> = batch
        .chunks(per.max(1))
        .map(|part| gather_shard(ro, part, c, game, (rows, l, hsz)))
        .collect();
    let adv_count: usize = out.iter().map(|s| s.adv.len()).sum();
    if c.normalize_advantages && adv_count > 1 {
        let all = || out.iter().flat_map(|s| s.adv.iter());
        let mean = all().sum::<f32>() / adv_count as f32;
        let var = all().map(|a| (a - mean).powi(2)).sum::<f32>() / adv_count as f32;
        let sd = var.sqrt() + 1e-8;
        for s in &mut out {
            s.adv.iter_mut().for_each(|a| *a = (*a - mean) / sd);
        }
    }
    let value_rows = if ro.value_weight.is_empty() {
        (batch.len() * c.rollout_steps) as f32
    } else {
        out.iter()
            .map(|s| s.value_weight.iter().sum::<f32>())
            .sum::<f32>()
            .max(1.0)
    };
    let totals = Totals {
        value_rows,
        choosing: adv_count,
        rows_with_end: out
            .iter()
            .map(|s| s.end_legal.iter().sum::<f32>())
            .sum::<f32>()
            .max(1.0),
    };
    (out, totals)
}

fn gather_shard(
    ro: &Rollout,
    part: &[usize],
    c: &PpoConfig,
    game: &Config,
    (rows, l, hsz): (usize, usize, usize),
) -> Shard {
    let t_len = c.rollout_steps;
    let na = game.num_actions();
    let end = game.encode(Action::End);
    let (y, colours) = (game.cards(), game.colours());
    let n = part.len() * t_len;
    let mut s = Shard {
        sequences: part.len(),
        obs: Vec::with_capacity(n * l),
        keep: Vec::with_capacity(n),
        old_v: Vec::with_capacity(n),
        ret: Vec::with_capacity(n),
        value_weight: Vec::with_capacity(ro.value_weight.len().min(n)),
        h0: Vec::with_capacity(part.len() * hsz),
        ..Shard::default()
    };
    for (j, &r) in part.iter().enumerate() {
        s.h0.extend_from_slice(&ro.h0[r * hsz..][..hsz]);
        for t in 0..t_len {
            let i = t * rows + r;
            s.obs.extend_from_slice(&ro.obs[i * l..][..l]);
            s.keep.push(ro.keeps[i]);
            s.old_v.push(ro.values[i]);
            s.ret.push(ro.returns[i]);
            if !ro.value_weight.is_empty() {
                s.value_weight.push(ro.value_weight[i]);
            }
            if ro.legal[i] <= 1 {
                continue;
            }
            s.choosing.push((j * t_len + t) as i64);
            s.masks.extend_from_slice(&ro.masks[i * na..][..na]);
            let at = s.one_hot.len();
            s.one_hot.resize(at + na, 0.0);
            s.one_hot[at + ro.actions[i]] = 1.0;
            s.old_logp.push(ro.logps[i]);
            s.adv.push(ro.adv[i]);
            if c.entropy_normalized {
                s.ent_weight.push(1.0 / (ro.legal[i] as f32).ln());
            }
            if c.end_entropy_coef > 0.0 || c.end_lookahead > 0.0 {
                s.end_legal.push(ro.masks[i * na + end]);
            }
            if c.end_lookahead > 0.0 {
                s.end_adv
                    .push((ro.end_rewards[i] - ro.values[i]) * ro.masks[i * na + end]);
            }
            if c.belief_aux > 0.0 {
                for &colour in &ro.truth[i * y..][..y] {
                    let at = s.truth.len();
                    s.truth.resize(at + colours, 0.0);
                    s.truth[at + colour as usize] = 1.0;
                }
            }
        }
    }
    s
}
