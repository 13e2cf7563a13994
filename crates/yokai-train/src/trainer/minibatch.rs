//! A minibatch's rows gathered from the rollout, cut into shards that learn side by side.
//!
//! On the CPU one minibatch's forward and backward pass mostly runs on one core: its
//! matrices are small (a GRU step is 32 sequences wide), so burn's kernels do not split
//! them. Sharding the minibatch's sequences over the worker threads, each shard with its
//! own autodiff graph, and adding the shards' gradients uses the other cores. The losses
//! divide by the whole minibatch's counts ([`Totals`]), so the shards' losses, and their
//! gradients, add up to the minibatch's: the same gradient step up to float rounding.

use super::addons::{AddOns, ShardColumns};
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
    /// With a central critic, every row's true colours (`[rows × Y·C]`); empty otherwise.
    pub colours: Vec<f32>,
    /// Rows with one legal action (seats waiting for their turn, or a forced NOOP) carry
    /// no policy gradient: the actor head, the policy loss and the entropy skip them, so
    /// their masks and actions are not even gathered. Indices `j·T + t`.
    pub choosing: Vec<i64>,
    /// Each choosing row's row in the rollout (`t·rows + r`), where the learner reads its
    /// legal mask in place.
    pub mask_rows: Vec<usize>,
    /// The action each choosing row took (its index in the game's action order).
    pub actions: Vec<usize>,
    pub old_logp: Vec<f32>,
    pub adv: Vec<f32>,
    /// The add-ons' rows, per choosing row.
    pub addons: ShardColumns,
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
    (c, addons): (&PpoConfig, &AddOns),
    game: &Config,
    (rows, l, hsz): (usize, usize, usize),
) -> (Vec<Shard>, Totals) {
    let shards = shards.clamp(1, batch.len().max(1));
    let per = batch.len().div_ceil(shards);
    let mut out: Vec<Shard> = batch
        .chunks(per.max(1))
        .map(|part| gather_shard(ro, part, (c, addons), game, (rows, l, hsz)))
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
    let value_rows = if ro.value_weight.is_none() {
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
            .flat_map(|s| s.addons.end.iter())
            .map(|end| end.legal.iter().sum::<f32>())
            .sum::<f32>()
            .max(1.0),
    };
    (out, totals)
}

fn gather_shard(
    ro: &Rollout,
    part: &[usize],
    (c, addons): (&PpoConfig, &AddOns),
    game: &Config,
    (rows, l, hsz): (usize, usize, usize),
) -> Shard {
    let t_len = c.rollout_steps;
    let n = part.len() * t_len;
    let yc = ro.colours.len() / ro.values.len().max(1);
    let mut s = Shard {
        sequences: part.len(),
        obs: Vec::with_capacity(n * l),
        keep: Vec::with_capacity(n),
        old_v: Vec::with_capacity(n),
        ret: Vec::with_capacity(n),
        h0: Vec::with_capacity(part.len() * hsz),
        ..Shard::default()
    };
    let cols = &mut s.addons;
    cols.end = addons.end.as_ref().map(|_| Default::default());
    cols.truth = addons.belief.as_ref().map(|_| Vec::new());
    cols.entropy_weight = addons.entropy.as_ref().map(|_| Vec::new());
    for (j, &r) in part.iter().enumerate() {
        s.h0.extend_from_slice(&ro.h0[r * hsz..][..hsz]);
        for t in 0..t_len {
            let i = t * rows + r;
            s.obs.extend_from_slice(&ro.obs[i * l..][..l]);
            s.keep.push(ro.keeps[i]);
            s.old_v.push(ro.values[i]);
            s.ret.push(ro.returns[i]);
            s.colours.extend_from_slice(&ro.colours[i * yc..][..yc]);
            if let Some(weight) = &ro.value_weight {
                s.value_weight.push(weight[i]);
            }
            if ro.legal[i] <= 1 {
                continue;
            }
            s.choosing.push((j * t_len + t) as i64);
            s.mask_rows.push(i);
            s.actions.push(ro.actions[i]);
            s.old_logp.push(ro.logps[i]);
            s.adv.push(ro.adv[i]);
            gather_addons(ro, i, (addons, &mut s.addons), game);
        }
    }
    s
}

/// The add-ons' rows of choosing row `i` of the rollout.
fn gather_addons(
    ro: &Rollout,
    i: usize,
    (addons, out): (&AddOns, &mut ShardColumns),
    game: &Config,
) {
    let na = game.num_actions();
    if let (Some(unit), Some(rows)) = (&addons.entropy, &mut out.entropy_weight) {
        unit.gather(ro.legal[i], rows);
    }
    if let (Some(unit), Some(rows)) = (&addons.end, &mut out.end) {
        let end_mask = ro.masks[i * na + game.encode(Action::End)];
        unit.gather(ro.columns.end.as_ref(), i, end_mask, ro.values[i], rows);
    }
    if let (Some(unit), Some(rows), Some(truth)) =
        (&addons.belief, &mut out.truth, &ro.columns.truth)
    {
        unit.gather(truth, i, game.colours(), rows);
    }
}
