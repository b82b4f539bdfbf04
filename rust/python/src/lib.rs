//! `sssbake._native`: the library behind the `sssbake` Python package
//! (python/sssbake). The package's Python side gives the friendly
//! signatures, reads in-memory USD stages with usd-core and defines the
//! exceptions; this side runs the library with the GIL released.

mod errors;
mod host;
mod profile;
mod run;
mod stage;
mod watch;

use pyo3::prelude::*;

/// The native module.
#[pymodule]
fn _native(module: &Bound<'_, PyModule>) -> PyResult<()> {
    module.add("VERSION", sssbake_io::VERSION)?;
    module.add("READ_STAGE", sssbake_io::usd_reader::READ_STAGE)?;
    module.add("WRITE_LAYER", sssbake_io::usd_writer::WRITE_LAYER)?;
    module.add_function(wrap_pyfunction!(run::bake, module)?)?;
    module.add_function(wrap_pyfunction!(run::plan, module)?)?;
    module.add_function(wrap_pyfunction!(run::report, module)?)?;
    module.add_function(wrap_pyfunction!(run::batch, module)?)?;
    module.add_function(wrap_pyfunction!(run::presets, module)?)?;
    module.add_function(wrap_pyfunction!(run::settings, module)?)?;
    module.add_function(wrap_pyfunction!(stage::uv_primvars, module)?)?;
    module.add_function(wrap_pyfunction!(profile::profile, module)?)?;
    module.add_function(wrap_pyfunction!(profile::profile_plot, module)?)?;
    module.add_function(wrap_pyfunction!(host::unwrap, module)?)?;
    module.add_function(wrap_pyfunction!(host::defaults, module)?)?;
    module.add_class::<host::PyScene>()?;
    module.add_class::<host::PyBakeResult>()?;
    Ok(())
}
