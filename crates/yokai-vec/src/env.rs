//! The batched environment: many games stepped together on worker threads, their
//! observations, masks, rewards and outcomes in flat buffers.

use crate::bits::{count_set, nth_set};
use crate::{episode_seed, Encoding, VecEnvOptions, VecError};
use rayon::prelude::*;
use yokai_engine::{
    derive_seed, ActionError, Config, Game, ImageChanges, ImageEncoder, ImageLayout, Outcome,
    Scalar, Seat,
};

/// One game and how many episodes it has finished.
#[derive(Clone)]
struct Slot {
    game: Game,
    episode: u64,
}

/// A buffer of `len` copies of `value`, or an error naming the buffer and its size where
/// the memory cannot be had: a huge `num_envs` must be an error the caller can report
/// (Python's `MemoryError`), not an abort of the process.
fn buffer<T: Clone>(
    len: usize,
    value: T,
    what: &'static str,
    num_envs: usize,
) -> Result<Vec<T>, VecError> {
    let mut v = reserve(len, what, num_envs)?;
    v.resize(len, value);
    Ok(v)
}

/// An empty vector with room for `len` elements, or the error of [`buffer`].
fn reserve<T>(len: usize, what: &'static str, num_envs: usize) -> Result<Vec<T>, VecError> {
    let bytes = (len as u128) * (std::mem::size_of::<T>() as u128);
    let refuse = || VecError::Memory {
        what,
        bytes,
        num_envs,
    };
    // A length that saturated (num_envs × sizes overflowed) lands here too.
    if bytes > isize::MAX as u128 {
        return Err(refuse());
    }
    let mut v = Vec::new();
    v.try_reserve_exact(len).map_err(|_| refuse())?;
    Ok(v)
}

/// N games of one configuration, stepped together.
pub struct VecEnv<T: Scalar> {
    config: Config,
    options: VecEnvOptions,
    slots: Vec<Slot>,
    observations: Vec<T>,
    adjacency: Vec<T>,
    masks: Vec<u8>,
    rewards: Vec<f32>,
    shaping: Vec<f32>,
    dones: Vec<u8>,
    acting: Vec<u8>,
    outcomes: Vec<Option<Outcome>>,
    /// The acting seats' actions of a joint step, gathered before applying.
    scratch: Vec<u32>,
    image: ImageEncoder<T>,
    sizes: Sizes,
    pool: std::sync::Arc<rayon::ThreadPool>,
}

/// Per-env sizes used inside the step loop.
#[derive(Clone, Copy, Debug)]
struct Sizes {
    players: usize,
    obs: usize,
    adjacency: usize,
    actions: usize,
}

impl<T: Scalar + Default> VecEnv<T> {
    pub fn new(config: Config, options: VecEnvOptions) -> Result<VecEnv<T>, VecError> {
        if options.num_envs == 0 {
            return Err(VecError::NoEnvs);
        }
        let threads = options
            .threads
            .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
        let pool = std::sync::Arc::new(
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .map_err(|e| VecError::Threads {
                    threads,
                    message: e.to_string(),
                })?,
        );
        let n = options.num_envs;
        let p = config.players();
        let sizes = Self::sizes(&config, options.encoding);
        let mut slots = reserve(n, "games", n)?;
        slots.extend((0..n).map(|i| Slot {
            game: Game::new(config, episode_seed(options.seed, i, 0)),
            episode: 0,
        }));
        let mut env = VecEnv {
            config,
            options: VecEnvOptions {
                chunk: options.chunk.max(1),
                ..options
            },
            slots,
            // Zero-size encodings keep one unused element per env so that the chunked zips
            // of the step loop stay aligned with the games.
            observations: buffer(
                n.saturating_mul(p).saturating_mul(sizes.obs.max(1)),
                T::ZERO,
                "observations",
                n,
            )?,
            adjacency: buffer(
                n.saturating_mul(sizes.adjacency.max(1)),
                T::ZERO,
                "adjacency",
                n,
            )?,
            masks: buffer(
                n.saturating_mul(p).saturating_mul(sizes.actions),
                0,
                "legal masks",
                n,
            )?,
            rewards: buffer(n, 0.0, "rewards", n)?,
            shaping: buffer(n, 0.0, "shaping", n)?,
            dones: buffer(n, 0, "done flags", n)?,
            acting: buffer(n, 0, "acting seats", n)?,
            outcomes: buffer(n, None, "outcomes", n)?,
            scratch: buffer(n, 0, "scratch", n)?,
            image: ImageEncoder::new(
                &config,
                match options.encoding {
                    Encoding::Image(_, layout) => layout,
                    _ => ImageLayout::Hwc,
                },
            ),
            sizes,
            pool,
        };
        env.reset();
        Ok(env)
    }

