#!/usr/bin/env python3
"""The README's MRCLAM table in one command: `lplace compare` over robots x seeds, averaged.

For every robot and seed this runs

    lplace compare --from-dir DATA --robot R --methods METHODS --seed S --format csv [configs]

keeps each method's unperturbed run (`run == main`) and prints, as Markdown,

* per robot, each method's ATE RMSE over the common window (the frames from the latest first
  fix of the methods in the run on: every method scored on the same frames), the mean over the
  seeds;
* the mean over the robots, and the same mean seed by seed (the particle filters and R-MCL
  depend on the seed; the grid does not, but the common window it is scored over does);
* each method's first fix (range over robots and seeds, seconds from the first frame) and its
  median time per step (wall time, so it depends on the machine and its load).

Needs cargo (builds `lplace` in release mode) or `--lplace PATH`; python3 alone, no packages.
The data set is read from --data, else $LPLACE_DATA/mrclam-dataset7, else
../shared/data/mrclam-dataset7 beside the repository.

    scripts/mrclam_table.py                                   # defaults, robots and seeds 1-5
    scripts/mrclam_table.py --methods fpg,pf:2000 --config config/grid-mrclam-accurate.ron \\
        --pf-config config/pf-calibrated.ron
    scripts/mrclam_table.py --methods fpg,pf:2000 --start-at-truth     # tracking

Exit codes: 0 the table was printed; 1 a run failed (its stderr is shown); 2 bad arguments.
"""

import argparse
import csv
import io
import os
import statistics
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent


def default_data() -> Path:
    base = os.environ.get("LPLACE_DATA")
    root = Path(base) if base else REPO.parent / "shared" / "data"
    return root / "mrclam-dataset7"


def int_list(text: str) -> list:
    """`1-5` or `1,3,4`."""
    out = []
    for part in text.split(","):
        lo, _, hi = part.partition("-")
        out.extend(range(int(lo), int(hi or lo) + 1))
    if not out:
        raise argparse.ArgumentTypeError("empty list")
    return out


