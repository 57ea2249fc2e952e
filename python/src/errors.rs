//! Crate errors as Python exceptions.
//!
//! `CheckError` is a plain Python class (`lplace/_errors.py`) so that it can carry attributes
//! under the stable ABI, where a Rust class cannot extend `Exception`; it is looked up when raised.

use lplace::engine::LoadError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// A load error as `lplace.CheckError(message, path, line, column, diagnostics)`, where the
/// position is the first error's and `diagnostics` lists every problem as a dict.
pub(crate) fn check_error(py: Python<'_>, e: &LoadError) -> PyErr {
    match build_check_error(py, e) {
        Ok(err) => err,
        Err(err) => err,
    }
}

fn build_check_error(py: Python<'_>, e: &LoadError) -> PyResult<PyErr> {
    let class = py.import("lplace._errors")?.getattr("CheckError")?;
    let mut items = Vec::with_capacity(e.diagnostics.len());
    let mut rendered = String::new();
    for d in &e.diagnostics {
        let (line, column) = d.line_col(&e.file);
        let text = d.render_plain(&e.file);
        let item = PyDict::new(py);
        item.set_item("path", &e.file.name)?;
        item.set_item("line", line)?;
        item.set_item("column", column)?;
        item.set_item("severity", if d.is_error() { "error" } else { "warning" })?;
        item.set_item("message", d.to_string())?;
        item.set_item("rendered", &text)?;
        items.push(item);
        rendered.push_str(&text);
    }
    // The position is the first error's (a warning may come before it in a cross-file check).
    let first = e
        .diagnostics
        .iter()
        .find(|d| d.is_error())
        .or(e.diagnostics.first());
    let (line, column) = first.map_or((0, 0), |d| d.line_col(&e.file));
    let message = format!("{e}\n{rendered}");
    let value = class.call1((message, &e.file.name, line, column, items))?;
    Ok(PyErr::from_value(value))
}
