//! A robot controller loop built on the embedding API: load once, then step at sensor rate.
//!
//! The "robot" here drives from corner P1 to corner P2 of paper 003's office and back, with
//! sensors that are right most of the time; each cycle fills the same frame and calls
//! `Engine::step`, which allocates nothing. The controller only acts on a chosen place and
//! treats disorientation as a reason to slow down and look again.
//!
//! Run: `cargo run --example embed --no-default-features` (the engine without the CLI).

use lplace::engine::{Engine, PerceptSlot};
use lplace::logic::{Decision, Disoriented};

/// What the sensor drivers deliver each cycle (a stand-in for real drivers).
struct Sensors {
    beacon_angle: Option<(f64, f64)>,
    beacon_distance: Option<(f64, f64)>,
    walls: [(usize, f64); 2],
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut engine = Engine::office()?;
    // Resolve percept names to slots once, outside the loop.
    let t = engine.percepts();
    let slot = |name: &str, args: &[&str]| -> Result<PerceptSlot, String> {
        t.slot(name, args)
            .ok_or_else(|| format!("the rules declare no percept {name}{args:?}"))
    };
    let angle = slot("beacon_angle", &[])?;
    let distance = slot("beacon_distance", &[])?;
    let dirs = ["North", "East", "South", "West"];
    let sonar: Vec<PerceptSlot> = dirs
        .iter()
        .map(|d| slot("sonar_wall", &[d]))
        .collect::<Result<_, _>>()?;
    let laser: Vec<PerceptSlot> = dirs
        .iter()
        .map(|d| slot("laser_wall", &[d]))
        .collect::<Result<_, _>>()?;
    let mut frame = engine.new_frame();

    for cycle in 0..12 {
        let s = read_sensors(cycle);
        frame.clear();
        if let Some((deg, v)) = s.beacon_angle {
            frame.set(angle, deg, Some(v));
        }
        if let Some((deg, v)) = s.beacon_distance {
            frame.set(distance, deg, Some(v));
        }
        frame.set(sonar[s.walls[0].0], s.walls[0].1, None);
        frame.set(laser[s.walls[1].0], s.walls[1].1, None);

        match engine.step(&frame) {
            Decision::Place { place, necessity } => {
                let name = &engine.map().places()[place].name;
                println!("cycle {cycle:2}: at {name} (N = {necessity:.2}) → continue the plan");
            }
            Decision::Disoriented(why) => {
                let what = match why {
                    Disoriented::NothingAboveThreshold { .. } => "no place stands out",
                    Disoriented::TooClose { .. } => "two places look alike",
                    Disoriented::Inconsistent { .. } => "the sensors contradict each other",
                    Disoriented::NoPlaces => "the map is empty",
                };
                println!("cycle {cycle:2}: disoriented ({what}) → slow down, look again");
            }
        }
    }
    Ok(())
}

/// Scripted readings: at P1 (beacon from 167.5° at 4.6 m, walls N and W), then P2 (116.6°,
/// 1.1 m, walls N and E), with the beacon missed every fourth cycle.
fn read_sensors(cycle: usize) -> Sensors {
    let at_p2 = (4..8).contains(&cycle);
    let seen = cycle % 4 != 3;
    let (a, l, wall) = if at_p2 {
        (116.0, 1.2, 1)
    } else {
        (168.0, 4.5, 3)
    };
    Sensors {
        beacon_angle: seen.then_some((0.9, a)),
        beacon_distance: seen.then_some((0.85, l)),
        walls: [(0, 0.8), (wall, 0.75)],
    }
}
