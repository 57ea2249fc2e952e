//! `lplace.Engine` and `lplace.Decision`: load, look up slots, step one frame (a dict or numpy
//! arrays) or many (an `n_frames × n_slots` array, GIL released).
//!
//! The per-frame path reuses one [`Frame`] held by the engine object, so a Python `step`
//! allocates only the returned `Decision` (its per-place arrays are made when first read), and
//! takes its arrays without numpy's borrow registry and its place name from interned strings:
//! those two were most of the cost Python added to a step.

use crate::errors::check_error;
use crate::stream::reason_code;
use lplace::engine::{Engine, Frame};
use lplace::logic::Decision;
use lplace::report::summary::reason_name;
use lplace::syntax::diagnostic::SourceFile;
use numpy::{PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::exceptions::{PyKeyError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyString, PyTuple};

/// A loaded and compiled map + rule file, with the buffers one step needs.
#[pyclass(module = "lplace._lplace", name = "Engine")]
pub struct PyEngine {
    pub(crate) engine: Engine,
    frame: Frame,
    /// The place names as Python strings, made once: a step hands out a reference.
    place_names: Vec<Py<PyString>>,
}

impl PyEngine {
    fn wrap(py: Python<'_>, engine: Engine) -> PyEngine {
        let frame = engine.new_frame();
        let place_names = engine
            .map()
            .places()
            .iter()
            .map(|p| PyString::intern(py, &p.name).unbind())
            .collect();
        PyEngine {
            engine,
            frame,
            place_names,
        }
    }

    fn decision(&self, py: Python<'_>, d: Decision) -> PyDecision {
        let dist = self.engine.distribution();
        let (place_index, necessity, reason) = match d {
            Decision::Place { place, necessity } => (Some(place), Some(necessity), None),
            Decision::Disoriented(why) => (None, None, Some(reason_name(&why))),
        };
        PyDecision {
            place: place_index.and_then(|k| self.place_names.get(k).map(|p| p.clone_ref(py))),
            place_index,
            necessity,
            inconsistency: dist.inconsistency,
            reason,
            support: dist.support.clone(),
            possibility: dist.possibility.clone(),
            necessities: dist.necessity.clone(),
        }
    }

    /// Fills the engine's frame from `{"name(args)": degree | (degree, value)}`; an unknown key
    /// is a `KeyError` naming it (the whole frame is refused, as `lplace eval --frame` does).
    fn fill_from_dict(&mut self, frame: &Bound<'_, PyDict>) -> PyResult<()> {
        self.frame.clear();
        for (key, item) in frame.iter() {
            let key: String = key.extract().map_err(|_| {
                PyTypeError::new_err("frame keys must be strings like \"sonar_wall(North)\"")
            })?;
            let (name, args) = split_instance(&key)
                .ok_or_else(|| PyKeyError::new_err(format!("malformed percept `{key}`")))?;
            let slot = self
                .engine
                .percepts()
                .slot(name, &args)
                .ok_or_else(|| PyKeyError::new_err(format!("unknown percept `{key}`")))?;
            let (degree, value) = if let Ok(t) = item.downcast::<PyTuple>() {
                if t.len() != 2 {
                    return Err(PyValueError::new_err(format!(
                        "percept `{key}`: expected a degree or a (degree, value) pair"
                    )));
                }
                let value: Option<f64> = t.get_item(1)?.extract()?;
                (t.get_item(0)?.extract::<f64>()?, value)
            } else {
                (item.extract::<f64>()?, None)
            };
            self.frame.set(slot, degree, value);
        }
        Ok(())
    }

    fn fill_from_arrays(
        &mut self,
        degrees: &Bound<'_, PyAny>,
        values: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        copy_row(&mut self.frame.degree, degrees, "degrees")?;
        match values {
            None => self.frame.value.fill(f64::NAN),
            Some(v) => copy_row(&mut self.frame.value, v, "values")?,
        }
        Ok(())
    }
}

/// Copies a contiguous float64 array of `dst.len()` entries into `dst`.
///
/// The array is read without taking a borrow in numpy's registry (`PyReadonlyArray1`): that
/// registry costs about as much as the rest of the call. The registry guards only against other
/// Rust borrows; here the GIL is held from the type check to the end of the copy, no Python code
/// runs in between, and this crate never holds a mutable view of a caller's array, so the read
/// is as safe as numpy's own C code reading it.
fn copy_row(dst: &mut [f64], src: &Bound<'_, PyAny>, what: &str) -> PyResult<()> {
    let array = src.downcast::<PyArray1<f64>>()?;
    // SAFETY: see above; `as_slice` itself refuses arrays that are not contiguous.
    let row = unsafe { array.as_slice() }?;
    if row.len() != dst.len() {
        return Err(PyValueError::new_err(format!(
            "{what} has {} entries, the engine has {} slots",
            row.len(),
            dst.len()
        )));
    }
    dst.copy_from_slice(row);
    Ok(())
}

/// `name(a, b)` → (`name`, [`a`, `b`]); `name` → (`name`, []). `None` when the parentheses
/// do not close at the end.
fn split_instance(key: &str) -> Option<(&str, Vec<&str>)> {
    let key = key.trim();
    match key.find('(') {
        None => Some((key, Vec::new())),
        Some(open) => {
            let inner = key.get(open + 1..)?.strip_suffix(')')?;
            let args = if inner.trim().is_empty() {
                Vec::new()
            } else {
                inner.split(',').map(str::trim).collect()
            };
            Some((key[..open].trim(), args))
        }
    }
}

/// Outputs of [`step_rows`]: one entry (or one row of `places` entries) per frame.
struct Columns {
    place: Vec<i64>,
    necessity: Vec<f64>,
    inconsistency: Vec<f64>,
    reason: Vec<i8>,
    support: Vec<f64>,
    possibility: Vec<f64>,
    necessities: Vec<f64>,
}

/// Steps the `n` rows of `degrees`/`values` (row-major, `slots` wide) through `engine` into
/// `frame`; pure Rust, run with the GIL released.
fn step_rows(
    engine: &mut Engine,
    frame: &mut Frame,
    n: usize,
    degrees: &[f64],
    values: Option<&[f64]>,
    slots: usize,
) -> Columns {
    let k = engine.map().places().len();
    let mut c = Columns {
        place: Vec::with_capacity(n),
        necessity: Vec::with_capacity(n),
        inconsistency: Vec::with_capacity(n),
        reason: Vec::with_capacity(n),
        support: Vec::with_capacity(n * k),
        possibility: Vec::with_capacity(n * k),
        necessities: Vec::with_capacity(n * k),
    };
    for i in 0..n {
        // `rows` checked that both arrays hold `n × slots` entries.
        let row = i * slots..(i + 1) * slots;
        if let Some(d) = degrees.get(row.clone()) {
            frame.degree.copy_from_slice(d);
        }
        match values.and_then(|v| v.get(row)) {
            Some(v) => frame.value.copy_from_slice(v),
            None => frame.value.fill(f64::NAN),
        }
        let d = engine.step(frame);
        let dist = engine.distribution();
        match d {
            Decision::Place { place, necessity } => {
                c.place.push(place as i64);
                c.necessity.push(necessity);
                c.reason.push(-1);
            }
            Decision::Disoriented(why) => {
                c.place.push(-1);
                c.necessity.push(f64::NAN);
                c.reason.push(reason_code(&why));
            }
        }
        c.inconsistency.push(dist.inconsistency);
        c.support.extend_from_slice(&dist.support);
        c.possibility.extend_from_slice(&dist.possibility);
        c.necessities.extend_from_slice(&dist.necessity);
    }
    c
}

/// Checks a `(n, slots)` C-contiguous float64 array and returns its rows as one slice.
fn rows<'a>(
    a: &'a PyReadonlyArray2<'_, f64>,
    slots: usize,
    what: &str,
) -> PyResult<(usize, &'a [f64])> {
    let shape = a.shape();
    if shape[1] != slots {
        return Err(PyValueError::new_err(format!(
            "{what} has {} columns, the engine has {slots} slots",
            shape[1]
        )));
    }
    Ok((shape[0], a.as_slice()?))
}

