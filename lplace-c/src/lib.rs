//! The C API of lplace: load a map and a rule file once, then per sensor frame clear, set the
//! percepts seen, and step — allocation-free and panic-free. The header `include/lplace.h` is
//! generated from this file by cbindgen (`lplace-c/cbindgen.toml`; the test `header` fails when
//! the checked-in header is stale).
//!
//! This crate is a thin layer over `lplace::engine` (the engine with its percept table and
//! frame) and depends on nothing else. It owns what C needs and Rust does not: an engine bundled
//! with its frame, place names as NUL-terminated strings, status codes instead of `Result`.
//!
//! # Contract, for every entry point
//! - No panic crosses into C: each body runs under [`std::panic::catch_unwind`], and a panic
//!   becomes [`LPLACE_ERR_PANIC`] (or a null / zero result where the function returns a pointer
//!   or a count). Rust's default hook still prints the panic to stderr.
//! - Null pointers are reported ([`LPLACE_ERR_NULL`]), never dereferenced.
//! - A slot the engine does not have is [`LPLACE_ERR_SLOT`], never an out-of-bounds write.
//! - `lplace_engine_clear`, `lplace_engine_set` and `lplace_engine_step` allocate nothing
//!   (tested with a counting allocator in `tests/api.rs`).
//!
//! What the library cannot check: that a non-null pointer points at what it should (an
//! engine from `lplace_engine_load` not yet freed, a NUL-terminated string, `n_args` readable
//! pointers). Those are the caller's side of the contract, as for any C library.

use std::ffi::{c_char, c_int, CStr, CString};
use std::panic::{catch_unwind, AssertUnwindSafe};

use lplace::engine::{Engine, Frame, LoadError, PerceptSlot};
use lplace::logic::{Decision, Disoriented};
use lplace::syntax::SourceFile;

/// Success.
pub const LPLACE_OK: c_int = 0;
/// `lplace_engine_slot`: the rules declare no such percept instance.
pub const LPLACE_SLOT_UNKNOWN: c_int = -1;
/// A pointer argument was null.
pub const LPLACE_ERR_NULL: c_int = -2;
/// A string argument was not valid UTF-8.
pub const LPLACE_ERR_UTF8: c_int = -3;
/// A slot outside the engine's percept table.
pub const LPLACE_ERR_SLOT: c_int = -4;
/// The library panicked (a bug in lplace); the engine should be freed and loaded again.
pub const LPLACE_ERR_PANIC: c_int = -5;

/// `LplaceDecision::reason`: a place was chosen.
pub const LPLACE_REASON_NONE: c_int = 0;
/// No place is supported up to the threshold.
pub const LPLACE_REASON_NOTHING_ABOVE_THRESHOLD: c_int = 1;
/// The best place does not stand out enough from the runner-up.
pub const LPLACE_REASON_TOO_CLOSE: c_int = 2;
/// The evidence contradicts itself too much.
pub const LPLACE_REASON_INCONSISTENT: c_int = 3;
/// The map has no places.
pub const LPLACE_REASON_NO_PLACES: c_int = 4;

/// The outcome of one step.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LplaceDecision {
    /// Index of the chosen place (see `lplace_engine_place_name`), or -1 when disoriented.
    pub place: c_int,
    /// The chosen place's necessity; when disoriented, the highest necessity of any place
    /// (what fell short of the threshold).
    pub necessity: f64,
    /// The inconsistency `Inc = 1 − max π` of the evidence.
    pub inconsistency: f64,
    /// `LPLACE_REASON_NONE` when a place was chosen, else why not (`LPLACE_REASON_*`).
    pub reason: c_int,
}

/// A loaded engine with its frame (opaque to C).
pub struct LplaceEngine {
    engine: Engine,
    frame: Frame,
    place_names: Vec<CString>,
}

/// Runs `f`, turning a panic into `on_panic`.
fn guard<T>(on_panic: T, f: impl FnOnce() -> T) -> T {
    catch_unwind(AssertUnwindSafe(f)).unwrap_or(on_panic)
}

