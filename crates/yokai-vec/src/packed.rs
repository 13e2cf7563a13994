//! Games whose state the caller keeps, as packed bytes ([`yokai_engine::PACKED_LEN`] per
//! game): reset, step and observe a batch of them on the worker threads.
//!
//! Why: a JAX training loop keeps the environment's state in a pytree and calls out to Rust
//! once per step for the whole batch; between calls nothing is kept here, so each call is a
//! pure function of its inputs. A game's deals come from a *stream* seed as in [`VecEnv`]:
//! episode `e` of stream `s` is dealt from `derive_seed(s, e)`, so the stream
//! `derive_seed(seed, i)` plays exactly the games of env `i` of a [`VecEnv`] seeded with
//! `seed` (a test steps both side by side).
//!
//! An illegal action does not fail the call (inside a jitted loop there is nobody to catch
//! it): that game is left as it was, with `illegal = 1`, reward 0 and not done. Waiting
//! seats must submit NOOP (index 0) as in [`VecEnv::step_joint`]. Bytes that are not a
//! packed game of the config are an error naming the game.
//!
//! [`VecEnv`]: crate::VecEnv
//! [`VecEnv::step_joint`]: crate::VecEnv::step_joint

use crate::{Encoding, VecError};
use rayon::prelude::*;
use yokai_engine::{derive_seed, Config, Game, Scalar, Seat, PACKED_LEN};

/// Games per work item, as [`crate::VecEnvOptions::chunk`].
const CHUNK: usize = 32;

/// Where a batch call writes, for `n` games of `P` seats and `N_a` actions. Every slice is
/// checked against `n` first; the call then fills all of them.
pub struct PackedBuffers<'a, T> {
    /// `[n, PACKED_LEN]`: the games after the call.
    pub states: &'a mut [u8],
    /// `[n]`: the episode each game is in (a reset starts at 0; an auto-reset adds 1).
    pub episodes: &'a mut [u32],
    /// `[n, P, …]`: each seat's observation in the encoding.
    pub observations: &'a mut [T],
    /// `[n, P, N_a]`: 1 where the seat may play the action.
    pub masks: &'a mut [u8],
    /// `[n]`: the seat to act.
    pub acting: &'a mut [u8],
    /// `[n]`: R on the step a game ends, else 0.
    pub rewards: &'a mut [f32],
    /// `[n]`: the step's shaping reward.
    pub shaping: &'a mut [f32],
    /// `[n]`: 1 on the step a game ends.
    pub dones: &'a mut [u8],
    /// `[n]`: 1 where the submitted actions were not legal (the game did not change).
    pub illegal: &'a mut [u8],
}

/// Owned buffers for `n` games, for callers that hand each call's results over whole (the
/// Python binding returns them as new arrays).
pub struct PackedOutputs<T> {
    pub states: Vec<u8>,
    pub episodes: Vec<u32>,
    pub observations: Vec<T>,
    pub masks: Vec<u8>,
    pub acting: Vec<u8>,
    pub rewards: Vec<f32>,
    pub shaping: Vec<f32>,
    pub dones: Vec<u8>,
    pub illegal: Vec<u8>,
}

impl<T: Scalar> PackedOutputs<T> {
    pub fn new(games: &PackedGames, n: usize) -> PackedOutputs<T> {
        let p = games.config().players();
        PackedOutputs {
            states: vec![0; n * PACKED_LEN],
            episodes: vec![0; n],
            observations: vec![T::ZERO; n * p * games.observation_len()],
            masks: vec![0; n * p * games.config().num_actions()],
            acting: vec![0; n],
            rewards: vec![0.0; n],
            shaping: vec![0.0; n],
            dones: vec![0; n],
            illegal: vec![0; n],
        }
    }

    /// Views of these buffers for one call.
    pub fn buffers(&mut self) -> PackedBuffers<'_, T> {
        PackedBuffers {
            states: &mut self.states,
            episodes: &mut self.episodes,
            observations: &mut self.observations,
            masks: &mut self.masks,
            acting: &mut self.acting,
            rewards: &mut self.rewards,
            shaping: &mut self.shaping,
            dones: &mut self.dones,
            illegal: &mut self.illegal,
        }
    }
}

/// One game's share of [`PackedBuffers`].
struct One<'b, T> {
    state: &'b mut [u8],
    episode: &'b mut u32,
    observations: &'b mut [T],
    masks: &'b mut [u8],
    acting: &'b mut u8,
    reward: &'b mut f32,
    shaping: &'b mut f32,
    done: &'b mut u8,
    illegal: &'b mut u8,
}

