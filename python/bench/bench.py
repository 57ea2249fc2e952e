"""Timings of the Python binding against its Rust references, in one run (not run in CI).

    python python/bench/bench.py [--frames-eval 1000000] [--logs 16] [--log-frames 200000]

1. `Engine.step` per frame (arrays, and a dict) against the bare Rust row step timed inside the
   extension (`rust_loop_ns(outputs=False)`): the overhead Python adds per frame.
2. `Engine.step_many` against the same loop timed inside Rust (`rust_loop_ns(outputs=True)`).
3. `lplace.evaluate` on a simulated N-frame stream against the `lplace eval` binary on the same
   file (decisions to /dev/null), best of three each.
4. `lplace.fleet.evaluate` over L simulated logs with a local Ray of 1 and of 2 workers, and
   the scale-out model (mean per-log seconds × logs ÷ workers) against the measured 2-worker time.

Prints one JSON object with every figure (seconds, ratios). Needs the `lplace` binary
(`$LPLACE_BIN`, else target/release/lplace) and ray.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import platform
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

import lplace
from lplace import _lplace

REPO = Path(__file__).resolve().parents[2]
BIN = Path(os.environ.get("LPLACE_BIN", REPO / "target" / "release" / "lplace"))


def best(f, repeat=5):
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        f()
        times.append(time.perf_counter() - t)
    return min(times)


def step_figures(n=100_000, rounds=5):
    """Python and Rust alternate in each round, so that both see the same load; the best round
    of each is kept."""
    e = lplace.Engine.office()
    rng = np.random.default_rng(7)
    s = len(e.slots)
    deg, val = rng.random((n, s)), rng.random((n, s)) * 360.0
    # Row views made before timing: the figure is the call, not numpy's indexing.
    drows, vrows = list(deg), list(val)
    frame = {name: (0.7, 90.0) for name in e.slots[:6]}
    step = e.step
    best_ = {k: float("inf") for k in ("rust_step", "py_step", "py_dict", "rust_loop", "many")}
    for _ in range(rounds):
        best_["rust_step"] = min(best_["rust_step"], _lplace.rust_loop_ns(e, deg, val, outputs=False) / n)
        t = time.perf_counter()
        for i in range(n):
            step(drows[i], vrows[i])
        best_["py_step"] = min(best_["py_step"], (time.perf_counter() - t) / n * 1e9)
        t = time.perf_counter()
        for _ in range(n // 4):
            step(frame)
        best_["py_dict"] = min(best_["py_dict"], (time.perf_counter() - t) / (n // 4) * 1e9)
        best_["rust_loop"] = min(best_["rust_loop"], _lplace.rust_loop_ns(e, deg, val, outputs=True) / n)
        t = time.perf_counter()
        e.step_many(deg, val)
        best_["many"] = min(best_["many"], (time.perf_counter() - t) / n * 1e9)
    return {
        "frames": n,
        "rust_row_step_ns": best_["rust_step"],
        "python_step_arrays_ns": best_["py_step"],
        "python_step_overhead_ns": best_["py_step"] - best_["rust_step"],
        "python_step_dict_6_percepts_ns": best_["py_dict"],
        "rust_loop_ns_per_frame": best_["rust_loop"],
        "step_many_ns_per_frame": best_["many"],
        "step_many_over_rust_loop": best_["many"] / best_["rust_loop"],
        "load_average_1min": os.getloadavg()[0],
    }


def simulate(path: Path, frames: int, seed: int) -> None:
    with open(path, "wb") as f:
        subprocess.run(
            [str(BIN), "simulate", "--steps", str(frames), "--seed", str(seed)],
            stdout=f,
            check=True,
        )


def evaluate_figures(tmp: Path, frames: int):
    stream = tmp / "big.jsonl"
    simulate(stream, frames, 11)

    def cli():
        with open(os.devnull, "wb") as null:
            r = subprocess.run([str(BIN), "eval", str(stream), "--summary", "none"], stdout=null)
            assert r.returncode in (0, 3)

    def py():
        res = lplace.evaluate(stream)
        assert res.table.num_rows > 0

    def cli_summary_only():
        r = subprocess.run([str(BIN), "eval", str(stream), "--only-summary"], capture_output=True)
        assert r.returncode in (0, 3)

    cli_s, py_s = best(cli, 3), best(py, 3)
    cli_quiet_s = best(cli_summary_only, 3)
    load = os.getloadavg()[0]
    return {
        "frames": frames,
        "bytes": stream.stat().st_size,
        "cli_eval_s": cli_s,
        "cli_eval_only_summary_s": cli_quiet_s,
        "python_evaluate_s": py_s,
        "evaluate_over_cli": py_s / cli_s,
        "load_average_1min": load,
    }


def fleet_run(paths, out: Path, workers: int):
    import ray

    from lplace import fleet

    ray.init(num_cpus=workers, include_dashboard=False, log_to_driver=False)
    try:
        fleet.evaluate(paths[:workers], out=out / "warm")  # worker start-up, imports
        t = time.perf_counter()
        table = fleet.evaluate(paths, out=out / f"w{workers}")
        wall = time.perf_counter() - t
    finally:
        ray.shutdown()
    assert set(table.column("status").to_pylist()) == {"ok"}
    return wall, table.column("seconds").to_pylist(), sum(table.column("frames").to_pylist())


def fleet_figures(tmp: Path, logs: int, log_frames: int):
    paths = []
    for i in range(logs):
        p = tmp / f"robot{i:02d}.jsonl"
        simulate(p, log_frames, 100 + i)
        paths.append(p)
    w1, per_log, frames = fleet_run(paths, tmp, 1)
    w2, per_log2, _ = fleet_run(paths, tmp, 2)
    c = sum(per_log) / len(per_log)
    model2 = math.ceil(logs / 2) * c
    return {
        "logs": logs,
        "frames_per_log": log_frames,
        "one_worker_s": w1,
        "two_workers_s": w2,
        "one_worker_frames_per_s": frames / w1,
        "two_workers_frames_per_s": frames / w2,
        "speedup_2_over_1": w1 / w2,
        "mean_log_s_one_worker": c,
        "mean_log_s_two_workers": sum(per_log2) / len(per_log2),
        "model_two_workers_s": model2,
        "model_over_measured": model2 / w2,
        "frames_per_worker_s": frames / sum(per_log),
        "load_average_1min": os.getloadavg()[0],
    }


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--frames-eval", type=int, default=1_000_000)
    ap.add_argument("--logs", type=int, default=16)
    ap.add_argument("--log-frames", type=int, default=200_000)
    ap.add_argument("--skip", nargs="*", default=[], choices=["step", "eval", "fleet"])
    args = ap.parse_args()
    out = {
        "date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()),
        "machine": f"{platform.machine()}, {os.cpu_count()} cores (shared host)",
        "python": sys.version.split()[0],
    }
    with tempfile.TemporaryDirectory(prefix="lplace-bench-") as d:
        tmp = Path(d)
        if "step" not in args.skip:
            out["step"] = step_figures()
            print(json.dumps(out["step"]), file=sys.stderr)
        if "eval" not in args.skip:
            out["evaluate"] = evaluate_figures(tmp, args.frames_eval)
            print(json.dumps(out["evaluate"]), file=sys.stderr)
        if "fleet" not in args.skip:
            out["fleet"] = fleet_figures(tmp, args.logs, args.log_frames)
    print(json.dumps(out, indent=2))


if __name__ == "__main__":
    main()
