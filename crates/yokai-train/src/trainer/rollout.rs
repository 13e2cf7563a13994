//! The rollout: the actor plays `rollout_steps` steps of every game with the current
//! network, recording what learning needs (observations and masks as each seat saw them,
//! actions, log-probabilities, values, episode starts, the add-ons' columns), then the value
//! targets: GAE over the real rewards, or with Off-Belief Learning the targets of the
//! fictitious continuations computed at each step.

use super::addons::belief_gain::Potentials;
use super::addons::Columns;
use super::Trainer;
use crate::distribution::{sample_row, unit_draw};
use crate::error::TrainError;
use crate::gae::gae;
use crate::network::{shards_on, ActBatch, Acted, ActorCritic, Encoder, Recurrent};
use crate::obl::{self, OblStep, StepInputs};
use burn::module::Module;
use rand_chacha::ChaCha8Rng;
use std::ops::Range;
use yokai_engine::{Action, Game, MetricsAccumulator};

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
    /// With a central critic, every row's true colours per step (`[T × rows × Y·C]`
    /// one-hot), which its value read; empty otherwise.
    pub colours: Vec<f32>,
    /// The games that ended during the rollout.
    pub games: MetricsAccumulator,
    /// Mean entropy of the acting seats' policies.
    pub entropy: f64,
    /// Net change in clustered colours paid by the clustering shaping, unweighted.
    pub cluster_reward: f64,
    /// What the belief-gain reward paid, unweighted (nats; see [`super::UpdateStats`]);
    /// `None` when it is off or has annealed away.
    pub belief_gain: Option<f64>,
    /// The add-ons' columns.
    pub columns: Columns,
    /// With Off-Belief Learning: 1 on the rows whose value target is an OBL target (the
    /// acting seats'), 0 on the others, whose value loss is off (`[T × rows]`). `None`
    /// otherwise: every row learns its value.
    pub value_weight: Option<Vec<f32>>,
}

/// What the rewards phase of a rollout keeps for the value targets.
struct Rewards {
    rewards: Vec<f32>,
    dones: Vec<f32>,
    /// Off-Belief Learning: per step and row, the target of an acting row's action.
    obl: Option<Vec<Option<f32>>>,
}

impl Rollout {
    /// A rollout of `t_len` steps of `rows` rows, observations of `l` floats, masks of
    /// `na`, in the observation and mask buffers of `spare`, the last update's rollout,
    /// when it has one. Every step's [`Actor::view`](crate::actor::Actor::view) writes
    /// every row's observation and mask whole, so the old contents never show; zeroing
    /// fresh buffers (the masks alone 12.7 MB on 9c: 64 games × 2 seats × 32 steps × 777
    /// floats) was 1.4 % of a `cpu-fast` update's CPU samples.
    fn reuse(
        t_len: usize,
        rows: usize,
        (l, na): (usize, usize),
        h0: Vec<f32>,
        spare: Option<Rollout>,
    ) -> Rollout {
        let n = t_len * rows;
        let (mut obs, mut masks) = spare.map_or((Vec::new(), Vec::new()), |r| (r.obs, r.masks));
        obs.resize(n * l, 0.0);
        masks.resize(n * na, 0.0);
        Rollout {
            obs,
            masks,
            actions: vec![0; n],
            logps: vec![0.0; n],
            values: vec![0.0; n],
            keeps: vec![0.0; n],
            legal: vec![0; n],
            adv: Vec::new(),
            returns: Vec::new(),
            h0,
            colours: Vec::new(),
            games: MetricsAccumulator::default(),
            entropy: 0.0,
            cluster_reward: 0.0,
            belief_gain: None,
            columns: Columns::default(),
            value_weight: None,
        }
    }
}

