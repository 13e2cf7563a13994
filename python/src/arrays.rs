//! NumPy at the boundary: read-only views of Rust buffers, and checked conversion of
//! user-supplied action arrays and dtype names.

use numpy::ndarray::{ArrayViewD, IxDyn};
use numpy::{Element, PyArrayDyn, PyArrayMethods, PyReadonlyArrayDyn, PyUntypedArrayMethods};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;

/// The two observation element types a caller can ask for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dtype {
    F32,
    U8,
}

impl Dtype {
    /// Accepts anything `numpy.dtype()` accepts (`"float32"`, `np.uint8`, …).
    pub fn parse(dtype: &Bound<'_, PyAny>) -> PyResult<Dtype> {
        let py = dtype.py();
        let name: String = match py.import("numpy")?.call_method1("dtype", (dtype,)) {
            Ok(d) => d.getattr("name")?.extract()?,
            Err(_) => {
                return Err(PyValueError::new_err(format!(
                    "dtype {} is not a NumPy dtype (expected float32 or uint8)",
                    dtype.repr()?
                )))
            }
        };
        match name.as_str() {
            "float32" => Ok(Dtype::F32),
            "uint8" => Ok(Dtype::U8),
            other => Err(PyValueError::new_err(format!(
                "observations come as float32 or uint8, not {other}"
            ))),
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Dtype::F32 => "float32",
            Dtype::U8 => "uint8",
        }
    }
}

/// A read-only NumPy array over `data`, kept alive by `owner`.
///
/// # Safety argument
/// `data` must live inside `owner` and never be reallocated while `owner` lives: the
/// buffers of `VecEnv` are allocated once in its constructor and only overwritten, so a
/// view shows the newest step's values (documented on `VecEnv.step`).
pub fn view<'py, T: Element>(
    owner: &Bound<'py, PyAny>,
    data: &[T],
    shape: &[usize],
) -> PyResult<Bound<'py, PyArrayDyn<T>>> {
    let array = ArrayViewD::from_shape(IxDyn(shape), data)
        .map_err(|e| PyValueError::new_err(format!("internal shape error: {e}")))?;
    // SAFETY: see above; the array's base object is `owner`, which owns `data`.
    let array = unsafe { PyArrayDyn::borrow_from_array(&array, owner.clone()) };
    // Read-only for Python: the buffers belong to the environment.
    drop(array.readwrite().make_nonwriteable());
    Ok(array)
}

/// An owned NumPy array of `data` in `shape`.
pub fn owned<'py, T: Element>(
    py: Python<'py>,
    data: Vec<T>,
    shape: &[usize],
) -> PyResult<Bound<'py, PyArrayDyn<T>>> {
    let array = numpy::ndarray::ArrayD::from_shape_vec(IxDyn(shape), data)
        .map_err(|e| PyValueError::new_err(format!("internal shape error: {e}")))?;
    Ok(PyArrayDyn::from_owned_array(py, array))
}

/// Integer actions from any array-like, as `u32`, and which of `shapes` they have. Refuses
/// floats and bools (TypeError), then any other shape (ValueError), then negative or
/// too-large values (IllegalActionError), with a message that says which.
pub fn actions(actions: &Bound<'_, PyAny>, shapes: &[&[usize]]) -> PyResult<(Vec<u32>, usize)> {
    // Fast paths for the dtypes NumPy and PyTorch hand over most often.
    if let Ok(a) = actions.extract::<PyReadonlyArrayDyn<'_, i64>>() {
        return convert(a, shapes);
    }
    if let Ok(a) = actions.extract::<PyReadonlyArrayDyn<'_, i32>>() {
        return convert(a, shapes);
    }
    let py = actions.py();
    let array = py.import("numpy")?.call_method1("asarray", (actions,))?;
    let kind: String = array.getattr("dtype")?.getattr("kind")?.extract()?;
    if kind != "i" && kind != "u" {
        let dtype = array.getattr("dtype")?.str()?.to_string();
        return Err(PyTypeError::new_err(format!(
            "actions must be integer action indices, got an array of dtype {dtype}"
        )));
    }
    if kind == "u" {
        let array = array.call_method1("astype", ("uint64",))?;
        return convert(array.extract::<PyReadonlyArrayDyn<'_, u64>>()?, shapes);
    }
    let array = array.call_method1("astype", ("int64",))?;
    convert(array.extract::<PyReadonlyArrayDyn<'_, i64>>()?, shapes)
}

fn convert<T>(array: PyReadonlyArrayDyn<'_, T>, shapes: &[&[usize]]) -> PyResult<(Vec<u32>, usize)>
where
    T: Element + Copy + TryInto<u32> + std::fmt::Display,
{
    let shape = array.shape();
    let Some(which) = shapes.iter().position(|s| *s == shape) else {
        let tuple = |s: &[usize]| match s {
            [n] => format!("({n},)"),
            _ => format!(
                "({})",
                s.iter()
                    .map(|d| d.to_string())
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        };
        let allowed: Vec<String> = shapes.iter().map(|s| tuple(s)).collect();
        return Err(PyValueError::new_err(format!(
            "actions must have shape {}, got {shape:?}",
            allowed.join(" or ")
        )));
    };
    let mut out = Vec::with_capacity(array.len());
    for &a in array.as_array().iter() {
        match a.try_into() {
            Ok(v) => out.push(v),
            Err(_) => {
                return Err(crate::errors::illegal(format!(
                    "action {a} is not an action index (indices are 0 or more)"
                )))
            }
        }
    }
    Ok((out, which))
}
