//! Trained networks as [`Policy`]s: load a policy file, a checkpoint or a run directory,
//! then seat the network anywhere a built-in bot can sit (`yokai eval`, Python, `play`).

use crate::artifact::safetensors;
use crate::artifact::{check_game, FileHeader, PolicyFile};
use crate::config::{ActConfig, TrainConfig};
use crate::device::default_device;
use crate::distribution::{decide_end_row, draw_row};
use crate::error::TrainError;
use crate::network::{for_network, ActorCritic, Encoder, GruCell, NetworkJob, Recurrent, SeatStep};
use crate::seen::SeenSeat;
use burn::prelude::*;
use burn::tensor::TensorData;
use rand_chacha::rand_core::SeedableRng;
use rand_chacha::ChaCha8Rng;
use std::path::{Path, PathBuf};
use yokai_agents::Policy;
use yokai_engine::{
    derive_seed, Action, ColourLabels, ColourNaming, Config, Game, Seat, SeatView, Symmetry,
};
use yokai_vec::Encoding;

/// A loaded network of any type, behind what a policy needs of it. Which type it is was
/// chosen once, by [`for_network`], when the file was loaded.
trait LoadedNet: std::fmt::Debug + Send + Sync {
    fn clone_box(&self) -> Box<dyn LoadedNet>;
    fn parameters(&self) -> Vec<f32>;
    fn write_safetensors(&self, metadata: &[(&str, String)], path: &Path)
        -> Result<(), TrainError>;
    fn encoding(&self) -> Encoding;
    fn hidden_size(&self) -> usize;
    fn recur(&self, obs: Tensor<2>, states: Tensor<2>, keep: Tensor<2>) -> Tensor<2>;
    fn policy_logits(&self, obs: Tensor<2>, states: Tensor<2>) -> Tensor<2>;
    fn step_views(
        &self,
        rows: &[SeenSeat],
        states: Vec<f32>,
        keep: Vec<f32>,
        device: &Device,
    ) -> SeatStep;
    fn colour_guesses(&self, rows: &[SeenSeat], states: &[f32], device: &Device)
        -> Option<Vec<u8>>;
    /// A seat-holder playing this network for `from`'s game, sampling with `seed`.
    fn seat(&self, from: &TrainedPolicy, seed: u64) -> Box<dyn Policy>;
}

impl<E: Encoder + 'static, M: Recurrent + 'static> LoadedNet for ActorCritic<E, M> {
    fn clone_box(&self) -> Box<dyn LoadedNet> {
        Box::new(self.clone())
    }
    fn parameters(&self) -> Vec<f32> {
        crate::tensor::parameters(self)
    }
    fn write_safetensors(
        &self,
        metadata: &[(&str, String)],
        path: &Path,
    ) -> Result<(), TrainError> {
        safetensors::write(self, metadata, path)
    }
    fn encoding(&self) -> Encoding {
        E::encoding()
    }
    fn hidden_size(&self) -> usize {
        ActorCritic::hidden_size(self)
    }
    fn recur(&self, obs: Tensor<2>, states: Tensor<2>, keep: Tensor<2>) -> Tensor<2> {
        ActorCritic::recur(self, obs, states, keep)
    }
    fn policy_logits(&self, obs: Tensor<2>, states: Tensor<2>) -> Tensor<2> {
        ActorCritic::policy_logits(self, obs, states)
    }
    fn step_views(
        &self,
        rows: &[SeenSeat],
        states: Vec<f32>,
        keep: Vec<f32>,
        device: &Device,
    ) -> SeatStep {
        ActorCritic::step_views(self, rows, states, keep, device)
    }
    fn colour_guesses(
        &self,
        rows: &[SeenSeat],
        states: &[f32],
        device: &Device,
    ) -> Option<Vec<u8>> {
        ActorCritic::colour_guesses(self, rows, states, device)
    }
    fn seat(&self, from: &TrainedPolicy, seed: u64) -> Box<dyn Policy> {
        Box::new(NetworkPolicy::new(self.clone(), from, seed))
    }
}

impl Clone for Box<dyn LoadedNet> {
    fn clone(&self) -> Self {
        self.clone_box()
    }
}

