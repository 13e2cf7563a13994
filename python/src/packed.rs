//! `yokai._core.PackedGames`: batches of games whose state Python keeps as packed bytes,
//! reset, stepped and observed in Rust on all cores. `yokai.jax` calls these from
//! `jax.pure_callback`; every call is a pure function of its arrays.

use crate::arrays;
use crate::errors::{config_error, YokaiError};
use crate::vec_env::vec_error;
use numpy::{PyReadonlyArray1, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use yokai_engine::{Config, PACKED_LEN};
use yokai_vec::{AutoReset, Encoding, PackedBuffers, PackedGames, PackedOutputs};

/// Batches of games held outside Rust as ``uint8[..., PACKED_LEN]`` arrays.
///
/// ``reset(streams)``, ``step(states, streams, episodes, actions, autoreset)`` and
/// ``observe(states, episodes)`` take arrays with one leading batch axis of n games and
/// return a dict of new NumPy arrays: ``state`` ``[n, PACKED_LEN]`` uint8, ``episode``
/// ``[n]`` uint32, ``obs`` ``[n, P, ...]`` float32, ``legal_mask`` ``[n, P, N_a]`` bool,
/// ``acting_seat`` ``[n]`` uint8, ``reward`` / ``shaping`` ``[n]`` float32, ``done`` /
/// ``illegal`` ``[n]`` bool. Episode e of stream s is dealt from ``derive_seed(s, e)``:
/// stream ``derive_seed(seed, i)`` plays the games of env i of ``VecEnv(seed=seed)``. An
/// illegal action leaves its game unchanged and sets ``illegal``; bytes that are not a
/// packed game of this config raise ``YokaiError`` naming the game.
#[pyclass(module = "yokai._core", name = "PackedGames", frozen)]
pub struct PyPackedGames {
    games: PackedGames,
    shape: Vec<usize>,
}

type Out = PackedOutputs<f32>;

/// The batch size of `array`'s first axis, or a ValueError naming it.
fn batch(what: &str, shape: &[usize], n: Option<usize>) -> PyResult<usize> {
    let Some(&first) = shape.first() else {
        return Err(PyValueError::new_err(format!("{what} needs a batch axis")));
    };
    match n {
        Some(n) if n != first => Err(PyValueError::new_err(format!(
            "{what} has {first} games on its first axis, the streams {n}"
        ))),
        _ => Ok(first),
    }
}

impl PyPackedGames {
    /// Run one batch call for `n` games without the GIL, and hand its outputs to Python.
    fn run<'py>(
        &self,
        py: Python<'py>,
        n: usize,
        call: impl FnOnce(PackedBuffers<'_, f32>) -> Result<(), yokai_vec::VecError> + Send,
    ) -> PyResult<Bound<'py, PyDict>> {
        let mut out = Out::new(&self.games, n);
        py.detach(|| call(out.buffers())).map_err(vec_error)?;
        self.dict(py, out, n)
    }

    fn dict<'py>(&self, py: Python<'py>, out: Out, n: usize) -> PyResult<Bound<'py, PyDict>> {
        let p = self.games.config().players();
        let n_a = self.games.config().num_actions();
        let d = PyDict::new(py);
        let mut obs_shape = vec![n, p];
        obs_shape.extend(&self.shape);
        // The flags are 0/1 bytes: NumPy views them as bool without a copy (a conversion in
        // Rust would copy every mask byte on every step of a jitted loop).
        let bools = |v: Vec<u8>, shape: &[usize]| {
            arrays::owned(py, v, shape)?.call_method1("view", ("bool",))
        };
        d.set_item("state", arrays::owned(py, out.states, &[n, PACKED_LEN])?)?;
        d.set_item("episode", arrays::owned(py, out.episodes, &[n])?)?;
        d.set_item("obs", arrays::owned(py, out.observations, &obs_shape)?)?;
        d.set_item("legal_mask", bools(out.masks, &[n, p, n_a])?)?;
        d.set_item("acting_seat", arrays::owned(py, out.acting, &[n])?)?;
        d.set_item("reward", arrays::owned(py, out.rewards, &[n])?)?;
        d.set_item("shaping", arrays::owned(py, out.shaping, &[n])?)?;
        d.set_item("done", bools(out.dones, &[n])?)?;
        d.set_item("illegal", bools(out.illegal, &[n])?)?;
        Ok(d)
    }

    fn states(states: &PyReadonlyArray2<'_, u8>, n: usize) -> PyResult<Vec<u8>> {
        let shape = states.shape();
        if shape != [n, PACKED_LEN] {
            return Err(PyValueError::new_err(format!(
                "states must have shape ({n}, {PACKED_LEN}), got {shape:?}"
            )));
        }
        Ok(states.as_array().iter().copied().collect())
    }
}

