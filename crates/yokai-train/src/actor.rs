//! The actor: the batched games, the symmetry each seat sees its game through, every seat's
//! memory, and each game's actions so far. It shows the network what every seat sees and
//! steps the games with the seats' choices; it knows nothing of learning. The trainer plays
//! through it, and so does Python's `yokai.TrainEnv`, so a trainer written in another
//! framework sees the games, the Other-Play symmetries and the centralised-training
//! columns exactly as this one does.

use crate::config::{ColourNames, TrainConfig};
use crate::distribution::unit_of;
use crate::error::TrainError;
use crate::seen::see_through;
use std::ops::Range;
use yokai_engine::{
    derive_seed, Action, Card, ColourLabels, Config, EpisodeRecord, Game, RecordedGame, Seat,
    Symmetry,
};
use yokai_vec::{episode_seed, Encoding, VecEnv, VecEnvOptions};

/// The seed of a run's batch of games.
fn env_seed(run_seed: u64) -> u64 {
    derive_seed(run_seed, 0xE5)
}

/// The seats of `game` (one [`ColourLabels`] and one row symmetry each, in seat order)
/// note the colours they see after its latest step. Where a seat's names change (and
/// always with `fresh` names), its row's symmetry takes them, its rotation kept: views and
/// belief targets then read the names from the row's symmetry, built once per change
/// rather than once per row and step.
fn note_colours(
    seats: &mut [ColourLabels],
    row_sym: &mut [(Symmetry, Symmetry)],
    game: &Game,
    fresh: bool,
) {
    for (s, (l, sym)) in seats.iter_mut().zip(row_sym).enumerate() {
        if l.update(&game.view(Seat(s as u8))) || fresh {
            let named = l.symmetry(game.config(), sym.0);
            *sym = (named, named.inverse());
        }
    }
}

/// The games of one run, as its seats see and play them. Row `r` of every buffer is seat
/// `r % P` of game `r / P`.
pub struct Actor {
    env: VecEnv<f32>,
    game: Config,
    /// The run's seed: each seat's symmetry is drawn from it per episode.
    seed: u64,
    /// The seed the batch of games was dealt from (a function of the run's seed).
    env_seed: u64,
    encoding: Encoding,
    /// The symmetries a seat may draw (identity only without Other-Play).
    symmetries: Vec<Symmetry>,
    /// Steps taken in every game so far (all games step together).
    steps: u64,
    /// `obl.symmetries_ramp` ([`TrainConfig::symmetry_ramp_steps`]): over this many steps
    /// the share of games dealt with drawn symmetries grows from 0 to 1; `None`: every game.
    ramp_steps: Option<u64>,
    /// Per row: the seat's symmetry this episode and its inverse. With colour names of its
    /// own (`labels`), the symmetry's colour permutation is the seat's names so far.
    row_sym: Vec<(Symmetry, Symmetry)>,
    /// With `network.colours` other than `dealt`, per row: the seat's colour names so far
    /// this episode, which replace its symmetry's colour permutation (they name the colours
    /// whatever the deal or a permutation called them).
    labels: Option<Vec<ColourLabels>>,
    /// Every row's recurrent memory `[rows × H]`, after the last observation it read.
    pub memory: Vec<f32>,
    /// Per game: the acting seats' actions so far in its current episode.
    pub history: Vec<Vec<u32>>,
    /// The last finished game of env 0 (deal seed, actions), to save as a replay.
    last_game: Option<(u64, Vec<u32>)>,
    obs_len: usize,
    n_actions: usize,
}

impl Actor {
    /// The games of a run of `config` with `seed`: `ppo.num_envs` games dealt from the
    /// run's seed, read in `encoding`, each seat seeing its game through a symmetry drawn
    /// from `algorithm.symmetries` per episode, every memory of width `hidden` zeroed.
    pub fn for_run(
        config: &TrainConfig,
        seed: u64,
        encoding: Encoding,
        hidden: usize,
    ) -> Result<Actor, TrainError> {
        let game = config.game_config()?;
        let mut options = VecEnvOptions::new(config.ppo.num_envs, env_seed(seed));
        options.encoding = encoding;
        options.threads = (config.run.threads > 0).then_some(config.run.threads);
        let env = VecEnv::<f32>::new(game, options)?;
        let s = config.algorithm.symmetries;
        let symmetries = Symmetry::enumerate(&game, s.colours(), s.rotations(), false);
        Ok(Actor::new(
            env,
            seed,
            env_seed(seed),
            symmetries,
            config.symmetry_ramp_steps(),
            config.network.colours,
            hidden,
        ))
    }

