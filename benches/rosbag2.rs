//! `extract --from rosbag2` against `--from carmen` on the same data, in one run: the whole
//! Intel log (910 scans) from memory, and the ROS 2 bag written from it by
//! `tests/rosbag/make_bag.py` (`$LPLACE_ROSBAG/intel`, else `target/rosbag/intel`), both through
//! the framer with `config/intel.ron`, frames built but not written. The goal: rosbag2 within
//! 1.5× of carmen. Skips with a message when the log or the bag is absent.

use std::hint::black_box;
use std::path::{Path, PathBuf};

use criterion::{criterion_group, criterion_main, Criterion};
use lplace::io::carmen_stream::{convert, CarmenFramer};
use lplace::io::rosbag2::{resolve_topics, BagConverter, TopicChoice};
use lplace::percept::ExtractConfig;

const ROOT: &str = env!("CARGO_MANIFEST_DIR");

fn inputs() -> Option<(Vec<u8>, Vec<u8>)> {
    let data = std::env::var_os("LPLACE_DATA")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(ROOT).join("../shared/data"));
    let bags = std::env::var_os("LPLACE_ROSBAG")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(ROOT).join("target/rosbag"));
    let log = std::fs::read(data.join("carmen-corrected-logs/intel-corrected.log")).ok()?;
    let bag = std::fs::read(bags.join("intel/intel.mcap")).ok()?;
    Some((log, bag))
}

fn bench(c: &mut Criterion) {
    let Some((log, bag)) = inputs() else {
        eprintln!("SKIP: the Intel log or the rosbag2 test bag is absent (see .ci/run)");
        return;
    };
    let cfg_text = std::fs::read_to_string(Path::new(ROOT).join("config/intel.ron"))
        .expect("config/intel.ron");
    let cfg = ExtractConfig::from_ron(&cfg_text).expect("config/intel.ron is valid");
    let topics = resolve_topics(&bag, &TopicChoice::default()).expect("the bag's topics");
    let mut g = c.benchmark_group("extract_intel_910_scans");
    g.sample_size(10);
    g.bench_function("carmen", |b| {
        b.iter(|| {
            let mut framer = CarmenFramer::new(cfg, None).expect("framer");
            let mut n = 0usize;
            let s = convert(
                &log[..],
                &mut framer,
                |f| -> Result<(), ()> {
                    n += black_box(&f).percepts.len();
                    Ok(())
                },
                |_| {},
            );
            (s.is_ok(), n)
        })
    });
    g.bench_function("rosbag2", |b| {
        b.iter(|| {
            let mut framer = CarmenFramer::new(cfg, None).expect("framer");
            let mut conv = BagConverter::new(&mut framer, topics.clone(), 0.0);
            let mut n = 0usize;
            let r = conv.push_file(
                &bag,
                |f| -> Result<(), ()> {
                    n += black_box(&f).percepts.len();
                    Ok(())
                },
                |_| {},
            );
            (r.is_ok(), n)
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