    fn sizes(config: &Config, encoding: Encoding) -> Sizes {
        Sizes {
            players: config.players(),
            obs: encoding.len(config),
            adjacency: if matches!(encoding, Encoding::Graph(_)) {
                config.cards() * config.cards()
            } else {
                0
            },
            actions: config.num_actions(),
        }
    }

    /// Reset every game to episode 0 of its seed stream and rewrite all buffers.
    pub fn reset(&mut self) {
        let seed = self.options.seed;
        let config = self.config;
        for (i, slot) in self.slots.iter_mut().enumerate() {
            slot.game = Game::new(config, episode_seed(seed, i, 0));
            slot.episode = 0;
        }
        self.rewards.fill(0.0);
        self.shaping.fill(0.0);
        self.dones.fill(0);
        self.outcomes.fill(None);
        let sizes = self.sizes;
        let encoding = self.options.encoding;
        let c = self.options.chunk;
        let image = &self.image;
        let (slots, obs, adj, masks, acting) = (
            &self.slots,
            &mut self.observations,
            &mut self.adjacency,
            &mut self.masks,
            &mut self.acting,
        );
        self.pool.install(|| {
            slots
                .par_chunks(c)
                .zip(obs.par_chunks_mut(c * sizes.players * sizes.obs.max(1)))
                .zip(adj.par_chunks_mut(c * sizes.adjacency.max(1)))
                .zip(masks.par_chunks_mut(c * sizes.players * sizes.actions))
                .zip(acting.par_chunks_mut(c))
                .for_each(|((((slots, obs), adj), masks), acting)| {
                    for (j, slot) in slots.iter().enumerate() {
                        write_env(
                            &slot.game, image, encoding, sizes, j, None, obs, adj, masks, acting,
                        );
                    }
                });
        });
    }

    /// Step every game with the acting seat's action (`actions[i]` for game i, an action
    /// index). All actions are checked first; an illegal one is an error naming the env, the
    /// seat, the action and the reason, and nothing changes.
    pub fn step(&mut self, actions: &[u32]) -> Result<(), VecError> {
        let n = self.options.num_envs;
        if actions.len() != n {
            return Err(VecError::ActionCount {
                expected: n,
                got: actions.len(),
                what: "one per game",
            });
        }
        match self.apply(actions) {
            Some(i) => self.check(i, self.acting[i] as usize, actions[i]),
            None => Ok(()),
        }
    }

    /// Step every game with one action per seat (`actions[i·P + s]`, NOOP = 0 for every seat
    /// but the acting one), the simultaneous-action API. The waiting seats' NOOPs are checked
    /// first, then the acting seats' actions as in [`VecEnv::step`]; the first illegal one is
    /// the error, and nothing changes.
    pub fn step_joint(&mut self, actions: &[u32]) -> Result<(), VecError> {
        let n = self.options.num_envs;
        let p = self.config.players();
        if actions.len() != n * p {
            return Err(VecError::ActionCount {
                expected: n * p,
                got: actions.len(),
                what: "one per game and seat",
            });
        }
        for i in 0..n {
            let acting = self.acting[i] as usize;
            for s in (0..p).filter(|&s| s != acting) {
                // A waiting seat's only legal action is NOOP (games here are never over),
                // so only a non-NOOP needs the mask and the reason.
                if actions[i * p + s] != 0 {
                    self.check(i, s, actions[i * p + s])?;
                }
            }
            self.scratch[i] = actions[i * p + acting];
        }
        let scratch = std::mem::take(&mut self.scratch);
        let bad = self.apply(&scratch);
        self.scratch = scratch;
        match bad {
            Some(i) => self.check(i, self.acting[i] as usize, self.scratch[i]),
            None => Ok(()),
        }
    }

