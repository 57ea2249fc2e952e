//! The C API against its contract: the same decisions as the Rust engine on the bundled
//! recording, a hand-worked frame, errors instead of crashes on null pointers, bad slots and
//! broken files, and no allocation per step (the counting global allocator the main crate's
//! `tests/alloc` uses, shared from `tests/support/counting_alloc.rs`).

#[path = "../../tests/support/counting_alloc.rs"]
mod counting_alloc;

use std::ffi::{c_char, CStr, CString};
use std::ptr::{null, null_mut};

use lplace::engine::Engine;
use lplace::io::record::FrameRecord;
use lplace::logic::{Decision, Disoriented};
use lplace_c::*;

#[global_allocator]
static GLOBAL: counting_alloc::Counting = counting_alloc::Counting;

const ROOT: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/..");

/// The bundled office engine through the C API.
fn office() -> *mut LplaceEngine {
    let e = unsafe { lplace_engine_load(null(), null(), null_mut(), 0) };
    assert!(!e.is_null(), "the bundled office loads");
    e
}

fn slot(e: *const LplaceEngine, name: &str, args: &[&str]) -> i32 {
    let name = CString::new(name).unwrap();
    let owned: Vec<CString> = args.iter().map(|a| CString::new(*a).unwrap()).collect();
    let ptrs: Vec<*const c_char> = owned.iter().map(|a| a.as_ptr()).collect();
    unsafe { lplace_engine_slot(e, name.as_ptr(), ptrs.as_ptr(), ptrs.len()) }
}

fn name_of(e: *const LplaceEngine, i: usize) -> String {
    let p = unsafe { lplace_engine_place_name(e, i) };
    assert!(!p.is_null());
    unsafe { CStr::from_ptr(p) }.to_str().unwrap().to_owned()
}

#[test]
fn hand_worked_frame_chooses_p2() {
    // The engine's own doc example: beacon from 116° at 1.1 m, walls North and East: P2.
    let e = office();
    unsafe { lplace_engine_clear(e) };
    for (name, args, degree, value) in [
        ("beacon_angle", &[][..], 0.9, 116.0),
        ("beacon_distance", &[], 0.9, 1.1),
        ("sonar_wall", &["North"], 0.8, f64::NAN),
        ("laser_wall", &["East"], 0.9, f64::NAN),
    ] {
        let s = slot(e, name, args);
        assert!(s >= 0, "{name}{args:?} has a slot");
        assert_eq!(unsafe { lplace_engine_set(e, s, degree, value) }, LPLACE_OK);
    }
    let mut d = LplaceDecision {
        place: -9,
        necessity: -1.0,
        inconsistency: -1.0,
        reason: -9,
    };
    assert_eq!(unsafe { lplace_engine_step(e, &mut d) }, LPLACE_OK);
    assert!(d.place >= 0, "a place is chosen: {d:?}");
    assert_eq!(name_of(e, d.place as usize), "P2");
    assert_eq!(d.reason, LPLACE_REASON_NONE);
    assert!((0.5..=1.0).contains(&d.necessity) && (0.0..=1.0).contains(&d.inconsistency));

    // Cleared, nothing is perceived: no place has support, so nothing is above the threshold.
    unsafe { lplace_engine_clear(e) };
    assert_eq!(unsafe { lplace_engine_step(e, &mut d) }, LPLACE_OK);
    assert_eq!(d.place, -1);
    assert_eq!(d.reason, LPLACE_REASON_NOTHING_ABOVE_THRESHOLD);
    unsafe { lplace_engine_free(e) };
}

/// The C API's decision for a Rust engine decision, derived independently of `lplace_c`.
fn expected(d: Decision, engine: &Engine) -> (i32, f64, i32) {
    match d {
        Decision::Place { place, necessity } => (place as i32, necessity, LPLACE_REASON_NONE),
        Decision::Disoriented(why) => {
            let best = engine
                .distribution()
                .necessity
                .iter()
                .copied()
                .fold(0.0, f64::max);
            let reason = match why {
                Disoriented::NothingAboveThreshold { .. } => 1,
                Disoriented::TooClose { .. } => 2,
                Disoriented::Inconsistent { .. } => 3,
                Disoriented::NoPlaces => 4,
            };
            (-1, best, reason)
        }
    }
}