    /// Bring the symmetries in over `ramp_steps` steps per game (`None`: in every game),
    /// for the games dealt from now on (a run whose budget changes).
    pub fn set_symmetry_ramp(&mut self, ramp_steps: Option<u64>) {
        self.ramp_steps = ramp_steps;
    }

    /// `env`'s games seen through `symmetries` (each seat draws one per episode from
    /// `seed`; brought in over `ramp_steps` steps when given, [`Actor::set_symmetry_ramp`])
    /// with its colours named as `colours` says, every memory of width `hidden` zeroed.
    pub fn new(
        env: VecEnv<f32>,
        seed: u64,
        env_seed: u64,
        symmetries: Vec<Symmetry>,
        ramp_steps: Option<u64>,
        colours: ColourNames,
        hidden: usize,
    ) -> Actor {
        let game = *env.config();
        let encoding = env.encoding();
        let (n, p) = (env.num_envs(), game.players());
        let identity = Symmetry::identity(&game);
        let mut actor = Actor {
            obs_len: encoding.shape(&game).iter().product(),
            n_actions: game.num_actions(),
            game,
            seed,
            env_seed,
            encoding,
            symmetries,
            steps: 0,
            ramp_steps,
            row_sym: vec![(identity, identity); n * p],
            labels: colours
                .naming()
                .map(|naming| vec![ColourLabels::new(&game, 0, naming); n * p]),
            memory: vec![0.0; n * p * hidden],
            history: vec![Vec::new(); n],
            last_game: None,
            env,
        };
        for i in 0..n {
            actor.draw_symmetries(i);
        }
        actor
    }

    pub fn env(&self) -> &VecEnv<f32> {
        &self.env
    }
    pub fn game(&self, i: usize) -> &Game {
        self.env.game(i)
    }
    /// Rows of the batch: every seat of every game.
    pub fn rows(&self) -> usize {
        self.row_sym.len()
    }
    /// Length of one row's observation.
    pub fn obs_len(&self) -> usize {
        self.obs_len
    }
    pub fn n_actions(&self) -> usize {
        self.n_actions
    }

    /// Where row `row`'s legal actions lie in its mask: [`Game::legal_span`] of its game
    /// and seat (the acting seat's substep's action groups, a waiting seat's NOOP). A
    /// symmetry moves an action only within its group (a card's MOVEs among the cells), so
    /// the span of the seat's view is the span of the true game; outside it the mask
    /// [`Actor::view`] writes is zero, and a sampler need not read there.
    pub fn legal_span(&self, row: usize) -> Range<usize> {
        let p = self.game.players();
        self.env.game(row / p).legal_span(Seat((row % p) as u8))
    }

    /// The symmetry row `row` sees its game through: its Other-Play symmetry, with its
    /// colour permutation replaced by the seat's own colour names where the network reads
    /// those (`network.colours`).
    pub fn symmetry(&self, row: usize) -> Symmetry {
        self.row_sym[row].0
    }

    /// Every row's [`Actor::symmetry`], in row order: how each seat sees its game this
    /// episode, for stepping networks on its states outside the batch (OBL).
    pub fn symmetries(&self) -> Vec<Symmetry> {
        self.row_sym.iter().map(|s| s.0).collect()
    }

    /// Whether game `env`'s current episode (drawing from `episode_stream`) sees through
    /// drawn symmetries: always without a ramp; with one, when the episode's own uniform
    /// falls under the share at the step it was dealt, which its actions so far date.
    fn draws_symmetries(&self, env: usize, episode_stream: u64) -> bool {
        let Some(ramp) = self.ramp_steps else {
            return true;
        };
        let dealt_at = self.steps.saturating_sub(self.history[env].len() as u64);
        unit_of(derive_seed(episode_stream, 0x200)) < (dealt_at as f64 / ramp as f64).min(1.0)
    }