    /// Is `action` legal for `seat` of game `env`? Reads the mask; on failure asks the game
    /// for the reason so the error says why.
    fn check(&self, env: usize, seat: usize, action: u32) -> Result<(), VecError> {
        let n_a = self.config.num_actions();
        let p = self.config.players();
        if allowed(&self.masks, n_a, p, env, seat, action) {
            return Ok(());
        }
        let game = &self.slots[env].game;
        let seat = Seat(seat as u8);
        let source = match self.config.decode(action as usize) {
            Err(source) => ActionError::Index { seat, source },
            Ok(a) => ActionError::Illegal {
                seat,
                action: a,
                reason: game
                    .check(seat, a)
                    .expect_err("the legal mask and Game::check agree (property-tested)"),
            },
        };
        Err(VecError::Action { env, source })
    }

    /// Check the acting seats' actions and, if all are legal, apply them; otherwise change
    /// nothing and return the first illegal game. Both run on the worker threads in one
    /// hand-over to the pool: a mask read per game is a cache miss per game, too slow to
    /// leave on the calling thread, and every hand-over costs a wake-up.
    fn apply(&mut self, actions: &[u32]) -> Option<usize> {
        let n_a = self.config.num_actions();
        let p = self.config.players();
        let config = self.config;
        let seed = self.options.seed;
        let encoding = self.options.encoding;
        let sizes = self.sizes;
        let c = self.options.chunk;
        let image = &self.image;
        let (slots, obs, adj, masks, rewards, shaping, dones, acting, outcomes) = (
            &mut self.slots,
            &mut self.observations,
            &mut self.adjacency,
            &mut self.masks,
            &mut self.rewards,
            &mut self.shaping,
            &mut self.dones,
            &mut self.acting,
            &mut self.outcomes,
        );
        self.pool.install(|| {
            // Checked a chunk at a time in a plain loop: per-item `position_first` costs
            // more in rayon's bookkeeping than the mask read it guards.
            let bad = actions
                .par_chunks(c)
                .enumerate()
                .filter_map(|(chunk, actions)| {
                    let start = chunk * c;
                    (start..start + actions.len()).find(|&i| {
                        !allowed(masks, n_a, p, i, acting[i] as usize, actions[i - start])
                    })
                })
                .min();
            if bad.is_some() {
                return bad;
            }
            slots
                .par_chunks_mut(c)
                .enumerate()
                .zip(actions.par_chunks(c))
                .zip(obs.par_chunks_mut(c * sizes.players * sizes.obs.max(1)))
                .zip(adj.par_chunks_mut(c * sizes.adjacency.max(1)))
                .zip(masks.par_chunks_mut(c * sizes.players * sizes.actions))
                .zip(rewards.par_chunks_mut(c))
                .zip(shaping.par_chunks_mut(c))
                .zip(dones.par_chunks_mut(c))
                .zip(acting.par_chunks_mut(c))
                .zip(outcomes.par_chunks_mut(c))
                .for_each(
                    |(
                        (
                            (
                                (
                                    ((((((chunk, slots), actions), obs), adj), masks), rewards),
                                    shaping,
                                ),
                                dones,
                            ),
                            acting,
                        ),
                        outcomes,
                    )| {
                        for (j, slot) in slots.iter_mut().enumerate() {
                            let action = config
                                .decode(actions[j] as usize)
                                .expect("validated against the legal mask");
                            let changes = slot.game.image_changes(action);
                            clear_masks(&slot.game, sizes, j, masks);
                            let step = slot.game.apply_unchecked(action);
                            rewards[j] = step.reward as f32;
                            shaping[j] = step.shaping as f32;
                            dones[j] = step.done as u8;
                            outcomes[j] = None;
                            if step.done {
                                outcomes[j] = slot.game.outcome();
                                slot.episode += 1;
                                let env = chunk * c + j;
                                slot.game =
                                    Game::new(config, episode_seed(seed, env, slot.episode));
                            }
                            // A game that just ended was reset above: written in full.
                            let changes = (!step.done).then_some(changes);
                            write_env(
                                &slot.game, image, encoding, sizes, j, changes, obs, adj, masks,
                                acting,
                            );
                        }
                    },
                );
            None
        })
    }