#[test]
fn same_decisions_as_the_rust_engine_on_the_bundled_recording() {
    let text = std::fs::read_to_string(format!("{ROOT}/recordings/office.jsonl")).unwrap();
    let mut engine = Engine::office().unwrap();
    let mut frame = engine.new_frame();
    let e = office();
    let mut frames = 0;
    for line in text.lines() {
        let rec = FrameRecord::parse(line).unwrap();
        let mut rejected = Vec::new();
        rec.fill(engine.percepts(), &mut frame, &mut rejected);
        assert!(rejected.is_empty());
        let (place, necessity, reason) = expected(engine.step(&frame), &engine);

        unsafe { lplace_engine_clear(e) };
        for p in &rec.percepts {
            let args: Vec<&str> = p.args.iter().map(String::as_str).collect();
            let s = slot(e, &p.name, &args);
            let v = p.value.unwrap_or(f64::NAN);
            assert_eq!(unsafe { lplace_engine_set(e, s, p.degree, v) }, LPLACE_OK);
        }
        let mut d = LplaceDecision {
            place: 0,
            necessity: 0.0,
            inconsistency: 0.0,
            reason: 0,
        };
        assert_eq!(unsafe { lplace_engine_step(e, &mut d) }, LPLACE_OK);
        assert_eq!((d.place, d.necessity, d.reason), (place, necessity, reason));
        assert_eq!(d.inconsistency, engine.distribution().inconsistency);
        frames += 1;
    }
    assert_eq!(frames, 2500);
    unsafe { lplace_engine_free(e) };
}

#[test]
fn misuse_is_an_error_not_a_crash() {
    let e = office();
    let n = unsafe { lplace_engine_slot_count(e) } as i32;
    let mut d = LplaceDecision {
        place: 0,
        necessity: 0.0,
        inconsistency: 0.0,
        reason: 0,
    };
    unsafe {
        assert_eq!(lplace_engine_set(e, -1, 0.5, 1.0), LPLACE_ERR_SLOT);
        assert_eq!(lplace_engine_set(e, n, 0.5, 1.0), LPLACE_ERR_SLOT);
        assert_eq!(lplace_engine_set(e, i32::MAX, 0.5, 1.0), LPLACE_ERR_SLOT);
        assert_eq!(
            lplace_engine_set(e, n - 1, f64::NAN, f64::INFINITY),
            LPLACE_OK
        );
        assert_eq!(lplace_engine_set(null_mut(), 0, 0.5, 1.0), LPLACE_ERR_NULL);
        assert_eq!(lplace_engine_step(null_mut(), &mut d), LPLACE_ERR_NULL);
        assert_eq!(lplace_engine_step(e, null_mut()), LPLACE_ERR_NULL);
        assert_eq!(
            lplace_engine_slot(null(), c"beacon_angle".as_ptr(), null(), 0),
            LPLACE_ERR_NULL
        );
        assert_eq!(lplace_engine_slot(e, null(), null(), 0), LPLACE_ERR_NULL);
        assert_eq!(
            lplace_engine_slot(e, c"sonar_wall".as_ptr(), null(), 1),
            LPLACE_ERR_NULL
        );
        let null_arg = [null::<c_char>()];
        assert_eq!(
            lplace_engine_slot(e, c"sonar_wall".as_ptr(), null_arg.as_ptr(), 1),
            LPLACE_ERR_NULL
        );
        let bad_utf8 = [0xffu8, 0];
        assert_eq!(
            lplace_engine_slot(e, bad_utf8.as_ptr().cast(), null(), 0),
            LPLACE_ERR_UTF8
        );
        assert_eq!(lplace_engine_place_count(null()), 0);
        assert_eq!(lplace_engine_slot_count(null()), 0);
        assert!(lplace_engine_place_name(null(), 0).is_null());
        assert!(lplace_engine_place_name(e, usize::MAX).is_null());
        lplace_engine_clear(null_mut());
        lplace_engine_free(null_mut());
        lplace_engine_free(e);
    }
    // Unknown instances: a wrong name, a wrong argument, a missing argument.
    let e = office();
    assert_eq!(slot(e, "no_such_percept", &[]), LPLACE_SLOT_UNKNOWN);
    assert_eq!(slot(e, "sonar_wall", &["Up"]), LPLACE_SLOT_UNKNOWN);
    assert_eq!(slot(e, "sonar_wall", &[]), LPLACE_SLOT_UNKNOWN);
    assert_ne!(
        slot(e, "sonar_wall", &["North"]),
        slot(e, "sonar_wall", &["East"])
    );
    unsafe { lplace_engine_free(e) };
}

