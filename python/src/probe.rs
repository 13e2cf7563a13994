//! Linear probes of card colours from Python (`yokai probe` in functions): record memories
//! of trained policies, or bring your own (any agent's states saved as NumPy arrays), and
//! get the accuracy per game step against the perfect-memory oracle and chance.
//!
//! A record set is a dict of arrays, one row per (episode, step, recorded seat):
//! `states` float32 `[N, H]`, `colours` uint8 `[N, Y]` (every card's true colour), `seen`
//! bool `[N, Y]` (cards the seat has observed itself), `steps` `[N]` (0 = the first state),
//! `episodes` `[N]`, and optionally `cells` `[N, Y]` (the board position, row-major over the
//! g × g grid, each card lies on; needed for probes by position).

use crate::errors::config_error;
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyReadonlyArray1, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::Path;
use yokai_engine::{Card, Config};
use yokai_train::probe::{evaluate, fit, record, Records, StepAccuracy, Target};
use yokai_train::TrainedPolicy;

/// Play ``games`` games with the trained policies ``policies`` (one path per seat: policy
/// file, checkpoint or run directory; all trained on one game), sampling actions from each
/// network, and record the memory of the seats ``probed`` (default: every seat) after every
/// step. Returns a record set (see ``probe_accuracy``). Deals and actions follow ``seed``.
#[pyfunction]
#[pyo3(signature = (policies, probed=None, games=500, seed=0))]
pub fn probe_records<'py>(
    py: Python<'py>,
    policies: Vec<String>,
    probed: Option<Vec<bool>>,
    games: usize,
    seed: u64,
) -> PyResult<Bound<'py, PyDict>> {
    let loaded = policies
        .iter()
        .map(|p| TrainedPolicy::load(Path::new(p)).map_err(config_error))
        .collect::<PyResult<Vec<_>>>()?;
    let game = match loaded.first() {
        Some(first) => *first.game(),
        None => {
            return Err(PyValueError::new_err(
                "probe_records needs one policy per seat",
            ))
        }
    };
    for policy in &loaded {
        policy.check_game(&game).map_err(config_error)?;
    }
    if loaded.len() != game.players() {
        return Err(PyValueError::new_err(format!(
            "{} policies for {game}, a {}-player game: give one per seat",
            loaded.len(),
            game.players()
        )));
    }
    let probed = probed.unwrap_or_else(|| vec![true; game.players()]);
    if probed.len() != game.players() || !probed.contains(&true) {
        return Err(PyValueError::new_err(format!(
            "probed must hold one flag per seat ({}), at least one of them true",
            game.players()
        )));
    }
    let widths: Vec<usize> = loaded
        .iter()
        .zip(&probed)
        .filter(|(_, &p)| p)
        .map(|(policy, _)| policy.hidden_size())
        .collect();
    if widths.windows(2).any(|w| w[0] != w[1]) {
        return Err(PyValueError::new_err(format!(
            "the probed seats' memories differ in width ({widths:?}): probe one kind at a time"
        )));
    }
    if games == 0 {
        return Err(PyValueError::new_err("games must be at least 1"));
    }
    let seats: Vec<&TrainedPolicy> = loaded.iter().collect();
    let records = py.detach(|| record(&game, &seats, &probed, games, seed));
    to_dict(py, &game, records)
}

/// Fit linear probes on the record set ``records`` (episodes whose index is not a multiple
/// of 5: 80 %), one per card (``by="card"``) or one per board position that holds a card
/// in at least 50 training rows (``by="position"``, the paper's probes; the records need
/// ``cells``), and report their accuracy per game step on the other episodes, or on all
/// of ``test`` when given (e.g. cross-play records of the same policy). Returns a
/// dict of arrays, one entry per step with at least ``min_rows`` rows: ``step``, ``all``
/// and ``oracle_all`` (share of cards named right by the probe and by the perfect-memory
/// oracle), ``unseen`` and ``oracle_unseen`` (the same over cards the seat has not seen;
/// NaN where it has seen all), ``rows``; ``head`` and ``head_unseen`` (the same for the
/// belief head's guesses) where the records hold ``head``; and ``chance`` (1 / colours).
#[pyfunction]
#[pyo3(signature = (config, records, test=None, min_rows=20, by="card"))]
pub fn probe_accuracy<'py>(
    py: Python<'py>,
    config: &str,
    records: &Bound<'py, PyDict>,
    test: Option<&Bound<'py, PyDict>>,
    min_rows: usize,
    by: &str,
) -> PyResult<Bound<'py, PyDict>> {
    let game = Config::resolve(config).map_err(config_error)?;
    let target = match by {
        "card" => Target::Card,
        "position" => Target::Position,
        _ => {
            return Err(PyValueError::new_err(format!(
                "by is \"card\" or \"position\", not {by:?}"
            )))
        }
    };
    let train = from_dict(&game, records, "records")?;
    if train.is_empty() {
        return Err(PyValueError::new_err("records holds no rows"));
    }
    let other = test.map(|t| from_dict(&game, t, "test")).transpose()?;
    if let Some(other) = &other {
        if other.hidden != train.hidden {
            return Err(PyValueError::new_err(format!(
                "test states have {} columns, records {}: probes read one memory width",
                other.hidden, train.hidden
            )));
        }
    }
    if target == Target::Position {
        for (name, r) in [("records", Some(&train)), ("test", other.as_ref())] {
            if r.is_some_and(|r| r.cells.is_empty()) {
                return Err(PyValueError::new_err(format!(
                    "by=\"position\" needs the cards' positions: {name} has no \"cells\" array"
                )));
            }
        }
    }
    let steps = py
        .detach(|| {
            let probes = fit(&game, &train, |e| e % 5 != 0, target)?;
            Ok::<_, yokai_train::probe::ProbeError>(match &other {
                Some(other) => evaluate(&game, &probes, other, |_| true, min_rows),
                None => evaluate(&game, &probes, &train, |e| e % 5 == 0, min_rows),
            })
        })
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    accuracy_dict(py, &game, &steps)
}