#[pymethods]
impl PyEngine {
    /// Loads, checks and compiles a map file and a rule file.
    #[staticmethod]
    fn load(
        py: Python<'_>,
        map_path: std::path::PathBuf,
        rules_path: std::path::PathBuf,
    ) -> PyResult<Self> {
        let read = |p: &std::path::Path| -> PyResult<SourceFile> {
            let text = std::fs::read_to_string(p)?;
            Ok(SourceFile::new(p.display().to_string(), text))
        };
        let (map, rules) = (read(&map_path)?, read(&rules_path)?);
        Engine::load(&map, &rules)
            .map(|e| PyEngine::wrap(py, e))
            .map_err(|e| check_error(py, &e))
    }

    /// Loads from the texts of a map and a rule file (named in diagnostics by `map_name`,
    /// `rules_name`).
    #[staticmethod]
    #[pyo3(signature = (map_text, rules_text, map_name = "<map>", rules_name = "<rules>"))]
    fn from_strings(
        py: Python<'_>,
        map_text: &str,
        rules_text: &str,
        map_name: &str,
        rules_name: &str,
    ) -> PyResult<Self> {
        let map = SourceFile::new(map_name, map_text);
        let rules = SourceFile::new(rules_name, rules_text);
        Engine::load(&map, &rules)
            .map(|e| PyEngine::wrap(py, e))
            .map_err(|e| check_error(py, &e))
    }

