//! A Python dict with the scene file's structure as a TOML table, every
//! value checked with its key path (`material[0].density`) in the error,
//! and nesting bounded: a dict nested 30,000 deep made the generic
//! converter (pythonize) recurse until the stack overflowed (a segfault);
//! here it is a `ValueError` at [`MAX_DEPTH`] levels, and no value deeper
//! than that is ever built (dropping one would recurse too).

use crate::args::{repr, scalar, type_name, Scalar};
use crate::errors::Failure;
use numpy::{PyArrayDescrMethods, PyUntypedArray, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyMapping, PyTuple};

/// The deepest nesting of tables and lists accepted (the root table is
/// level 1). A scene file needs 6: the root, the `particles` list, one
/// group, its `spheres` list, one sphere, its `position`; 32 leaves room
/// for any future key and is far below what the stack holds (each level
/// takes a few hundred bytes of the thread's stack, which is at least
/// 2 MiB).
pub const MAX_DEPTH: usize = 32;

const ALLOWED: &str =
    "allowed: a number, a bool, a str, a list or a dict; leave a key out for its default";

fn refuse(path: &str, why: String) -> Failure {
    Failure::Input(format!("scene dict: `{path}`: {why}"))
}

/// The dict `scene` as a TOML table.
pub fn table(scene: &Bound<'_, PyAny>) -> Result<toml::Table, Failure> {
    if scene.cast::<PyDict>().is_err() && scene.cast::<PyMapping>().is_err() {
        return Err(Failure::Input(format!(
            "scene: {} of type {} (allowed: a dict with the scene file's structure)",
            repr(scene),
            type_name(scene)
        )));
    }
    match value(scene, "", 1)? {
        toml::Value::Table(t) => Ok(t),
        _ => Err(Failure::Failed(
            "scene dict: the root is not a table".into(),
        )),
    }
}

fn joined(path: &str, key: &str) -> String {
    if path.is_empty() {
        key.to_string()
    } else {
        format!("{path}.{key}")
    }
}

/// The path as shown: `<root>` for the dict itself.
fn shown(path: &str) -> &str {
    if path.is_empty() {
        "<root>"
    } else {
        path
    }
}

fn too_deep(path: &str) -> Failure {
    Failure::Input(format!(
        "scene dict: `{}…` is nested deeper than {MAX_DEPTH} levels of dicts and lists (a scene needs at most 6)",
        path.chars().take(120).collect::<String>()
    ))
}

/// `obj` at `path`, `depth` levels down (the root dict is level 1).
fn value(obj: &Bound<'_, PyAny>, path: &str, depth: usize) -> Result<toml::Value, Failure> {
    let nested = |obj: &Bound<'_, PyAny>| {
        obj.cast::<PyDict>().is_ok()
            || obj.cast::<PyList>().is_ok()
            || obj.cast::<PyTuple>().is_ok()
            || obj.cast::<PyMapping>().is_ok()
            || obj.cast::<PyUntypedArray>().is_ok()
    };
    if nested(obj) && depth > MAX_DEPTH {
        return Err(too_deep(path));
    }
    if let Ok(array) = obj.cast::<PyUntypedArray>() {
        // Integers, floats (float32 → float64 exactly) and booleans, as
        // the nested lists `tolist()` gives.
        let dtype = array.dtype();
        if !matches!(dtype.kind(), b'b' | b'i' | b'u' | b'f') {
            return Err(refuse(
                shown(path),
                format!(
                    "a NumPy array of dtype {} (allowed: integers, floats or booleans)",
                    dtype
                        .str()
                        .map_or_else(|_| "?".to_string(), |s| s.to_string())
                ),
            ));
        }
        let list = obj
            .call_method0("tolist")
            .map_err(|e| Failure::Failed(format!("scene dict: `{path}`: tolist(): {e}")))?;
        if list.cast::<PyUntypedArray>().is_ok() {
            return Err(Failure::Failed(format!(
                "scene dict: `{path}`: tolist() gave an array"
            )));
        }
        return value(&list, path, depth);
    }
    let items = if let Ok(dict) = obj.cast::<PyDict>() {
        Some(dict.items().into_any())
    } else if let Ok(mapping) = obj.cast::<PyMapping>() {
        Some(
            mapping
                .items()
                .map_err(|e| refuse(shown(path), format!("cannot read its items: {e}")))?
                .into_any(),
        )
    } else {
        None
    };
    if let Some(items) = items {
        let mut table = toml::Table::new();
        let items = items
            .try_iter()
            .map_err(|e| refuse(shown(path), format!("cannot read its items: {e}")))?;
        for item in items {
            let item =
                item.map_err(|e| refuse(shown(path), format!("cannot read its items: {e}")))?;
            let (key, v): (Bound<'_, PyAny>, Bound<'_, PyAny>) = item
                .extract()
                .map_err(|e| refuse(shown(path), format!("cannot read its items: {e}")))?;
            let key = match scalar(&key) {
                Scalar::Str(k) => k,
                _ => {
                    return Err(refuse(
                        shown(path),
                        format!(
                            "the key {} is of type {} (allowed: str keys)",
                            repr(&key),
                            type_name(&key)
                        ),
                    ))
                }
            };
            let converted = value(&v, &joined(path, &key), depth + 1)?;
            table.insert(key, converted);
        }
        return Ok(toml::Value::Table(table));
    }
    if obj.cast::<PyList>().is_ok() || obj.cast::<PyTuple>().is_ok() {
        let mut array = Vec::new();
        let items = obj
            .try_iter()
            .map_err(|e| refuse(shown(path), format!("cannot read its items: {e}")))?;
        for (i, item) in items.enumerate() {
            let item =
                item.map_err(|e| refuse(shown(path), format!("cannot read its items: {e}")))?;
            array.push(value(&item, &format!("{path}[{i}]"), depth + 1)?);
        }
        return Ok(toml::Value::Array(array));
    }
    match scalar(obj) {
        Scalar::Bool(b) => Ok(toml::Value::Boolean(b)),
        Scalar::Int(Some(n)) => i64::try_from(n).map(toml::Value::Integer).map_err(|_| {
            refuse(
                path,
                format!("{n} does not fit a 64-bit integer (allowed: −2^63 to 2^63 − 1; a float for a larger value)"),
            )
        }),
        Scalar::Int(None) => Err(refuse(
            path,
            format!(
                "{} does not fit a 64-bit integer (allowed: −2^63 to 2^63 − 1; a float for a larger value)",
                repr(obj)
            ),
        )),
        Scalar::Float(x) => Ok(toml::Value::Float(x)),
        Scalar::Str(s) => Ok(toml::Value::String(s)),
        Scalar::Other(t) => Err(refuse(path, format!("{} of type {t} ({ALLOWED})", repr(obj)))),
    }
}
