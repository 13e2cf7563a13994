//! `yokai.VecEnv`: N games stepped together in Rust, seen from Python as NumPy views.

use crate::arrays::{self, Dtype};
use crate::errors::{config_error, illegal};
use numpy::PyArrayDyn;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use yokai_engine::{render_seat, render_truth, Config, Outcome};
use yokai_vec::{Encoding, VecEnv as RustVecEnv, VecEnvOptions, VecError};

/// The batched environment in the dtype the caller chose.
enum Inner {
    F32(RustVecEnv<f32>),
    U8(RustVecEnv<u8>),
}

/// Run `$body` with `$env` bound to the batched environment, whatever its dtype.
macro_rules! with_env {
    ($inner:expr, $env:ident => $body:expr) => {
        match $inner {
            Inner::F32($env) => $body,
            Inner::U8($env) => $body,
        }
    };
}

/// N games of one configuration, stepped together on all cores.
///
/// ``reset()`` and ``step()`` return a dict of NumPy arrays that *view* the environment's
/// own buffers: no copy is made, and the next ``step()`` or ``reset()`` overwrites them in
/// place. Keep ``arr.copy()`` of anything you need later. The arrays are read-only.
///
/// Keys: ``obs`` ``[N, P, ...]`` (every seat's observation), ``legal_mask`` ``[N, P, N_a]``
/// uint8, ``reward`` ``[N]`` float32 (the game reward R on the step a game ends, else 0),
/// ``shaping`` ``[N]`` float32, ``done`` ``[N]`` bool, ``acting_seat`` ``[N]`` uint8,
/// ``adjacency`` ``[N, Y, Y]`` (graph encodings only) and ``final``: a dict of ``[N]``
/// arrays with the metrics of the games that ended on this step (``reward``, ``won``,
/// ``early_end``, ``length``, ``correct_hints``, ``wrong_hints``, ``score``; 0 where
/// ``done`` is False).
///
/// A game that ends is reset in the same step: on that step ``reward``, ``shaping``,
/// ``done`` and ``final`` describe the finished game, while ``obs``, ``legal_mask`` and
/// ``acting_seat`` already show the first state of the next one.
#[pyclass(module = "yokai._core", name = "VecEnv")]
pub struct PyVecEnv {
    inner: Inner,
    config: Config,
    options: VecEnvOptions,
    encoding_name: String,
    dtype: Dtype,
}

impl PyVecEnv {
    fn build(config: Config, options: VecEnvOptions, dtype: Dtype) -> PyResult<Inner> {
        let inner = match dtype {
            Dtype::F32 => RustVecEnv::new(config, options).map(Inner::F32),
            Dtype::U8 => RustVecEnv::new(config, options).map(Inner::U8),
        };
        inner.map_err(vec_error)
    }

    /// The dict of views described in the class docs.
    fn arrays<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyDict>> {
        let py = slf.py();
        let owner = slf.as_any();
        let this = slf.borrow();
        let n = this.options.num_envs;
        let p = this.config.players();
        let out = PyDict::new(py);
        let mut obs_shape = vec![n, p];
        obs_shape.extend(this.options.encoding.shape(&this.config));
        with_env!(&this.inner, env => {
            if this.options.encoding != Encoding::None {
                out.set_item("obs", arrays::view(owner, env.observations(), &obs_shape)?)?;
            }
            if let Encoding::Graph(_) = this.options.encoding {
                let y = this.config.cards();
                out.set_item("adjacency", arrays::view(owner, env.adjacency(), &[n, y, y])?)?;
            }
            let n_a = this.config.num_actions();
            out.set_item("legal_mask", arrays::view(owner, env.legal_masks(), &[n, p, n_a])?)?;
            out.set_item("reward", arrays::view(owner, env.rewards(), &[n])?)?;
            out.set_item("shaping", arrays::view(owner, env.shaping(), &[n])?)?;
            // SAFETY: `dones` holds only 0 and 1, which are the two valid bit patterns of
            // `bool`, and has the same size and alignment.
            let dones: &[bool] = unsafe {
                std::slice::from_raw_parts(env.dones().as_ptr().cast::<bool>(), n)
            };
            out.set_item("done", arrays::view(owner, dones, &[n])?)?;
            out.set_item("acting_seat", arrays::view(owner, env.acting_seats(), &[n])?)?;
            out.set_item("final", final_metrics(py, env.outcomes())?)?;
        });
        Ok(out)
    }
}