    /// The bundled office example (`maps/office.map`, `rules/office.lpl`).
    #[staticmethod]
    fn office(py: Python<'_>) -> PyResult<Self> {
        Engine::office()
            .map(|e| PyEngine::wrap(py, e))
            .map_err(|e| check_error(py, &e))
    }

    /// Place names, in the order of the per-place arrays.
    #[getter]
    fn places(&self, py: Python<'_>) -> Vec<Py<PyString>> {
        self.place_names.iter().map(|p| p.clone_ref(py)).collect()
    }

    /// Each place's pose `(x, y)` in the map frame (metres), in `places` order.
    #[getter]
    fn place_poses(&self) -> Vec<(f64, f64)> {
        self.engine
            .map()
            .places()
            .iter()
            .map(|p| (p.pose.0, p.pose.1))
            .collect()
    }

    /// Percept instances (`name(args…)`), in slot order.
    #[getter]
    fn slots(&self) -> Vec<String> {
        self.engine
            .percepts()
            .instances()
            .iter()
            .map(ToString::to_string)
            .collect()
    }

    /// The slot of percept instance `name(args…)`; `KeyError` when the rules do not declare it.
    #[pyo3(signature = (name, args = Vec::new()))]
    fn slot(&self, name: &str, args: Vec<String>) -> PyResult<usize> {
        let refs: Vec<&str> = args.iter().map(String::as_str).collect();
        self.engine
            .percepts()
            .slot(name, &refs)
            .map(|s| s.0 as usize)
            .ok_or_else(|| {
                PyKeyError::new_err(format!("unknown percept `{name}({})`", args.join(", ")))
            })
    }

    /// Steps one frame: a dict `{"name(args)": degree | (degree, value)}`, or a float64 array
    /// of degrees (one per slot) with an optional array of values (NaN = none).
    #[pyo3(signature = (frame, values = None))]
    fn step(
        &mut self,
        py: Python<'_>,
        frame: &Bound<'_, PyAny>,
        values: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<PyDecision> {
        match frame.downcast::<PyDict>() {
            Ok(dict) => {
                if values.is_some() {
                    return Err(PyTypeError::new_err(
                        "values goes with an array of degrees, not with a dict frame",
                    ));
                }
                self.fill_from_dict(dict)?
            }
            Err(_) => self.fill_from_arrays(frame, values)?,
        }
        let d = self.engine.step(&self.frame);
        Ok(self.decision(py, d))
    }

    /// Steps every row of an `(n_frames, n_slots)` float64 array of degrees (and optional
    /// values) with the GIL released. Returns a dict of arrays: `place` (int64, -1 when
    /// disoriented), `necessity` (NaN when disoriented), `inconsistency`, `reason` (int8 index
    /// into `lplace.REASONS`, -1 when a place was chosen), and `(n_frames, n_places)` arrays
    /// `support`, `possibility`, `necessities`.
    #[pyo3(signature = (degrees, values = None))]
    fn step_many<'py>(
        &mut self,
        py: Python<'py>,
        degrees: PyReadonlyArray2<'py, f64>,
        values: Option<PyReadonlyArray2<'py, f64>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let slots = self.frame.degree.len();
        let (n, d) = rows(&degrees, slots, "degrees")?;
        let v = match &values {
            None => None,
            Some(v) => {
                let (m, v) = rows(v, slots, "values")?;
                if m != n {
                    return Err(PyValueError::new_err(format!(
                        "values has {m} rows, degrees has {n}"
                    )));
                }
                Some(v)
            }
        };
        let (engine, frame) = (&mut self.engine, &mut self.frame);
        let c = py.allow_threads(|| step_rows(engine, frame, n, d, v, slots));
        let k = self.place_names.len();
        let out = PyDict::new(py);
        out.set_item("place", PyArray1::from_vec(py, c.place))?;
        out.set_item("necessity", PyArray1::from_vec(py, c.necessity))?;
        out.set_item("inconsistency", PyArray1::from_vec(py, c.inconsistency))?;
        out.set_item("reason", PyArray1::from_vec(py, c.reason))?;
        for (key, v) in [
            ("support", c.support),
            ("possibility", c.possibility),
            ("necessities", c.necessities),
        ] {
            let a: Bound<'py, PyArray2<f64>> = PyArray1::from_vec(py, v).reshape([n, k])?;
            out.set_item(key, a)?;
        }
        Ok(out)
    }