impl<E: Encoder, M: Recurrent> Trainer<E, M> {
    /// Play `rollout_steps` steps in every game with the current network, sampling from
    /// `rng`; `shaping` weighs the shaping reward in the returns.
    pub(super) fn collect(
        &mut self,
        shaping: f64,
        rng: &mut ChaCha8Rng,
    ) -> Result<Rollout, TrainError> {
        let t_len = self.config.ppo.rollout_steps;
        let (rows, na) = (self.actor.rows(), self.actor.n_actions());
        let dims = (self.actor.obs_len(), na);
        let spare = self.spare.take();
        let mut ro = Rollout::reuse(t_len, rows, dims, self.actor.memory.clone(), spare);
        if let Some(end) = &self.addons.end {
            ro.columns.end = end.column(t_len, rows);
        }
        if let Some(belief) = &self.addons.belief {
            ro.columns.truth = Some(belief.column(t_len, rows, self.game.cards()));
        }
        if let Some(gain) = &self.addons.gain {
            ro.columns.potentials = gain.column(self.progress(), t_len, &self.actor);
        }
        let mut kept = Rewards {
            rewards: vec![0.0; t_len * rows],
            dones: vec![0.0; t_len * rows],
            obl: (self.config.obl.level > 0).then(|| vec![None; t_len * rows]),
        };
        let mut cluster =
            (self.addons.cluster.as_ref()).and_then(|unit| unit.start(shaping, &self.actor));
        let net = self.model.valid();
        let end = self.game.encode(Action::End);
        let mut entropy = (0f64, 0u64);
        for t in 0..t_len {
            // Observe and act: every seat reads its view, the choosing seats draw.
            let (joint, acting) = self.act(&net, &mut ro, t, rng, &mut entropy);
            // Off-Belief Learning: the acting rows' targets from fictitious continuations.
            let worlds = match &mut kept.obl {
                Some(targets) => {
                    let step = self.obl_step(&net, t, &joint, shaping as f32)?;
                    for (r, target) in step.targets {
                        targets[t * rows + r] = Some(target);
                    }
                    step.worlds
                }
                None => Vec::new(),
            };
            if let Some(column) = &mut ro.columns.end {
                // Under OBL, what END pays in the world drawn from the seat's belief (the
                // fictitious game its target comes from), never the true one.
                let masks = &ro.masks[t * rows * na..][..rows * na];
                let actor = &self.actor;
                let game = |i: usize| -> &Game { worlds.get(i).unwrap_or_else(|| actor.game(i)) };
                column.record(t, &acting, (masks, na, end), game);
            }
            // Step the games, then read what the step paid.
            self.actor.step(&joint, &acting)?;
            self.tally_rewards(t, shaping, &mut kept, cluster.as_mut(), &mut ro.games);
        }
        ro.entropy = if entropy.1 > 0 {
            entropy.0 / entropy.1 as f64
        } else {
            0.0
        };
        ro.cluster_reward = cluster.map_or(0.0, |c| c.paid);
        self.value_targets(&net, &mut ro, kept);
        if let (Some(gain), Some(paid)) = (&mut self.addons.gain, &ro.columns.potentials) {
            gain.keep(paid);
        }
        Ok(ro)
    }