/// The `final` dict: one array per metric over the games that ended this step.
pub fn final_metrics<'py>(
    py: Python<'py>,
    outcomes: &[Option<Outcome>],
) -> PyResult<Bound<'py, PyDict>> {
    let n = outcomes.len();
    let metric = |f: fn(&Outcome) -> i32| -> Vec<i32> {
        outcomes.iter().map(|o| o.as_ref().map_or(0, f)).collect()
    };
    let flag = |f: fn(&Outcome) -> bool| -> Vec<bool> {
        outcomes.iter().map(|o| o.as_ref().is_some_and(f)).collect()
    };
    let out = PyDict::new(py);
    out.set_item("reward", arrays::owned(py, metric(|o| o.reward), &[n])?)?;
    out.set_item("won", arrays::owned(py, flag(|o| o.won), &[n])?)?;
    out.set_item("early_end", arrays::owned(py, flag(|o| o.early_end), &[n])?)?;
    out.set_item(
        "length",
        arrays::owned(py, metric(|o| o.length as i32), &[n])?,
    )?;
    out.set_item(
        "correct_hints",
        arrays::owned(py, metric(|o| o.correct_hints as i32), &[n])?,
    )?;
    out.set_item(
        "wrong_hints",
        arrays::owned(py, metric(|o| o.wrong_hints as i32), &[n])?,
    )?;
    out.set_item("score", arrays::owned(py, metric(|o| o.score), &[n])?)?;
    Ok(out)
}

pub fn vec_error(e: VecError) -> PyErr {
    match e {
        VecError::Action { .. } => illegal(&e),
        VecError::ActionCount { .. }
        | VecError::EnvIndex { .. }
        | VecError::FinishedOnRestore { .. }
        | VecError::BufferLength { .. } => PyValueError::new_err(e.to_string()),
        VecError::Packed { .. } => crate::errors::YokaiError::new_err(e.to_string()),
        VecError::NoEnvs
        | VecError::Encoding(_)
        | VecError::Threads { .. }
        | VecError::PackedEncoding => config_error(&e),
        VecError::Memory { .. } => pyo3::exceptions::PyMemoryError::new_err(e.to_string()),
    }
}

#[pymethods]
impl PyVecEnv {
    /// ``config``: a configuration name (``"9c-2p-perfect"``, ``"16c-2p-imperfect"``, …) or
    /// the path of a TOML file. ``obs``: ``image``, ``graph`` (each also ``-public`` or
    /// ``-private``) or ``none``. ``dtype``: ``float32`` or ``uint8`` (unscaled integers).
    /// ``threads``: worker threads, one per core when None. Episode ``e`` of game ``i`` is
    /// dealt from ``yokai.episode_seed(seed, i, e)``.
    #[new]
    #[pyo3(signature = (config="9c-2p-perfect", num_envs=1024, seed=0, obs="image", dtype=None, threads=None))]
    fn new(
        config: &str,
        num_envs: usize,
        seed: u64,
        obs: &str,
        dtype: Option<&Bound<'_, PyAny>>,
        threads: Option<usize>,
    ) -> PyResult<Self> {
        let config = Config::resolve(config).map_err(config_error)?;
        let encoding = Encoding::parse(obs).map_err(vec_error)?;
        let dtype = match dtype {
            Some(d) => Dtype::parse(d)?,
            None => Dtype::F32,
        };
        if threads == Some(0) {
            return Err(config_error(
                "threads must be at least 1 (or None for one per core)",
            ));
        }
        let options = VecEnvOptions {
            encoding,
            threads,
            ..VecEnvOptions::new(num_envs, seed)
        };
        Ok(PyVecEnv {
            inner: Self::build(config, options, dtype)?,
            config,
            options,
            encoding_name: obs.to_string(),
            dtype,
        })
    }

