//! `Engine::step` builds the place distribution in two passes over the places and decides from
//! their extremes; `step_within` a set of every place takes the separate passes (conditioning on
//! every place changes nothing). Both are compared bit for bit on random generated maps, every
//! t-norm, implication and normalisation, plain and negated room and region heads, and hostile
//! frames; room and region degrees (computed when read) against `PlaceSet`'s Π and N.

use lplace::core::rng::SplitMix64;
use lplace::engine::query::room_set;
use lplace::engine::{Engine, Frame, OFFICE_RULES};
use lplace::logic::PlaceSet;
use lplace::sim::{large_map::lattice_office, SimConfig, Simulator};
use lplace::syntax::diagnostic::SourceFile;

/// The office rules with the operators under test, and set heads of every kind: the rooms'
/// (`at_place(P_i) -> in_room(R_i)`), a negated room head, a region's and a negated one.
fn rules(rng: &mut SplitMix64) -> String {
    let pick = |rng: &mut SplitMix64, xs: &[&'static str]| xs[rng.below(xs.len())];
    let tnorm = pick(rng, &["min", "product", "lukasiewicz"]);
    let imp = pick(rng, &["residuum", "min_mp"]);
    let norm = pick(rng, &["min", "product"]);
    let mut text: String = OFFICE_RULES
        .lines()
        .map(|l| match l.trim_start() {
            t if t.starts_with("tnorm") => format!("tnorm = {tnorm};"),
            t if t.starts_with("implication") => format!("implication = {imp};"),
            t if t.starts_with("normalisation") => format!("normalisation = {norm};"),
            _ => l.to_string(),
        })
        .collect::<Vec<_>>()
        .join("\n");
    text.push_str(
        "\npercept e0(time);\npercept e1(time);\nregion G0 = {P0, P1, P2};\n\
         |- (e0(t) -> !in_room(R0), 0.7);\n|- (e1(t) -> in_region(G0), 0.6);\n\
         |- (walls(t) -> !in_region(G0), 0.3);\n",
    );
    text
}

/// Some percepts of a simulated frame made hostile: missing, NaN, `−0`, out of range.
fn mangle(rng: &mut SplitMix64, f: &mut Frame) {
    for s in 0..f.degree.len() {
        match rng.below(12) {
            0 => f.degree[s] = f64::NAN,
            1 => f.degree[s] = -0.0,
            2 => (f.degree[s], f.value[s]) = (0.0, f64::NAN),
            3 => f.degree[s] = 1.5,
            4 => f.degree[s] = rng.unit(),
            5 => f.value[s] = f64::NAN,
            _ => {}
        }
    }
}

fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

/// Columns, height, Inc and decision of `a` (two passes) and `b` (separate passes).
fn same(a: &Engine, b: &Engine, at: &str) {
    let (x, y) = (a.distribution(), b.distribution());
    assert_eq!(bits(&x.support), bits(&y.support), "{at}");
    assert_eq!(bits(&x.exclusion), bits(&y.exclusion), "{at}");
    assert_eq!(bits(&x.possibility_raw), bits(&y.possibility_raw), "{at}");
    assert_eq!(bits(&x.possibility), bits(&y.possibility), "{at}");
    assert_eq!(bits(&x.necessity), bits(&y.necessity), "{at}");
    assert_eq!(x.height.to_bits(), y.height.to_bits(), "{at}");
    assert_eq!(x.inconsistency.to_bits(), y.inconsistency.to_bits(), "{at}");
    let (da, db) = (format!("{:?}", a.decision()), format!("{:?}", b.decision()));
    assert_eq!(da, db, "{at}");
}

/// Room and region degrees against [`PlaceSet::possibility`] and [`PlaceSet::necessity`].
fn check_sets(e: &Engine, at: &str) {
    let pi = &e.distribution().possibility;
    let map = e.map();
    let rooms: Vec<PlaceSet> = (0..map.rooms().len()).map(|r| room_set(map, r)).collect();
    let regions = e.rules().regions.iter();
    let regions = regions.map(|(_, ks)| PlaceSet::from_indices(pi.len(), ks.iter().copied()));
    for (sets, got) in [(rooms, e.rooms()), (regions.collect(), e.regions())] {
        for (i, set) in sets.iter().enumerate() {
            let (p, n) = (set.possibility(pi), set.necessity(pi));
            assert_eq!(got.possibility[i].to_bits(), p.to_bits(), "{at} set {i}");
            assert_eq!(got.necessity[i].to_bits(), n.to_bits(), "{at} set {i}");
        }
    }
}

#[test]
fn two_passes_give_the_separate_passes_bit_for_bit() {
    let mut rng = SplitMix64::new(16);
    let mut supported = 0;
    for case in 0..40 {
        let n = 3 + rng.below(120);
        let text = lattice_office(n, case);
        let rules = rules(&mut rng);
        let mut fast = Engine::load(
            &SourceFile::new("m.map", text.as_str()),
            &SourceFile::new("r.lpl", rules.as_str()),
        )
        .expect("the generated map and rules load");
        let mut plain = fast.clone();
        let cfg = SimConfig {
            steps: 60,
            seed: case,
            ..SimConfig::default()
        };
        let records: Vec<_> = Simulator::for_engine(&fast, cfg).collect();
        let table = fast.percepts().clone();
        let every = PlaceSet::all(n);
        let known = PlaceSet::from_indices(n, (0..n).filter(|k| k % 3 != 1));
        for (step, rec) in records.iter().enumerate() {
            let at = format!("case {case} step {step}");
            let mut f = fast.new_frame();
            rec.fill(&table, &mut f, &mut Vec::new());
            for name in ["e0", "e1"] {
                if let Some(s) = table.slot(name, &[]) {
                    f.set(s, rng.unit(), None);
                }
            }
            if rng.below(3) == 0 {
                mangle(&mut rng, &mut f);
            }
            if rng.below(8) == 0 {
                // A step within a known set, then two passes again: rooms follow each step.
                fast.step_within(&f, Some(&known));
                check_sets(&fast, &format!("{at} (known)"));
            }
            fast.step(&f);
            plain.step_within(&f, Some(&every));
            same(&fast, &plain, &at);
            supported += usize::from(fast.distribution().support.iter().any(|&s| s > 0.0));
            // Reading the rooms only now and then: a later read must see its own step.
            if rng.below(2) == 0 {
                check_sets(&fast, &at);
            }
        }
    }
    assert!(supported > 300, "only {supported} frames supported a place");
}
