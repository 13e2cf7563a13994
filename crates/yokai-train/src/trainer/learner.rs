//! The learner: the PPO epochs over a rollout, each minibatch a set of whole row sequences
//! replayed from the state stored at the rollout's start; the clipped policy and value
//! losses, the entropy bonus, the add-ons' terms, the global gradient-norm clip and the
//! Adam step.

use super::addons::{AddOns, ShardColumns};
use super::minibatch::{self, Shard, Totals};
use super::rollout::Rollout;
use super::row_groups::{MaskRows, RowGroups};
use super::Trainer;
use crate::network::{shards_on, ActionLogits, ActorCritic, Encoder, Recurrent};
use crate::tensor::{rows_tensor, tensor1, tensor2};
use burn::module::{Module, ModuleMapper, ModuleVisitor, Param};
use burn::optim::{GradientsAccumulator, GradientsParams};
use burn::prelude::*;
use burn::tensor::TensorData;
use rand_chacha::ChaCha8Rng;
use yokai_engine::deal::shuffle;

/// What the epochs of one update report (means over minibatches).
#[derive(Default)]
pub(super) struct Losses {
    pub policy: f64,
    pub value: f64,
    /// Mean |log π_new − log π_old| of the first minibatch before any step (see
    /// `UpdateStats::replay_error`).
    pub replay_error: f64,
    /// With `belief_aux`: the colour cross-entropy (nats per card) and the share of cards
    /// whose most likely colour is the true one.
    pub belief: Option<(f64, f64)>,
    /// The PPO diagnostics CleanRL and JaxMARL log (see `UpdateStats`): the estimated KL
    /// from the rollout's policy, the share of clipped ratios, the gradients' global norm
    /// before clipping.
    pub approx_kl: f64,
    pub clip_fraction: f64,
    pub grad_norm: f64,
}

impl<E: Encoder, M: Recurrent> Trainer<E, M> {
    /// `epochs` passes over the rollout in `minibatches` shuffled sets of whole rows, at the
    /// learning rate and entropy bonus of this update.
    pub(super) fn learn_epochs(
        &mut self,
        ro: &Rollout,
        lr: f64,
        entropy_coef: f32,
        rng: &mut ChaCha8Rng,
    ) -> Losses {
        let c = self.config.ppo.clone();
        let rows = self.actor.rows();
        let mb = rows / c.minibatches;
        let mut sum = Losses::default();
        let mut count = 0u64;
        let mut order: Vec<usize> = (0..rows).collect();
        for _ in 0..c.epochs {
            shuffle(rng, &mut order);
            for k in 0..c.minibatches {
                let end = if k + 1 == c.minibatches {
                    rows
                } else {
                    (k + 1) * mb
                };
                let batch = &order[k * mb..end];
                let step = self.learn(batch, ro, lr, entropy_coef);
                if count == 0 {
                    sum.replay_error = step.replay_error;
                }
                sum.policy += step.policy;
                sum.value += step.value;
                sum.approx_kl += step.approx_kl;
                sum.clip_fraction += step.clip_fraction;
                sum.grad_norm += step.grad_norm;
                if let Some((loss, accuracy)) = step.belief {
                    let (l, a) = sum.belief.unwrap_or((0.0, 0.0));
                    sum.belief = Some((l + loss, a + accuracy));
                }
                count += 1;
            }
        }
        let n = count as f64;
        Losses {
            policy: sum.policy / n,
            value: sum.value / n,
            replay_error: sum.replay_error,
            belief: sum.belief.map(|(l, a)| (l / n, a / n)),
            approx_kl: sum.approx_kl / n,
            clip_fraction: sum.clip_fraction / n,
            grad_norm: sum.grad_norm / n,
        }
    }