    /// Restart every game at episode 0 of its seed stream (of ``seed`` when given, which
    /// then replaces the constructor's seed) and return the arrays.
    #[pyo3(signature = (seed=None))]
    fn reset<'py>(slf: Bound<'py, Self>, seed: Option<u64>) -> PyResult<Bound<'py, PyDict>> {
        {
            let mut this = slf.borrow_mut();
            match seed {
                Some(seed) if seed != this.options.seed => {
                    this.options.seed = seed;
                    let (config, options, dtype) = (this.config, this.options, this.dtype);
                    this.inner = Self::build(config, options, dtype)?;
                }
                _ => with_env!(&mut this.inner, env => env.reset()),
            }
        }
        Self::arrays(&slf)
    }

    /// Step every game. ``actions``: integer array ``[N]`` (the acting seat's action of
    /// each game) or ``[N, P]`` (one per seat, NOOP = 0 for all but the acting seat). Every
    /// action is checked before any game moves: an illegal one raises
    /// ``IllegalActionError`` naming the game, seat, action and reason, and nothing changes.
    fn step<'py>(
        slf: Bound<'py, Self>,
        actions: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let (n, p) = {
            let this = slf.borrow();
            (this.options.num_envs, this.config.players())
        };
        // Shape [N]: the acting seats' actions; [N, P]: one per seat.
        let (actions, which) = arrays::actions(actions, &[&[n], &[n, p]])?;
        let joint = which == 1;
        {
            let mut this = slf.borrow_mut();
            let inner = &mut this.inner;
            let py = slf.py();
            py.detach(|| {
                with_env!(inner, env => if joint { env.step_joint(&actions) } else { env.step(&actions) })
            })
            .map_err(vec_error)?;
        }
        Self::arrays(&slf)
    }

    /// A uniformly random legal action of the acting seat of every game, as ``uint32``
    /// ``[N]``, drawn in Rust from ``seed`` (fast enough for benchmarks and baselines).
    fn sample_actions<'py>(
        &self,
        py: Python<'py>,
        seed: u64,
    ) -> PyResult<Bound<'py, PyArrayDyn<u32>>> {
        let n = self.options.num_envs;
        let mut out = vec![0u32; n];
        with_env!(&self.inner, env => env.sample_legal(seed, &mut out));
        arrays::owned(py, out, &[n])
    }

    /// Play ``steps`` batched steps of uniformly random legal actions entirely in Rust (the
    /// sampler of ``yokai bench``, seeded ``seed``, ``seed + 1``, …), with the GIL released.
    /// Returns the number of games that ended. For benchmarks: comparing it with a Python
    /// loop over ``sample_actions`` and ``step`` shows what the binding costs.
    fn run_random(&mut self, py: Python<'_>, steps: u64, seed: u64) -> PyResult<u64> {
        let n = self.options.num_envs;
        let inner = &mut self.inner;
        py.detach(|| {
            with_env!(inner, env => {
                // On the environment's own threads: no hand-over per step.
                env.on_workers(|env| {
                    let mut actions = vec![0u32; n];
                    let mut ended = 0u64;
                    for t in 0..steps {
                        env.sample_legal(seed.wrapping_add(t), &mut actions);
                        env.step(&actions)?;
                        ended += env.dones().iter().map(|&d| d as u64).sum::<u64>();
                    }
                    Ok(ended)
                })
            })
        })
        .map_err(vec_error)
    }

    /// The readable name of action index ``action`` (e.g. ``"move card 4 to r2c6"``).
    fn action_name(&self, action: usize) -> PyResult<String> {
        self.config
            .decode(action)
            .map(|a| a.to_string())
            .map_err(illegal)
    }

    /// Text picture of game ``env``: the true board, or what ``seat`` knows of it.
    #[pyo3(signature = (env, seat=None))]
    fn render(&self, env: i64, seat: Option<&Bound<'_, PyAny>>) -> PyResult<String> {
        if !(0..self.options.num_envs as i64).contains(&env) {
            return Err(PyValueError::new_err(format!(
                "there is no game {env} in a batch of {}",
                self.options.num_envs
            )));
        }
        with_env!(&self.inner, e => {
            let game = e.game(env as usize);
            match seat {
                None => Ok(render_truth(game)),
                Some(s) => Ok(render_seat(game, crate::errors::seat_arg(s, self.config.players())?)),
            }
        })
    }

    /// Number of games N.
    #[getter]
    fn num_envs(&self) -> usize {
        self.options.num_envs
    }
    /// Number of seats P.
    #[getter]
    fn num_players(&self) -> usize {
        self.config.players()
    }
    /// Size of the action space N_a.
    #[getter]
    fn num_actions(&self) -> usize {
        self.config.num_actions()
    }
    /// Shape of one seat's observation (``obs`` is ``[N, P, *observation_shape]``).
    #[getter]
    fn observation_shape(&self) -> Vec<usize> {
        self.options.encoding.shape(&self.config)
    }
    /// The configuration's short name (or its full description for custom configs).
    #[getter]
    fn config(&self) -> String {
        self.config
            .short_name()
            .unwrap_or_else(|| self.config.to_string())
    }
    /// The observation encoding.
    #[getter]
    fn obs(&self) -> &str {
        &self.encoding_name
    }
    /// The observation dtype name.
    #[getter]
    fn dtype(&self) -> &'static str {
        self.dtype.name()
    }
    /// The seed of the current seed streams.
    #[getter]
    fn seed(&self) -> u64 {
        self.options.seed
    }

    fn __len__(&self) -> usize {
        self.options.num_envs
    }

    fn __repr__(&self) -> String {
        format!(
            "VecEnv(config={:?}, num_envs={}, seed={}, obs={:?}, dtype={:?})",
            self.config(),
            self.options.num_envs,
            self.options.seed,
            self.encoding_name,
            self.dtype.name()
        )
    }
}