    /// Put game `env` back where it was: episode `episode` of its seed stream with the
    /// acting seats' `actions` (action indices) applied, and rewrite its buffers. A trainer
    /// saves `(episode, actions)` per game in a checkpoint so that a resumed run continues
    /// every unfinished game exactly. Rewards, shaping and done of that game read 0 and no
    /// outcome, as after a reset. An illegal or finishing action is an error and leaves the
    /// game as it was.
    pub fn restore(&mut self, env: usize, episode: u64, actions: &[u32]) -> Result<(), VecError> {
        if env >= self.options.num_envs {
            return Err(VecError::EnvIndex {
                env,
                num_envs: self.options.num_envs,
            });
        }
        let mut game = Game::new(self.config, episode_seed(self.options.seed, env, episode));
        for &a in actions {
            let step = game
                .apply_index(a as usize)
                .map_err(|source| VecError::Action { env, source })?;
            if step.done {
                return Err(VecError::FinishedOnRestore { env });
            }
        }
        self.slots[env] = Slot { game, episode };
        self.rewards[env] = 0.0;
        self.shaping[env] = 0.0;
        self.dones[env] = 0;
        self.outcomes[env] = None;
        let sizes = self.sizes;
        let (obs, adj, masks, acting) = (
            &mut self.observations[env * sizes.players * sizes.obs.max(1)..],
            &mut self.adjacency[env * sizes.adjacency.max(1)..],
            &mut self.masks[env * sizes.players * sizes.actions..],
            &mut self.acting[env..],
        );
        write_env(
            &self.slots[env].game,
            &self.image,
            self.options.encoding,
            sizes,
            0,
            None,
            obs,
            adj,
            masks,
            acting,
        );
        Ok(())
    }

    /// Run `work` on one of this environment's worker threads, and return its result. Calls
    /// to `step` and `sample_legal` from inside then split their games across the workers
    /// directly, instead of handing each call over from an outside thread and sleeping until
    /// it is done. A loop that steps many times in Rust (a benchmark, a rollout with a Rust
    /// policy) saves one wake-up per call this way.
    pub fn on_workers<R: Send>(&mut self, work: impl FnOnce(&mut Self) -> R + Send) -> R
    where
        T: Send,
    {
        let pool = std::sync::Arc::clone(&self.pool);
        pool.install(|| work(self))
    }

    // --- buffers -----------------------------------------------------------------------

    pub fn config(&self) -> &Config {
        &self.config
    }
    pub fn num_envs(&self) -> usize {
        self.options.num_envs
    }
    pub fn encoding(&self) -> Encoding {
        self.options.encoding
    }
    /// Shape of the observation buffer: `[N, P, …]`.
    pub fn observation_shape(&self) -> Vec<usize> {
        let mut s = vec![self.options.num_envs, self.config.players()];
        s.extend(self.options.encoding.shape(&self.config));
        s
    }
    pub fn observations(&self) -> &[T] {
        let sizes = self.sizes;
        &self.observations[..self.options.num_envs * sizes.players * sizes.obs]
    }
    /// `[N, Y, Y]` for graph encodings, empty otherwise.
    pub fn adjacency(&self) -> &[T] {
        let sizes = self.sizes;
        &self.adjacency[..self.options.num_envs * sizes.adjacency]
    }
    /// `[N, P, N_a]`, 1 where legal.
    pub fn legal_masks(&self) -> &[u8] {
        &self.masks
    }
    pub fn rewards(&self) -> &[f32] {
        &self.rewards
    }
    pub fn shaping(&self) -> &[f32] {
        &self.shaping
    }
    pub fn dones(&self) -> &[u8] {
        &self.dones
    }
    pub fn acting_seats(&self) -> &[u8] {
        &self.acting
    }
    pub fn outcomes(&self) -> &[Option<Outcome>] {
        &self.outcomes
    }
    /// The current game of one environment (for inspection, rendering, tests).
    pub fn game(&self, env: usize) -> &Game {
        &self.slots[env].game
    }
    /// How many episodes environment `env` has finished.
    pub fn episodes(&self, env: usize) -> u64 {
        self.slots[env].episode
    }