/// Copies `msg` into the caller's buffer `err` of `err_len` bytes, truncated at a character
/// boundary and always NUL-terminated (nothing is written when `err` is null or `err_len` 0).
///
/// # Safety
/// `err` is null or points at `err_len` writable bytes.
unsafe fn write_error(err: *mut c_char, err_len: usize, msg: &str) {
    if err.is_null() || err_len == 0 {
        return;
    }
    let mut n = msg.len().min(err_len - 1);
    while !msg.is_char_boundary(n) {
        n -= 1;
    }
    // SAFETY: n + 1 <= err_len bytes, which the caller guarantees are writable.
    unsafe {
        std::ptr::copy_nonoverlapping(msg.as_ptr(), err.cast::<u8>(), n);
        *err.add(n) = 0;
    }
}

/// The message for a load failure: the summary line, then each diagnostic with its caret.
fn load_error_text(e: &LoadError) -> String {
    let mut s = e.to_string();
    for d in &e.diagnostics {
        s.push('\n');
        s.push_str(&d.render_plain(&e.file));
    }
    s
}

/// Reads a file named by a C string.
///
/// # Safety
/// `path` is a non-null, NUL-terminated string.
unsafe fn read_named(path: *const c_char, what: &str) -> Result<SourceFile, String> {
    // SAFETY: the caller's contract.
    let name = unsafe { CStr::from_ptr(path) }
        .to_str()
        .map_err(|_| format!("{what} path is not valid UTF-8"))?;
    let text = std::fs::read_to_string(name)
        .map_err(|e| format!("cannot read {what} file `{name}`: {e}"))?;
    Ok(SourceFile::new(name, text))
}

/// Loads the engine, or says why not.
///
/// # Safety
/// As [`lplace_engine_load`] for the two paths.
unsafe fn load(map_path: *const c_char, rules_path: *const c_char) -> Result<Engine, String> {
    match (map_path.is_null(), rules_path.is_null()) {
        (true, true) => Engine::office().map_err(|e| load_error_text(&e)),
        (false, false) => {
            // SAFETY: both non-null; NUL termination is the caller's contract.
            let (map, rules) = unsafe {
                (
                    read_named(map_path, "map")?,
                    read_named(rules_path, "rule")?,
                )
            };
            Engine::load(&map, &rules).map_err(|e| load_error_text(&e))
        }
        _ => Err("give both a map and a rule file, or neither (the bundled office)".to_owned()),
    }
}

/// Parses, checks and compiles a map file and a rule file. With both paths null, loads the
/// bundled office example (paper 003). Returns null on failure, with the reason (every
/// diagnostic, with line, column and caret) in `err` — NUL-terminated and truncated to
/// `err_len` bytes; `err` may be null. Free the engine with `lplace_engine_free`.
///
/// # Safety
/// Non-null paths are NUL-terminated strings; `err` is null or points at `err_len` writable
/// bytes.
#[no_mangle]
pub unsafe extern "C" fn lplace_engine_load(
    map_path: *const c_char,
    rules_path: *const c_char,
    err: *mut c_char,
    err_len: usize,
) -> *mut LplaceEngine {
    let made = guard(Err("lplace panicked while loading".to_owned()), || {
        // SAFETY: forwarded contract.
        let engine = unsafe { load(map_path, rules_path) }?;
        let place_names = engine
            .map()
            .places()
            .iter()
            .map(|p| CString::new(p.name.as_str()).map_err(|_| "a place name holds NUL".to_owned()))
            .collect::<Result<Vec<_>, _>>()?;
        let frame = engine.new_frame();
        Ok(Box::new(LplaceEngine {
            engine,
            frame,
            place_names,
        }))
    });
    match made {
        Ok(e) => Box::into_raw(e),
        Err(msg) => {
            // SAFETY: forwarded contract.
            unsafe { write_error(err, err_len, &msg) };
            std::ptr::null_mut()
        }
    }
}

/// Frees an engine (null is ignored). The pointer and the place names it gave out are invalid
/// afterwards.
///
/// # Safety
/// `e` is null or an engine from `lplace_engine_load` not yet freed.
#[no_mangle]
pub unsafe extern "C" fn lplace_engine_free(e: *mut LplaceEngine) {
    if e.is_null() {
        return;
    }
    guard((), || {
        // SAFETY: the caller's contract: `e` came from Box::into_raw and is freed once.
        drop(unsafe { Box::from_raw(e) });
    });
}