fn to_dict<'py>(py: Python<'py>, game: &Config, r: Records) -> PyResult<Bound<'py, PyDict>> {
    let (n, y) = (r.len(), game.cards());
    let out = PyDict::new(py);
    let states = Array2::from_shape_vec((n, r.hidden), r.states).expect("rows × width");
    let colours = Array2::from_shape_vec((n, y), r.colours).expect("rows × cards");
    let seen = Array2::from_shape_fn((n, y), |(i, k)| r.seen[i].contains(Card(k as u8)));
    let cells = Array2::from_shape_vec((n, y), r.cells).expect("rows × cards");
    out.set_item("cells", cells.into_pyarray(py))?;
    out.set_item("states", states.into_pyarray(py))?;
    out.set_item("colours", colours.into_pyarray(py))?;
    out.set_item("seen", seen.into_pyarray(py))?;
    let steps: Vec<i64> = r.steps.iter().map(|&s| s as i64).collect();
    let episodes: Vec<i64> = r.episodes.iter().map(|&e| e as i64).collect();
    out.set_item("steps", steps.into_pyarray(py))?;
    out.set_item("episodes", episodes.into_pyarray(py))?;
    if !r.head.is_empty() {
        let head = Array2::from_shape_vec((n, y), r.head).expect("rows × cards");
        out.set_item("head", head.into_pyarray(py))?;
    }
    Ok(out)
}

/// A record set from a dict of arrays, every shape and value checked against `game`.
fn from_dict(game: &Config, d: &Bound<'_, PyDict>, what: &str) -> PyResult<Records> {
    let item = |key: &str| {
        d.get_item(key)?
            .ok_or_else(|| PyValueError::new_err(format!("{what} has no \"{key}\" array")))
    };
    let bad = |msg: String| PyValueError::new_err(format!("{what}: {msg}"));
    let states = item("states")?;
    let states: PyReadonlyArray2<f32> = states
        .call_method1("astype", ("float32",))?
        .extract()
        .map_err(|_| bad("states must be a 2-D array [rows, width]".into()))?;
    let colours = item("colours")?;
    let colours: PyReadonlyArray2<u8> = colours
        .call_method1("astype", ("uint8",))?
        .extract()
        .map_err(|_| bad("colours must be a 2-D array [rows, cards]".into()))?;
    let seen = item("seen")?;
    let seen: PyReadonlyArray2<bool> = seen
        .call_method1("astype", ("bool",))?
        .extract()
        .map_err(|_| bad("seen must be a 2-D array [rows, cards]".into()))?;
    let vector = |key: &str| -> PyResult<Vec<i64>> {
        let a = item(key)?;
        let a: PyReadonlyArray1<i64> = a
            .call_method1("astype", ("int64",))?
            .extract()
            .map_err(|_| bad(format!("{key} must be a 1-D array [rows]")))?;
        Ok(a.as_array().to_vec())
    };
    let (steps, episodes) = (vector("steps")?, vector("episodes")?);
    let [n, hidden] = [states.shape()[0], states.shape()[1]];
    let y = game.cards();
    for (name, shape) in [("colours", colours.shape()), ("seen", seen.shape())] {
        if shape != [n, y] {
            return Err(bad(format!(
                "{name} has shape {shape:?}, expected [{n}, {y}] (rows of states × cards of {game})"
            )));
        }
    }
    if steps.len() != n || episodes.len() != n {
        return Err(bad(format!(
            "steps and episodes need {n} entries (rows of states), not {} and {}",
            steps.len(),
            episodes.len()
        )));
    }
    let colours = colours.as_array().iter().copied().collect::<Vec<u8>>();
    check_colours(&colours, game).map_err(&bad)?;
    let head = card_array::<u8>(d, "head", "uint8", [n, y], game, &bad)?.unwrap_or_default();
    check_colours(&head, game).map_err(|e| bad(format!("head: {e}")))?;
    if steps.iter().any(|&v| !(0..=u16::MAX as i64).contains(&v))
        || episodes
            .iter()
            .any(|&v| !(0..=u32::MAX as i64).contains(&v))
    {
        return Err(bad(
            "steps must lie in 0..=65535 and episodes in 0..2³²".into()
        ));
    }
    let cells = match card_array::<i64>(d, "cells", "int64", [n, y], game, &bad)? {
        None => Vec::new(),
        Some(cells) => {
            let count = game.geometry().cells() as i64;
            if let Some(c) = cells.iter().find(|&&c| !(0..count).contains(&c)) {
                return Err(bad(format!(
                    "cell {c} is not on {game}'s board (cells 0..{count})"
                )));
            }
            cells.iter().map(|&c| c as u8).collect()
        }
    };
    let states = states.as_array().iter().copied().collect::<Vec<f32>>();
    if states.iter().any(|v| !v.is_finite()) {
        return Err(bad("states hold NaN or infinite values".into()));
    }
    let seen = seen.as_array();
    Ok(Records {
        hidden,
        states,
        colours,
        cells,
        seen: (0..n)
            .map(|i| {
                (0..y)
                    .filter(|&k| seen[[i, k]])
                    .map(|k| Card(k as u8))
                    .collect()
            })
            .collect(),
        steps: steps.iter().map(|&s| s as u16).collect(),
        episodes: episodes.iter().map(|&e| e as u32).collect(),
        head,
    })
}

