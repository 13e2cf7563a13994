//! Trained networks as [`Policy`]s: load a policy file, a checkpoint or a run directory,
//! then seat the network anywhere a built-in bot can sit (`yokai eval`, Python, `play`).

use crate::artifact::safetensors;
use crate::artifact::{check_game, FileHeader, PolicyFile};
use crate::config::{ActConfig, EncoderKind, MemoryKind};
use crate::device::default_device;
use crate::distribution::{decide_end_row, sample_row};
use crate::error::TrainError;
use crate::network::{
    ActorCritic, CnnEncoder, Encoder, GraphEncoder, GruCell, MlpEncoder, PublicPrivateEncoder,
    Recurrent, SeatStep, TransformerXl,
};
use burn::prelude::*;
use burn::tensor::TensorData;
use rand_chacha::rand_core::SeedableRng;
use rand_chacha::ChaCha8Rng;
use std::path::{Path, PathBuf};
use yokai_agents::Policy;
use yokai_engine::{Action, Config, Game, Seat, SeatView};
use yokai_vec::Encoding;

/// A loaded network, one variant per encoder type.
#[derive(Clone, Debug)]
enum Net {
    Cnn(Box<ActorCritic<CnnEncoder, GruCell>>),
    PublicPrivate(Box<ActorCritic<PublicPrivateEncoder, GruCell>>),
    Mlp(Box<ActorCritic<MlpEncoder, GruCell>>),
    Graph(Box<ActorCritic<GraphEncoder, GruCell>>),
    CnnTrxl(Box<ActorCritic<CnnEncoder, TransformerXl>>),
    PublicPrivateTrxl(Box<ActorCritic<PublicPrivateEncoder, TransformerXl>>),
    MlpTrxl(Box<ActorCritic<MlpEncoder, TransformerXl>>),
    GraphTrxl(Box<ActorCritic<GraphEncoder, TransformerXl>>),
}

/// `$body` with `$m` bound to the network of whichever variant `$net` holds: the one place
/// that lists the variants, so a new encoder type is one line here.
macro_rules! with_net {
    ($net:expr, $m:ident => $body:expr) => {
        match $net {
            Net::Cnn($m) => $body,
            Net::PublicPrivate($m) => $body,
            Net::Mlp($m) => $body,
            Net::Graph($m) => $body,
            Net::CnnTrxl($m) => $body,
            Net::PublicPrivateTrxl($m) => $body,
            Net::MlpTrxl($m) => $body,
            Net::GraphTrxl($m) => $body,
        }
    };
}

/// The observation encoding a network's encoder reads.
fn encoding_of<E: Encoder, M: Recurrent>(_: &ActorCritic<E, M>) -> Encoding {
    E::encoding()
}

/// A trained network loaded from disk, ready to be seated any number of times.
#[derive(Clone, Debug)]
pub struct TrainedPolicy {
    net: Net,
    game: Config,
    header: FileHeader,
    path: PathBuf,
    device: Device,
    /// `act.end_threshold` of the file's config, unless overridden.
    end_threshold: Option<f32>,
}

