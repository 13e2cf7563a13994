//! OBL levels ≥ 2: the previous level, whose self-play the belief model is trained on and
//! which plays the partners inside the fictitious continuations unless `obl.partner` is
//! `learner` (`partners`).
//!
//! **The belief** conditions on the acting seat's real history: every row's belief memory
//! steps on the row's real observation at every rollout step ([`PreviousLevel::observe`])
//! and is saved in checkpoints, so a resume continues it exactly. The trained belief model
//! and its curve are saved there too ([`SavedBelief`]): a resume loads them instead of
//! training the belief again (minutes per resume at the CPU presets' 10,000 updates).

use super::belief::first_hand_slots;
use super::learn::{BeliefStats, BeliefTrainConfig, BeliefTrainer, LevelBelow};
use super::model::BeliefModel;
use crate::actor::Actor;
use crate::artifact::{load_record, record_bytes};
use crate::config::{BeliefOf, TrainConfig};
use crate::error::TrainError;
use crate::policy::TrainedPolicy;
use crate::tensor::{tensor2, to_vec};
use burn::prelude::*;
use burn::tensor::Bytes;
use rand_chacha::ChaCha8Rng;
use std::borrow::Cow;
use std::path::Path;
use yokai_engine::{derive_seed, Colour, Config, Part, Seat};
use yokai_vec::Encoding;

/// Updates at the end of the belief's training whose figures are averaged for the report.
const REPORTED_UPDATES: usize = 20;

/// The level below a level ≥ 2 run: its policy and the belief trained on its games.
pub(crate) struct PreviousLevel {
    pub policy: TrainedPolicy,
    pub belief: BeliefModel,
    /// Every training update's figures, in order (each measured on its rollout before
    /// learning from it): the belief's learning curve.
    pub belief_curve: Vec<BeliefStats>,
    /// The belief's memory of every row of the run's games `[rows × H_belief]`.
    pub memory: Vec<f32>,
}

/// A belief model trained before, as a checkpoint keeps it: the model's record (burn's
/// format) and its training curve (`CURVE_ENTRY` bytes per update), read back from the
/// checkpoint `path`.
pub(crate) struct SavedBelief<'a> {
    pub path: &'a Path,
    pub model: &'a [u8],
    pub curve: &'a [u8],
}

/// The checkpoint sections of the belief model and of its curve.
pub(crate) const BELIEF_SECTION: &str = "belief";
pub(crate) const BELIEF_CURVE_SECTION: &str = "belief_curve";

impl PreviousLevel {
    /// Load `obl.previous` (seed N's `seed-N` inside it where there is one) and the belief:
    /// `saved` where a checkpoint kept it, else trained on the level's self-play (on every
    /// seed run's in turn under `obl.belief_of = "all-seeds"`), deterministically in
    /// `seed`; its memory of the run's `rows` rows starts at zero.
    pub fn load(
        config: &TrainConfig,
        game: &Config,
        seed: u64,
        rows: usize,
        device: &Device,
        saved: Option<SavedBelief<'_>>,
    ) -> Result<PreviousLevel, TrainError> {
        let given = config
            .obl
            .previous
            .as_ref()
            .expect("validated: levels ≥ 2 name their previous level");
        let policy = load_below(&crate::artifact::names::seed_path(given, seed), game)?;
        if let Some(saved) = saved {
            let (belief, belief_curve) = saved.read(config, game, device)?;
            return Ok(PreviousLevel {
                policy,
                memory: vec![0.0; rows * belief.hidden_size()],
                belief,
                belief_curve,
            });
        }
        let belief_config =
            BeliefTrainConfig::small(config.obl.belief_hidden, config.obl.belief_updates);
        let population = match config.obl.belief_of {
            BeliefOf::OwnSeed => vec![policy.clone()],
            BeliefOf::AllSeeds => {
                let runs = crate::artifact::names::seed_runs(given);
                if runs.is_empty() {
                    return Err(TrainError::Obl(format!(
                        "obl.belief_of = \"all-seeds\" reads every seed-N run of obl.previous, \
                         and {} holds none",
                        given.display()
                    )));
                }
                if runs.len() > belief_config.num_envs {
                    return Err(TrainError::Obl(format!(
                        "obl.belief_of = \"all-seeds\": {} holds {} seed runs, and the belief \
                         plays {} games at a time, one seed each",
                        given.display(),
                        runs.len(),
                        belief_config.num_envs
                    )));
                }
                runs.iter()
                    .map(|dir| load_below(dir, game))
                    .collect::<Result<_, _>>()?
            }
        };
        let mut trainer = BeliefTrainer::new(
            *game,
            belief_config,
            LevelBelow::Networks(population),
            derive_seed(seed, 0xB0B),
            device.clone(),
        )?;
        let belief_curve = (0..config.obl.belief_updates)
            .map(|_| trainer.update())
            .collect();
        let belief = trainer.into_model();
        Ok(PreviousLevel {
            policy,
            memory: vec![0.0; rows * belief.hidden_size()],
            belief,
            belief_curve,
        })
    }

