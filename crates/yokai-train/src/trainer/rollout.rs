//! Acting: one rollout of `rollout_steps` steps in every game, with what learning needs
//! (observations and masks as each seat saw them, actions, log-probabilities, values,
//! episode starts) and the GAE advantages and returns.

use super::Trainer;
use crate::distribution::sample_row;
use crate::error::TrainError;
use crate::gae::gae;
use crate::network::{shards_on, Encoder, Recurrent};
use burn::module::Module;
use rand_chacha::ChaCha8Rng;
use yokai_engine::{Action, MetricsAccumulator};
use yokai_vec::episode_seed;

/// One rollout, time-major (`[T, rows, …]`), as learning reads it.
pub(super) struct Rollout {
    pub obs: Vec<f32>,
    pub masks: Vec<f32>,
    pub actions: Vec<usize>,
    pub logps: Vec<f32>,
    pub values: Vec<f32>,
    pub keeps: Vec<f32>,
    /// The row's number of legal actions at that step (1: a waiting seat or a forced move,
    /// which carries no policy gradient).
    pub legal: Vec<u32>,
    pub adv: Vec<f32>,
    pub returns: Vec<f32>,
    /// Every row's recurrent state at the start of the rollout (`[rows × H]`).
    pub h0: Vec<f32>,
    /// The games that ended during the rollout.
    pub games: MetricsAccumulator,
    /// Mean entropy of the acting seats' policies.
    pub entropy: f64,
    /// Net change in clustered colours paid by the clustering shaping, unweighted.
    pub cluster_reward: f64,
    /// With `end_lookahead`: per row and step, what END would pay in the row's game at that
    /// step (`[T × rows]`; meaningful where the row's mask allows END). Empty when off.
    pub end_rewards: Vec<f32>,
    /// With `belief_aux`: per step, row and card, the card's true colour as the row's seat
    /// sees colours (its symmetry's relabelling applied), `[T × rows × Y]`, filled for the
    /// acting seats' rows only. Empty when off.
    pub truth: Vec<u8>,
    /// With Off-Belief Learning: 1 on the rows whose value target is an OBL target (the
    /// acting seats'), 0 on the others, whose value loss is off (`[T × rows]`). Empty
    /// otherwise: every row learns its value.
    pub value_weight: Vec<f32>,
}