/// Loading a policy file's network as a [`NetworkJob`]: the type its config names, its
/// weights from the file.
struct Load<'a> {
    opened: &'a PolicyFile,
    device: &'a Device,
}

impl NetworkJob for Load<'_> {
    type Output = Result<Box<dyn LoadedNet>, TrainError>;
    fn run<E: Encoder + 'static, M: Recurrent + 'static>(self) -> Self::Output {
        let (config, game) = (&self.opened.config, &self.opened.game);
        let net = ActorCritic::<E, M>::new(config, game, 0, self.device);
        Ok(Box::new(self.opened.load_into(net)?))
    }
}

/// A trained network loaded from disk, ready to be seated any number of times.
#[derive(Clone, Debug)]
pub struct TrainedPolicy {
    net: Box<dyn LoadedNet>,
    game: Config,
    /// The training config the file holds (parsed once, from its header or metadata).
    config: TrainConfig,
    header: FileHeader,
    path: PathBuf,
    device: Device,
    /// `act.end_threshold` of the file's config, unless overridden.
    end_threshold: Option<f32>,
    /// `act.temperature` of the file's config (1 when absent), unless overridden.
    temperature: f32,
}

impl TrainedPolicy {
    /// Load `path`: a policy file, a checkpoint, or a run directory (its `policy.ykp`, else
    /// its checkpoint).
    pub fn load(path: &Path) -> Result<TrainedPolicy, TrainError> {
        TrainedPolicy::from_file(PolicyFile::open(path)?)
    }

    /// Load a policy file held in memory; `name` stands for its path in messages and
    /// tables (the pretrained agents: `pretrained:quick/0`).
    pub fn load_bytes(bytes: &[u8], name: &str) -> Result<TrainedPolicy, TrainError> {
        TrainedPolicy::from_file(PolicyFile::from_bytes(bytes, name)?)
    }

    fn from_file(opened: PolicyFile) -> Result<TrainedPolicy, TrainError> {
        let device = default_device();
        let net = for_network(
            &opened.config.network,
            Load {
                opened: &opened,
                device: &device,
            },
        )?;
        Ok(TrainedPolicy {
            net,
            end_threshold: opened.config.act.end_threshold,
            temperature: opened.config.act.temperature(),
            config: opened.config,
            game: opened.game,
            header: opened.header,
            path: opened.path,
            device,
        })
    }

    /// How the policy chooses END when it plays: `Some(t)` decides it (END where P(END) > t,
    /// see `act.end_threshold`), `None` draws it like any action.
    pub fn end_threshold(&self) -> Option<f32> {
        self.end_threshold
    }
    /// Play with another END rule than the file's (`yokai eval --end`, Python's `end=`); a
    /// threshold outside (0, 1) is refused.
    pub fn set_end_threshold(&mut self, threshold: Option<f64>) -> Result<(), TrainError> {
        self.end_threshold = threshold
            .map(ActConfig::end_threshold_from)
            .transpose()
            .map_err(|why| TrainError::Mismatch {
                path: self.path.display().to_string(),
                message: format!("act.end_threshold {why}"),
            })?;
        Ok(())
    }

    /// The temperature its moves are drawn at (`act.temperature`; 0 takes the most likely).
    pub fn temperature(&self) -> f32 {
        self.temperature
    }
    /// Draw moves at another temperature than the file's (`yokai eval --temperature`,
    /// Python's `temperature=`); one below 0 or not finite is refused.
    pub fn set_temperature(&mut self, temperature: f64) -> Result<(), TrainError> {
        self.temperature =
            ActConfig::temperature_from(temperature).map_err(|why| TrainError::Mismatch {
                path: self.path.display().to_string(),
                message: format!("act.temperature {why}"),
            })?;
        Ok(())
    }

    /// The game the network was trained on (its observation and action sizes fit only it).
    pub fn game(&self) -> &Config {
        &self.game
    }
    /// The config the network was trained with.
    pub fn config(&self) -> &TrainConfig {
        &self.config
    }
    /// Every parameter of the network, flattened (to compare two trained networks: the
    /// files themselves also hold burn's per-process parameter ids).
    pub fn parameters(&self) -> Vec<f32> {
        self.net.parameters()
    }

