//! Python bindings of shotdamp: the module `shotdamp._native`, wrapped by the pure-Python
//! package `shotdamp` (python/shotdamp). Every computation runs the library's own code paths
//! (the same numbers as the command line, bit for bit), with the interpreter lock released,
//! on a thread that a Ctrl-C stops at its next simulated point. Nothing panics across the
//! boundary: a panic becomes a Python `RuntimeError`.

mod compute;
mod convert;
mod runs;
mod structure;
mod system;

use pyo3::prelude::*;

/// The native part of the `shotdamp` package.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_class::<structure::Structure>()?;
    m.add_class::<structure::Damper>()?;
    m.add_class::<system::System>()?;
    m.add_class::<system::Steady>()?;
    m.add_class::<system::Orbit>()?;
    m.add_class::<runs::Experiment>()?;
    m.add_function(wrap_pyfunction!(runs::load, m)?)?;
    m.add_function(wrap_pyfunction!(runs::run_experiment, m)?)?;
    m.add_function(wrap_pyfunction!(runs::design, m)?)?;
    m.add_function(wrap_pyfunction!(runs::report, m)?)?;
    m.add_function(wrap_pyfunction!(runs::study, m)?)?;
    m.add_function(wrap_pyfunction!(runs::study_merge, m)?)?;
    Ok(())
}