/// The batch calls' fixed inputs.
#[derive(Clone, Copy, Debug)]
pub struct PackedGames {
    config: Config,
    encoding: Encoding,
    obs_len: usize,
}

/// What a step does with a game that ends.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AutoReset {
    /// Deal the stream's next episode in its place (the observations show the new game).
    Yes,
    /// Keep the finished game (any further action is illegal).
    No,
}

impl PackedGames {
    /// Batches of `config` observed in `encoding`. The graph encodings are refused: their
    /// adjacency is a second buffer per game that this interface does not carry.
    pub fn new(config: Config, encoding: Encoding) -> Result<PackedGames, VecError> {
        if matches!(encoding, Encoding::Graph(_)) {
            return Err(VecError::PackedEncoding);
        }
        Ok(PackedGames {
            config,
            encoding,
            obs_len: encoding.len(&config),
        })
    }

    pub fn config(&self) -> &Config {
        &self.config
    }

    /// Values in one seat's observation.
    pub fn observation_len(&self) -> usize {
        self.obs_len
    }

    /// Deal episode 0 of every stream (`streams[i]` for game i).
    pub fn reset<T: Scalar>(
        &self,
        streams: &[u64],
        out: PackedBuffers<'_, T>,
    ) -> Result<(), VecError> {
        self.each(streams.len(), out, |i, one| {
            let game = Game::new(self.config, derive_seed(streams[i], 0));
            *one.episode = 0;
            self.write(&game, one, 0, 0, false, false);
            Ok(())
        })
    }

    /// Step every game with one action per seat (`actions[i·P + s]`, NOOP = 0 for the
    /// waiting seats). `episodes[i]` is the episode game i is in; with [`AutoReset::Yes`] a
    /// game that ends is replaced by episode `episodes[i] + 1` of `streams[i]`.
    pub fn step<T: Scalar>(
        &self,
        states: &[u8],
        streams: &[u64],
        episodes: &[u32],
        actions: &[u32],
        reset: AutoReset,
        out: PackedBuffers<'_, T>,
    ) -> Result<(), VecError> {
        let n = streams.len();
        let p = self.config.players();
        check_len("states", n * PACKED_LEN, states.len())?;
        check_len("episodes", n, episodes.len())?;
        check_len("actions (one per game and seat)", n * p, actions.len())?;
        self.each(n, out, |i, one| {
            let mut game = self.unpack(states, i)?;
            let actions = &actions[i * p..][..p];
            let mut episode = episodes[i];
            let Some(action) = self.legal_action(&game, actions) else {
                *one.episode = episode;
                self.write(&game, one, 0, 0, false, true);
                return Ok(());
            };
            let step = game.apply_unchecked(action);
            if step.done && reset == AutoReset::Yes {
                episode = episode.wrapping_add(1);
                game = Game::new(self.config, derive_seed(streams[i], episode as u64));
            }
            *one.episode = episode;
            self.write(&game, one, step.reward, step.shaping, step.done, false);
            Ok(())
        })
    }

    /// Observations, masks and acting seats of the games as they are (rewards 0, not done,
    /// episodes as given).
    pub fn observe<T: Scalar>(
        &self,
        states: &[u8],
        episodes: &[u32],
        out: PackedBuffers<'_, T>,
    ) -> Result<(), VecError> {
        let n = episodes.len();
        check_len("states", n * PACKED_LEN, states.len())?;
        self.each(n, out, |i, one| {
            let game = self.unpack(states, i)?;
            *one.episode = episodes[i];
            self.write(&game, one, 0, 0, false, false);
            Ok(())
        })
    }

    fn unpack(&self, states: &[u8], i: usize) -> Result<Game, VecError> {
        Game::unpack(self.config, &states[i * PACKED_LEN..][..PACKED_LEN])
            .map_err(|source| VecError::Packed { env: i, source })
    }

    /// The acting seat's action if every seat's submission is legal.
    fn legal_action(&self, game: &Game, actions: &[u32]) -> Option<yokai_engine::Action> {
        let acting = game.current_seat().index();
        let waiting_noop = (0..actions.len()).all(|s| s == acting || actions[s] == 0);
        let action = self.config.decode(actions[acting] as usize).ok()?;
        (waiting_noop && game.check(Seat(acting as u8), action).is_ok()).then_some(action)
    }