    pub fn header(&self) -> &FileHeader {
        &self.header
    }
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Write the network's weights as a SafeTensors file, with the training config, the
    /// game, the observation encoding and the memory width as metadata (see
    /// [`crate::artifact::safetensors`]).
    pub fn write_safetensors(&self, path: &Path) -> Result<(), TrainError> {
        use safetensors::*;
        let metadata = [
            (META_TRAIN_CONFIG, self.header.train_config.clone()),
            (META_GAME, self.header.game.clone()),
            (META_ENCODING, format!("{:?}", self.encoding())),
            (
                META_OBSERVATION_SHAPE,
                format!("{:?}", self.encoding().shape(&self.game)),
            ),
            (META_HIDDEN, self.hidden_size().to_string()),
        ];
        self.net.write_safetensors(&metadata, path)
    }

    /// A trained network fits only the game it was trained on.
    pub fn check_game(&self, game: &Config) -> Result<(), TrainError> {
        check_game(&self.path, &self.game, game)
    }

    /// The observation encoding the network reads.
    pub fn encoding(&self) -> Encoding {
        self.net.encoding()
    }

    /// Width of the network's recurrent state.
    pub fn hidden_size(&self) -> usize {
        self.net.hidden_size()
    }

    /// One step of the network's memory for `rows` seats at once, as in training:
    /// observations `[rows × L]` (in [`TrainedPolicy::encoding`]), states `[rows × H]`,
    /// `keep` `[rows]` (0 zeroes a row's state first: an episode starts). Returns the new
    /// states, without running the heads: for callers that only follow the seats' memories
    /// (a partner replayed up to the present).
    pub fn recur_batch(&self, obs: Vec<f32>, states: Vec<f32>, keep: Vec<f32>) -> Vec<f32> {
        let (o, s, k) = self.batch_tensors(obs, states, keep);
        crate::tensor::to_vec(self.net.recur(o, s, k))
    }

    /// Observations `[rows, L]`, states `[rows, H]` and `keep` `[rows, 1]` as tensors.
    fn batch_tensors(
        &self,
        obs: Vec<f32>,
        states: Vec<f32>,
        keep: Vec<f32>,
    ) -> (Tensor<2>, Tensor<2>, Tensor<2>) {
        let rows = keep.len();
        let d = &self.device;
        let h = self.hidden_size();
        let l = obs.len() / rows.max(1);
        (
            Tensor::from_data(TensorData::new(obs, [rows, l]), d),
            Tensor::from_data(TensorData::new(states, [rows, h]), d),
            Tensor::from_data(TensorData::new(keep, [rows, 1]), d),
        )
    }

    /// [`ActorCritic::step_seats`] of this policy's network, on its device: every seat's
    /// memory steps, and the actor runs for the seats whose turn it is. For callers that
    /// drive many seats of many games (the probe recorder, OBL's belief data and partners).
    pub fn step_seats(&self, rows: &[(&Game, Seat)], states: Vec<f32>, keep: Vec<f32>) -> SeatStep {
        let views: Vec<SeenSeat> = rows.iter().map(|&(g, s)| SeenSeat::plain(g, s)).collect();
        self.step_views(&views, states, keep)
    }

    /// [`TrainedPolicy::step_seats`] for seats that see their games through a symmetry
    /// each: the acting rows' logits are in the seat's view.
    pub fn step_views(&self, rows: &[SeenSeat], states: Vec<f32>, keep: Vec<f32>) -> SeatStep {
        self.net.step_views(rows, states, keep, &self.device)
    }

    /// Whether the network has a colour layer (the belief head), which it has exactly when
    /// its config's `ppo.belief_aux` is on ([`crate::network::ActorCritic::new`]).
    pub fn has_colour_layer(&self) -> bool {
        self.config.ppo.belief_aux > 0.0
    }