/// Number of places of the map (0 for a null engine).
///
/// # Safety
/// `e` is null or a live engine.
#[no_mangle]
pub unsafe extern "C" fn lplace_engine_place_count(e: *const LplaceEngine) -> usize {
    // SAFETY: the caller's contract.
    let Some(e) = (unsafe { e.as_ref() }) else {
        return 0;
    };
    guard(0, || e.place_names.len())
}

/// The name of place `i` (in map order), valid until the engine is freed; null when `e` is
/// null or `i` is out of range.
///
/// # Safety
/// `e` is null or a live engine.
#[no_mangle]
pub unsafe extern "C" fn lplace_engine_place_name(
    e: *const LplaceEngine,
    i: usize,
) -> *const c_char {
    // SAFETY: the caller's contract.
    let Some(e) = (unsafe { e.as_ref() }) else {
        return std::ptr::null();
    };
    guard(std::ptr::null(), || {
        e.place_names
            .get(i)
            .map_or(std::ptr::null(), |s| s.as_ptr())
    })
}

/// Number of percept slots (instances such as `sonar_wall(North)`); 0 for a null engine.
///
/// # Safety
/// `e` is null or a live engine.
#[no_mangle]
pub unsafe extern "C" fn lplace_engine_slot_count(e: *const LplaceEngine) -> usize {
    // SAFETY: the caller's contract.
    let Some(e) = (unsafe { e.as_ref() }) else {
        return 0;
    };
    guard(0, || e.engine.percepts().len())
}

/// The slot of percept instance `percept(args[0], …, args[n_args − 1])`, e.g. `"sonar_wall"`
/// with `{"North"}`. Look slots up once, before the control loop (this allocates). Returns the
/// slot (≥ 0), `LPLACE_SLOT_UNKNOWN` when the rules declare no such instance, or
/// `LPLACE_ERR_NULL` / `LPLACE_ERR_UTF8` / `LPLACE_ERR_PANIC`.
///
/// # Safety
/// `e` is null or a live engine; `percept` is null or NUL-terminated; `args` is null (only
/// with `n_args` 0) or points at `n_args` pointers, each null or NUL-terminated.
#[no_mangle]
pub unsafe extern "C" fn lplace_engine_slot(
    e: *const LplaceEngine,
    percept: *const c_char,
    args: *const *const c_char,
    n_args: usize,
) -> c_int {
    // SAFETY: the caller's contract.
    let Some(e) = (unsafe { e.as_ref() }) else {
        return LPLACE_ERR_NULL;
    };
    if percept.is_null() || (args.is_null() && n_args > 0) {
        return LPLACE_ERR_NULL;
    }
    guard(LPLACE_ERR_PANIC, || {
        // SAFETY: non-null and NUL-terminated by contract.
        let Ok(name) = unsafe { CStr::from_ptr(percept) }.to_str() else {
            return LPLACE_ERR_UTF8;
        };
        let mut owned: Vec<&str> = Vec::with_capacity(n_args);
        for k in 0..n_args {
            // SAFETY: `args` holds n_args pointers by contract.
            let a = unsafe { *args.add(k) };
            if a.is_null() {
                return LPLACE_ERR_NULL;
            }
            // SAFETY: non-null and NUL-terminated by contract.
            let Ok(s) = unsafe { CStr::from_ptr(a) }.to_str() else {
                return LPLACE_ERR_UTF8;
            };
            owned.push(s);
        }
        match e.engine.percepts().slot(name, &owned) {
            Some(PerceptSlot(s)) => c_int::try_from(s).unwrap_or(LPLACE_SLOT_UNKNOWN),
            None => LPLACE_SLOT_UNKNOWN,
        }
    })
}

/// Marks every percept missing again (start of a frame). Null is ignored.
///
/// # Safety
/// `e` is null or a live engine.
#[no_mangle]
pub unsafe extern "C" fn lplace_engine_clear(e: *mut LplaceEngine) {
    // SAFETY: the caller's contract.
    if let Some(e) = unsafe { e.as_mut() } {
        guard((), || e.frame.clear());
    }
}