    /// One gradient step on the rows `batch` of the rollout; returns its losses and the mean
    /// |Δ log π| against the rollout before the step. On the CPU the minibatch's sequences
    /// are cut into one shard per worker thread, which learn side by side
    /// ([`super::minibatch`]).
    fn learn(&mut self, batch: &[usize], ro: &Rollout, lr: f64, entropy_coef: f32) -> Losses {
        let c = crate::config::PpoConfig {
            entropy_coef,
            ..self.config.ppo.clone()
        };
        let dims = (
            self.actor.rows(),
            self.actor.obs_len(),
            self.model.hidden_size(),
        );
        let (shards, totals) = minibatch::gather(
            ro,
            batch,
            shards_on(&self.infer_device),
            (&c, &self.addons),
            &self.game,
            dims,
        );
        let (model, device) = (&self.model, &self.device);
        let job = ShardJob {
            totals: &totals,
            masks: &ro.masks,
            c: &c,
            addons: &self.addons,
            game: &self.game,
            d: device,
        };
        let mut outs: Vec<ShardOut> = if shards.len() == 1 {
            shards.into_iter().map(|s| job.step(model, s)).collect()
        } else {
            use rayon::prelude::*;
            // Each shard learns on its own copy of the parameters (same ids, a graph of
            // its own), so the shards' backward passes do not share a lock.
            shards
                .into_par_iter()
                .map(|s| job.step(&model.clone().fork(device), s))
                .collect()
        };
        // The shards' gradients summed, parameter by parameter (a gradient missing in a
        // shard without a choosing row, the actor's, counts as 0).
        let mut sum = GradientsAccumulator::new();
        for out in &mut outs {
            sum.accumulate(&self.model, std::mem::take(&mut out.grads));
        }
        let mut grads = sum.grads();
        let grad_norm = clip_global_norm(&self.model, &mut grads, c.max_grad_norm);
        let model = self.model.clone();
        self.model = self.optim.step(lr, model, grads);
        let total = |f: fn(&ShardOut) -> f64| outs.iter().map(f).sum::<f64>();
        let n = totals.choosing;
        let y = self.game.cards();
        Losses {
            policy: total(|o| o.policy),
            value: total(|o| o.value),
            replay_error: total(|o| o.abs_delta) / n.max(1) as f64,
            approx_kl: total(|o| o.kl) / n.max(1) as f64,
            clip_fraction: total(|o| o.clipped) / n.max(1) as f64,
            grad_norm,
            belief: (self.addons.belief.is_some() && n > 0).then(|| {
                let hits = total(|o| o.belief_hits as f64);
                (total(|o| o.belief), hits / (n * y) as f64)
            }),
        }
    }
}

/// What one shard's forward and backward pass gives: its gradients, and its parts of the
/// minibatch's losses (each already divided by the minibatch's totals, so they add up).
struct ShardOut {
    grads: GradientsParams,
    policy: f64,
    value: f64,
    /// Σ |log π_new − log π_old| over the shard's choosing rows.
    abs_delta: f64,
    /// Σ (r − 1) − log r over the shard's choosing rows, r = π_new / π_old: the unbiased,
    /// never negative estimator of KL(π_old ‖ π_new) that CleanRL logs as `approx_kl`.
    kl: f64,
    /// Choosing rows whose ratio lies outside [1 − clip, 1 + clip].
    clipped: f64,
    belief: f64,
    /// Cards whose most likely colour is the true one.
    belief_hits: u64,
}

/// What every shard of a minibatch shares: the minibatch's totals, the rollout's legal
/// masks (which the shards read in place), the settings, the add-ons that are on, the game
/// and the device.
struct ShardJob<'a> {
    totals: &'a Totals,
    masks: &'a [f32],
    c: &'a crate::config::PpoConfig,
    addons: &'a AddOns,
    game: &'a yokai_engine::Config,
    d: &'a Device,
}