    /// Other-Play: each seat of game `env` draws its own symmetry for the game's current
    /// episode, a function of (seed, env, episode, seat). With a ramp, the game first
    /// decides whether its seats draw at all (by the share when it was dealt, which its
    /// actions so far date), else each seat keeps the identity.
    fn draw_symmetries(&mut self, env: usize) {
        let p = self.game.players();
        let k = self.symmetries.len() as u64;
        let episode_stream = derive_seed(
            derive_seed(derive_seed(self.seed, 0x0B), env as u64),
            self.env.episodes(env),
        );
        let draws = self.draws_symmetries(env, episode_stream);
        let identity = Symmetry::identity(&self.game);
        for s in 0..p {
            let pick = derive_seed(episode_stream, s as u64) % k;
            let sym = if draws {
                self.symmetries[pick as usize]
            } else {
                identity
            };
            self.row_sym[env * p + s] = (sym, sym.inverse());
        }
        if let Some(labels) = &mut self.labels {
            let seats = &mut labels[env * p..][..p];
            for (s, l) in seats.iter_mut().enumerate() {
                *l = ColourLabels::new(
                    &self.game,
                    derive_seed(episode_stream, 0x100 + s as u64),
                    l.naming(),
                );
            }
            let syms = &mut self.row_sym[env * p..][..p];
            note_colours(seats, syms, self.env.game(env), true);
        }
    }

    /// With `network.colours` other than `dealt`: the colour names of row `row`'s seat so
    /// far this episode.
    pub fn colour_labels(&self, row: usize) -> Option<ColourLabels> {
        self.labels.as_ref().map(|l| l[row])
    }

    /// Every row's observation and legal mask as its seat sees them (its symmetry applied).
    pub fn view(&self, obs: &mut [f32], masks: &mut [f32]) {
        let (l, na) = (self.obs_len, self.n_actions);
        let src_obs = self.env.observations();
        let src_masks = self.env.legal_masks();
        let mut mask_f = vec![0f32; na];
        for (r, (sym, _)) in self.row_sym.iter().enumerate() {
            let o_in = &src_obs[r * l..][..l];
            let o_out = &mut obs[r * l..][..l];
            let (m_in, m_out) = (&src_masks[r * na..][..na], &mut masks[r * na..][..na]);
            let as_float = |out: &mut [f32]| {
                for (m, &b) in out.iter_mut().zip(m_in) {
                    *m = b as f32;
                }
            };
            if sym.is_identity() {
                o_out.copy_from_slice(o_in);
                as_float(m_out);
                continue;
            }
            as_float(&mut mask_f);
            see_through(sym, &self.game, self.encoding, o_in, o_out);
            sym.apply_mask(&self.game, &mask_f, m_out)
                .expect("buffers sized from the same config");
        }
    }

    /// The true colour of every card of `row`'s game, named as the row's seat sees colours
    /// (its symmetry's relabelling applied).
    pub fn view_truth(&self, row: usize, out: &mut [u8]) {
        let game = self.env.game(row / self.game.players());
        let sym = self.row_sym[row].0;
        for (k, colour) in out.iter_mut().enumerate() {
            *colour = sym.map_colour(game.colour_of(Card(k as u8))).0;
        }
    }

    /// Every row's [`Actor::view_truth`] one-hot over the colours: `[rows × Y·C]`, what a
    /// central critic reads.
    pub fn colour_one_hots(&self) -> Vec<f32> {
        let (y, c) = (self.game.cards(), self.game.colours());
        let mut colours = vec![0u8; y];
        let mut out = vec![0f32; self.rows() * y * c];
        for (r, row) in out.chunks_exact_mut(y * c).enumerate() {
            self.view_truth(r, &mut colours);
            for (card, &colour) in colours.iter().enumerate() {
                row[card * c + colour as usize] = 1.0;
            }
        }
        out
    }