/// Sets one percept of the current frame: its degree in [0, 1] (1 = fully supported) and its
/// measured value, `NAN` for none. A NaN degree counts as missing and one outside [0, 1] is
/// clamped, as in the Rust engine. Returns `LPLACE_OK`, `LPLACE_ERR_NULL`, `LPLACE_ERR_SLOT`
/// or `LPLACE_ERR_PANIC`.
///
/// # Safety
/// `e` is null or a live engine.
#[no_mangle]
pub unsafe extern "C" fn lplace_engine_set(
    e: *mut LplaceEngine,
    slot: c_int,
    degree: f64,
    value: f64,
) -> c_int {
    // SAFETY: the caller's contract.
    let Some(e) = (unsafe { e.as_mut() }) else {
        return LPLACE_ERR_NULL;
    };
    let Ok(slot) = u32::try_from(slot) else {
        return LPLACE_ERR_SLOT;
    };
    guard(LPLACE_ERR_PANIC, || {
        let value = (!value.is_nan()).then_some(value);
        if e.frame.set(PerceptSlot(slot), degree, value) {
            LPLACE_OK
        } else {
            LPLACE_ERR_SLOT
        }
    })
}

/// Evaluates the current frame and decides, into `*out`. Allocates nothing. Returns
/// `LPLACE_OK`, `LPLACE_ERR_NULL` (nothing is written) or `LPLACE_ERR_PANIC`. The frame is
/// kept: clear it before setting the next one.
///
/// # Safety
/// `e` is null or a live engine; `out` is null or points at a writable `LplaceDecision`.
#[no_mangle]
pub unsafe extern "C" fn lplace_engine_step(
    e: *mut LplaceEngine,
    out: *mut LplaceDecision,
) -> c_int {
    // SAFETY: the caller's contract.
    let (Some(e), Some(out)) = (unsafe { e.as_mut() }, unsafe { out.as_mut() }) else {
        return LPLACE_ERR_NULL;
    };
    guard(LPLACE_ERR_PANIC, || {
        let d = e.engine.step(&e.frame);
        *out = to_c(d, e.engine.distribution());
        LPLACE_OK
    })
}

/// The C form of a decision.
fn to_c(d: Decision, dist: &lplace::logic::PlaceDistribution) -> LplaceDecision {
    let best = dist.necessity.iter().copied().fold(0.0, f64::max);
    let (place, necessity, reason) = match d {
        Decision::Place { place, necessity } => (
            c_int::try_from(place).unwrap_or(-1),
            necessity,
            LPLACE_REASON_NONE,
        ),
        Decision::Disoriented(why) => (-1, best, reason_code(&why)),
    };
    LplaceDecision {
        place,
        necessity,
        inconsistency: dist.inconsistency,
        reason,
    }
}

fn reason_code(d: &Disoriented) -> c_int {
    match d {
        Disoriented::NothingAboveThreshold { .. } => LPLACE_REASON_NOTHING_ABOVE_THRESHOLD,
        Disoriented::TooClose { .. } => LPLACE_REASON_TOO_CLOSE,
        Disoriented::Inconsistent { .. } => LPLACE_REASON_INCONSISTENT,
        Disoriented::NoPlaces => LPLACE_REASON_NO_PLACES,
    }
}

/// The name of a reason code as `lplace eval` prints it (`"too_close"`, …; `"none"` for
/// `LPLACE_REASON_NONE`), or null for an unknown code. A static string.
#[no_mangle]
pub extern "C" fn lplace_reason_name(reason: c_int) -> *const c_char {
    let s: &'static CStr = match reason {
        LPLACE_REASON_NONE => c"none",
        LPLACE_REASON_NOTHING_ABOVE_THRESHOLD => c"nothing_above_threshold",
        LPLACE_REASON_TOO_CLOSE => c"too_close",
        LPLACE_REASON_INCONSISTENT => c"inconsistent",
        LPLACE_REASON_NO_PLACES => c"no_places",
        _ => return std::ptr::null(),
    };
    s.as_ptr()
}
