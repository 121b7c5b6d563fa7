//! Arguments from Python, checked by hand instead of by PyO3's extraction,
//! so that every bad argument is a `ValueError` naming the argument, its
//! value and what is allowed (PyO3 would raise `TypeError` for `1.5` where
//! an integer is expected and `OverflowError` for `-1` or `2**70`), and
//! NumPy values of any dtype are converted where that is exact or
//! sensible (integers and float32 to float64) or refused by name
//! (complex, object, strings).

use crate::errors::Failure;
use numpy::{
    PyArrayDescrMethods, PyArrayDyn, PyArrayMethods, PyUntypedArray, PyUntypedArrayMethods,
};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyFloat, PyInt, PyString};
use std::path::PathBuf;

/// A Python scalar sorted by what it can stand for.
pub enum Scalar {
    Bool(bool),
    /// An integer (Python or NumPy); `None` when it does not fit an i128.
    Int(Option<i128>),
    Float(f64),
    Str(String),
    /// Anything else: its type name (`NoneType`, `bytes`, `complex128`…).
    Other(String),
}

/// The type name of `obj`, as Python prints it.
pub fn type_name(obj: &Bound<'_, PyAny>) -> String {
    obj.get_type()
        .name()
        .map_or_else(|_| "?".to_string(), |n| n.to_string())
}

/// `repr(obj)`, cut to 80 characters.
pub fn repr(obj: &Bound<'_, PyAny>) -> String {
    let text = obj
        .repr()
        .map_or_else(|_| "?".to_string(), |r| r.to_string());
    if text.chars().count() > 80 {
        format!("{}…", text.chars().take(80).collect::<String>())
    } else {
        text
    }
}

fn numpy_type<'py>(py: Python<'py>, name: &str) -> Option<Bound<'py, PyAny>> {
    py.import("numpy").ok()?.getattr(name).ok()
}

fn is_numpy(obj: &Bound<'_, PyAny>, name: &str) -> bool {
    numpy_type(obj.py(), name).is_some_and(|t| obj.is_instance(&t).unwrap_or(false))
}

/// Sorts a scalar: bool and `numpy.bool_` → Bool; int and `numpy.integer`
/// → Int; float and `numpy.floating` (float16/32/64, longdouble) → Float;
/// str → Str; the rest (None, bytes, complex, NumPy complex…) → Other.
pub fn scalar(obj: &Bound<'_, PyAny>) -> Scalar {
    if obj.is_instance_of::<PyBool>() || is_numpy(obj, "bool_") {
        return Scalar::Bool(obj.is_truthy().unwrap_or(false));
    }
    if obj.is_instance_of::<PyInt>() || is_numpy(obj, "integer") {
        return Scalar::Int(obj.extract::<i128>().ok());
    }
    if obj.is_instance_of::<PyFloat>() || is_numpy(obj, "floating") {
        return match obj.extract::<f64>() {
            Ok(x) => Scalar::Float(x),
            Err(_) => Scalar::Other(type_name(obj)),
        };
    }
    if obj.is_instance_of::<PyString>() {
        if let Ok(s) = obj.extract::<String>() {
            return Scalar::Str(s);
        }
    }
    Scalar::Other(type_name(obj))
}

/// A whole number in `min..=max` (Python int or NumPy integer; not a
/// bool, not a float even if whole).
pub fn whole(obj: &Bound<'_, PyAny>, name: &str, min: u64, max: u64) -> Result<u64, Failure> {
    let allowed = format!("allowed: a whole number from {min} to {max}");
    match scalar(obj) {
        Scalar::Int(Some(n)) if n >= i128::from(min) && n <= i128::from(max) => Ok(n as u64),
        Scalar::Int(_) => Err(Failure::Input(format!("{name}: {} ({allowed})", repr(obj)))),
        _ => Err(Failure::Input(format!(
            "{name}: {} of type {} ({allowed})",
            repr(obj),
            type_name(obj)
        ))),
    }
}

/// [`whole`] as a usize.
pub fn index(obj: &Bound<'_, PyAny>, name: &str, min: usize, max: usize) -> Result<usize, Failure> {
    // usize ≤ 64 bits on every target PyO3 supports.
    whole(obj, name, min as u64, max as u64).map(|n| n as usize)
}

/// A real number (Python int or float, NumPy integer or floating), not
/// a bool; its range is the caller's to check.
pub fn real(obj: &Bound<'_, PyAny>, name: &str) -> Result<f64, Failure> {
    match scalar(obj) {
        Scalar::Float(x) => Ok(x),
        Scalar::Int(Some(n)) => Ok(n as f64),
        _ => Err(Failure::Input(format!(
            "{name}: {} of type {} (allowed: a real number)",
            repr(obj),
            type_name(obj)
        ))),
    }
}

/// The most worker threads (as `dembound scene --threads`).
pub const MAX_THREADS: usize = 1024;

/// `threads=`: 1 (None) or 1 to [`MAX_THREADS`].
pub fn threads(obj: Option<&Bound<'_, PyAny>>) -> Result<usize, Failure> {
    match obj {
        None => Ok(1),
        Some(t) if t.is_none() => Ok(1),
        Some(t) => index(t, "threads", 1, MAX_THREADS),
    }
}

/// A file or directory path: str or `os.PathLike`.
pub fn path(obj: &Bound<'_, PyAny>, name: &str) -> Result<PathBuf, Failure> {
    let refuse = || {
        Failure::Input(format!(
            "{name}: {} of type {} (allowed: a path, str or os.PathLike)",
            repr(obj),
            type_name(obj)
        ))
    };
    if obj.is_none() {
        return Err(refuse());
    }
    let path: PathBuf = obj.extract().map_err(|_| refuse())?;
    if path.as_os_str().is_empty() {
        return Err(Failure::Input(format!(
            "{name}: '' (allowed: a non-empty path)"
        )));
    }
    Ok(path)
}