    /// A uniformly random legal action for the acting seat of every game, drawn from the
    /// masks with a counter-based generator (deterministic in `(seed, env)` and thread
    /// count). For benchmarks and smoke tests.
    pub fn sample_legal(&self, seed: u64, out: &mut [u32]) {
        let n_a = self.config.num_actions();
        let p = self.config.players();
        let c = self.options.chunk;
        let (masks, acting, slots) = (&self.masks, &self.acting, &self.slots);
        self.pool.install(|| {
            out.par_chunks_mut(c).enumerate().for_each(|(chunk, out)| {
                for (j, o) in out.iter_mut().enumerate() {
                    let env = chunk * c + j;
                    let seat = Seat(acting[env]);
                    // Legal actions lie in the substep's span, a few bytes except at MOVE.
                    let span = slots[env].game.legal_span(seat);
                    let mask = &masks[(env * p + seat.index()) * n_a..][span.clone()];
                    let count = count_set(mask);
                    let r = derive_seed(seed, env as u64);
                    let k = ((r as u128 * count as u128) >> 64) as u32;
                    *o = (span.start + nth_set(mask, k)) as u32;
                }
            });
        });
    }
}

/// Whether the mask of `seat` in game `env` allows action index `action` (an index out of
/// range is not allowed).
#[inline(always)]
fn allowed(masks: &[u8], n_a: usize, p: usize, env: usize, seat: usize, action: u32) -> bool {
    (action as usize) < n_a && masks[(env * p + seat) * n_a + action as usize] == 1
}

/// Zero the mask entries of game `j` of a chunk that its current state has set, before an
/// action (see [`Game::clear_legal_mask`]).
#[inline]
fn clear_masks(game: &Game, sizes: Sizes, j: usize, masks: &mut [u8]) {
    for s in 0..sizes.players {
        let mask = &mut masks[(j * sizes.players + s) * sizes.actions..][..sizes.actions];
        game.clear_legal_mask(Seat(s as u8), mask);
    }
}

/// Write observations, adjacency, masks and acting seat of game `j` of a chunk: in full
/// (`changes` is `None`: a new game, a reset, a restore), or in place after one action whose
/// [`ImageChanges`] are given, over buffers that held the state before it and whose masks
/// [`clear_masks`] cleared. Both give the same buffers (the equivalence tests compare every
/// buffer every step).
#[allow(clippy::too_many_arguments)]
#[inline]
fn write_env<T: Scalar>(
    game: &Game,
    image: &ImageEncoder<T>,
    encoding: Encoding,
    sizes: Sizes,
    j: usize,
    changes: Option<ImageChanges>,
    obs: &mut [T],
    adj: &mut [T],
    masks: &mut [u8],
    acting: &mut [u8],
) {
    acting[j] = game.current_seat().0;
    for s in 0..sizes.players {
        let seat = Seat(s as u8);
        let o = &mut obs[(j * sizes.players + s) * sizes.obs.max(1)..][..sizes.obs];
        match (encoding, changes) {
            (Encoding::Image(part, _), Some(changes)) => image.update(game, seat, part, changes, o),
            (Encoding::Image(part, _), None) => image.write(game, seat, part, o),
            // Graph features are a few hundred values: always rewritten whole.
            (Encoding::Graph(part), _) => game.write_nodes(seat, part, o),
            (Encoding::None, _) => Ok(()),
        }
        .expect("buffers are sized from the same config");
        let mask = &mut masks[(j * sizes.players + s) * sizes.actions..][..sizes.actions];
        match changes {
            Some(_) => game.mark_legal_mask(seat, mask),
            None => game.write_legal_mask(seat, mask),
        }
    }
    if sizes.adjacency > 0 {
        game.write_adjacency(&mut adj[j * sizes.adjacency..][..sizes.adjacency])
            .expect("buffers are sized from the same config");
    }
}