    /// The checkpoint sections that keep the trained belief ([`SavedBelief`]).
    pub fn belief_sections(&self) -> [(String, Vec<u8>); 2] {
        let model = record_bytes(self.belief.clone());
        let curve = self.belief_curve.iter().flat_map(curve_entry).collect();
        [
            (BELIEF_SECTION.into(), model),
            (BELIEF_CURVE_SECTION.into(), curve),
        ]
    }

    /// The figures reported: slot-weighted means over the last `REPORTED_UPDATES` updates
    /// of the belief's training (one rollout of 16 games is too few to compare a belief
    /// with its baseline).
    pub fn belief_stats(&self) -> BeliefStats {
        let tail = self.belief_curve.len().saturating_sub(REPORTED_UPDATES);
        BeliefStats::mean(self.belief_curve[tail..].iter().copied())
    }

    /// Every row's belief memory reads its observation of this step, `keep` 0 where an
    /// episode starts. Every seat's memory steps on every step, as it did on the previous
    /// level's games it learnt from.
    pub fn observe(&mut self, actor: &Actor, keep: &[f32], dev: &Device) {
        let rows = keep.len();
        let obs = true_observations(actor);
        let l = obs.len() / rows;
        let hb = self.belief.hidden_size();
        let h = self.belief.step(
            tensor2(obs.into_owned(), [rows, l], dev),
            tensor2(std::mem::take(&mut self.memory), [rows, hb], dev),
            tensor2(keep.to_vec(), [rows, 1], dev),
        );
        self.memory = to_vec(h);
    }

    /// A colouring per game from the belief model, for its acting seat, from the memory
    /// that seat's real history built ([`PreviousLevel::observe`]).
    pub fn sample_beliefs(
        &self,
        actor: &Actor,
        dev: &Device,
        rng: &mut ChaCha8Rng,
    ) -> Vec<Vec<Colour>> {
        let game = *actor.env().config();
        let n = actor.env().num_envs();
        let (y, p) = (game.cards(), game.players());
        let hb = self.belief.hidden_size();
        let graph = Encoding::Graph(Part::Full);
        let l: usize = graph.shape(&game).iter().product();
        let (mut obs, mut adjacency) = (vec![0f32; n * l], vec![0f32; n * y * y]);
        let mut first = Vec::with_capacity(n * y);
        let mut states = Vec::with_capacity(n * hb);
        for i in 0..n {
            let real = actor.game(i);
            let seat = real.current_seat();
            let row = i * p + seat.index();
            states.extend_from_slice(&self.memory[row * hb..][..hb]);
            graph
                .write(real, seat, &mut obs[i * l..][..l])
                .expect("buffers sized from the same config");
            real.write_adjacency(&mut adjacency[i * y * y..][..y * y])
                .expect("buffers sized from the same config");
            first.extend(first_hand_slots(real, seat));
        }
        let states = tensor2(states, [n, hb], dev);
        self.belief
            .sample(&game, states, &obs, &adjacency, &first, rng)
    }
}

