//! `yokai.Agent`: a built-in policy (random, greedy, belief) or a trained network playing
//! one seat of an `Env`.

use crate::env::PyEnv;
use crate::errors::{config_error, illegal};
use pyo3::prelude::*;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use yokai_agents::Policy;
use yokai_engine::{Config, Game};
#[cfg(feature = "trained")]
use yokai_train::{EndRule, PlayRule, PolicySource, TrainedPolicy};

/// A built-in policy by name (``"random"``, ``"greedy"``, ``"belief"``, with parameters as
/// ``"belief:continue_win=0.9"``), or a trained policy given as the path of a policy file,
/// checkpoint or run directory (``yokai train``). It sees only what its seat may know. A
/// trained policy plays only the game it was trained on.
///
/// Bots that follow the game (``belief``) must be shown every action: call
/// ``agent.observe(env, seat, action)`` for every agent *before* ``env.step(action)``, or
/// use ``yokai.play`` which does it for you.
#[pyclass(module = "yokai._core", name = "Agent")]
pub struct PyAgent {
    name: String,
    /// A trained policy's file and the game it was trained on (`None` for built-in bots).
    trained: Option<(PathBuf, Config)>,
    /// A Mutex only to make the class `Sync` for PyO3; methods take `&mut self`.
    policy: Mutex<Box<dyn Policy>>,
}

impl PyAgent {
    fn policy(&mut self) -> &mut Box<dyn Policy> {
        self.policy.get_mut().unwrap_or_else(|e| e.into_inner())
    }

    /// A trained network fits only the game it was trained on.
    fn check_game(&self, game: &Game) -> PyResult<()> {
        // Without the trainer no agent is a trained one: nothing to check.
        #[cfg(not(feature = "trained"))]
        let _ = game;
        match &self.trained {
            #[cfg(feature = "trained")]
            Some((path, trained)) => {
                yokai_train::artifact::check_game(path, trained, game.config())
                    .map_err(config_error)
            }
            _ => Ok(()),
        }
    }
}

#[pymethods]
impl PyAgent {
    /// ``end`` (trained policies only) chooses how END is played: ``None`` as the training
    /// config says (``act.end_threshold``), ``"draw"`` like any other action, or a
    /// probability in (0, 1): END wherever the network gives it more than that.
    /// ``temperature`` (trained policies only) draws the other moves from
    /// softmax(logits / T): ``None`` as the training config says (``act.temperature``, 1
    /// when absent), 0 the most likely legal move.
    #[new]
    #[pyo3(signature = (name, seed=0, end=None, temperature=None))]
    fn new(
        name: &str,
        seed: u64,
        end: Option<&Bound<'_, PyAny>>,
        temperature: Option<f64>,
    ) -> PyResult<Self> {
        let Seated {
            label,
            trained,
            mut policy,
        } = seat(name, seed, end, temperature)?;
        policy.reset(seed);
        Ok(PyAgent {
            name: label,
            trained,
            policy: Mutex::new(policy),
        })
    }

    /// Seed ``seed`` of the pretrained agents of ``preset``, built into the package
    /// (``yokai.pretrained_agents()`` lists them with their scores), as
    /// ``Agent("pretrained:PRESET/SEED", agent_seed, end, temperature)``: ``agent_seed``
    /// seeds the agent's draws.
    #[staticmethod]
    #[pyo3(signature = (preset, seed=0, agent_seed=0, end=None, temperature=None))]
    fn pretrained(
        preset: &str,
        seed: u64,
        agent_seed: u64,
        end: Option<&Bound<'_, PyAny>>,
        temperature: Option<f64>,
    ) -> PyResult<Self> {
        PyAgent::new(
            &format!("pretrained:{preset}/{seed}"),
            agent_seed,
            end,
            temperature,
        )
    }

    /// Start a new game.
    fn reset(&mut self, seed: u64) {
        self.policy().reset(seed);
    }

    /// The action index this agent plays as the acting seat of ``env``.
    fn act(&mut self, env: PyRef<'_, PyEnv>) -> PyResult<usize> {
        let game = env.game();
        self.check_game(game)?;
        if game.is_over() {
            return Err(illegal("the game is over"));
        }
        let action = self.policy().act(&game.view(game.current_seat()));
        Ok(game.config().encode(action))
    }

    /// Show this agent, sitting at ``seat``, that the acting seat of ``env`` is about to
    /// play ``action``.
    fn observe(
        &mut self,
        env: PyRef<'_, PyEnv>,
        seat: &Bound<'_, PyAny>,
        action: usize,
    ) -> PyResult<()> {
        let game = env.game();
        self.check_game(game)?;
        let seat = crate::errors::seat_arg(seat, game.config().players())?;
        let action = game.config().decode(action).map_err(illegal)?;
        self.policy()
            .observe(&game.view(seat), game.current_seat(), action);
        Ok(())
    }

    #[getter]
    fn name(&self) -> String {
        self.name.clone()
    }