#[pymethods]
impl PyPackedGames {
    /// Games of ``config`` (a name or TOML path) observed in ``encoding`` (``image``,
    /// ``image-chw``, the ``-public`` / ``-private`` parts, or ``none``).
    #[new]
    #[pyo3(signature = (config, encoding = "image"))]
    fn new(config: &str, encoding: &str) -> PyResult<Self> {
        let config = Config::resolve(config).map_err(config_error)?;
        let encoding = Encoding::parse(encoding).map_err(config_error)?;
        let games = PackedGames::new(config, encoding).map_err(vec_error)?;
        Ok(PyPackedGames {
            games,
            shape: encoding.shape(&config),
        })
    }

    /// Bytes per packed game.
    #[classattr]
    fn packed_len() -> usize {
        PACKED_LEN
    }

    /// Shape of one seat's observation.
    #[getter]
    fn observation_shape(&self) -> Vec<usize> {
        self.shape.clone()
    }

    #[getter]
    fn num_actions(&self) -> usize {
        self.games.config().num_actions()
    }

    #[getter]
    fn num_players(&self) -> usize {
        self.games.config().players()
    }

    /// Deal episode 0 of every stream (``uint64[n]``).
    fn reset<'py>(
        &self,
        py: Python<'py>,
        streams: PyReadonlyArray1<'py, u64>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let streams: Vec<u64> = streams.as_array().to_vec();
        let n = streams.len();
        self.run(py, n, |out| self.games.reset(&streams, out))
    }

    /// Step every game with one action per seat (``actions`` ``uint32[n, P]``, NOOP = 0
    /// for waiting seats). With ``autoreset`` a game that ends is replaced by the next
    /// episode of its stream.
    fn step<'py>(
        &self,
        py: Python<'py>,
        states: PyReadonlyArray2<'py, u8>,
        streams: PyReadonlyArray1<'py, u64>,
        episodes: PyReadonlyArray1<'py, u32>,
        actions: PyReadonlyArray2<'py, u32>,
        autoreset: bool,
    ) -> PyResult<Bound<'py, PyDict>> {
        let n = batch("streams", streams.shape(), None)?;
        batch("episodes", episodes.shape(), Some(n))?;
        let p = self.games.config().players();
        if actions.shape() != [n, p] {
            return Err(PyValueError::new_err(format!(
                "actions must have shape ({n}, {p}), one per game and seat, got {:?}",
                actions.shape()
            )));
        }
        let states = Self::states(&states, n)?;
        let streams: Vec<u64> = streams.as_array().to_vec();
        let episodes: Vec<u32> = episodes.as_array().to_vec();
        let actions: Vec<u32> = actions.as_array().iter().copied().collect();
        let reset = if autoreset {
            AutoReset::Yes
        } else {
            AutoReset::No
        };
        self.run(py, n, |out| {
            self.games
                .step(&states, &streams, &episodes, &actions, reset, out)
        })
    }

    /// Observations, masks and acting seats of the games as they are.
    fn observe<'py>(
        &self,
        py: Python<'py>,
        states: PyReadonlyArray2<'py, u8>,
        episodes: PyReadonlyArray1<'py, u32>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let n = batch("episodes", episodes.shape(), None)?;
        let states = Self::states(&states, n)?;
        let episodes: Vec<u32> = episodes.as_array().to_vec();
        self.run(py, n, |out| self.games.observe(&states, &episodes, out))
    }

    /// One packed game's board as text, as the truth shows it (to look at a state held
    /// in a pytree).
    fn render(&self, state: PyReadonlyArray1<'_, u8>) -> PyResult<String> {
        let bytes = state.as_array().to_vec();
        let game = yokai_engine::Game::unpack(*self.games.config(), &bytes)
            .map_err(|e| YokaiError::new_err(e.to_string()))?;
        Ok(yokai_engine::render_truth(&game))
    }
}