    /// Per row: 0 where the row's next step starts an episode (its game has no step yet),
    /// which zeroes that row's recurrent state, else 1.
    pub fn keeps(&self) -> Vec<f32> {
        let p = self.game.players();
        (0..self.rows())
            .map(|r| (self.env.game(r / p).steps() > 0) as u8 as f32)
            .collect()
    }

    /// What END would pay in each game now (`Game::end_reward`, the game's R if its acting
    /// seat ended it), where the acting seat may END; 0 where it may not. What the END term
    /// of `ppo.end_lookahead` reads.
    pub fn end_rewards(&self) -> Vec<f32> {
        let end = self.game.encode(Action::End);
        let (na, p) = (self.n_actions, self.game.players());
        let masks = self.env.legal_masks();
        (0..self.env.num_envs())
            .map(|i| {
                let row = i * p + self.env.acting_seats()[i] as usize;
                if masks[row * na + end] == 1 {
                    self.env.game(i).end_reward() as f32
                } else {
                    0.0
                }
            })
            .collect()
    }

    /// Map a row's chosen action from its seat's view back to the true game.
    pub fn to_true_action(&self, row: usize, view_action: usize) -> usize {
        self.row_sym[row]
            .1
            .apply_action_index(&self.game, view_action)
    }

    /// Step every game with the rows' true-frame actions `joint`, `acting[i]` the seat
    /// that acts in game `i` (as read before the step). A game that ends is dealt again
    /// (its seats draw new symmetries); the last finished game of env 0 is kept as a replay.
    pub fn step(&mut self, joint: &[u32], acting: &[u8]) -> Result<(), yokai_vec::VecError> {
        let p = self.game.players();
        self.env.step_joint(joint)?;
        self.steps += 1;
        for (i, &seat) in acting.iter().enumerate() {
            let action = joint[i * p + seat as usize];
            if self.env.dones()[i] == 1 {
                if i == 0 {
                    let mut actions = std::mem::take(&mut self.history[0]);
                    actions.push(action);
                    // The environment has already moved on to the next episode.
                    let finished = self.env.episodes(0) - 1;
                    self.last_game = Some((episode_seed(self.env_seed, 0, finished), actions));
                }
                self.history[i].clear();
                self.draw_symmetries(i);
            } else {
                self.history[i].push(action);
                if let Some(labels) = &mut self.labels {
                    let syms = &mut self.row_sym[i * p..][..p];
                    note_colours(&mut labels[i * p..][..p], syms, self.env.game(i), false);
                }
            }
        }
        Ok(())
    }

    /// The learner's memory of `seat` in game `i` after it read this step's observation.
    pub fn memory_of(&self, i: usize, seat: Seat) -> &[f32] {
        let hsz = self.memory.len() / self.rows();
        let row = i * self.game.players() + seat.index();
        &self.memory[row * hsz..][..hsz]
    }

    /// The first state of game `i`'s current episode (its deal) and the actions since.
    pub fn episode_so_far(&self, i: usize) -> (Game, &[u32]) {
        let seed = episode_seed(self.env_seed, i, self.env.episodes(i));
        (Game::new(self.game, seed), &self.history[i])
    }

    /// Each game's episode index.
    pub fn episodes(&self) -> Vec<u64> {
        (0..self.env.num_envs())
            .map(|i| self.env.episodes(i))
            .collect()
    }

    /// Put every game back where a checkpoint left it, `steps` steps into the run: game `i`
    /// in episode `episodes[i]` after `history[i]`, with `memory` as every row's memory.
    pub fn restore(
        &mut self,
        steps: u64,
        episodes: &[u64],
        history: Vec<Vec<u32>>,
        memory: Vec<f32>,
    ) -> Result<(), yokai_vec::VecError> {
        for (i, actions) in history.iter().enumerate() {
            self.env.restore(i, episodes[i], actions)?;
        }
        self.history = history;
        self.memory = memory;
        self.steps = steps;
        for i in 0..self.env.num_envs() {
            self.draw_symmetries(i);
            self.replay_colours(i);
        }
        Ok(())
    }