    /// The belief head's guess of every card's colour, `[rows × Y]`, at the seats `rows`
    /// (at least one) whose memories after reading their state are `states` (as
    /// [`TrainedPolicy::step_seats`] returns them); `None` for a network without a colour
    /// layer ([`crate::network::ActorCritic::colour_guesses`]).
    pub fn colour_guesses(&self, rows: &[(&Game, Seat)], states: &[f32]) -> Option<Vec<u8>> {
        let views: Vec<SeenSeat> = rows.iter().map(|&(g, s)| SeenSeat::plain(g, s)).collect();
        self.net.colour_guesses(&views, states, &self.device)
    }

    /// One step of seat `seat`'s memory in `game` (from `state`; `keep` 0 starts a fresh
    /// one), and, where the seat is to act, every one of its action logits, MOVEs
    /// included where none is legal ([`TrainedPolicy::step_seats`] leaves those at 0):
    /// for comparing this network with one run elsewhere, logit by logit. Returns the
    /// logits (`None` where the seat waits) and the new state.
    pub fn step_seat_every_logit(
        &self,
        game: &Game,
        seat: Seat,
        state: Vec<f32>,
        keep: f32,
    ) -> (Option<Vec<f32>>, Vec<f32>) {
        let encoding = self.encoding();
        let mut obs = vec![0f32; encoding.shape(game.config()).iter().product()];
        encoding
            .write(game, seat, &mut obs)
            .expect("a buffer sized from the game's own config");
        let (obs, state, keep) = self.batch_tensors(obs, state, vec![keep]);
        let h = self.net.recur(obs.clone(), state, keep);
        let logits = (game.current_seat() == seat)
            .then(|| crate::tensor::to_vec(self.net.policy_logits(obs, h.clone())));
        (logits, crate::tensor::to_vec(h))
    }

    /// A fresh seat-holder; `seed` drives its action sampling.
    pub fn build(&self, seed: u64) -> Box<dyn Policy> {
        self.net.seat(self, seed)
    }
}

/// One seat played by a network: keeps its GRU state and steps it on every game step,
/// whoever acts, exactly as in training.
pub struct NetworkPolicy<E: Encoder, M: Recurrent = GruCell> {
    model: ActorCritic<E, M>,
    name: String,
    device: Device,
    hidden: Vec<f32>,
    obs: Vec<f32>,
    mask: Vec<f32>,
    /// With `network.colours` other than `dealt`: the seat's colour names this game (drawn
    /// again at every reset) and the symmetry that shows them (rebuilt only when they
    /// change), and the observation as the deal names the colours.
    labels: Option<(ColourLabels, Symmetry)>,
    dealt: Vec<f32>,
    game: Config,
    /// Set when `act` already stepped the memory for the current game step.
    stepped: bool,
    rng: ChaCha8Rng,
    /// The END rule and END's action index.
    end_threshold: Option<f32>,
    end: usize,
    /// The temperature moves are drawn at, and the row it scales.
    temperature: f32,
    scaled: Vec<f32>,
}

impl<E: Encoder, M: Recurrent> NetworkPolicy<E, M> {
    fn new(model: ActorCritic<E, M>, from: &TrainedPolicy, seed: u64) -> Self {
        let len: usize = E::encoding().shape(&from.game).iter().product();
        NetworkPolicy {
            hidden: vec![0.0; model.hidden_size()],
            model,
            name: from.path.display().to_string(),
            device: from.device.clone(),
            obs: vec![0.0; len],
            mask: vec![0.0; from.game.num_actions()],
            labels: from
                .config
                .network
                .colours
                .naming()
                .map(|naming| named(&from.game, labels_for(&from.game, seed, naming))),
            dealt: vec![0.0; len],
            game: from.game,
            stepped: false,
            rng: ChaCha8Rng::seed_from_u64(seed),
            end_threshold: from.end_threshold,
            end: from.game.encode(Action::End),
            temperature: from.temperature,
            scaled: Vec::new(),
        }
    }

