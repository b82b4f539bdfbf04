//! The library's errors as the package's exceptions (python/sssbake/errors.py):
//! one class per kind, carrying the file, object and field where known.

use pyo3::prelude::*;
use pyo3::types::PyDict;
use sssbake::Error;

/// `error` as an instance of its kind's class in `sssbake.errors`.
pub fn to_python(py: Python<'_>, error: Error) -> PyErr {
    match build(py, &error) {
        Ok(exception) => exception,
        // The package itself is broken: say what the library said anyway.
        Err(broken) => broken,
    }
}

fn build(py: Python<'_>, error: &Error) -> PyResult<PyErr> {
    let module = py.import("sssbake.errors")?;
    let details = PyDict::new(py);
    let class = match error {
        Error::Input(input) => {
            details.set_item("file", &input.file)?;
            details.set_item("object", &input.object)?;
            details.set_item("field", &input.field)?;
            "InputError"
        }
        Error::Setting { field, .. } => {
            details.set_item("field", field)?;
            "SettingError"
        }
        Error::Output { path, .. } => {
            details.set_item("file", path)?;
            "OutputError"
        }
        Error::Cancelled => "Cancelled",
    };
    // The limits as the keyword arguments call them.
    let message = error
        .clone()
        .naming_limit(|field| format!("the {field} argument"))
        .to_string();
    let instance = module.getattr(class)?.call((message,), Some(&details))?;
    Ok(PyErr::from_value(instance))
}

/// Runs `work`, turning a library error into its exception.
pub fn or_raise<T>(py: Python<'_>, result: Result<T, Error>) -> PyResult<T> {
    result.map_err(|e| to_python(py, e))
}
