//! The `lplace._lplace` extension module: the engine ([`engine`]), stream evaluation
//! ([`stream`]), CARMEN extraction ([`extract`]) and map surveys ([`survey`]) of the `lplace`
//! crate, for the pure-Python package `lplace` (python/lplace) that wraps them into numpy
//! arrays, pyarrow tables and Ray tasks.
//!
//! Nothing here decides anything: every decision, summary, percept stream and surveyed map comes
//! from the crate's own code (`Engine`, `report::StreamRun`, `io::carmen_stream`,
//! `survey::Survey`), so that Python and the command line give the same results. This crate only converts values and errors at the
//! boundary and releases the GIL around long loops. Errors cross as Python exceptions:
//! diagnostics as `lplace.CheckError` (defined in Python, `lplace/_errors.py`), bad arguments as
//! `ValueError`/`KeyError`/`TypeError`, unreadable files as `OSError`.
//!
//! Depends on `lplace` (its default features, so that the crate built for the command line is
//! reused), pyo3 and numpy.

use pyo3::prelude::*;

mod engine;
mod errors;
mod extract;
mod stream;
mod survey;

/// The bundled office recording, which `lplace eval` reads when given no stream.
const OFFICE_RECORDING: &str = include_str!("../../recordings/office.jsonl");

#[pymodule]
fn _lplace(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<engine::PyEngine>()?;
    m.add_class::<engine::PyDecision>()?;
    m.add_class::<stream::StreamBatches>()?;
    m.add_function(wrap_pyfunction!(stream::evaluate_columns, m)?)?;
    m.add_function(wrap_pyfunction!(extract::extract_carmen, m)?)?;
    m.add_function(wrap_pyfunction!(survey::survey_run, m)?)?;
    m.add_function(wrap_pyfunction!(engine::rust_loop_ns, m)?)?;
    m.add("REASONS", stream::REASONS.to_vec())?;
    m.add("OFFICE_MAP", lplace::engine::OFFICE_MAP)?;
    m.add("OFFICE_RULES", lplace::engine::OFFICE_RULES)?;
    m.add("OFFICE_RECORDING", OFFICE_RECORDING)?;
    Ok(())
}