    fn write<T: Scalar>(
        &self,
        game: &Game,
        one: One<'_, T>,
        reward: i32,
        shaping: i32,
        done: bool,
        illegal: bool,
    ) {
        one.state.copy_from_slice(&game.pack());
        *one.acting = game.current_seat().0;
        *one.reward = reward as f32;
        *one.shaping = shaping as f32;
        *one.done = done as u8;
        *one.illegal = illegal as u8;
        let n_a = self.config.num_actions();
        for s in 0..self.config.players() {
            let seat = Seat(s as u8);
            self.encoding
                .write(
                    game,
                    seat,
                    &mut one.observations[s * self.obs_len..][..self.obs_len],
                )
                .expect("buffers are sized from the same config");
            game.write_legal_mask(seat, &mut one.masks[s * n_a..][..n_a]);
        }
    }

    /// Check `out` against `n` games, then run `work` for each game on the worker threads;
    /// the error of the lowest-numbered game that failed, if any.
    fn each<T: Scalar>(
        &self,
        n: usize,
        out: PackedBuffers<'_, T>,
        work: impl Fn(usize, One<'_, T>) -> Result<(), VecError> + Sync,
    ) -> Result<(), VecError> {
        let p = self.config.players();
        let n_a = self.config.num_actions();
        let per_obs = p * self.obs_len;
        check_len("states out", n * PACKED_LEN, out.states.len())?;
        check_len("episodes out", n, out.episodes.len())?;
        check_len("observations", n * per_obs, out.observations.len())?;
        check_len("masks", n * p * n_a, out.masks.len())?;
        for (what, len) in [
            ("acting", out.acting.len()),
            ("rewards", out.rewards.len()),
            ("shaping", out.shaping.len()),
            ("dones", out.dones.len()),
            ("illegal", out.illegal.len()),
        ] {
            check_len(what, n, len)?;
        }
        // Zero-size observations (encoding `none`) still need one chunk per chunk of games.
        let mut empty = vec![T::ZERO; n.div_ceil(CHUNK) * usize::from(per_obs == 0)];
        let (obs, obs_chunk) = match per_obs {
            0 => (&mut empty[..], 1),
            _ => (&mut *out.observations, CHUNK * per_obs),
        };
        let failures: Vec<VecError> = out
            .states
            .par_chunks_mut(CHUNK * PACKED_LEN)
            .zip(out.episodes.par_chunks_mut(CHUNK))
            .zip(obs.par_chunks_mut(obs_chunk))
            .zip(out.masks.par_chunks_mut(CHUNK * p * n_a))
            .zip(out.acting.par_chunks_mut(CHUNK))
            .zip(out.rewards.par_chunks_mut(CHUNK))
            .zip(out.shaping.par_chunks_mut(CHUNK))
            .zip(out.dones.par_chunks_mut(CHUNK))
            .zip(out.illegal.par_chunks_mut(CHUNK))
            .enumerate()
            .filter_map(
                |(
                    chunk,
                    (
                        (((((((states, episodes), obs), masks), acting), rewards), shaping), dones),
                        illegal,
                    ),
                )| {
                    let start = chunk * CHUNK;
                    (0..episodes.len()).find_map(|j| {
                        let one = One {
                            state: &mut states[j * PACKED_LEN..][..PACKED_LEN],
                            episode: &mut episodes[j],
                            observations: match per_obs {
                                0 => &mut [],
                                _ => &mut obs[j * per_obs..][..per_obs],
                            },
                            masks: &mut masks[j * p * n_a..][..p * n_a],
                            acting: &mut acting[j],
                            reward: &mut rewards[j],
                            shaping: &mut shaping[j],
                            done: &mut dones[j],
                            illegal: &mut illegal[j],
                        };
                        work(start + j, one).err()
                    })
                },
            )
            .collect();
        // Each chunk reports its first failure; chunks come back in order.
        match failures.into_iter().next() {
            Some(e) => Err(e),
            None => Ok(()),
        }
    }
}

fn check_len(what: &'static str, expected: usize, got: usize) -> Result<(), VecError> {
    if expected == got {
        Ok(())
    } else {
        Err(VecError::BufferLength {
            what,
            expected,
            got,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{episode_seed, VecEnv, VecEnvOptions};
    use yokai_engine::{ImageLayout, Part};

    /// Packed games on streams `derive_seed(seed, i)` play the games of a `VecEnv` seeded
    /// with `seed`, auto-resets included: every buffer equal at every step.
    #[test]
    fn packed_games_step_as_the_vec_env_does() {
        for name in ["9c-2p-perfect", "9c-3p-imperfect"] {
            let config = Config::from_name(name).unwrap();
            let encoding = Encoding::Image(Part::Full, ImageLayout::Chw);
            let (n, seed) = (70, 11);
            let mut options = VecEnvOptions::new(n, seed);
            options.encoding = encoding;
            let mut vec = VecEnv::<f32>::new(config, options).unwrap();
            let games = PackedGames::new(config, encoding).unwrap();
            let streams: Vec<u64> = (0..n as u64).map(|i| derive_seed(seed, i)).collect();
            assert_eq!(derive_seed(streams[5], 0), episode_seed(seed, 5, 0));
            let mut a = PackedOutputs::<f32>::new(&games, n);
            games.reset(&streams, a.buffers()).unwrap();
            let p = config.players();
            let mut finished = 0;
            for t in 0..300 {
                assert_eq!(a.observations, vec.observations(), "{name} step {t}");
                assert_eq!(a.masks, vec.legal_masks());
                assert_eq!(a.acting, vec.acting_seats());
                let mut acting = vec![0u32; n];
                vec.sample_legal(t, &mut acting);
                let mut joint = vec![0u32; n * p];
                for i in 0..n {
                    joint[i * p + a.acting[i] as usize] = acting[i];
                }
                vec.step(&acting).unwrap();
                let mut b = PackedOutputs::<f32>::new(&games, n);
                let states = std::mem::take(&mut a.states);
                let episodes = std::mem::take(&mut a.episodes);
                games
                    .step(
                        &states,
                        &streams,
                        &episodes,
                        &joint,
                        AutoReset::Yes,
                        b.buffers(),
                    )
                    .unwrap();
                a = b;
                assert_eq!(a.rewards, vec.rewards());
                assert_eq!(a.shaping, vec.shaping());
                assert_eq!(a.dones, vec.dones());
                assert!(a.illegal.iter().all(|&x| x == 0));
                for i in 0..n {
                    assert_eq!(a.episodes[i] as u64, vec.episodes(i));
                }
                finished += a.dones.iter().filter(|&&d| d == 1).count();
            }
            assert!(finished > n, "{name}: only {finished} games finished");
        }
    }

    #[test]
    fn an_illegal_action_leaves_its_game_unchanged_and_is_flagged() {
        let config = Config::from_name("9c-2p-perfect").unwrap();
        let games = PackedGames::new(config, Encoding::None).unwrap();
        let mut a = PackedOutputs::<f32>::new(&games, 2);
        games.reset(&[1, 2], a.buffers()).unwrap();
        // Game 0: the acting seat moves at substep 0 (illegal); game 1: the waiting seat
        // does not submit NOOP. Game 1's acting seat observes card 0 (legal on its own).
        let observe0 = config.encode(yokai_engine::Action::Observe(yokai_engine::Card(0)));
        let mv = config.num_actions() as u32 - 1;
        let step = |joint: [u32; 4]| {
            let mut out = PackedOutputs::<f32>::new(&games, 2);
            let (states, episodes) = (&a.states, &a.episodes);
            games
                .step(
                    states,
                    &[1, 2],
                    episodes,
                    &joint,
                    AutoReset::Yes,
                    out.buffers(),
                )
                .unwrap();
            out
        };
        let b = step([mv, 0, observe0 as u32, 5]);
        assert_eq!(b.illegal, [1, 1]);
        assert_eq!(b.states, a.states);
        assert_eq!((b.rewards, b.dones), (vec![0.0, 0.0], vec![0, 0]));
        // The same with the waiting seat's NOOP is legal and changes game 1.
        let c = step([mv, 0, observe0 as u32, 0]);
        assert_eq!(c.illegal, [1, 0]);
        assert_ne!(c.states[PACKED_LEN..], a.states[PACKED_LEN..]);
    }

    #[test]
    fn bad_states_and_lengths_are_errors_naming_the_game_or_buffer() {
        let config = Config::from_name("9c-2p-perfect").unwrap();
        let games = PackedGames::new(config, Encoding::None).unwrap();
        let mut a = PackedOutputs::<f32>::new(&games, 40);
        let streams: Vec<u64> = (0..40).collect();
        games.reset(&streams, a.buffers()).unwrap();
        let mut states = a.states.clone();
        states[35 * PACKED_LEN + 20] ^= 1;
        states[37 * PACKED_LEN + 20] ^= 1;
        let mut b = PackedOutputs::<f32>::new(&games, 40);
        let err = games
            .observe(&states, &a.episodes, b.buffers())
            .unwrap_err();
        assert!(matches!(err, VecError::Packed { env: 35, .. }), "{err}");
        assert!(err.to_string().contains("game 35"), "{err}");
        let err = games
            .observe(&states[1..], &a.episodes, b.buffers())
            .unwrap_err();
        assert!(err.to_string().contains("states"), "{err}");
        assert!(PackedGames::new(config, Encoding::Graph(Part::Full)).is_err());
    }
}