    /// Step the memory on `view`; returns the observation and the new state as tensors,
    /// for `act` to run the actor on.
    fn remember(&mut self, view: &SeatView<'_>) -> (Tensor<2>, Tensor<2>) {
        let out = match self.labels {
            Some(_) => &mut self.dealt,
            None => &mut self.obs,
        };
        match E::encoding() {
            Encoding::Image(part, layout) => view.write_image_in(part, layout, out),
            Encoding::Graph(part) => view.write_nodes(part, out),
            Encoding::None => Ok(()),
        }
        .expect("buffers sized from the policy's own game config");
        if let Some((labels, sym)) = &mut self.labels {
            if labels.update(view) {
                *sym = labels.symmetry(&self.game, Symmetry::identity(&self.game));
            }
            match E::encoding() {
                Encoding::Image(part, layout) => {
                    sym.apply_image_in(&self.game, part, layout, &self.dealt, &mut self.obs)
                }
                Encoding::Graph(part) => {
                    sym.apply_nodes(&self.game, part, &self.dealt, &mut self.obs)
                }
                Encoding::None => Ok(()),
            }
            .expect("buffers sized from the policy's own game config");
        }
        let d = &self.device;
        let h = self.hidden.len();
        let obs = Tensor::from_data(TensorData::new(self.obs.clone(), [1, self.obs.len()]), d);
        let state = self.model.recur(
            obs.clone(),
            Tensor::from_data(TensorData::new(self.hidden.clone(), [1, h]), d),
            Tensor::ones([1, 1], d),
        );
        self.hidden = crate::tensor::to_vec(state.clone());
        (obs, state)
    }
}

impl<E: Encoder, M: Recurrent> Policy for NetworkPolicy<E, M> {
    fn name(&self) -> String {
        self.name.clone()
    }
    fn reset(&mut self, seed: u64) {
        self.hidden.iter_mut().for_each(|h| *h = 0.0);
        self.stepped = false;
        self.rng = ChaCha8Rng::seed_from_u64(seed);
        if let Some((labels, _)) = self.labels {
            self.labels = Some(named(
                &self.game,
                labels_for(&self.game, seed, labels.naming()),
            ));
        }
    }
    fn act(&mut self, view: &SeatView<'_>) -> Action {
        let (obs, state) = self.remember(view);
        let logits = crate::tensor::to_vec(self.model.policy_logits(obs, state));
        self.stepped = true;
        view.write_legal_mask(&mut self.mask);
        let u = crate::distribution::unit_draw(&mut self.rng);
        let a = match self.end_threshold {
            Some(t) => decide_end_row(
                &logits,
                &mut self.mask,
                u,
                self.end,
                t,
                self.temperature,
                &mut self.scaled,
            ),
            None => draw_row(&logits, &self.mask, u, self.temperature, &mut self.scaled),
        };
        view.config()
            .decode(a)
            .expect("sampled among the legal actions of this config")
    }
    fn observe(&mut self, before: &SeatView<'_>, _actor: Seat, _action: Action) {
        if self.stepped {
            self.stepped = false;
        } else {
            self.remember(before);
        }
    }
}

/// A seat's colour names for a new game, their ties drawn from the seat's seed.
fn labels_for(game: &Config, seed: u64, naming: ColourNaming) -> ColourLabels {
    ColourLabels::new(game, derive_seed(seed, 0xC0), naming)
}