    /// Step `t` of the rollout's acting: every row reads its view of its game (and with
    /// OBL ≥ 2 the belief's memory too), the network runs on the rows that choose, and every
    /// row draws its action (a waiting seat its NOOP). Returns the rows' true-frame actions
    /// and each game's acting seat; adds the acting seats' entropies to `entropy`.
    fn act(
        &mut self,
        net: &ActorCritic<E, M>,
        ro: &mut Rollout,
        t: usize,
        rng: &mut ChaCha8Rng,
        entropy: &mut (f64, u64),
    ) -> (Vec<u32>, Vec<u8>) {
        let (rows, l, na) = (
            self.actor.rows(),
            self.actor.obs_len(),
            self.actor.n_actions(),
        );
        let p = self.game.players();
        let (o, m) = (
            &mut ro.obs[t * rows * l..][..rows * l],
            &mut ro.masks[t * rows * na..][..rows * na],
        );
        self.actor.view(o, m);
        let keep = self.actor.keeps();
        ro.keeps[t * rows..][..rows].copy_from_slice(&keep);
        if let Some(previous) = &mut self.previous {
            previous.observe(&self.actor, &keep, &self.infer_device);
        }
        // Each row's legal actions lie in its span (its substep's action groups): counting
        // and drawing read those columns only, at most 37 of 777 on 9c off the MOVE
        // substep (740 at it), one for a waiting seat. The other columns are illegal, so
        // the counts and draws are those over the whole row.
        let spans: Vec<Range<usize>> = (0..rows).map(|r| self.actor.legal_span(r)).collect();
        let legal = &mut ro.legal[t * rows..][..rows];
        for (r, count) in legal.iter_mut().enumerate() {
            let mask = &m[r * na..][spans[r].clone()];
            *count = mask.iter().filter(|&&x| x > 0.5).count() as u32;
        }
        // The actor runs on the rows that choose; `chosen` holds their logits in row
        // order. A row with one legal action (a waiting seat's NOOP, a forced move) is
        // drawn from zero logits: its only action has log-prob 0 and entropy 0 whatever
        // its logit, so the draws below are unchanged.
        let choosing: Vec<usize> = (0..rows).filter(|&r| legal[r] > 1).collect();
        let dev = &self.infer_device;
        let acted = self.run_network(
            net,
            (o, &keep, &choosing),
            t,
            ro.columns.potentials.as_mut(),
        );
        if net.critic_is_central() {
            let colours = self.actor.colour_one_hots();
            let values = net.values_of(&acted.states, &colours, dev);
            ro.values[t * rows..][..rows].copy_from_slice(&values);
            ro.colours.extend(colours);
        } else {
            ro.values[t * rows..][..rows].copy_from_slice(&acted.values);
        }
        self.actor.memory = acted.states;
        let acting = self.actor.env().acting_seats().to_vec();
        // Learning reads the belief targets of the rows that choose, which are the acting
        // seats' rows.
        if let Some(truth) = &mut ro.columns.truth {
            truth.record(t, &acting, &self.actor);
        }
        let mut next_chosen = acted.logits.chunks_exact(na);
        let no_choice = vec![0f32; na];
        let mut joint = vec![0u32; rows];
        for r in 0..rows {
            let u = unit_draw(rng);
            let logits = if legal[r] > 1 {
                next_chosen
                    .next()
                    .expect("one row of logits per choosing row")
            } else {
                &no_choice[..]
            };
            let span = spans[r].clone();
            let (a, lp, h) =
                sample_row(&logits[span.clone()], &m[r * na..][span.clone()], u, false);
            let a = span.start + a;
            ro.actions[t * rows + r] = a;
            ro.logps[t * rows + r] = lp;
            if acting[r / p] as usize == r % p {
                entropy.0 += h as f64;
                entropy.1 += 1;
            }
            joint[r] = self.actor.to_true_action(r, a) as u32;
        }
        (joint, acting)
    }

    /// The network's acting step at rollout step `t` (`0..=T`, the last for the values
    /// after the rollout) on every row's observation, with `keep` and the `choosing` rows
    /// as [`ActorCritic::act`] takes them, from the actor's memory. With the belief gain's
    /// `potentials`, it also reads every row's colour layer and records the step's potentials.
    fn run_network(
        &self,
        net: &ActorCritic<E, M>,
        (obs, keep, choosing): (&[f32], &[f32], &[usize]),
        t: usize,
        potentials: Option<&mut Potentials>,
    ) -> Acted {
        let dev = &self.infer_device;
        let batch = ActBatch::new(obs, &self.actor.memory, keep, choosing);
        let acted = net.act_with(batch, potentials.is_some(), dev, shards_on(dev));
        if let Some(potentials) = potentials {
            potentials.record(t, &acted.colour_log_probs, &self.actor);
        }
        acted
    }

    /// OBL's targets of rollout step `t`, given the rows' true-frame actions `joint`.
    pub(super) fn obl_step(
        &self,
        net: &ActorCritic<E, M>,
        t: usize,
        joint: &[u32],
        shaping: f32,
    ) -> Result<OblStep, TrainError> {
        obl::targets(StepInputs {
            config: &self.config,
            seed: self.seed,
            step: self.update * self.config.ppo.rollout_steps as u64 + t as u64,
            actor: &self.actor,
            net,
            device: &self.infer_device,
            previous: self.previous.as_ref(),
            joint,
            shaping,
        })
    }