impl ShardJob<'_> {
    /// The PPO loss of one shard of a minibatch, divided by the minibatch's totals, and
    /// its gradients with respect to `model`'s parameters.
    fn step<E: Encoder, M: Recurrent>(&self, model: &ActorCritic<E, M>, s: Shard) -> ShardOut {
        let (c, d) = (self.c, self.d);
        let (bm, t_len, hsz) = (s.sequences, c.rollout_steps, model.hidden_size());
        let l = s.obs.len() / (bm * t_len);
        // The choosing rows at the MOVE substep, read before the observations become a
        // tensor: only their MOVE logits can be legal, so only theirs are computed.
        let moving = model.rows_at_move(&s.obs, &s.choosing);
        let obs: Tensor<3> = Tensor::from_data(TensorData::new(s.obs, [bm, t_len, l]), d);
        let states = model.unroll(
            obs.clone(),
            tensor2(s.h0, [bm, hsz], d),
            tensor2(s.keep, [bm, t_len], d),
        );
        let colours = (!s.colours.is_empty()).then(|| {
            let (n, width) = (bm * t_len, s.colours.len() / (bm * t_len));
            tensor2(s.colours, [n, width], d)
        });
        // What the heads read, once for the critic and the actor's chunks below.
        let states = model.head_input(states);
        let values = model.values_of_head(states.clone(), colours);
        let value_loss = self.value_loss(values, s.old_v, s.ret, s.value_weight);
        let zero = Tensor::<1>::zeros([1], d).sum();
        let mut policy = PolicyTerms {
            loss: zero.clone(),
            entropy: zero.clone(),
            end_bonus: zero.clone(),
            belief: zero,
            belief_hits: 0,
            diagnostics: (0.0, 0.0, 0.0),
        };
        if !s.choosing.is_empty() {
            // The actor head reads the choosing rows only; the pointer head also reads
            // their observations.
            let n = s.choosing.len();
            let idx = rows_tensor(s.choosing, d);
            let row_obs = if model.actor_reads_observations() {
                obs.reshape([bm * t_len, l]).select(0, idx.clone())
            } else {
                Tensor::zeros([n, 1], d)
            };
            let heads = model.action_logits_of_head(row_obs, states.select(0, idx), &moving);
            let rows = ChoosingRows {
                moving,
                mask_rows: s.mask_rows,
                actions: s.actions,
                old_logp: s.old_logp,
                adv: s.adv,
                addons: s.addons,
            };
            policy = self.policy_terms(heads, rows);
        }
        let loss = policy.loss.clone() + value_loss.clone() * c.value_coef
            - policy.entropy * c.entropy_coef
            - policy.end_bonus;
        let loss = match &self.addons.belief {
            Some(unit) => loss + policy.belief.clone() * unit.weight,
            None => loss,
        };
        let (abs_delta, kl, clipped) = policy.diagnostics;
        ShardOut {
            grads: GradientsParams::from_grads(loss.backward(), model),
            policy: policy.loss.into_scalar::<f32>() as f64,
            value: value_loss.into_scalar::<f32>() as f64,
            abs_delta,
            kl,
            clipped,
            belief: policy.belief.into_scalar::<f32>() as f64,
            belief_hits: policy.belief_hits,
        }
    }

    /// PPO's clipped value loss over the shard's rows (with OBL, the rows of weight 1),
    /// divided by the minibatch's rows that learn their value.
    fn value_loss(
        &self,
        v: Tensor<1>,
        old_v: Vec<f32>,
        ret: Vec<f32>,
        weight: Vec<f32>,
    ) -> Tensor<1> {
        let (c, d) = (self.c, self.d);
        let old_v = tensor1(old_v, d);
        let ret = tensor1(ret, d);
        let v_clipped = old_v.clone() + (v.clone() - old_v).clamp(-c.value_clip, c.value_clip);
        let per_row = (v - ret.clone())
            .square()
            .max_pair((v_clipped - ret).square());
        let sum = if weight.is_empty() {
            per_row.sum()
        } else {
            (per_row * tensor1(weight, d)).sum()
        };
        sum / self.totals.value_rows * 0.5
    }

    /// The terms read off the choosing rows' heads: the clipped policy loss, the entropy
    /// bonus, the END add-ons' bonus, the belief loss, and the ratio diagnostics. The
    /// softmax runs over each row's group of columns that can be legal ([`RowGroups`]),
    /// whose per-row terms come back in the rows' own order.
    fn policy_terms(
        &self,
        (logits, colour_logits): (ActionLogits, Option<Tensor<3>>),
        rows: ChoosingRows,
    ) -> PolicyTerms {
        let (c, d) = (self.c, self.d);
        let n_all = self.totals.choosing as f32;
        let ShardColumns {
            end,
            truth,
            entropy_weight,
        } = rows.addons;
        let zero = || Tensor::<1>::zeros([1], d).sum();
        let (mut belief, mut belief_hits) = (zero(), 0);
        // The network has a colour layer exactly when the belief add-on is on. Its loss is
        // a sum over cards of rows in their own order.
        if let (Some(unit), Some(colour_logits), Some(truth)) =
            (&self.addons.belief, colour_logits, truth)
        {
            let out = unit.loss(colour_logits, truth, n_all, d);
            (belief, belief_hits) = (out.loss, out.hits);
        }
        let groups = RowGroups::new(
            logits,
            &rows.moving,
            MaskRows {
                all: self.masks,
                rows: &rows.mask_rows,
                na: self.game.num_actions(),
            },
            &rows.actions,
            self.game,
            d,
        );
        let [logp, row_entropy, log_p_end] = groups.terms();
        let end_bonus = match (&self.addons.end, end) {
            (Some(unit), Some(end_rows)) => {
                unit.bonus(log_p_end, end_rows, self.totals.rows_with_end, d)
            }
            _ => zero(),
        };
        let entropy = match (&self.addons.entropy, entropy_weight) {
            (Some(unit), Some(weights)) => unit.weigh(row_entropy, weights, d) / n_all,
            _ => row_entropy.sum() / n_all,
        };
        let adv = tensor1(rows.adv, d);
        let delta = logp - tensor1(rows.old_logp, d);
        let ratio = delta.clone().exp();
        let diagnostics = ratio_diagnostics(delta.detach(), ratio.clone().detach(), c.clip);
        let clipped = ratio.clone().clamp(1.0 - c.clip, 1.0 + c.clip);
        let loss = (ratio * adv.clone()).min_pair(clipped * adv).sum().neg() / n_all;
        PolicyTerms {
            loss,
            entropy,
            end_bonus,
            belief,
            belief_hits,
            diagnostics,
        }
    }
}

