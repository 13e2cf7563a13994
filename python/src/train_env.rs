//! `yokai.TrainEnv`: the batched games of a training run as the Rust trainer plays them,
//! for trainers written in Python (`yokai.torch_train`). Every seat of every game is a row;
//! each row sees its game through its Other-Play symmetry; the centralised-training columns
//! (true colours, what END would pay) come with every observation. It is the trainer's own
//! `Actor`, so a run in another framework sees exactly what `yokai train` sees.

use crate::arrays;
use crate::errors::config_error;
use crate::vec_env::{final_metrics, vec_error};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use yokai_engine::{Action, Config};
use yokai_train::actor::Actor;
use yokai_train::network::encoding_of;
use yokai_train::{Override, TrainConfig};

/// The games of one training run (``ppo.num_envs`` games of the config's game, dealt from
/// the run's ``seed``), as the Rust trainer's rollout sees and plays them.
///
/// Row ``r`` is seat ``r % P`` of game ``r // P``. ``observe()`` returns owned arrays:
/// ``obs`` ``[rows, ...]`` float32 in the encoding the config's network reads (graph node
/// features for the compact network), ``legal_mask`` ``[rows, N_a]`` float32, both as the
/// row's seat sees its game (its Other-Play symmetry applied); ``keep`` ``[rows]`` float32
/// (0 where the row's next step starts an episode: zero its memory); ``acting_seat``
/// ``[N]``; ``truth`` ``[rows, Y]`` uint8, every card's true colour in the row's colour
/// labels (centralised training only); ``end_reward`` ``[N]`` float32, what END would pay
/// now where the acting seat may END (else 0). ``step(actions)`` takes one action per row
/// in the row's own view (a waiting seat's NOOP) and returns ``reward``, ``shaping``,
/// ``done`` and ``final`` as ``VecEnv.step`` does; finished games are dealt again.
#[pyclass(module = "yokai._core", name = "TrainEnv", unsendable)]
pub struct PyTrainEnv {
    actor: Actor,
    config: TrainConfig,
    game: Config,
    name: String,
}

#[pymethods]
impl PyTrainEnv {
    #[new]
    #[pyo3(signature = (config, seed = 0, set = Vec::new()))]
    fn new(config: &str, seed: u64, set: Vec<String>) -> PyResult<Self> {
        let overrides = set
            .iter()
            .map(|s| s.parse::<Override>())
            .collect::<Result<Vec<_>, _>>()
            .map_err(config_error)?;
        let (config, name) = TrainConfig::named(config, &overrides).map_err(config_error)?;
        let game = config.game_config().map_err(config_error)?;
        let encoding = encoding_of(&config.network);
        let actor = Actor::for_run(&config, seed, encoding, 0).map_err(config_error)?;
        Ok(PyTrainEnv {
            actor,
            config,
            game,
            name,
        })
    }

