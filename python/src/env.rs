//! `yokai.Env`: one game with full introspection, for debugging, search and play.

use crate::arrays::{self, Dtype};
use crate::errors::{config_error, illegal, replay_error};
use numpy::PyArrayDyn;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use yokai_engine::{
    render_seat, render_truth, Action, ActionError, Config, EpisodeRecord, Game, Outcome,
    RecordedGame, Scalar, Seat,
};
use yokai_vec::Encoding;

/// One game of Yōkai that records its actions.
///
/// Seats are numbered 0..P-1; a method that takes ``seat=None`` means the acting seat.
/// Actions are indices into the action space (see ``action_name``) or their names
/// (``"observe card 3"``, ``"move card 4 to r2c6"``, …).
#[pyclass(module = "yokai._core", name = "Env")]
#[derive(Clone)]
pub struct PyEnv {
    game: RecordedGame,
    /// The seed of the current deal (None for a replay of an explicit deal).
    seed: Option<u64>,
}

impl PyEnv {
    pub(crate) fn game(&self) -> &Game {
        self.game.game()
    }

    fn config_ref(&self) -> &Config {
        self.game.game().config()
    }

    fn seat(&self, seat: Option<&Bound<'_, PyAny>>) -> PyResult<Seat> {
        match seat {
            None => Ok(self.game().current_seat()),
            Some(s) => crate::errors::seat_arg(s, self.config_ref().players()),
        }
    }

    /// An action given as an index (a Python int or anything with ``__index__``, such as a
    /// NumPy integer) or a name. Every index outside the action space, however large or
    /// negative, is an ``IllegalActionError``; ``bool`` and non-integers are a ``TypeError``.
    fn action(&self, action: &Bound<'_, PyAny>) -> PyResult<Action> {
        if let Ok(name) = action.extract::<String>() {
            return name.parse::<Action>().map_err(illegal);
        }
        // True would otherwise be index 1 (END).
        let index = crate::errors::int_index(action, "an action is an int index or a name")?;
        let n = self.config_ref().num_actions();
        let out_of_range = || illegal(format!("action {index} is not an action index (0..{n})"));
        let index: i64 = index.extract().map_err(|_| out_of_range())?;
        let index = usize::try_from(index).map_err(|_| out_of_range())?;
        self.config_ref().decode(index).map_err(illegal)
    }

    fn write_observation<T: Scalar + numpy::Element>(
        &self,
        py: Python<'_>,
        seat: Seat,
        encoding: Encoding,
    ) -> PyResult<Py<PyAny>> {
        let config = self.config_ref();
        let shape = encoding.shape(config);
        let mut out = vec![T::ZERO; shape.iter().product()];
        let written = match encoding {
            Encoding::Image(part, layout) => {
                self.game().write_image_in(seat, part, layout, &mut out)
            }
            Encoding::Graph(part) => self.game().write_nodes(seat, part, &mut out),
            Encoding::None => {
                return Err(PyValueError::new_err(
                    "encoding `none` has no observation; use image or graph",
                ))
            }
        };
        written.map_err(|e| PyValueError::new_err(e.to_string()))?;
        Ok(arrays::owned(py, out, &shape)?.into_any().unbind())
    }
}

fn outcome_dict<'py>(py: Python<'py>, o: &Outcome) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("reward", o.reward)?;
    d.set_item("score", o.score)?;
    d.set_item("won", o.won)?;
    d.set_item("early_end", o.early_end)?;
    d.set_item("length", o.length)?;
    d.set_item("correct_hints", o.correct_hints)?;
    d.set_item("wrong_hints", o.wrong_hints)?;
    d.set_item("clustered", o.clustered)?;
    d.set_item("face_down", o.face_down)?;
    d.set_item("revealed_unplaced", o.revealed_unplaced)?;
    Ok(d)
}

fn action_error(e: ActionError) -> PyErr {
    match e {
        ActionError::WrongCount { .. } | ActionError::NoSuchSeat { .. } => {
            PyValueError::new_err(e.to_string())
        }
        _ => illegal(e),
    }
}

#[pymethods]
impl PyEnv {
    /// ``config``: a configuration name or TOML path; ``seed`` chooses the deal.
    #[new]
    #[pyo3(signature = (config="9c-2p-perfect", seed=0))]
    fn new(config: &str, seed: u64) -> PyResult<Self> {
        let config = Config::resolve(config).map_err(config_error)?;
        Ok(PyEnv {
            game: RecordedGame::new(config, seed),
            seed: Some(seed),
        })
    }