/// `sets=`: a list (or tuple) of `key=value` strings.
pub fn sets(obj: Option<&Bound<'_, PyAny>>) -> Result<Vec<String>, Failure> {
    let Some(obj) = obj.filter(|o| !o.is_none()) else {
        return Ok(Vec::new());
    };
    if obj.is_instance_of::<PyString>() {
        return Err(Failure::Input(format!(
            "sets: {} is one str (allowed: a list of `key=value` strings, [{}])",
            repr(obj),
            repr(obj)
        )));
    }
    let refuse = |why: String| {
        Failure::Input(format!(
            "sets: {why} (allowed: a list of `key=value` strings)"
        ))
    };
    let items = obj
        .try_iter()
        .map_err(|_| refuse(format!("{} of type {}", repr(obj), type_name(obj))))?;
    let mut out = Vec::new();
    for (i, item) in items.enumerate() {
        let item = item.map_err(|e| refuse(e.to_string()))?;
        match scalar(&item) {
            Scalar::Str(s) => out.push(s),
            _ => {
                return Err(refuse(format!(
                    "item {i} is {} of type {}",
                    repr(&item),
                    type_name(&item)
                )))
            }
        }
    }
    Ok(out)
}

/// The dtype kinds converted to float64 exactly (integers, floats).
fn numeric_kind(kind: u8) -> bool {
    matches!(kind, b'i' | b'u' | b'f')
}

/// `numpy.asarray(obj)`, refusing what NumPy cannot make an array of
/// (ragged lists).
fn as_array<'py>(
    obj: &Bound<'py, PyAny>,
    name: &str,
) -> Result<Bound<'py, PyUntypedArray>, Failure> {
    let np = obj
        .py()
        .import("numpy")
        .map_err(|e| Failure::Failed(format!("cannot import numpy: {e}")))?;
    let array = np
        .call_method1("asarray", (obj,))
        .map_err(|e| Failure::Input(format!("{name}: not an array of numbers: {e}")))?;
    array
        .cast_into::<PyUntypedArray>()
        .map_err(|_| Failure::Input(format!("{name}: not an array of numbers")))
}

/// An array of numbers with `shape` (`None`: any length on that axis) as
/// float64 values, row-major: any integer or float dtype is converted;
/// complex, bool, object, string dtypes are refused naming the dtype.
pub fn floats(
    obj: &Bound<'_, PyAny>,
    name: &str,
    shape: &[Option<usize>],
) -> Result<(Vec<f64>, Vec<usize>), Failure> {
    let want = shape
        .iter()
        .map(|d| d.map_or("n".to_string(), |n| n.to_string()))
        .collect::<Vec<_>>()
        .join(", ");
    let want = if shape.len() == 1 {
        format!("({want},)")
    } else {
        format!("({want})")
    };
    if obj.is_none() {
        return Err(Failure::Input(format!(
            "{name}: None (allowed: an array of real numbers of shape {want})"
        )));
    }
    let array = as_array(obj, name)?;
    let dtype = array.dtype();
    if !numeric_kind(dtype.kind()) {
        return Err(Failure::Input(format!(
            "{name}: an array of dtype {} (allowed: integers or floats, converted to float64)",
            dtype
                .str()
                .map_or_else(|_| "?".to_string(), |s| s.to_string())
        )));
    }
    let got = array.shape().to_vec();
    let fits = got.len() == shape.len()
        && got
            .iter()
            .zip(shape)
            .all(|(g, w)| w.is_none_or(|w| *g == w));
    if !fits {
        return Err(Failure::Input(format!(
            "{name}: shape {got:?}, expected {want}"
        )));
    }
    let converted = array
        .call_method1("astype", ("float64",))
        .map_err(|e| Failure::Input(format!("{name}: cannot convert to float64: {e}")))?;
    let converted = converted
        .cast_into::<PyArrayDyn<f64>>()
        .map_err(|_| Failure::Failed(format!("{name}: astype(float64) gave no float64 array")))?;
    let values = converted
        .to_vec()
        .map_err(|e| Failure::Failed(format!("{name}: {e}")))?;
    Ok((values, got))
}

/// An (n,) array of flags: bool dtype, or integers that are all 0 or 1.
pub fn flags(obj: &Bound<'_, PyAny>, name: &str, n: usize) -> Result<Vec<bool>, Failure> {
    let array = as_array(obj, name)?;
    let kind = array.dtype().kind();
    if array.shape() != [n] {
        return Err(Failure::Input(format!(
            "{name}: shape {:?}, expected ({n},)",
            array.shape()
        )));
    }
    if kind == b'b' {
        return array
            .cast_into::<PyArrayDyn<bool>>()
            .map_err(|e| Failure::Failed(format!("{name}: {e}")))?
            .to_vec()
            .map_err(|e| Failure::Failed(format!("{name}: {e}")));
    }
    let refuse = || {
        Failure::Input(format!(
            "{name}: an array of dtype {} (allowed: booleans, or integers 0 and 1)",
            array
                .dtype()
                .str()
                .map_or_else(|_| "?".to_string(), |s| s.to_string())
        ))
    };
    if !matches!(kind, b'i' | b'u') {
        return Err(refuse());
    }
    let (values, _) = floats(obj, name, &[Some(n)])?;
    if values.iter().any(|x| *x != 0.0 && *x != 1.0) {
        return Err(refuse());
    }
    Ok(values.iter().map(|x| *x == 1.0).collect())
}