    /// Every row's view, the games' acting seats and the centralised-training columns.
    fn observe<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let a = &self.actor;
        let (rows, na, n) = (a.rows(), a.n_actions(), self.config.ppo.num_envs);
        let mut obs = vec![0f32; rows * a.obs_len()];
        let mut masks = vec![0f32; rows * na];
        a.view(&mut obs, &mut masks);
        let y = self.game.cards();
        let mut truth = vec![0u8; rows * y];
        for (r, out) in truth.chunks_exact_mut(y).enumerate() {
            a.view_truth(r, out);
        }
        let out = PyDict::new(py);
        let mut obs_shape = vec![rows];
        obs_shape.extend(a.env().encoding().shape(&self.game));
        out.set_item("obs", arrays::owned(py, obs, &obs_shape)?)?;
        out.set_item("legal_mask", arrays::owned(py, masks, &[rows, na])?)?;
        out.set_item("keep", arrays::owned(py, a.keeps(), &[rows])?)?;
        let acting = a.env().acting_seats().to_vec();
        out.set_item("acting_seat", arrays::owned(py, acting, &[n])?)?;
        out.set_item("truth", arrays::owned(py, truth, &[rows, y])?)?;
        out.set_item("end_reward", arrays::owned(py, a.end_rewards(), &[n])?)?;
        Ok(out)
    }

    /// Step every game with one action per row, each in its row's view.
    fn step<'py>(
        &mut self,
        py: Python<'py>,
        actions: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let rows = self.actor.rows();
        let (view, _) = arrays::actions(actions, &[&[rows]])?;
        let na = self.actor.n_actions();
        if let Some((r, &a)) = view.iter().enumerate().find(|(_, &a)| a as usize >= na) {
            return Err(crate::errors::illegal(format!(
                "row {r}: action {a} is outside the action space (0..{na})"
            )));
        }
        let joint: Vec<u32> = view
            .iter()
            .enumerate()
            .map(|(r, &a)| self.actor.to_true_action(r, a as usize) as u32)
            .collect();
        let acting = self.actor.env().acting_seats().to_vec();
        self.actor.step(&joint, &acting).map_err(vec_error)?;
        let env = self.actor.env();
        let n = env.num_envs();
        let out = PyDict::new(py);
        out.set_item("reward", arrays::owned(py, env.rewards().to_vec(), &[n])?)?;
        out.set_item("shaping", arrays::owned(py, env.shaping().to_vec(), &[n])?)?;
        let done: Vec<bool> = env.dones().iter().map(|&d| d == 1).collect();
        out.set_item("done", arrays::owned(py, done, &[n])?)?;
        out.set_item("final", final_metrics(py, env.outcomes())?)?;
        Ok(out)
    }

    /// The resolved training config (TOML, every field written out).
    #[getter]
    fn train_config(&self) -> String {
        self.config.to_toml()
    }
    /// The config's short name (the preset's, or the file's stem).
    #[getter]
    fn name(&self) -> String {
        self.name.clone()
    }
    /// The game's config (TOML), as policy files store it.
    #[getter]
    fn game_config(&self) -> String {
        self.game.to_toml()
    }
    #[getter]
    fn num_envs(&self) -> usize {
        self.config.ppo.num_envs
    }
    #[getter]
    fn num_players(&self) -> usize {
        self.game.players()
    }
    #[getter]
    fn num_rows(&self) -> usize {
        self.actor.rows()
    }
    #[getter]
    fn num_actions(&self) -> usize {
        self.game.num_actions()
    }
    #[getter]
    fn num_cards(&self) -> usize {
        self.game.cards()
    }
    #[getter]
    fn num_colours(&self) -> usize {
        self.game.colours()
    }
    #[getter]
    fn num_hints(&self) -> usize {
        self.game.hints()
    }
    #[getter]
    fn grid(&self) -> usize {
        self.game.grid()
    }
    /// The shape of one row's observation.
    #[getter]
    fn observation_shape(&self) -> Vec<usize> {
        self.actor.env().encoding().shape(&self.game)
    }
    /// The index of END in the action space.
    #[getter]
    fn end_action(&self) -> usize {
        self.game.encode(Action::End)
    }
    /// Node feature channels a network reads the board from: ``row``, ``col`` (scaled by
    /// 1 / (grid − 1)), ``id`` ((card + 1) / Y) and ``hinted``.
    #[getter]
    fn channels<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let ch = self.game.image_channels();
        let out = PyDict::new(py);
        for (k, v) in [
            ("row", ch.row),
            ("col", ch.col),
            ("id", ch.id),
            ("hinted", ch.hinted),
        ] {
            out.set_item(k, v)?;
        }
        Ok(out)
    }
    fn __repr__(&self) -> String {
        format!(
            "TrainEnv({:?}, {} games of {}, {} rows)",
            self.name,
            self.config.ppo.num_envs,
            self.game,
            self.actor.rows()
        )
    }
}

/// A float32 NumPy array.
type Array<'py> = Bound<'py, numpy::PyArrayDyn<f32>>;

/// The logits of seat ``seat`` of ``env``'s game under the trained network at ``path``,
/// after its memory ``state`` (``None``: a fresh one) reads the seat's observation now:
/// ``(logits [N_a] float32 or None where the seat waits, new state [H] float32)``. For
/// checking a network run elsewhere (PyTorch) against the Rust one, step by step.
#[pyfunction]
#[pyo3(signature = (path, env, seat, state = None))]
pub fn policy_step<'py>(
    py: Python<'py>,
    path: &str,
    env: PyRef<'py, crate::env::PyEnv>,
    seat: usize,
    state: Option<Vec<f32>>,
) -> PyResult<(Option<Array<'py>>, Array<'py>)> {
    let policy =
        yokai_train::TrainedPolicy::load(std::path::Path::new(path)).map_err(config_error)?;
    let game = env.game();
    policy.check_game(game.config()).map_err(config_error)?;
    if seat >= game.config().players() {
        return Err(PyValueError::new_err(format!(
            "seat {seat} is not a seat of {}",
            game.config()
        )));
    }
    let h = policy.hidden_size();
    let (state, keep) = match state {
        Some(s) if s.len() != h => {
            return Err(PyValueError::new_err(format!(
                "state has {} numbers; this network's memory has {h}",
                s.len()
            )))
        }
        Some(s) => (s, 1.0),
        None => (vec![0.0; h], 0.0),
    };
    // Every logit, MOVEs included where none is legal: this is for comparing networks.
    let (logits, state) =
        policy.step_seat_every_logit(game, yokai_engine::Seat(seat as u8), state, keep);
    let logits = logits
        .map(|l| arrays::owned(py, l.clone(), &[l.len()]))
        .transpose()?;
    Ok((logits, arrays::owned(py, state, &[h])?))
}