/// Colour names with the symmetry that shows them (no rotation: a seated policy sees its
/// game as dealt but for the names).
fn named(game: &Config, labels: ColourLabels) -> (ColourLabels, Symmetry) {
    (labels, labels.symmetry(game, Symmetry::identity(game)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::network::MlpEncoder;
    use crate::trainer::Trainer;

    /// A network that reads its own colour names (first-seen or public-first), seated as a
    /// [`Policy`] that replays each batch row's episode so far (with that row's tie rank),
    /// reads the observation
    /// and holds the names the trainer shows that row now: the names follow the episode in
    /// both, so a policy plays with the names it learnt with.
    #[test]
    fn a_named_colours_policy_reads_in_play_what_it_read_in_training() {
        for names in ["first-seen", "public-first"] {
            let config = TrainConfig::from_toml_str(
                &format!(
                    r#"
game = "9c-2p-perfect"
[network]
preset = "compact"
hidden = 16
colours = "{names}"
[ppo]
num_envs = 8
rollout_steps = 16
total_steps = 512
[run]
threads = 1
"#
                ),
                "tiny named colours",
            )
            .unwrap();
            let mut trainer = Trainer::<MlpEncoder>::new(config, 4).unwrap();
            trainer.update().unwrap();
            let policy = TrainedPolicy::load_bytes(&trainer.policy().to_bytes(), "tiny").unwrap();
            let game = *trainer.env().config();
            let (obs, _) = trainer.views();
            let l = obs.len() / (8 * game.players());
            let mut two_seen = 0;
            for row in 0..8 * game.players() {
                let (i, seat) = (row / game.players(), Seat((row % game.players()) as u8));
                let labels = trainer.actor().colour_labels(row).unwrap();
                two_seen += (labels.seen() >= 2) as usize;
                let mut seated = NetworkPolicy::new(trainer.model().clone(), &policy, 0);
                seated.labels = Some(named(&game, labels.restart()));
                let (mut replay, actions) = trainer.actor().episode_so_far(i);
                seated.remember(&replay.view(seat));
                for &a in actions {
                    replay.apply_index(a as usize).unwrap();
                    seated.remember(&replay.view(seat));
                }
                assert_eq!(
                    seated.labels.map(|(l, _)| l),
                    Some(labels),
                    "{names} row {row}"
                );
                assert_eq!(seated.obs, obs[row * l..][..l], "{names} row {row}");
            }
            assert!(
                two_seen >= 4,
                "{names}: only {two_seen} seats have seen two colours"
            );
        }
    }

    /// `step_seat_every_logit` gives the state and the logits `step_seats` gives, except
    /// the MOVE logits outside the MOVE substep, which it computes (non-zero) where
    /// `step_seats` leaves 0; and `None` for a waiting seat. Over a game of random play.
    #[test]
    fn every_logit_is_step_seats_with_the_move_logits_filled_in() {
        use rand_chacha::rand_core::Rng;
        let text = "game = \"9c-2p-perfect\"\n[network]\npreset = \"compact\"\nhidden = 16\n\
                    head = \"pointer\"\n[ppo]\nnum_envs = 4\nrollout_steps = 8\n\
                    total_steps = 64\n[run]\nthreads = 1\n";
        let config = TrainConfig::from_toml_str(text, "tiny pointer").unwrap();
        let trainer = Trainer::<MlpEncoder>::new(config, 2).unwrap();
        let policy = TrainedPolicy::load_bytes(&trainer.policy().to_bytes(), "tiny").unwrap();
        let game_config = *policy.game();
        let (y, g) = (game_config.cards(), game_config.grid());
        let moves = 2 + y..2 + y + y * g * g;
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        let mut game = Game::new(game_config, 3);
        let mut states = vec![vec![0f32; 16]; 2];
        let (mut filled, mut same) = (0, 0);
        while !game.is_over() {
            for seat in [Seat(0), Seat(1)] {
                let k = seat.0 as usize;
                let keep = if game.steps() == 0 { 0.0 } else { 1.0 };
                let stepped = policy.step_seats(&[(&game, seat)], states[k].clone(), vec![keep]);
                let (every, state) =
                    policy.step_seat_every_logit(&game, seat, states[k].clone(), keep);
                assert_eq!(state, stepped.states);
                match (stepped.logits(0), every) {
                    (None, None) => {}
                    (Some(part), Some(every)) => {
                        let at_move = game.substep() == yokai_engine::Substep::Move;
                        for (a, (&p, &e)) in part.iter().zip(&every).enumerate() {
                            if moves.contains(&a) && !at_move {
                                assert_eq!(p, 0.0);
                                assert_ne!(e, 0.0, "MOVE logit {a}");
                            } else {
                                assert!((p - e).abs() <= 1e-5 * (1.0 + e.abs()), "{a}: {p} vs {e}");
                            }
                        }
                        if at_move {
                            same += 1
                        } else {
                            filled += 1
                        }
                    }
                    (p, e) => panic!(
                        "seat {k}: logits {:?} against {:?}",
                        p.is_some(),
                        e.is_some()
                    ),
                }
                states[k] = state;
            }
            let legal = game.legal_actions(game.current_seat());
            game.apply(legal[(rng.next_u64() % legal.len() as u64) as usize])
                .unwrap();
        }
        assert!(
            filled > 5 && same > 2,
            "{filled} rows filled in, {same} at MOVE"
        );
    }
}