    fn __repr__(&self) -> String {
        format!("Agent({:?})", self.name.clone())
    }
}

/// A policy as an `Agent` holds it: the name it shows, a trained policy's file and game,
/// and the seat-holder.
struct Seated {
    label: String,
    trained: Option<(PathBuf, Config)>,
    policy: Box<dyn Policy>,
}

/// `name` read as every front end reads a policy ([`PolicySource`]), seated with `seed`;
/// `end` and `temperature`, when given, are the END rule and the temperature of a trained
/// policy (a bot's are refused).
#[cfg(feature = "trained")]
fn seat(
    name: &str,
    seed: u64,
    end: Option<&Bound<'_, PyAny>>,
    temperature: Option<f64>,
) -> PyResult<Seated> {
    let mut source = PolicySource::parse(name).map_err(config_error)?;
    let rule = PlayRule {
        end: end.map(end_rule).transpose()?.unwrap_or_default(),
        temperature,
    };
    source.set_play_rule(rule, true).map_err(config_error)?;
    let trained = source
        .trained()
        .map(|p| (p.path().to_path_buf(), *p.game()));
    Ok(Seated {
        label: match trained {
            Some(_) => name.to_string(),
            None => source.name(),
        },
        trained,
        policy: source.build(seed),
    })
}

/// Without the trainer only the bots can sit: a path, an END rule or a temperature is
/// refused.
#[cfg(not(feature = "trained"))]
fn seat(
    name: &str,
    seed: u64,
    end: Option<&Bound<'_, PyAny>>,
    temperature: Option<f64>,
) -> PyResult<Seated> {
    if Path::new(name).exists() || name.starts_with("pretrained:") {
        return Err(config_error(format!(
            "`{name}` is a trained policy, but this build of yokai has no trained-policy support \
             (built with --no-default-features): install it with the default features"
        )));
    }
    if end.is_some() {
        return Err(config_error(format!(
            "`end` sets how a trained policy plays END; `{name}` is not a trained policy"
        )));
    }
    if temperature.is_some() {
        return Err(config_error(format!(
            "`temperature` sets how a trained policy draws its moves; `{name}` is not a trained policy"
        )));
    }
    let spec: yokai_agents::PolicySpec = name.parse().map_err(config_error)?;
    Ok(Seated {
        label: spec.to_string(),
        trained: None,
        policy: spec.build(seed),
    })
}

/// The `end` argument: ``"draw"`` or a probability (checked where the policy takes it,
/// `TrainedPolicy::set_end_threshold`).
#[cfg(feature = "trained")]
fn end_rule(end: &Bound<'_, PyAny>) -> PyResult<EndRule> {
    let bad = || format!("end={end}: give None, \"draw\" or a probability in (0, 1)");
    if let Ok(text) = end.extract::<String>() {
        return match text.as_str() {
            "draw" => Ok(EndRule::Draw),
            _ => Err(pyo3::exceptions::PyValueError::new_err(bad())),
        };
    }
    if end.is_instance_of::<pyo3::types::PyBool>() {
        return Err(pyo3::exceptions::PyValueError::new_err(bad()));
    }
    end.extract::<f64>().map(EndRule::Threshold).map_err(|_| {
        pyo3::exceptions::PyTypeError::new_err("end must be None, \"draw\" or a float in (0, 1)")
    })
}

/// The pretrained agents built into the package, one dict per preset: ``preset``,
/// ``about``, ``command`` (how they were trained), ``steps``, ``seeds``, and their
/// self-play score with themselves, ``sp_r`` and ``sp_se`` per seed over ``games`` games.
#[cfg(feature = "trained")]
#[pyfunction]
pub fn pretrained_agents<'py>(py: Python<'py>) -> PyResult<Vec<Bound<'py, pyo3::types::PyDict>>> {
    use pyo3::types::PyDict;
    yokai_train::pretrained::entries()
        .into_iter()
        .map(|e| {
            let d = PyDict::new(py);
            d.set_item("preset", e.preset)?;
            d.set_item("about", e.about)?;
            d.set_item("command", e.command)?;
            d.set_item("steps", e.steps)?;
            d.set_item("seeds", e.seeds)?;
            d.set_item("sp_r", e.sp_r)?;
            d.set_item("sp_se", e.sp_se)?;
            d.set_item("games", e.games)?;
            Ok(d)
        })
        .collect()
}

/// Every parameter of the trained network at ``path`` (policy file, checkpoint or run
/// directory), flattened in the network's order as float32: to check that two runs trained
/// the same network (the files themselves also hold per-process parameter ids).
#[cfg(feature = "trained")]
#[pyfunction]
pub fn policy_parameters<'py>(
    py: Python<'py>,
    path: &str,
) -> PyResult<Bound<'py, numpy::PyArray1<f32>>> {
    use numpy::IntoPyArray;
    let policy = TrainedPolicy::load(Path::new(path)).map_err(config_error)?;
    Ok(policy.parameters().into_pyarray(py))
}
