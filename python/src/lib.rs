//! # yokai-python — the `yokai._core` extension module
//!
//! Thin PyO3 bindings: [`vec_env`] exposes the batched environment as zero-copy NumPy
//! views, [`env`] one game with full introspection. Every Rust error becomes a Python
//! exception carrying the engine's message ([`errors`]); nothing panics across the
//! boundary. The pure-Python parts (PettingZoo wrapper, benchmark) live in `python/yokai`.

mod agent;
mod arrays;
mod env;
mod errors;
mod packed;
#[cfg(feature = "trained")]
mod probe;
#[cfg(feature = "trained")]
mod train_env;
mod vec_env;

use pyo3::prelude::*;
use yokai_engine::Config;

/// The seed derived from ``seed`` for ``index``: ``derive_seed(seed, i)`` is the stream of
/// game i of ``VecEnv(seed=seed)``, whose episode e is dealt from
/// ``derive_seed(stream, e)`` (``yokai.jax`` keeps such streams).
#[pyfunction]
#[pyo3(name = "derive_seed")]
fn derive_seed_py(seed: u64, index: u64) -> u64 {
    yokai_engine::derive_seed(seed, index)
}

/// The seed of episode ``episode`` of game ``env`` in a ``VecEnv`` seeded with ``seed``:
/// ``Env(config, seed=episode_seed(seed, i, e))`` deals the same game.
#[pyfunction]
fn episode_seed(seed: u64, env: usize, episode: u64) -> u64 {
    yokai_vec::episode_seed(seed, env, episode)
}

/// The seeds ``text`` names: ``"0..3"`` (0, 1, 2), ``"0,4,7"`` or ``"5"``, as
/// ``yokai train --seeds`` reads them (one definition for both).
#[pyfunction]
fn parse_seeds(text: &str) -> PyResult<Vec<u64>> {
    yokai_agents::parse_seeds(text).map_err(errors::config_error)
}

/// The names of the built-in configurations.
#[pyfunction]
fn configs() -> Vec<String> {
    Config::presets().iter().map(|c| c.to_string()).collect()
}

#[pymodule]
#[pyo3(name = "_core")]
fn yokai_core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add_class::<vec_env::PyVecEnv>()?;
    m.add_class::<env::PyEnv>()?;
    m.add_class::<agent::PyAgent>()?;
    m.add_class::<packed::PyPackedGames>()?;
    m.add_function(wrap_pyfunction!(episode_seed, m)?)?;
    m.add_function(wrap_pyfunction!(derive_seed_py, m)?)?;
    m.add_function(wrap_pyfunction!(configs, m)?)?;
    m.add_function(wrap_pyfunction!(parse_seeds, m)?)?;
    #[cfg(feature = "trained")]
    {
        m.add_function(wrap_pyfunction!(agent::policy_parameters, m)?)?;
        m.add_function(wrap_pyfunction!(agent::pretrained_agents, m)?)?;
        m.add_function(wrap_pyfunction!(probe::probe_records, m)?)?;
        m.add_function(wrap_pyfunction!(probe::probe_accuracy, m)?)?;
        m.add_function(wrap_pyfunction!(train_env::policy_step, m)?)?;
        m.add_class::<train_env::PyTrainEnv>()?;
    }
    m.add("YokaiError", py.get_type::<errors::YokaiError>())?;
    m.add("ConfigError", py.get_type::<errors::ConfigError>())?;
    m.add(
        "IllegalActionError",
        py.get_type::<errors::IllegalActionError>(),
    )?;
    m.add("ReplayError", py.get_type::<errors::ReplayError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
