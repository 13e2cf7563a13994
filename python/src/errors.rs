//! Rust errors as Python exceptions. Every error keeps the engine's message, which names
//! what was wrong and where (the seat, the action, the step, the file).

use pyo3::create_exception;
use pyo3::exceptions::PyValueError;
use pyo3::PyErr;

create_exception!(
    _core,
    YokaiError,
    PyValueError,
    "Base class of every error raised by the Yōkai engine (a ValueError)."
);
create_exception!(
    _core,
    ConfigError,
    YokaiError,
    "A configuration name, TOML file or option that does not describe a playable game."
);
create_exception!(
    _core,
    IllegalActionError,
    YokaiError,
    "An action that is not legal now, or an index outside the action space; the game is unchanged."
);
create_exception!(
    _core,
    ReplayError,
    YokaiError,
    "A replay record that is not valid JSON or that does not replay to the recorded game."
);

pub fn config_error(e: impl std::fmt::Display) -> PyErr {
    ConfigError::new_err(e.to_string())
}

pub fn illegal(e: impl std::fmt::Display) -> PyErr {
    IllegalActionError::new_err(e.to_string())
}

pub fn replay_error(e: impl std::fmt::Display) -> PyErr {
    ReplayError::new_err(e.to_string())
}

/// `value` as a Python int: itself, or what its ``__index__`` gives (NumPy integers).
/// ``bool`` and non-integers are a TypeError that says `expected` and names the type given
/// (``True`` is an int to Python, and would otherwise be index 1).
pub fn int_index<'py>(
    value: &pyo3::Bound<'py, pyo3::PyAny>,
    expected: &str,
) -> pyo3::PyResult<pyo3::Bound<'py, pyo3::PyAny>> {
    use pyo3::types::{PyAnyMethods, PyTypeMethods};
    let type_error = || {
        pyo3::exceptions::PyTypeError::new_err(format!(
            "{expected}, not {}",
            value
                .get_type()
                .name()
                .map(|n| n.to_string())
                .unwrap_or_default()
        ))
    };
    if value.is_instance_of::<pyo3::types::PyBool>() {
        return Err(type_error());
    }
    value
        .py()
        .import("operator")?
        .call_method1("index", (value,))
        .map_err(|_| type_error())
}

/// A seat given from Python: an int (or anything with ``__index__``, such as a NumPy
/// integer) in range, else a ValueError naming it, however large or negative; ``bool`` and
/// non-integers are a TypeError.
pub fn seat_arg(
    seat: &pyo3::Bound<'_, pyo3::PyAny>,
    players: usize,
) -> pyo3::PyResult<yokai_engine::Seat> {
    use pyo3::types::PyAnyMethods;
    let index = int_index(seat, "a seat is an int")?;
    // Python ints may be huge or negative: anything outside 0..players is named as given.
    match index.extract::<i64>() {
        Ok(s) if (0..players as i64).contains(&s) => Ok(yokai_engine::Seat(s as u8)),
        _ => Err(PyValueError::new_err(format!(
            "there is no seat {index} in a {players}-player game"
        ))),
    }
}