/// A shard's choosing rows, as the policy terms read them.
struct ChoosingRows {
    /// The positions of the rows at the MOVE substep (the pointer head's MOVE rows).
    moving: Vec<usize>,
    /// Each row's row in the rollout's masks.
    mask_rows: Vec<usize>,
    actions: Vec<usize>,
    old_logp: Vec<f32>,
    adv: Vec<f32>,
    addons: ShardColumns,
}

/// The policy-side terms of a shard's loss (zero where the shard has no choosing row).
struct PolicyTerms {
    loss: Tensor<1>,
    entropy: Tensor<1>,
    end_bonus: Tensor<1>,
    belief: Tensor<1>,
    belief_hits: u64,
    /// Σ |Δ log π|, Σ (r − 1 − log r), clipped ratios.
    diagnostics: (f64, f64, f64),
}

/// Over rows with log-ratios `delta` = log π_new − log π_old and ratios `ratio` = e^delta
/// (the loss's own, detached): Σ |delta| (the replay check), Σ (r − 1 − log r)
/// (approximate KL) and the count of ratios outside [1 − clip, 1 + clip], read back in one
/// transfer.
fn ratio_diagnostics(delta: Tensor<1>, ratio: Tensor<1>, clip: f32) -> (f64, f64, f64) {
    let kl = (ratio.clone() - 1.0 - delta.clone()).sum();
    let outside = (ratio - 1.0).abs().greater_elem(clip).float().sum();
    let sums = Tensor::cat(vec![delta.abs().sum(), kl, outside], 0);
    let v = crate::tensor::to_vec(sums);
    (v[0] as f64, v[1] as f64, v[2] as f64)
}