    /// After the games stepped at `t`: every row's reward (the game's, the annealed
    /// shaping, the clustering add-on's; the belief gain's is added once the rollout's last
    /// potentials are known, in [`Trainer::value_targets`]) and done flag, and the metrics
    /// of the games that ended.
    fn tally_rewards(
        &self,
        t: usize,
        shaping: f64,
        kept: &mut Rewards,
        mut cluster: Option<&mut super::addons::cluster::ClusterTally>,
        games: &mut MetricsAccumulator,
    ) {
        let env = self.actor.env();
        let (rows, p) = (self.actor.rows(), self.game.players());
        for i in 0..env.num_envs() {
            let mut reward = env.rewards()[i] + shaping as f32 * env.shaping()[i];
            let done = env.dones()[i] == 1;
            if let Some(extra) = cluster
                .as_mut()
                .and_then(|c| c.reward(&self.actor, i, done))
            {
                reward += extra;
            }
            for s in 0..p {
                kept.rewards[t * rows + i * p + s] = reward;
                kept.dones[t * rows + i * p + s] = done as u8 as f32;
            }
            if done {
                if let Some(o) = env.outcomes()[i] {
                    games.add(&o);
                }
            }
        }
    }

    /// The rollout's advantages and value targets: with OBL the continuations' targets on
    /// the acting rows (the others learn nothing); else GAE, bootstrapped from the values of
    /// the observations after the last step.
    fn value_targets(&self, net: &ActorCritic<E, M>, ro: &mut Rollout, mut kept: Rewards) {
        if let Some(obl) = kept.obl {
            let target = |i: usize| obl[i].unwrap_or(ro.values[i]);
            let all = 0..ro.values.len();
            ro.adv = all.clone().map(|i| target(i) - ro.values[i]).collect();
            ro.returns = all.map(target).collect();
            ro.value_weight = Some(obl.iter().map(|x| x.is_some() as u8 as f32).collect());
            return;
        }
        // The state reached here is not kept: the next rollout starts from these
        // observations.
        let (last_obs, _) = self.views();
        let dev = &self.infer_device;
        let keep = self.actor.keeps();
        // The belief gain of the rollout's last step reads the potentials after it.
        let t_len = self.config.ppo.rollout_steps;
        let potentials = ro.columns.potentials.as_mut();
        let acted = self.run_network(net, (&last_obs, &keep, &[]), t_len, potentials);
        if let Some(potentials) = &mut ro.columns.potentials {
            ro.belief_gain = Some(potentials.pay(&mut kept.rewards, &kept.dones));
        }
        let last_values = if net.critic_is_central() {
            net.values_of(&acted.states, &self.actor.colour_one_hots(), dev)
        } else {
            acted.values
        };
        let c = &self.config.ppo;
        let (adv, returns) = gae(
            &kept.rewards,
            &ro.values,
            &kept.dones,
            &last_values,
            c.gamma,
            c.gae_lambda,
        );
        (ro.adv, ro.returns) = (adv, returns);
        if let Some(potentials) = &ro.columns.potentials {
            potentials.credit(&mut ro.adv);
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::network::MlpEncoder;
    use crate::trainer::Trainer;
    use crate::TrainConfig;

    /// Two updates of Other-Play with the pointer head (which reads the observations and
    /// every choosing row's mask) on one thread; before the second, `spoil` may write over
    /// the first rollout's buffers that the second reuses. Returns the parameters after.
    fn two_updates(spoil: bool) -> Vec<f32> {
        let mut c = TrainConfig::from_toml_str(
            "[algorithm]\nname = \"op\"\nsymmetries = \"both\"\n\
             [network]\npreset = \"compact\"\nhidden = 16\nhead = \"pointer\"\n\
             [ppo]\nnum_envs = 8\nrollout_steps = 8\nminibatches = 2\n[run]\nthreads = 1\n",
            "test",
        )
        .unwrap();
        c.ppo.total_steps = 64 * 4;
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap();
        pool.install(|| {
            let mut trainer = Trainer::<MlpEncoder>::new(c, 3).unwrap();
            trainer.update().unwrap();
            let spare = trainer.spare.as_mut().expect("the first rollout is kept");
            assert!(!spare.obs.is_empty() && !spare.masks.is_empty());
            if spoil {
                spare.obs.fill(f32::NAN);
                spare.masks.fill(f32::NAN);
            }
            trainer.update().unwrap();
            trainer.parameters()
        })
    }

    /// Runs `f` on one worker thread with a fresh trainer (seed 8) of 4 games of the
    /// compact pointer network, the belief loss and the belief gain at 0.2, `rollout_steps`
    /// steps per rollout and `extra` lines of `[ppo]`.
    fn on_one_thread_with_belief_gain(
        rollout_steps: usize,
        extra: &str,
        f: impl FnOnce(Trainer<MlpEncoder>) + Send,
    ) {
        let c = TrainConfig::from_toml_str(
            &format!(
                "[network]\npreset = \"compact\"\nhidden = 16\nhead = \"pointer\"\n\
                 [ppo]\nnum_envs = 4\nrollout_steps = {rollout_steps}\nminibatches = 1\n\
                 belief_aux = 0.5\nbelief_gain = 0.2\n{extra}[run]\nthreads = 1\n"
            ),
            "test",
        )
        .unwrap();
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap();
        pool.install(|| f(Trainer::<MlpEncoder>::new(c, 8).unwrap()));
    }

    /// The belief gain's potentials are recorded at the states they belong to: at a
    /// rollout's first step every game is at its first state with an empty memory, and
    /// each game's recorded potential is what the colour layer gives the true colours
    /// there, through the seat-by-seat path `yokai probe` uses (`step_seats`, then
    /// `colour_log_probs`), summed over both seats.
    #[test]
    fn a_rollouts_first_potentials_are_the_colour_layers_at_the_first_states() {
        use crate::seen::SeenSeat;
        use burn::module::Module;
        use rand_chacha::rand_core::SeedableRng;
        use yokai_engine::{Card, Seat};
        on_one_thread_with_belief_gain(3, "", |mut trainer| {
            let games: Vec<_> = (0..4).map(|i| trainer.actor.game(i).clone()).collect();
            let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
            let ro = trainer.collect(1.0, &mut rng).unwrap();
            let potentials = ro.columns.potentials.as_ref().expect("recorded");
            let net = trainer.model.valid();
            let device = trainer.infer_device.clone();
            let h = net.hidden_size();
            for (i, game) in games.iter().enumerate() {
                let seats = [(game, Seat(0)), (game, Seat(1))];
                let step = net.step_seats(&seats, vec![0.0; 2 * h], vec![0.0; 2], &device);
                let views = [
                    SeenSeat::plain(game, Seat(0)),
                    SeenSeat::plain(game, Seat(1)),
                ];
                let (lp, colours) = net.colour_log_probs(&views, &step.states, &device).unwrap();
                let y = lp.len() / (2 * colours);
                let expected: f32 = (0..2 * y)
                    .map(|j| {
                        let colour = game.colour_of(Card((j % y) as u8)).0 as usize;
                        lp[j * colours + colour]
                    })
                    .sum();
                let got = potentials.at(0, i);
                assert!(
                    (got - expected).abs() < 1e-3,
                    "game {i}: {got} against {expected}"
                );
            }
        });
    }

    /// The waiting form of the belief gain carries each row's last acting share from one
    /// rollout to the next: after a rollout the trainer holds, for each game's seat that
    /// acted last, the share recorded at that state, and no share for a seat that has not
    /// acted in its current game.
    #[test]
    fn the_waiting_form_carries_the_last_acting_shares_to_the_next_rollout() {
        use rand_chacha::rand_core::SeedableRng;
        on_one_thread_with_belief_gain(5, "belief_gain_seats = \"waiting\"\n", |mut trainer| {
            let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
            let ro = trainer.collect(1.0, &mut rng).unwrap();
            let potentials = ro.columns.potentials.as_ref().expect("recorded");
            let held = trainer.addons.gain.as_ref().expect("on").held();
            assert_eq!(held.len(), trainer.actor.rows());
            // The last paid step is 4: the seat acting there holds its share at step 4,
            // unless that step ended its game (an END), after which neither seat holds any.
            let mut carried = 0;
            for i in 0..4 {
                let r = i * 2 + potentials.acting_at(4, i) as usize;
                match held[r] {
                    Some(share) => {
                        assert_eq!(share, potentials.share_at(4, r), "game {i}");
                        carried += 1;
                    }
                    None => assert_eq!(held[i * 2..][..2], [None, None], "game {i}"),
                }
            }
            assert!(carried > 0, "some game went on past step 4");
        });
    }

    /// The next update writes over the last rollout's observation and mask buffers, so
    /// nothing they held shows: with every float of them NaN before the second update it
    /// learns the same parameters, bit for bit, and they are finite.
    #[test]
    fn what_a_reused_rollout_held_never_shows() {
        let (kept, spoiled) = (two_updates(false), two_updates(true));
        assert!(kept.iter().all(|p| p.is_finite()));
        assert_eq!(kept, spoiled);
    }
}
