//! Scenario values between Python and TOML, directly (JSON has no infinity or NaN, which
//! a user may well put in a dict to see it refused by name).

use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};

/// How deep a scenario may nest (a dict that holds itself would recurse for ever).
const MAX_DEPTH: usize = 32;

/// A Python value as TOML: dicts (string keys), lists and tuples, str, bool, int, float,
/// and numpy's integers, booleans and floats (values taken from arrays or DataFrames);
/// `None` values of a dict are left out (TOML has no null: the key's default applies).
/// An unsupported value is a TypeError naming the dotted path to it.
pub fn to_toml(value: &Bound<'_, PyAny>, path: &str) -> PyResult<toml::Value> {
    to_toml_at(value, path, 0)
}

fn to_toml_at(value: &Bound<'_, PyAny>, path: &str, depth: usize) -> PyResult<toml::Value> {
    let fail = |what: String| PyTypeError::new_err(format!("scenario{path}: {what}"));
    if depth > MAX_DEPTH {
        return Err(fail(format!("nested more than {MAX_DEPTH} levels deep")));
    }
    if let Ok(dict) = value.cast::<PyDict>() {
        let mut table = toml::Table::new();
        for (key, item) in dict.iter() {
            let key: String = key
                .extract()
                .map_err(|_| fail("keys must be strings".into()))?;
            if item.is_none() {
                continue;
            }
            let inner = to_toml_at(&item, &format!("{path}.{key}"), depth + 1)?;
            table.insert(key, inner);
        }
        return Ok(toml::Value::Table(table));
    }
    if value.is_instance_of::<PyList>() || value.is_instance_of::<PyTuple>() {
        let items = value
            .try_iter()?
            .enumerate()
            .map(|(i, item)| to_toml_at(&item?, &format!("{path}[{i}]"), depth + 1))
            .collect::<PyResult<Vec<_>>>()?;
        return Ok(toml::Value::Array(items));
    }
    if value.is_instance_of::<PyString>() {
        return Ok(toml::Value::String(value.extract()?));
    }
    // bool before int (a Python bool is an int); numpy.bool_ is neither.
    if value.is_instance_of::<PyBool>() || is_numpy(value, &["bool", "bool_"])? {
        return Ok(toml::Value::Boolean(value.is_truthy()?));
    }
    // int, numpy integers: anything with __index__ is an integer, not a float.
    if value.is_instance_of::<PyInt>() || value.hasattr("__index__")? {
        let integer = value.call_method0("__index__")?;
        return integer
            .extract::<i64>()
            .map(toml::Value::Integer)
            .map_err(|_| fail(format!("{integer} does not fit in a 64-bit integer")));
    }
    if value.is_instance_of::<PyFloat>() {
        return Ok(toml::Value::Float(value.extract()?));
    }
    // numpy floats and other numbers: as a float when they convert to one.
    if let Ok(x) = value.extract::<f64>() {
        return Ok(toml::Value::Float(x));
    }
    Err(fail(format!(
        "a {} cannot be written to a scenario (use dict, list, str, bool, int or float)",
        value.get_type().name()?
    )))
}

/// Whether `value` is an instance of one of numpy's scalar types `names`.
fn is_numpy(value: &Bound<'_, PyAny>, names: &[&str]) -> PyResult<bool> {
    let kind = value.get_type();
    let module: String = kind.module()?.extract()?;
    let name: String = kind.name()?.extract()?;
    Ok(module == "numpy" && names.contains(&name.as_str()))
}

/// A TOML value as Python: tables as dicts, arrays as lists, date-times as strings.
pub fn to_python<'py>(py: Python<'py>, value: &toml::Value) -> PyResult<Bound<'py, PyAny>> {
    Ok(match value {
        toml::Value::String(s) => PyString::new(py, s).into_any(),
        toml::Value::Integer(i) => i.into_pyobject(py)?.into_any(),
        toml::Value::Float(x) => PyFloat::new(py, *x).into_any(),
        toml::Value::Boolean(b) => PyBool::new(py, *b).to_owned().into_any(),
        toml::Value::Datetime(d) => PyString::new(py, &d.to_string()).into_any(),
        toml::Value::Array(items) => {
            let list = PyList::empty(py);
            for item in items {
                list.append(to_python(py, item)?)?;
            }
            list.into_any()
        }
        toml::Value::Table(table) => {
            let dict = PyDict::new(py);
            for (key, item) in table {
                dict.set_item(key, to_python(py, item)?)?;
            }
            dict.into_any()
        }
    })
}