    /// With colour names of their own: game `i`'s seats name the colours of its current
    /// episode as they did when it was played, by replaying it from its deal (the names
    /// follow the episode step by step, so the game as it stands is not enough).
    fn replay_colours(&mut self, i: usize) {
        let Some(mut labels) = self.labels.take() else {
            return;
        };
        let p = self.game.players();
        let (mut game, actions) = self.episode_so_far(i);
        let actions = actions.to_vec();
        let (seats, syms) = (&mut labels[i * p..][..p], &mut self.row_sym[i * p..][..p]);
        for l in seats.iter_mut() {
            *l = l.restart();
        }
        note_colours(seats, syms, &game, true);
        for a in actions {
            game.apply_index(a as usize)
                .expect("actions the environment has just replayed");
            note_colours(seats, syms, &game, false);
        }
        self.labels = Some(labels);
    }

    /// The last game of env 0 that finished, as played in training (deal and actions).
    pub fn last_finished_game(&self) -> Option<EpisodeRecord> {
        let (seed, actions) = self.last_game.as_ref()?;
        let mut game = RecordedGame::new(self.game, *seed);
        for &a in actions {
            let action = self.game.decode(a as usize).expect("an index of this game");
            game.apply(action)
                .expect("actions recorded from the environment are legal");
        }
        Some(game.into_record())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::network::{Encoder, MlpEncoder};
    use rand_chacha::rand_core::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// Under Other-Play's symmetries (colours and rotations) and colour names of the seats'
    /// own, every row's view of its legal mask is zero outside [`Actor::legal_span`] and has
    /// a legal action inside it, over random play on 9c-2p and 16c-3p: what lets the
    /// rollout count and draw over the span alone.
    #[test]
    fn every_rows_legal_actions_lie_in_its_span() {
        for (game, colours) in [("9c-2p-perfect", "first-seen"), ("16c-3p", "dealt")] {
            let config = TrainConfig::from_toml_str(
                &format!(
                    "game = \"{game}\"\n[algorithm]\nname = \"op\"\nsymmetries = \"both\"\n\
                     [network]\ncolours = \"{colours}\"\n[ppo]\nnum_envs = 6\n[run]\nthreads = 1\n"
                ),
                "test",
            )
            .unwrap();
            let mut actor = Actor::for_run(&config, 3, MlpEncoder::encoding(), 4).unwrap();
            let na = actor.n_actions();
            let mut rng = ChaCha8Rng::seed_from_u64(11);
            let (mut narrow, mut wide) = (0, 0);
            for _ in 0..400 {
                step_randomly(&mut actor, &mut rng, |r, legal, span| {
                    assert!(!legal.is_empty(), "{game}: row {r} has no legal action");
                    assert!(
                        legal.iter().all(|a| span.contains(a)),
                        "{game}: row {r}'s legal actions {legal:?} leave its span {span:?}"
                    );
                    if span.len() < na / 2 {
                        narrow += 1;
                    } else {
                        wide += 1;
                    }
                });
            }
            // Both kinds of span were met: waiting seats and substeps off MOVE, and MOVE.
            assert!(
                narrow > 0 && wide > 0,
                "{game}: {narrow} narrow, {wide} wide spans"
            );
        }
    }

    /// One step of every game, each row playing a uniformly random legal action of its
    /// view, after `look(row, the view's legal actions, the row's legal span)`.
    fn step_randomly(
        actor: &mut Actor,
        rng: &mut ChaCha8Rng,
        mut look: impl FnMut(usize, &[usize], Range<usize>),
    ) {
        let (rows, na) = (actor.rows(), actor.n_actions());
        let (mut obs, mut masks) = (vec![0f32; rows * actor.obs_len()], vec![0f32; rows * na]);
        actor.view(&mut obs, &mut masks);
        let mut joint = vec![0u32; rows];
        for (r, action) in joint.iter_mut().enumerate() {
            let mask = &masks[r * na..][..na];
            let legal: Vec<usize> = (0..na).filter(|&a| mask[a] > 0.5).collect();
            look(r, &legal, actor.legal_span(r));
            let a = legal[(rng.next_u64() % legal.len() as u64) as usize];
            *action = actor.to_true_action(r, a) as u32;
        }
        let acting = actor.env().acting_seats().to_vec();
        actor.step(&joint, &acting).unwrap();
    }

    /// Random play of `actor` for `steps` steps; per game dealt (its step, whether any of
    /// its seats drew a symmetry other than the identity).
    fn play_randomly(actor: &mut Actor, steps: usize, rng: &mut ChaCha8Rng) -> Vec<(u64, bool)> {
        let (rows, p) = (actor.rows(), actor.game.players());
        let drawn =
            |actor: &Actor, i: usize| (0..p).any(|s| !actor.symmetry(i * p + s).is_identity());
        let mut deals: Vec<(u64, bool)> = (0..rows / p).map(|i| (0, drawn(actor, i))).collect();
        for _ in 0..steps {
            step_randomly(actor, rng, |_, _, _| {});
            for i in 0..rows / p {
                if actor.history[i].is_empty() {
                    deals.push((actor.steps, drawn(actor, i)));
                }
            }
        }
        deals
    }

    /// `obl.symmetries_ramp`: at the switch level the games dealt at the start play without
    /// symmetries, the share drawing them grows with the step they are dealt at, every game
    /// dealt after the ramp draws as without one; and a game restored mid-episode sees
    /// through the symmetries it was dealt with, as a resumed run must.
    #[test]
    fn the_symmetry_ramp_brings_the_symmetries_in_by_the_step_a_game_is_dealt() {
        // 200 updates of 4 steps per game: the ramp covers the first 400 steps.
        let text = |level: u32| {
            format!(
                "game = \"9c-2p-perfect\"\n[algorithm]\nname = \"op\"\nsymmetries = \"both\"\n\
                 [ppo]\nnum_envs = 64\nrollout_steps = 4\ntotal_steps = 51200\n[run]\nthreads = 1\n\
                 [obl]\nlevel = {level}\nprevious = \"below\"\nsymmetries_from_level = 4\n\
                 symmetries_ramp = 0.5\n"
            )
        };
        let config = TrainConfig::from_toml_str(&text(4), "test").unwrap();
        assert_eq!(config.symmetry_ramp_steps(), Some(400));
        let above = TrainConfig::from_toml_str(&text(5), "test").unwrap();
        assert_eq!(
            above.symmetry_ramp_steps(),
            None,
            "a level above the switch"
        );

        let mut actor = Actor::for_run(&config, 5, MlpEncoder::encoding(), 4).unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(2);
        let mut deals = play_randomly(&mut actor, 250, &mut rng);
        // Mid-ramp and mid-episode: a copy restored from the loop state draws alike.
        let mut copy = Actor::for_run(&config, 5, MlpEncoder::encoding(), 4).unwrap();
        let (episodes, history) = (actor.episodes(), actor.history.clone());
        copy.restore(actor.steps, &episodes, history, actor.memory.clone())
            .unwrap();
        assert_eq!(copy.symmetries(), actor.symmetries());
        assert!(actor.history.iter().any(|h| !h.is_empty()));
        deals.extend(play_randomly(&mut actor, 550, &mut rng));

        let share = |from: u64, to: u64| {
            let d: Vec<bool> = deals
                .iter()
                .filter(|(at, _)| (from..to).contains(at))
                .map(|&(_, drawn)| drawn)
                .collect();
            assert!(d.len() >= 100, "{} games dealt in {from}..{to}", d.len());
            d.iter().filter(|&&x| x).count() as f64 / d.len() as f64
        };
        assert!(
            deals[..64].iter().all(|&(_, drawn)| !drawn),
            "dealt at step 0"
        );
        let (early, middle, after) = (share(0, 80), share(160, 240), share(400, 800));
        assert!(
            early < 0.25,
            "share dealt in the ramp's first fifth: {early}"
        );
        assert!(
            (0.3..0.7).contains(&middle),
            "share dealt in the ramp's middle fifth: {middle}"
        );
        assert!(after > 0.95, "share dealt after the ramp: {after}");
    }
}