impl TrainedPolicy {
    /// Load `path`: a policy file, a checkpoint, or a run directory (its `policy.ykp`, else
    /// its checkpoint).
    pub fn load(path: &Path) -> Result<TrainedPolicy, TrainError> {
        let opened = PolicyFile::open(path)?;
        let device = default_device();
        let (config, game) = (&opened.config, &opened.game);
        // The file's weights in a network of the type its config names.
        macro_rules! load {
            () => {
                Box::new(opened.load_into(ActorCritic::new(config, game, 0, &device))?)
            };
        }
        use EncoderKind::*;
        let net = match (config.network.encoder(), config.network.memory) {
            (Cnn, MemoryKind::Gru) => Net::Cnn(load!()),
            (PublicPrivate, MemoryKind::Gru) => Net::PublicPrivate(load!()),
            (Mlp, MemoryKind::Gru) => Net::Mlp(load!()),
            (Gcn | Gatv2 | Relation, MemoryKind::Gru) => Net::Graph(load!()),
            (Cnn, MemoryKind::Trxl) => Net::CnnTrxl(load!()),
            (PublicPrivate, MemoryKind::Trxl) => Net::PublicPrivateTrxl(load!()),
            (Mlp, MemoryKind::Trxl) => Net::MlpTrxl(load!()),
            (Gcn | Gatv2 | Relation, MemoryKind::Trxl) => Net::GraphTrxl(load!()),
        };
        Ok(TrainedPolicy {
            net,
            end_threshold: config.act.end_threshold,
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

    /// The game the network was trained on (its observation and action sizes fit only it).
    pub fn game(&self) -> &Config {
        &self.game
    }
    /// Every parameter of the network, flattened (to compare two trained networks: the
    /// files themselves also hold burn's per-process parameter ids).
    pub fn parameters(&self) -> Vec<f32> {
        with_net!(&self.net, net => crate::tensor::parameters(net.as_ref()))
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
        with_net!(&self.net, m => write(m.as_ref(), &metadata, path))
    }

    /// A trained network fits only the game it was trained on.
    pub fn check_game(&self, game: &Config) -> Result<(), TrainError> {
        check_game(&self.path, &self.game, game)
    }

    /// The observation encoding the network reads.
    pub fn encoding(&self) -> Encoding {
        with_net!(&self.net, m => encoding_of(m.as_ref()))
    }

    /// Width of the network's recurrent state.
    pub fn hidden_size(&self) -> usize {
        with_net!(&self.net, m => m.hidden_size())
    }

    /// One step of the network's memory for `rows` seats at once, as in training:
    /// observations `[rows × L]` (in [`TrainedPolicy::encoding`]), states `[rows × H]`,
    /// `keep` `[rows]` (0 zeroes a row's state first: an episode starts). Returns the new
    /// states, without running the heads: for callers that only follow the seats' memories
    /// (a partner replayed up to the present).
    pub fn recur_batch(&self, obs: Vec<f32>, states: Vec<f32>, keep: Vec<f32>) -> Vec<f32> {
        let (o, s, k) = self.batch_tensors(obs, states, keep);
        crate::tensor::to_vec(with_net!(&self.net, m => m.recur(o, s, k)))
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
        with_net!(&self.net, m => m.step_seats(rows, states, keep, &self.device))
    }

    /// A fresh seat-holder; `seed` drives its action sampling.
    pub fn build(&self, seed: u64) -> Box<dyn Policy> {
        with_net!(&self.net, m => Box::new(NetworkPolicy::new((**m).clone(), self, seed)))
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
    /// Set when `act` already stepped the memory for the current game step.
    stepped: bool,
    rng: ChaCha8Rng,
    /// The END rule and END's action index.
    end_threshold: Option<f32>,
    end: usize,
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
            stepped: false,
            rng: ChaCha8Rng::seed_from_u64(seed),
            end_threshold: from.end_threshold,
            end: from.game.encode(Action::End),
        }
    }

    /// Step the memory on `view`; returns the observation and the new state as tensors,
    /// for `act` to run the actor on.
    fn remember(&mut self, view: &SeatView<'_>) -> (Tensor<2>, Tensor<2>) {
        match E::encoding() {
            Encoding::Image(part, layout) => view.write_image_in(part, layout, &mut self.obs),
            Encoding::Graph(part) => view.write_nodes(part, &mut self.obs),
            Encoding::None => Ok(()),
        }
        .expect("buffers sized from the policy's own game config");
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
    }
    fn act(&mut self, view: &SeatView<'_>) -> Action {
        let (obs, state) = self.remember(view);
        let logits = crate::tensor::to_vec(self.model.policy_logits(obs, state));
        self.stepped = true;
        view.write_legal_mask(&mut self.mask);
        let u = crate::distribution::unit_draw(&mut self.rng);
        let a = match self.end_threshold {
            Some(t) => decide_end_row(&logits, &mut self.mask, u, self.end, t),
            None => sample_row(&logits, &self.mask, u, false).0,
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