/// The optional array `key` of a record set as `dtype`, flat (`None` where absent), checked
/// to have the shape `[rows, cards]`.
fn card_array<T: numpy::Element + Copy>(
    d: &Bound<'_, PyDict>,
    key: &str,
    dtype: &str,
    [n, y]: [usize; 2],
    game: &Config,
    bad: &impl Fn(String) -> PyErr,
) -> PyResult<Option<Vec<T>>> {
    let Some(a) = d.get_item(key)? else {
        return Ok(None);
    };
    let a: PyReadonlyArray2<T> = a
        .call_method1("astype", (dtype,))?
        .extract()
        .map_err(|_| bad(format!("{key} must be a 2-D array [rows, cards]")))?;
    if a.shape() != [n, y] {
        return Err(bad(format!(
            "{key} has shape {:?}, expected [{n}, {y}] (rows of states × cards of {game})",
            a.shape()
        )));
    }
    Ok(Some(a.as_array().iter().copied().collect()))
}

/// Every colour of `colours` exists in `game`.
fn check_colours(colours: &[u8], game: &Config) -> Result<(), String> {
    match colours.iter().find(|&&c| c as usize >= game.colours()) {
        Some(c) => Err(format!(
            "colour {c} does not exist in {game} ({} colours)",
            game.colours()
        )),
        None => Ok(()),
    }
}

/// A share of a step that may be missing.
type Share = fn(&StepAccuracy) -> Option<f64>;

fn accuracy_dict<'py>(
    py: Python<'py>,
    game: &Config,
    steps: &[StepAccuracy],
) -> PyResult<Bound<'py, PyDict>> {
    let out = PyDict::new(py);
    let column = |f: fn(&StepAccuracy) -> f64| steps.iter().map(f).collect::<Vec<f64>>();
    let step: Vec<i64> = steps.iter().map(|s| s.step as i64).collect();
    let rows: Vec<i64> = steps.iter().map(|s| s.rows as i64).collect();
    out.set_item("step", step.into_pyarray(py))?;
    out.set_item("all", column(|s| s.all).into_pyarray(py))?;
    out.set_item("oracle_all", column(|s| s.oracle_all).into_pyarray(py))?;
    // Shares that may be missing at a step (no unseen card, no belief head): NaN there.
    let optional: [(&str, Share); 4] = [
        ("unseen", |s| s.unseen),
        ("oracle_unseen", |s| s.oracle_unseen),
        ("head", |s| s.head),
        ("head_unseen", |s| s.head_unseen),
    ];
    let has_head = steps.iter().any(|s| s.head.is_some());
    for (key, f) in optional {
        if key.starts_with("head") && !has_head {
            continue;
        }
        let values: Vec<f64> = steps.iter().map(|s| f(s).unwrap_or(f64::NAN)).collect();
        out.set_item(key, values.into_pyarray(py))?;
    }
    out.set_item("rows", rows.into_pyarray(py))?;
    out.set_item("chance", 1.0 / game.colours() as f64)?;
    Ok(out)
}