impl SavedBelief<'_> {
    /// The belief model (of `obl.belief_hidden` units for `game`) and its curve, refused
    /// unless the record fits that model and the curve has `obl.belief_updates` updates.
    fn read(
        &self,
        config: &TrainConfig,
        game: &Config,
        device: &Device,
    ) -> Result<(BeliefModel, Vec<BeliefStats>), TrainError> {
        let shown = self.path.display().to_string();
        let empty = BeliefModel::new(game, config.obl.belief_hidden, 0, device);
        let model = Bytes::from_bytes_vec(self.model.to_vec());
        let belief = load_record(empty, model, &shown, "OBL belief model")?;
        if self.curve.len() as u64 != CURVE_ENTRY as u64 * config.obl.belief_updates {
            return Err(TrainError::Mismatch {
                path: shown,
                message: format!(
                    "its belief curve has {} bytes, {CURVE_ENTRY} per update, and its config \
                     trains the belief for obl.belief_updates = {}",
                    self.curve.len(),
                    config.obl.belief_updates
                ),
            });
        }
        let curve = self.curve.chunks_exact(CURVE_ENTRY).map(read_curve_entry);
        Ok((belief, curve.collect()))
    }
}

/// Bytes of one update of the belief curve in a checkpoint: cross-entropy, baseline and KL
/// as f64 and the slots as u64, little-endian. Binary, so that a resumed run's curve (and
/// its `belief.jsonl`) is the saved one to the bit; JSON would round some figures' last bit.
const CURVE_ENTRY: usize = 32;

fn curve_entry(s: &BeliefStats) -> [u8; CURVE_ENTRY] {
    let mut out = [0; CURVE_ENTRY];
    let values = [
        s.cross_entropy.to_bits(),
        s.uniform_cross_entropy.to_bits(),
        s.uniform_kl.to_bits(),
        s.slots as u64,
    ];
    for (chunk, v) in out.chunks_exact_mut(8).zip(values) {
        chunk.copy_from_slice(&v.to_le_bytes());
    }
    out
}

fn read_curve_entry(bytes: &[u8]) -> BeliefStats {
    let word = |k: usize| u64::from_le_bytes(bytes[8 * k..][..8].try_into().expect("8 bytes"));
    BeliefStats {
        cross_entropy: f64::from_bits(word(0)),
        uniform_cross_entropy: f64::from_bits(word(1)),
        uniform_kl: f64::from_bits(word(2)),
        slots: word(3) as usize,
    }
}

/// A run of the level below, checked for this game and for colours named as dealt.
fn load_below(path: &std::path::Path, game: &Config) -> Result<TrainedPolicy, TrainError> {
    let policy = TrainedPolicy::load(path)?;
    policy.check_game(game)?;
    let names = policy.config().network.colours;
    if names != crate::config::ColourNames::Dealt {
        return Err(TrainError::Obl(format!(
            "{}: its network names colours as network.colours = \"{names}\", which OBL's \
             partners do not keep: train the level below with colours as dealt",
            policy.path().display()
        )));
    }
    Ok(policy)
}

/// What the belief model reads at this step: every row's graph observation (`[rows × L]`,
/// row g·P + seat) of the true game, never a seat's Other-Play view — the belief names
/// true colours, and learnt from games seen without a symmetry. The compact network reads
/// the same graph observation, so the environment's buffer (written before any symmetry)
/// is borrowed; for the paper's image encoding it is written here.
pub(crate) fn true_observations(actor: &Actor) -> Cow<'_, [f32]> {
    let game = *actor.env().config();
    let graph = Encoding::Graph(Part::Full);
    if actor.env().encoding() == graph {
        return Cow::Borrowed(actor.env().observations());
    }
    let (p, rows) = (game.players(), actor.rows());
    let l: usize = graph.shape(&game).iter().product();
    let mut o = vec![0f32; rows * l];
    for r in 0..rows {
        graph
            .write(actor.game(r / p), Seat((r % p) as u8), &mut o[r * l..][..l])
            .expect("buffers sized from the same config");
    }
    Cow::Owned(o)
}