/// Scale all gradients together so that their global L2 norm is at most `max_norm`, and
/// return the norm before scaling. burn's own clipping (`GradientClipping::Norm`) clips
/// each parameter's tensor by its own norm, which changes the gradient's direction; PPO's
/// clip (as in CleanRL's `clip_grad_norm_`) scales all of them by one factor.
fn clip_global_norm<M: Module>(model: &M, grads: &mut GradientsParams, max_norm: f32) -> f64 {
    struct Norm<'a> {
        grads: &'a GradientsParams,
        sum: f64,
    }
    impl ModuleVisitor for Norm<'_> {
        fn visit_float<const D: usize>(&mut self, param: &Param<Tensor<D>>) {
            if let Some(g) = self.grads.get::<D>(param.id) {
                self.sum += g.square().sum().into_scalar::<f32>() as f64;
            }
        }
    }
    struct Scale<'a> {
        grads: &'a mut GradientsParams,
        factor: f32,
    }
    impl ModuleMapper for Scale<'_> {
        fn map_float<const D: usize>(&mut self, param: Param<Tensor<D>>) -> Param<Tensor<D>> {
            if let Some(g) = self.grads.remove::<D>(param.id) {
                self.grads.register(param.id, g.mul_scalar(self.factor));
            }
            param
        }
    }
    let mut norm = Norm {
        grads: &*grads,
        sum: 0.0,
    };
    model.visit(&mut norm);
    let total = norm.sum.sqrt() as f32;
    if total > max_norm {
        let mut scale = Scale {
            grads,
            factor: max_norm / (total + 1e-6),
        };
        let _ = model.clone().map(&mut scale);
    }
    total as f64
}

/// 1 − Var(returns − values) / Var(returns) over the rows with weight > 0 (all rows when
/// `weight` is empty): 1 when the critic predicts its targets exactly, 0 when it does no
/// better than their mean, negative when worse. `None` when the targets do not vary.
pub(super) fn explained_variance(values: &[f32], returns: &[f32], weight: &[f32]) -> Option<f64> {
    let rows = (0..values.len()).filter(|&i| weight.get(i).is_none_or(|&w| w > 0.0));
    let (mut n, mut sr, mut sr2, mut se, mut se2) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for i in rows {
        let (r, e) = (returns[i] as f64, (returns[i] - values[i]) as f64);
        n += 1.0;
        sr += r;
        sr2 += r * r;
        se += e;
        se2 += e * e;
    }
    let var = |s: f64, s2: f64| s2 / n - (s / n) * (s / n);
    let var_returns = var(sr, sr2);
    (n > 0.0 && var_returns > 1e-12).then(|| 1.0 - var(se, se2) / var_returns)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn explained_variance_is_one_for_a_perfect_critic_and_zero_for_the_mean() {
        let returns = [1.0, 2.0, 3.0, 6.0];
        assert_eq!(explained_variance(&returns, &returns, &[]), Some(1.0));
        let mean = [3.0; 4];
        assert!(explained_variance(&mean, &returns, &[]).unwrap().abs() < 1e-12);
        // A critic off by a constant explains all the variance; one that predicts the
        // opposite explains less than none.
        let shifted = returns.map(|r| r + 5.0);
        assert!((explained_variance(&shifted, &returns, &[]).unwrap() - 1.0).abs() < 1e-12);
        let opposite = returns.map(|r| 6.0 - r);
        assert!(explained_variance(&opposite, &returns, &[]).unwrap() < 0.0);
        // Rows of weight 0 are left out; constant targets explain nothing to compare.
        let weights = [1.0, 1.0, 0.0, 0.0];
        let values = [1.0, 2.0, 99.0, -99.0];
        assert_eq!(explained_variance(&values, &returns, &weights), Some(1.0));
        assert_eq!(explained_variance(&[0.0; 3], &[2.0; 3], &[]), None);
    }

    #[test]
    fn ratio_diagnostics_measure_kl_and_clipping_as_cleanrl_does() {
        let d = crate::device::default_device();
        let logr = [0.0f32, 0.1, -0.3, 0.25];
        let delta = tensor1(logr.to_vec(), &d);
        let (abs, kl, outside) = ratio_diagnostics(delta.clone(), delta.exp(), 0.2);
        let want_kl: f64 = logr
            .iter()
            .map(|&x| (x as f64).exp() - 1.0 - x as f64)
            .sum();
        assert!((abs - 0.65).abs() < 1e-6, "{abs}");
        assert!((kl - want_kl).abs() < 1e-6, "{kl} vs {want_kl}");
        // r = 1, 1.105, 0.741, 1.284: two lie outside [0.8, 1.2].
        assert_eq!(outside, 2.0);
    }
}