    fn __repr__(&self) -> String {
        format!(
            "Engine({} places, {} percept slots)",
            self.place_names.len(),
            self.frame.degree.len()
        )
    }
}

/// The Rust references for the benchmarks, timed inside Rust with no Python object per frame:
/// with `outputs`, the same loop as `Engine.step_many` (the same output columns); without, each
/// row copied into the frame and stepped, nothing kept (what one Python `step` does in Rust).
/// Returns nanoseconds for all rows.
#[pyfunction]
#[pyo3(signature = (engine, degrees, values = None, outputs = true))]
pub(crate) fn rust_loop_ns(
    py: Python<'_>,
    engine: &mut PyEngine,
    degrees: PyReadonlyArray2<'_, f64>,
    values: Option<PyReadonlyArray2<'_, f64>>,
    outputs: bool,
) -> PyResult<u64> {
    let slots = engine.frame.degree.len();
    let (n, d) = rows(&degrees, slots, "degrees")?;
    let v = match &values {
        None => None,
        Some(v) => match rows(v, slots, "values")? {
            (m, v) if m == n => Some(v),
            (m, _) => {
                return Err(PyValueError::new_err(format!(
                    "values has {m} rows, degrees has {n}"
                )))
            }
        },
    };
    let (e, frame) = (&mut engine.engine, &mut engine.frame);
    Ok(py.allow_threads(|| {
        let start = std::time::Instant::now();
        if outputs {
            std::hint::black_box(step_rows(e, frame, n, d, v, slots));
        } else {
            for i in 0..n {
                let row = i * slots..(i + 1) * slots;
                if let Some(d) = d.get(row.clone()) {
                    frame.degree.copy_from_slice(d);
                }
                match v.and_then(|v| v.get(row)) {
                    Some(v) => frame.value.copy_from_slice(v),
                    None => frame.value.fill(f64::NAN),
                }
                std::hint::black_box(e.step(frame));
            }
        }
        u64::try_from(start.elapsed().as_nanos()).unwrap_or(u64::MAX)
    }))
}

/// The outcome of one step.
#[pyclass(module = "lplace._lplace", name = "Decision", frozen)]
pub struct PyDecision {
    /// The chosen place's name, `None` when disoriented.
    #[pyo3(get)]
    place: Option<Py<PyString>>,
    /// The chosen place's index into `Engine.places`.
    #[pyo3(get)]
    place_index: Option<usize>,
    /// The chosen place's necessity, `None` when disoriented.
    #[pyo3(get)]
    necessity: Option<f64>,
    /// `Inc = 1 − max π`.
    #[pyo3(get)]
    inconsistency: f64,
    reason: Option<&'static str>,
    support: Vec<f64>,
    possibility: Vec<f64>,
    necessities: Vec<f64>,
}

#[pymethods]
impl PyDecision {
    /// Why no place was chosen (`nothing_above_threshold`, `too_close`, `inconsistent`,
    /// `no_places`), `None` when a place was.
    #[getter]
    fn reason(&self) -> Option<&'static str> {
        self.reason
    }

    /// Per-place support `α_k`.
    #[getter]
    fn support<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.support)
    }

    /// Per-place possibility `Π_k`.
    #[getter]
    fn possibility<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.possibility)
    }

    /// Per-place necessity `N_k`.
    #[getter]
    fn necessities<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.necessities)
    }

    fn __repr__(&self, py: Python<'_>) -> String {
        let place = self
            .place
            .as_ref()
            .map(|p| p.bind(py).to_string_lossy().into_owned());
        match (place, self.necessity) {
            (Some(p), Some(n)) => format!(
                "Decision(place={p:?}, necessity={n:.4}, inconsistency={:.4})",
                self.inconsistency
            ),
            _ => format!(
                "Decision(place=None, reason={:?}, inconsistency={:.4})",
                self.reason.unwrap_or(""),
                self.inconsistency
            ),
        }
    }
}