def script_parser(doc: str) -> argparse.ArgumentParser:
    """The MRCLAM scripts' parser: help from the module text, `--data`, `--jobs`, `--lplace`."""
    p = argparse.ArgumentParser(
        description=doc.split("\n\n")[0],
        epilog="\n\n".join(doc.split("\n\n")[1:]),
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("--data", type=Path, default=default_data(), help="MRCLAM data set folder")
    p.add_argument("--jobs", type=int, default=2, help="runs at once (default 2)")
    p.add_argument("--lplace", type=Path, help="the lplace binary (default: cargo build)")
    return p


def parse_checked(p: argparse.ArgumentParser) -> argparse.Namespace:
    """Parses, refusing (exit 2) a folder without the survey and fewer than one job."""
    a = p.parse_args()
    if not (a.data / "Landmark_Groundtruth.dat").is_file():
        p.error(f"{a.data} holds no Landmark_Groundtruth.dat (set --data or LPLACE_DATA)")
    if a.jobs < 1:
        p.error("--jobs must be at least 1")
    return a


def parse_args() -> argparse.Namespace:
    p = script_parser(__doc__)
    p.add_argument("--robots", type=int_list, default=[1, 2, 3, 4, 5], help="e.g. 1-5 or 2,4")
    p.add_argument("--seeds", type=int_list, default=[1, 2, 3, 4, 5], help="e.g. 1-5")
    p.add_argument("--methods", default="fpg,pf:500,pf:2000,rmcl", help="as lplace compare")
    p.add_argument("--config", help="grid configuration (lplace compare --config)")
    p.add_argument("--pf-config", help="particle filter configuration")
    p.add_argument("--rmcl-config", help="Fuzzy R-MCL configuration")
    p.add_argument("--start-at-truth", action="store_true", help="tracking (fpg and pf only)")
    return parse_checked(p)


def main_rows(text: str) -> list:
    """The unperturbed rows (`run == main`) of `lplace compare --format csv`."""
    return [r for r in csv.DictReader(io.StringIO(text)) if r["run"] == "main"]


def lplace_binary(given) -> Path:
    if given:
        return given
    subprocess.run(
        ["cargo", "build", "--release", "--locked", "--quiet", "--bin", "lplace"],
        cwd=REPO,
        check=True,
    )
    return REPO / "target" / "release" / "lplace"


def run_one(args, exe: Path, robot: int, seed: int) -> dict:
    cmd = [str(exe), "compare", "--from-dir", str(args.data), "--robot", str(robot),
           "--methods", args.methods, "--seed", str(seed), "--format", "csv"]
    for flag, value in (("--config", args.config), ("--pf-config", args.pf_config),
                        ("--rmcl-config", args.rmcl_config)):
        if value:
            cmd += [flag, value]
    if args.start_at_truth:
        cmd.append("--start-at-truth")
    done = subprocess.run(cmd, cwd=REPO, capture_output=True, text=True)
    if done.returncode != 0:
        raise RuntimeError(f"robot {robot} seed {seed}: exit {done.returncode}\n{done.stderr}")
    return {r["method"]: r for r in main_rows(done.stdout)}


def fmt(v: float) -> str:
    return f"{v:.3f}"


def print_table(args, methods: list, runs: dict) -> None:
    ate = lambda m, r, s: float(runs[r, s][m]["ate_common_rmse_m"])  # noqa: E731
    print("| robot | " + " | ".join(methods) + " |")
    print("|---" * (len(methods) + 1) + "|")
    per_robot = {m: [] for m in methods}
    for r in args.robots:
        cells = []
        for m in methods:
            v = statistics.mean(ate(m, r, s) for s in args.seeds)
            per_robot[m].append(v)
            cells.append(fmt(v))
        print(f"| {r} | " + " | ".join(cells) + " |")
    print("| **mean** | " + " | ".join(f"**{fmt(statistics.mean(per_robot[m]))}**"
                                     for m in methods) + " |")
    print()
    print("Mean over the robots, seed by seed (" + ", ".join(map(str, args.seeds)) + "):")
    for m in methods:
        by_seed = [statistics.mean(ate(m, r, s) for r in args.robots) for s in args.seeds]
        print(f"* {m}: " + " / ".join(map(fmt, by_seed)))
    print()
    print("| method | first fix [s] | time per step, median [µs] |")
    print("|---|---|---|")
    for m in methods:
        fixes = [float(runs[k][m]["first_fix_s"]) for k in runs if runs[k][m]["first_fix_s"]]
        steps = [float(runs[k][m]["time_per_step_us"]) for k in runs]
        span = f"{min(fixes):.1f}–{max(fixes):.1f}" if fixes else "never"
        print(f"| {m} | {span} | {statistics.median(steps):.1f} |")


def main() -> int:
    args = parse_args()
    methods = [m.strip() for m in args.methods.split(",") if m.strip()]
    try:
        exe = lplace_binary(args.lplace)
    except (OSError, subprocess.CalledProcessError) as e:
        print(f"mrclam_table: cannot build lplace: {e}", file=sys.stderr)
        return 1
    keys = [(r, s) for r in args.robots for s in args.seeds]
    total = len(keys)
    runs = {}
    with ThreadPoolExecutor(max_workers=args.jobs) as pool:
        futures = {k: pool.submit(run_one, args, exe, *k) for k in keys}
        for i, (k, f) in enumerate(futures.items(), 1):
            try:
                runs[k] = f.result()
            except (OSError, RuntimeError) as e:
                print(f"mrclam_table: {e}", file=sys.stderr)
                return 1
            print(f"\rmrclam_table: {i}/{total} runs", end="", file=sys.stderr, flush=True)
    print(file=sys.stderr)
    missing = [(m, k) for k in keys for m in methods if m not in runs[k]]
    if missing:
        print(f"mrclam_table: no row for {missing[0][0]} in robot {missing[0][1][0]}",
              file=sys.stderr)
        return 1
    print_table(args, methods, runs)
    return 0


if __name__ == "__main__":
    sys.exit(main())