    /// Deal a new game from ``seed``; without one, from the previous seed + 1.
    #[pyo3(signature = (seed=None))]
    fn reset(&mut self, seed: Option<u64>) {
        let seed = seed.unwrap_or_else(|| self.seed.map_or(0, |s| s.wrapping_add(1)));
        self.game = RecordedGame::new(*self.config_ref(), seed);
        self.seed = Some(seed);
    }

    /// Play the acting seat's ``action`` (index or name). Returns ``(reward, shaping,
    /// done)``: the game reward R on the final step (else 0) and the step's shaping reward.
    /// Raises ``IllegalActionError`` (the game unchanged) for an illegal action.
    fn step(&mut self, action: &Bound<'_, PyAny>) -> PyResult<(i32, i32, bool)> {
        let action = self.action(action)?;
        self.step_action(action)
    }

    /// Play one action per seat (NOOP for every seat but the acting one), all checked.
    fn step_joint(&mut self, actions: Vec<Bound<'_, PyAny>>) -> PyResult<(i32, i32, bool)> {
        let actions = actions
            .iter()
            .map(|a| self.action(a))
            .collect::<PyResult<Vec<Action>>>()?;
        let step = self.game.step_joint(&actions).map_err(action_error)?;
        Ok((step.reward, step.shaping, step.done))
    }

    /// Legal action indices of ``seat`` (only NOOP for a seat that is not acting).
    #[pyo3(signature = (seat=None))]
    fn legal_actions(&self, seat: Option<&Bound<'_, PyAny>>) -> PyResult<Vec<usize>> {
        let seat = self.seat(seat)?;
        let mut out = Vec::new();
        self.game().for_each_legal_index(seat, |i| out.push(i));
        Ok(out)
    }