#[test]
fn place_names_and_reasons_match_the_rust_side() {
    let engine = Engine::office().unwrap();
    let e = office();
    let places = engine.map().places();
    assert_eq!(unsafe { lplace_engine_place_count(e) }, places.len());
    for (i, p) in places.iter().enumerate() {
        assert_eq!(name_of(e, i), p.name);
    }
    unsafe { lplace_engine_free(e) };
    let reasons = [
        Disoriented::NothingAboveThreshold {
            best: 0,
            support: 0.0,
        },
        Disoriented::TooClose {
            best: 0,
            runner_up: 1,
            necessity: 0.0,
        },
        Disoriented::Inconsistent { inconsistency: 1.0 },
        Disoriented::NoPlaces,
    ];
    for (code, why) in (1..).zip(&reasons) {
        let s = unsafe { CStr::from_ptr(lplace_reason_name(code)) };
        assert_eq!(
            s.to_str().unwrap(),
            lplace::report::summary::reason_name(why)
        );
    }
    assert!(lplace_reason_name(99).is_null() && lplace_reason_name(-1).is_null());
}

/// Loads through the C API, returning the engine (maybe null) and the error text.
fn load(map: Option<&str>, rules: Option<&str>, err_len: usize) -> (*mut LplaceEngine, String) {
    let map = map.map(|m| CString::new(m).unwrap());
    let rules = rules.map(|r| CString::new(r).unwrap());
    let mut err = vec![b'#' as c_char; err_len + 8];
    let e = unsafe {
        lplace_engine_load(
            map.as_ref().map_or(null(), |m| m.as_ptr()),
            rules.as_ref().map_or(null(), |r| r.as_ptr()),
            err.as_mut_ptr(),
            err_len,
        )
    };
    if err_len == 0 || !e.is_null() {
        assert_eq!(
            err[0], b'#' as c_char,
            "nothing written on success or into 0 bytes"
        );
        return (e, String::new());
    }
    let msg = unsafe { CStr::from_ptr(err.as_ptr()) }
        .to_string_lossy()
        .into_owned();
    assert!(
        msg.len() < err_len,
        "the message fits its buffer with the NUL"
    );
    (e, msg)
}

#[test]
fn load_failures_say_why() {
    let map = format!("{ROOT}/maps/office.map");
    let rules = format!("{ROOT}/rules/office.lpl");
    let (e, _) = load(Some(&map), Some(&rules), 256);
    assert!(!e.is_null());
    unsafe { lplace_engine_free(e) };

    let (e, msg) = load(Some("/nonexistent/x.map"), Some(&rules), 256);
    assert!(
        e.is_null() && msg.contains("cannot read map file `/nonexistent/x.map`"),
        "{msg}"
    );
    let (e, msg) = load(Some(&map), None, 256);
    assert!(e.is_null() && msg.contains("or neither"), "{msg}");

    // A rule file with an error: the diagnostic with its line and column.
    let dir = std::env::temp_dir().join(format!("lplace-c-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let bad = dir.join("bad.lpl");
    std::fs::write(&bad, "|- foo(t) -> at_place(P_i);\n").unwrap();
    let (e, msg) = load(Some(&map), Some(bad.to_str().unwrap()), 4096);
    assert!(e.is_null());
    assert!(
        msg.contains("rule file") && msg.contains("bad.lpl:1:4"),
        "{msg}"
    );
    // Truncated to the buffer, still NUL-terminated; a 0-byte or null buffer is left alone.
    let (e, short) = load(Some(&map), Some(bad.to_str().unwrap()), 10);
    assert!(e.is_null() && short.len() == 9 && msg.starts_with(&short));
    let (e, _) = load(Some(&map), Some(bad.to_str().unwrap()), 0);
    assert!(e.is_null());
    let e = unsafe { lplace_engine_load(null(), c"x".as_ptr(), null_mut(), 64) };
    assert!(e.is_null());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn clear_set_step_allocate_nothing() {
    let e = office();
    let n = unsafe { lplace_engine_slot_count(e) } as i32;
    let mut d = LplaceDecision {
        place: 0,
        necessity: 0.0,
        inconsistency: 0.0,
        reason: 0,
    };
    // Counted per thread: the other tests run in parallel and allocate.
    let before = counting_alloc::allocations();
    let mut chosen = 0;
    for k in 0..1000i32 {
        unsafe {
            lplace_engine_clear(e);
            for s in 0..n {
                let degree = match (k + s) % 7 {
                    0 => f64::NAN,
                    1 => 1.5,
                    _ => f64::from((k * 31 + s * 17) % 100) / 100.0,
                };
                lplace_engine_set(e, s, degree, f64::from((k * 13 + s * 7) % 360));
            }
            lplace_engine_set(e, n, 0.5, 0.0); // a bad slot on the way allocates nothing either
            assert_eq!(lplace_engine_step(e, &mut d), LPLACE_OK);
        }
        chosen += i32::from(d.place >= 0);
    }
    let after = counting_alloc::allocations();
    assert_eq!(
        after - before,
        0,
        "the loop allocated {} times",
        after - before
    );
    assert!(chosen <= 1000);
    unsafe { lplace_engine_free(e) };
}