impl<E: Encoder, M: Recurrent> Trainer<E, M> {
    /// Play `rollout_steps` steps in every game with the current network, sampling from
    /// `rng`; `shaping` weighs the shaping reward in the returns.
    pub(super) fn collect(
        &mut self,
        shaping: f64,
        rng: &mut ChaCha8Rng,
    ) -> Result<Rollout, TrainError> {
        let c = self.config.ppo.clone();
        let (rows, l, na) = (self.rows, self.obs_len, self.n_actions);
        let t_len = c.rollout_steps;
        let p = self.game.players();
        let n = c.num_envs;
        let mut obs = vec![0f32; t_len * rows * l];
        let mut masks = vec![0f32; t_len * rows * na];
        let mut actions = vec![0usize; t_len * rows];
        let mut logps = vec![0f32; t_len * rows];
        let mut values = vec![0f32; t_len * rows];
        let mut rewards = vec![0f32; t_len * rows];
        let mut dones = vec![0f32; t_len * rows];
        let mut keeps = vec![0f32; t_len * rows];
        let mut legal = vec![0u32; t_len * rows];
        // Clustering shaping: per game, the clustered colours of its current state, counted
        // once per step (after it) and carried to the next step as its "before".
        let cluster_weight = shaping as f32 * c.cluster_shaping;
        let mut clustered: Vec<f32> = if cluster_weight > 0.0 {
            (0..n)
                .map(|i| self.env.game(i).clustered_colours() as f32)
                .collect()
        } else {
            Vec::new()
        };
        let mut cluster_reward = 0f64;
        let lookahead = c.end_lookahead > 0.0;
        let end = self.game.encode(Action::End);
        let mut end_rewards = if lookahead {
            vec![0f32; t_len * rows]
        } else {
            Vec::new()
        };
        let y = self.game.cards();
        let mut truth = if c.belief_aux > 0.0 {
            vec![0u8; t_len * rows * y]
        } else {
            Vec::new()
        };
        // Off-Belief Learning: the acting rows' value targets from fictitious continuations.
        let obl = self.config.obl.level > 0;
        let mut obl_targets: Vec<Option<f32>> = if obl {
            vec![None; t_len * rows]
        } else {
            Vec::new()
        };
        let h0 = self.state.hidden.clone();
        let net = self.model.valid();
        let dev = self.infer_device.clone();
        let shards = shards_on(&dev);
        let mut joint = vec![0u32; rows];
        let no_choice = vec![0f32; na];
        let mut games = MetricsAccumulator::default();
        let (mut ent_sum, mut ent_rows) = (0f64, 0u64);
        for t in 0..t_len {
            let (o, m) = (
                &mut obs[t * rows * l..][..rows * l],
                &mut masks[t * rows * na..][..rows * na],
            );
            self.view(o, m);
            let keep = self.keeps();
            keeps[t * rows..][..rows].copy_from_slice(&keep);
            self.step_belief_memory(o, &keep);
            for r in 0..rows {
                legal[t * rows + r] = m[r * na..][..na].iter().filter(|&&x| x > 0.5).count() as u32;
            }
            // The actor runs on the rows that choose; `chosen` holds their logits in row
            // order. A row with one legal action (a waiting seat's NOOP, a forced move) is
            // drawn from zero logits: its only action has log-prob 0 and entropy 0 whatever
            // its logit, so the draws below are unchanged.
            let choosing: Vec<usize> = (0..rows).filter(|&r| legal[t * rows + r] > 1).collect();
            let acted = net.act(o, &self.state.hidden, &keep, &choosing, &dev, shards);
            values[t * rows..][..rows].copy_from_slice(&acted.values);
            self.state.hidden = acted.states;
            let chosen = acted.logits;
            let mut next_chosen = chosen.chunks_exact(na);
            let acting = self.env.acting_seats().to_vec();
            // Learning reads the belief targets of the rows that choose, which are the
            // acting seats' rows: the waiting seats' are left at 0.
            if !truth.is_empty() {
                for (i, &seat) in acting.iter().enumerate() {
                    let r = i * p + seat as usize;
                    self.view_truth(r, &mut truth[(t * rows + r) * y..][..y]);
                }
            }
            for r in 0..rows {
                let u = crate::distribution::unit_draw(rng);
                let logits = if legal[t * rows + r] > 1 {
                    next_chosen
                        .next()
                        .expect("one row of logits per choosing row")
                } else {
                    &no_choice[..]
                };
                let (a, lp, h) = sample_row(logits, &m[r * na..][..na], u, false);
                actions[t * rows + r] = a;
                logps[t * rows + r] = lp;
                if acting[r / p] as usize == r % p {
                    ent_sum += h as f64;
                    ent_rows += 1;
                }
                joint[r] = self.to_true_action(r, a) as u32;
            }
            let worlds = if obl {
                let step = self.obl_targets(&net, t, &joint, shaping as f32)?;
                for (r, target) in step.targets {
                    obl_targets[t * rows + r] = Some(target);
                }
                step.worlds
            } else {
                Vec::new()
            };
            if lookahead {
                for (i, &seat) in acting.iter().enumerate() {
                    let r = i * p + seat as usize;
                    if m[r * na + end] > 0.5 {
                        // Under OBL, what END pays in the world drawn from the seat's belief
                        // (the fictitious game its target comes from), never the true one.
                        let game = worlds.get(i).unwrap_or_else(|| self.env.game(i));
                        end_rewards[t * rows + r] = game.end_reward() as f32;
                    }
                }
            }
            self.env.step_joint(&joint)?;
            for i in 0..n {
                let mut reward = self.env.rewards()[i] + shaping as f32 * self.env.shaping()[i];
                let done = self.env.dones()[i] == 1;
                if cluster_weight > 0.0 {
                    let after = self.env.game(i).clustered_colours() as f32;
                    // A finished game has been dealt again: its last step keeps the game's
                    // reward, which counts the clustered colours itself.
                    if !done {
                        reward += cluster_weight * (after - clustered[i]);
                        cluster_reward += (after - clustered[i]) as f64;
                    }
                    clustered[i] = after;
                }
                for s in 0..p {
                    rewards[t * rows + i * p + s] = reward;
                    dones[t * rows + i * p + s] = done as u8 as f32;
                }
                if done {
                    if let Some(o) = self.env.outcomes()[i] {
                        games.add(&o);
                    }
                    if i == 0 {
                        let mut actions = std::mem::take(&mut self.state.history[0]);
                        actions.push(joint[acting[0] as usize]);
                        // The environment has already moved on to the next episode.
                        let finished = self.env.episodes(0) - 1;
                        let seed = episode_seed(self.env_seed(), 0, finished);
                        self.last_game = Some((seed, actions));
                    }
                    self.state.history[i].clear();
                    self.draw_symmetries(i);
                } else {
                    let seat = acting[i] as usize;
                    self.state.history[i].push(joint[i * p + seat]);
                }
            }
        }
        let (adv, returns, value_weight) = if obl {
            // The OBL target is the return of the acting rows; the others learn nothing.
            let target = |i: usize| obl_targets[i].unwrap_or(values[i]);
            let adv = (0..t_len * rows).map(|i| target(i) - values[i]).collect();
            let returns = (0..t_len * rows).map(target).collect();
            let weight = obl_targets
                .iter()
                .map(|x| x.is_some() as u8 as f32)
                .collect();
            (adv, returns, weight)
        } else {
            // Values of the observations after the last step bootstrap the returns; the
            // state reached here is not kept, since the next rollout starts from these
            // observations.
            let mut last_obs = vec![0f32; rows * l];
            let mut last_masks = vec![0f32; rows * na];
            self.view(&mut last_obs, &mut last_masks);
            let last_values = net
                .act(
                    &last_obs,
                    &self.state.hidden,
                    &self.keeps(),
                    &[],
                    &dev,
                    shards,
                )
                .values;
            let (adv, returns) = gae(
                &rewards,
                &values,
                &dones,
                &last_values,
                c.gamma,
                c.gae_lambda,
            );
            (adv, returns, Vec::new())
        };

        Ok(Rollout {
            obs,
            masks,
            actions,
            logps,
            values,
            keeps,
            legal,
            adv,
            returns,
            h0,
            games,
            entropy: if ent_rows > 0 {
                ent_sum / ent_rows as f64
            } else {
                0.0
            },
            cluster_reward,
            end_rewards,
            truth,
            value_weight,
        })
    }
}