    /// Legal-action mask of ``seat``: uint8 ``[N_a]``, 1 = legal.
    #[pyo3(signature = (seat=None))]
    fn legal_mask<'py>(
        &self,
        py: Python<'py>,
        seat: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Bound<'py, PyArrayDyn<u8>>> {
        let seat = self.seat(seat)?;
        let n_a = self.config_ref().num_actions();
        let mut out = vec![0u8; n_a];
        self.game().write_legal_mask(seat, &mut out);
        arrays::owned(py, out, &[n_a])
    }

    /// The readable name of an action index.
    fn action_name(&self, action: usize) -> PyResult<String> {
        self.config_ref()
            .decode(action)
            .map(|a| a.to_string())
            .map_err(illegal)
    }

    /// The index of an action name (the inverse of ``action_name``).
    fn action_index(&self, name: &str) -> PyResult<usize> {
        let action: Action = name.parse().map_err(illegal)?;
        if !self.config_ref().action_fits(action) {
            return Err(illegal(format!(
                "`{action}` does not exist in this configuration"
            )));
        }
        Ok(self.config_ref().encode(action))
    }

    /// Text picture: the true board (``seat=None``) or what ``seat`` knows.
    #[pyo3(signature = (seat=None))]
    fn render(&self, seat: Option<&Bound<'_, PyAny>>) -> PyResult<String> {
        match seat {
            None => Ok(render_truth(self.game())),
            Some(s) => Ok(render_seat(self.game(), self.seat(Some(s))?)),
        }
    }

    /// ``seat``'s observation (acting seat by default) as a new array. ``encoding``:
    /// ``image``/``graph`` (each also ``-public``/``-private``); ``dtype`` float32 or uint8.
    #[pyo3(signature = (seat=None, encoding="image", dtype=None))]
    fn observation(
        &self,
        py: Python<'_>,
        seat: Option<&Bound<'_, PyAny>>,
        encoding: &str,
        dtype: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Py<PyAny>> {
        let seat = self.seat(seat)?;
        let encoding = Encoding::parse(encoding).map_err(crate::vec_env::vec_error)?;
        match dtype.map(Dtype::parse).transpose()?.unwrap_or(Dtype::F32) {
            Dtype::F32 => self.write_observation::<f32>(py, seat, encoding),
            Dtype::U8 => self.write_observation::<u8>(py, seat, encoding),
        }
    }

    /// The card adjacency matrix ``[Y, Y]`` (float32) of the graph encoding.
    fn adjacency<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArrayDyn<f32>>> {
        let y = self.config_ref().cards();
        let mut out = vec![0f32; y * y];
        self.game()
            .write_adjacency(&mut out)
            .map_err(|e| PyValueError::new_err(e.to_string()))?;
        arrays::owned(py, out, &[y, y])
    }

    /// The true colour index of every card ``[Y]`` (hidden information: for analysis and
    /// centralised critics, never for a policy).
    fn ground_truth<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArrayDyn<u8>>> {
        let y = self.config_ref().cards();
        let mut out = vec![0u8; y];
        self.game()
            .write_ground_truth(&mut out)
            .map_err(|e| PyValueError::new_err(e.to_string()))?;
        arrays::owned(py, out, &[y])
    }

    /// The game so far as a JSON replay record (config, deal, actions, outcome).
    fn to_replay(&self) -> String {
        self.game.record().to_json()
    }

    /// Rebuild a game from ``to_replay()`` output, re-checking every action; raises
    /// ``ReplayError`` naming the failing step.
    #[staticmethod]
    fn from_replay(text: &str) -> PyResult<PyEnv> {
        let record = EpisodeRecord::from_json(text).map_err(replay_error)?;
        let seed = match record.deal {
            yokai_engine::DealSource::Seed(s) => Some(s),
            yokai_engine::DealSource::Explicit(_) => None,
        };
        let game = RecordedGame::from_record(record).map_err(replay_error)?;
        Ok(PyEnv { game, seed })
    }

    /// An independent copy of the game (for search or what-if analysis).
    fn copy(&self) -> PyEnv {
        self.clone()
    }
    fn __copy__(&self) -> PyEnv {
        self.clone()
    }
    fn __deepcopy__(&self, _memo: &Bound<'_, PyAny>) -> PyEnv {
        self.clone()
    }

    /// The seat that acts now.
    #[getter]
    fn acting_seat(&self) -> usize {
        self.game().current_seat().0 as usize
    }
    /// The substep of the turn: 0 first OBSERVE (or END), 1 second OBSERVE, 2 MOVE, 3 hint.
    #[getter]
    fn substep(&self) -> usize {
        self.game().substep().index()
    }
    /// Whether the game is over.
    #[getter]
    fn done(&self) -> bool {
        self.game().is_over()
    }
    /// Steps played so far.
    #[getter]
    fn steps(&self) -> usize {
        self.game().steps()
    }
    /// Final metrics as a dict once the game is over, else None.
    #[getter]
    fn outcome<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        self.game()
            .outcome()
            .map(|o| outcome_dict(py, &o))
            .transpose()
    }
    /// Action indices played so far (the acting seat's, one per step).
    #[getter]
    fn history(&self) -> Vec<u16> {
        self.game.record().actions.clone()
    }
    /// The seed of the deal, or None for a replayed explicit deal.
    #[getter]
    fn seed(&self) -> Option<u64> {
        self.seed
    }
    #[getter]
    fn num_players(&self) -> usize {
        self.config_ref().players()
    }
    #[getter]
    fn num_actions(&self) -> usize {
        self.config_ref().num_actions()
    }
    #[getter]
    fn num_cards(&self) -> usize {
        self.config_ref().cards()
    }
    #[getter]
    fn num_colours(&self) -> usize {
        self.config_ref().colours()
    }
    /// The configuration's short name (or its description for custom configs).
    #[getter]
    fn config(&self) -> String {
        let c = self.config_ref();
        c.short_name().unwrap_or_else(|| c.to_string())
    }
    /// Shape of one seat's observation in ``encoding``.
    #[pyo3(signature = (encoding="image"))]
    fn observation_shape(&self, encoding: &str) -> PyResult<Vec<usize>> {
        let encoding = Encoding::parse(encoding).map_err(crate::vec_env::vec_error)?;
        Ok(encoding.shape(self.config_ref()))
    }

    fn __repr__(&self) -> String {
        format!(
            "Env(config={:?}, seed={:?}, step={}, acting_seat={}, done={})",
            self.config(),
            self.seed,
            self.steps(),
            self.acting_seat(),
            self.done()
        )
    }
}

impl PyEnv {
    fn step_action(&mut self, action: Action) -> PyResult<(i32, i32, bool)> {
        let step = self.game.apply(action).map_err(action_error)?;
        Ok((step.reward, step.shaping, step.done))
    }
}
