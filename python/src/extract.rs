//! `lplace.extract`: a CARMEN log turned into a percept stream, as `lplace extract --from carmen`
//! writes it (the same `io::carmen_stream::convert`, the same JSON per frame), with malformed
//! log lines returned rather than printed.

use lplace::io::carmen_stream::{convert, CarmenFramer};
use lplace::map::Map;
use lplace::percept::ExtractConfig;
use lplace::syntax::diagnostic::SourceFile;
use lplace::syntax::parse_map;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::io::Write;

/// Converts the CARMEN log at `log`. `map_path` gives each frame's true place; `config` is the
/// extractor's RON text. Frames go to the file `out` when given (and are then not returned),
/// else they are returned as a list of JSON lines. Returns a dict with `records`, `frames`,
/// `lines`, `lasers`, `odoms`, `malformed` (a list of messages, one per skipped log line).
#[pyfunction]
#[pyo3(signature = (log, map_path = None, config = None, out = None))]
pub(crate) fn extract_carmen<'py>(
    py: Python<'py>,
    log: std::path::PathBuf,
    map_path: Option<std::path::PathBuf>,
    config: Option<&str>,
    out: Option<std::path::PathBuf>,
) -> PyResult<Bound<'py, PyDict>> {
    let mut cfg = match config {
        // As `lplace extract` without `--config`.
        None => ExtractConfig::travelling(),
        Some(text) => {
            ExtractConfig::from_ron(text).map_err(|e| PyValueError::new_err(e.to_string()))?
        }
    };
    let map = match &map_path {
        None => None,
        Some(p) => {
            let src = SourceFile::new(p.display().to_string(), std::fs::read_to_string(p)?);
            let render = |d: Vec<lplace::syntax::diagnostic::Diagnostic>| {
                let text: String = d.iter().map(|d| d.render_plain(&src)).collect();
                PyValueError::new_err(format!("map {}:\n{text}", src.name))
            };
            let ast = parse_map(&src.text).map_err(render)?;
            Some(Map::from_ast(&ast).map_err(render)?)
        }
    };
    // As `lplace extract`: the map's `axis` statement is the building's axis.
    if let Some(axis) = map.as_ref().and_then(Map::axis_deg) {
        cfg.compass.axis_deg = axis;
    }
    let file = std::fs::File::open(&log)?;
    let mut framer = CarmenFramer::new(cfg, map.as_ref().map(Map::places))
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    let mut sink = match &out {
        Some(p) => Some(std::io::BufWriter::new(std::fs::File::create(p)?)),
        None => None,
    };
    let mut records: Vec<String> = Vec::new();
    let mut malformed: Vec<String> = Vec::new();
    let summary = py.allow_threads(|| {
        convert(
            std::io::BufReader::new(file),
            &mut framer,
            |frame| -> std::io::Result<()> {
                let line = serde_json::to_string(&frame).map_err(std::io::Error::from)?;
                match &mut sink {
                    Some(w) => {
                        w.write_all(line.as_bytes())?;
                        w.write_all(b"\n")
                    }
                    None => {
                        records.push(line);
                        Ok(())
                    }
                }
            },
            |e| malformed.push(e.to_string()),
        )
        .and_then(|s| {
            if let Some(w) = &mut sink {
                w.flush()?;
            }
            Ok(s)
        })
    })?;
    let d = PyDict::new(py);
    d.set_item("records", if out.is_some() { None } else { Some(records) })?;
    d.set_item("frames", summary.frames)?;
    d.set_item("lines", summary.stats.lines)?;
    d.set_item("lasers", summary.stats.lasers)?;
    d.set_item("odoms", summary.stats.odoms)?;
    d.set_item("malformed", malformed)?;
    Ok(d)
}
