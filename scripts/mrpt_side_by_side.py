#!/usr/bin/env python3
"""MRPT's particle-filter localization beside lplace on the mapped CARMEN buildings.

Issue 17, item 7: the peer a user would pick instead of lplace is MRPT's `pf-localization`
(Monte Carlo localization on an occupancy grid). For each building this script

1. builds an occupancy grid from the same survey run lplace's map was surveyed on (the
   corrected log; `carmen2simplemap`, the grid is made from the simple map by `pf-localization`
   with the settings of `MetricMap` below),
2. rebuilds the run's raw odometry from the log's ODOM lines as `lplace extract` reads it (the
   corrected logs carry the corrected pose in both FLASER pose slots, and their ODOM lines are
   re-chained from each scan's corrected pose: only the motion within one segment between two
   scans is raw) and converts the run with it (`carmen2rawlog`),
3. runs `pf-localization` started at the known first pose, and from no prior (uniform over the
   grid's free cells) with 5,000 and 40,000 particles, and parses the estimates from its log
   (it writes no pose file),
4. looks every estimate up in the floor-plan map's place extents (`examples/place_of_pose`, lplace's own
   `contains`, as `lplace extract --map` labels the truth) and scores it as lplace is scored,
5. prints one Markdown row per building and protocol, lplace's own rows first: the defaults
   (the floor-plan map surveyed on the log with `rules/laser.lpl`, as the README's table) and,
   where the building has one, its map surveyed with `rules/intel.lpl`.

Scoring (per scan whose corrected pose lies in some extent, "at a place"):
  decided           the filter has converged, spread <= --decided-spread (default 1.0), and its
                    mean pose lies in some place's extent;
  right             decided, and that place is the truth's;
  confidently wrong decided, wrong, and spread <= --confident-spread (default 0.5).
The spread is what pf-localization prints as `tr(cov)`: the square root of the trace of the
particles' covariance over (x, y, heading), in m and rad. lplace's row uses its own summary:
decided = a place asserted, confidently wrong = wrong with necessity >= 0.9. Time per scan:
pf-localization's own `Done in` time of each filter step (no log parsing, no map building);
lplace's is the wall time of `lplace extract` plus `lplace eval` over the whole log, process
start and JSON included, divided by the scans, the median of --lplace-repeats passes (the
survey, like the filter's map building, is not timed).

Needs (installs nothing): MRPT's applications, on Debian 12 `apt-get install mrpt-apps`
(MRPT 2.5.8: carmen2simplemap, carmen2rawlog, pf-localization); cargo (builds `lplace` and
`examples/place_of_pose`); the logs under $LPLACE_DATA (else ../shared/data).
Not run by CI. Runs `pf-localization` under `nice -n 10`.

    scripts/mrpt_side_by_side.py                      # every building, all protocols, 1 run each
    scripts/mrpt_side_by_side.py --runs 3 --buildings intel --particles 5000
"""

import argparse
import gzip
import json
import math
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
TOOLS = ("carmen2simplemap", "carmen2rawlog", "pf-localization")

# The buildings of the README's table: the log (plain or gzipped; `lplace extract` reads
# either, and the copies rewritten for MRPT are plain), the floor-plan map (its extents are the
# truth and the places looked up; lplace's default row surveys it on the log), the map surveyed
# with `rules/intel.lpl` and the extractor config it was surveyed with (`None` for a building
# that has no such map), and the laser's angle between beams (only Freiburg 101's log states it).
BUILDINGS = {
    "intel": {
        "name": "Intel Research Lab",
        "log": "carmen-corrected-logs/intel-corrected.log",
        "plan": "maps/intel-plan.map",
        "map": "maps/intel.map",
        "config": "config/intel.ron",
        "resolution_deg": 1.0,
    },
    "freiburg-101": {
        "name": "Freiburg 101",
        "log": "carmen-corrected-logs/freiburg-101-corrected.log",
        "plan": "maps/freiburg-101-plan.map",
        "map": "maps/freiburg-101.map",
        "config": "config/freiburg-101.ron",
        "resolution_deg": 0.5,
    },
    "seattle": {
        "name": "Seattle",
        "log": "carmen-corrected-logs/seattle-corrected.log.gz",
        "plan": "maps/seattle-plan.map",
        "map": "maps/seattle.map",
        "config": "config/seattle.ron",
        "resolution_deg": 0.5,
    },
    "csail": {
        "name": "CSAIL",
        "log": "carmen-corrected-logs/csail-corrected.log",
        "plan": "maps/csail-plan.map",
        "map": None,
        "config": None,
        "resolution_deg": 0.5,
    },
}

# lplace's first row is the README's table's "survey on the log, score the same log" row: the
# defaults (extract without a config, `rules/laser.lpl` and its tracker block), the floor-plan
# map surveyed on the log. The second, where the building has one, is the map surveyed with
# `rules/intel.lpl`, scored with that rule file and tracker.
DEFAULT_RULES = "rules/laser.lpl"
RULES = "rules/intel.lpl"
TRACKER = "config/intel-tracker.ron"

# Readings at or beyond this are no-returns (the logs write 81.83 / 81.91 m); MRPT's default
# laser is 0.5 degrees per beam and 81 m, so both are written as PARAM lines, the only ones the
# rewritten logs carry (Intel's log states no resolution, Seattle's has no PARAM line at all).
NO_RETURN_M = 80.0


class ScriptError(Exception):
    """A problem the script reports on one line and exits 2 with."""


def run(cmd, **kw):
    """Runs a command, raising ScriptError with its output's tail on failure."""
    p = subprocess.run(cmd, capture_output=True, text=True, **kw)
    if p.returncode != 0:
        tail = (p.stdout + p.stderr)[-2000:]
        raise ScriptError(f"{' '.join(map(str, cmd))} exited {p.returncode}:\n{tail}")
    return p


def data_dir():
    env = os.environ.get("LPLACE_DATA")
    return Path(env) if env else REPO.parent / "shared" / "data"


def cargo_targets():
    """Builds lplace, examples/place_of_pose and examples/time_per_scan; returns the three
    executables."""
    run(["cargo", "build", "--release", "--quiet", "--bin", "lplace",
         "--example", "place_of_pose", "--example", "time_per_scan"], cwd=REPO)
    meta = json.loads(run(["cargo", "metadata", "--format-version", "1", "--no-deps"],
                          cwd=REPO).stdout)
    release = Path(meta["target_directory"]) / "release"
    examples = release / "examples"
    return release / "lplace", examples / "place_of_pose", examples / "time_per_scan"


# ---------------------------------------------------------------- the log, rewritten for MRPT


def open_log(path):
    """The log as text, unpacked when its name ends in .gz."""
    return gzip.open(path, "rt") if path.suffix == ".gz" else open(path)


def wrap(a):
    return math.atan2(math.sin(a), math.cos(a))


def relative(a, b):
    """Pose b in the frame of pose a."""
    dx, dy = b[0] - a[0], b[1] - a[1]
    c, s = math.cos(a[2]), math.sin(a[2])
    return (c * dx + s * dy, -s * dx + c * dy, wrap(b[2] - a[2]))


def compose(a, d):
    """Pose a moved by the increment d, expressed in a's frame."""
    c, s = math.cos(a[2]), math.sin(a[2])
    return (a[0] + c * d[0] - s * d[1], a[1] + s * d[0] + c * d[1], wrap(a[2] + d[2]))


def read_log(path):
    """The FLASER scans (ranges, corrected pose, t, raw odometry increment since the scan
    before, None for the first), the increment as `lplace extract` reads it (src/io/
    carmen_stream.rs): (last ODOM before the scan) relative to the previous scan's odom pose,
    the ODOM chain restarting from that pose after every scan. An ODOM restating the previous
    scan's odom pose is that restart, not a reading of no motion; a segment with no other ODOM
    falls back to the two scans' poses (Seattle: one of 240, an 80 degree turn)."""
    scans, prev, last = [], None, None
    with open_log(path) as f:
        for n, line in enumerate(f, 1):
            tok = line.split()
            if not tok:
                continue
            try:
                if tok[0] == "ODOM":
                    pose = tuple(map(float, tok[1:4]))
                    if pose != prev:
                        last = pose
                elif tok[0] == "FLASER":
                    k = int(tok[1])
                    ranges = tok[2:2 + k]
                    corrected = tuple(map(float, tok[2 + k:5 + k]))
                    odom = tuple(map(float, tok[5 + k:8 + k]))
                    inc = None if prev is None else relative(prev, last or odom)
                    scans.append((ranges, corrected, float(tok[8 + k]), inc))
                    prev, last = odom, None
            except (ValueError, IndexError) as e:
                raise ScriptError(f"{path}:{n}: unreadable {tok[0]} line ({e})")
    if not scans:
        raise ScriptError(f"{path}: no FLASER lines")
    return scans


def beam_param(b, beams):
    """PARAM laser_front_laser_resolution for MRPT, which spreads the beams evenly over
    resolution x beams, centred ahead: resolution x (beams - 1) / beams gives the log's angle
    between beams (361 beams over 180 degrees exactly; 180 or 360 beams, whose last is one step
    short of the left, a fan turned half a step to the left)."""
    return b["resolution_deg"] * (beams - 1) / beams


def write_logs(b, scans, work):
    """Two CARMEN logs for MRPT: the survey (corrected pose, for the grid) and the run (the raw
    odometry composed from the first corrected pose, in both pose slots so that the laser sits
    at the robot's origin as in the survey)."""
    beams = {len(r) for r, _, _, _ in scans}
    if len(beams) != 1:
        raise ScriptError(f"{b['name']}: scans of {sorted(beams)} beams; MRPT takes one laser")
    params = [
        f"PARAM laser_front_laser_resolution {beam_param(b, beams.pop()):.9f} nohost 0",
        f"PARAM robot_front_laser_max {NO_RETURN_M} nohost 0",
    ]
    survey, raw = work / "survey.log", work / "run.log"
    odom = scans[0][1]
    with open(survey, "w") as fs, open(raw, "w") as fr:
        for f in (fs, fr):
            f.write("\n".join(params) + "\n")
        for ranges, (x, y, th), t, inc in scans:
            head = f"FLASER {len(ranges)} {' '.join(ranges)}"
            fs.write(f"{head} {x} {y} {th} {x} {y} {th} {t} nohost {t}\n")
            if inc is not None:
                odom = compose(odom, inc)
            ox, oy, oa = odom
            fr.write(f"{head} {ox} {oy} {oa} {ox} {oy} {oa} {t} nohost {t}\n")
    run(["carmen2simplemap", "-q", "-w", "-i", survey, "-o", work / "survey.simplemap"])
    run(["carmen2rawlog", "-q", "-w", "-i", raw, "-o", work / "run.rawlog"])
    return work / "survey.simplemap", work / "run.rawlog"


# ---------------------------------------------------------------- pf-localization


def ini_text(b, simplemap, rawlog, out_dir, particles, init):
    """pf-localization's configuration: a fixed particle count (no KLD adaptation), the
    likelihood field on a 5 cm grid, the given initial distribution."""
    beams = 180.0 / b["resolution_deg"]
    decimation = max(1, round(beams / 36))  # about 36 rays per scan in the likelihood
    return f"""
[KLD_options]
KLD_binSize_PHI_deg=10
KLD_binSize_XY=0.10
KLD_delta=0.01
KLD_epsilon=0.01
KLD_maxSampleSize={particles}
KLD_minSampleSize={particles}

[PF_options]
PF_algorithm=0
resamplingMethod=0
adaptiveSampleSize=0
BETA=0.5
sampleSize={particles}

[DummyOdometryParams]
minStdXY=0.10
minStdPHI=2.0

[LocalizationExperiment]
map_file={simplemap}
rawlog_file={rawlog}
logOutput_dir={out_dir}
3DSceneFrequency=-1
experimentRepetitions=1
particles_count={particles}
SAVE_STATS_ONLY=false
SHOW_PROGRESS_3D_REAL_TIME=false
{init}

[MetricMap]
occupancyGrid_count=1
gasGrid_count=0
pointsMap_count=0
beaconMap_count=0
likelihoodMapSelection=-1
enableInsertion_gridMaps=1

[MetricMap_occupancyGrid_00_creationOpts]
resolution=0.05

[MetricMap_occupancyGrid_00_insertOpts]
mapAltitude=0
useMapAltitude=0
maxDistanceInsertion=30
maxOccupancyUpdateCertainty=0.55
considerInvalidRangesAsFreeSpace=0

[MetricMap_occupancyGrid_00_likelihoodOpts]
likelihoodMethod=4
LF_decimation={decimation}
LF_stdHit=0.20
LF_maxCorrsDistance=0.30
LF_zHit=0.95
LF_zRandom=0.05
LF_maxRange=30
LF_alternateAverageMethod=0
"""


def init_known(first):
    """Uniform over a 0.2 m box and 4 degrees around the first corrected pose."""
    x, y, th = first
    d = math.degrees(th)
    return (f"init_PDF_mode=1\ninit_PDF_min_x={x - 0.1}\ninit_PDF_max_x={x + 0.1}\n"
            f"init_PDF_min_y={y - 0.1}\ninit_PDF_max_y={y + 0.1}\n"
            f"init_PDF_min_yaw_deg={d - 2}\ninit_PDF_max_yaw_deg={d + 2}")


def init_uniform(scans):
    """Uniform over the grid's free cells within the survey's bounding box and 20 m around."""
    xs = [p[0] for _, p, _, _ in scans]
    ys = [p[1] for _, p, _, _ in scans]
    return (f"init_PDF_mode=0\ninit_PDF_min_x={min(xs) - 20}\ninit_PDF_max_x={max(xs) + 20}\n"
            f"init_PDF_min_y={min(ys) - 20}\ninit_PDF_max_y={max(ys) + 20}\n"
            "init_PDF_min_yaw_deg=-180\ninit_PDF_max_yaw_deg=180")


ESTIMATE = re.compile(r"PDF estimation: \(([-\d.e+]+),([-\d.e+]+),([-\d.e+]+)(?:deg)?\).*"
                      r"tr\(cov\): ([-\d.e+naif]+)")
DONE = re.compile(r"Done in ([\d.]+)ms")


def run_pf(b, simplemap, rawlog, work, tag, particles, init):
    """One pf-localization run: per scan the mean pose and spread, and the step times (ms)."""
    out = work / tag
    ini = work / f"{tag}.ini"
    ini.write_text(ini_text(b, simplemap, rawlog, out, particles, init))
    p = run(["nice", "-n", "10", "pf-localization", ini])
    text = p.stdout + p.stderr
    (work / f"{tag}.txt").write_text(text)
    est = [(float(m[1]), float(m[2]), float(m[4])) for m in ESTIMATE.finditer(text)]
    times = [float(m[1]) for m in DONE.finditer(text)]
    return est, times


# ---------------------------------------------------------------- scoring


def places_of(lookup, map_path, points):
    """The place holding each point, or None (examples/place_of_pose)."""
    text = "".join(f"{x} {y}\n" for x, y in points)
    p = run([lookup, REPO / map_path], input=text)
    names = p.stdout.split("\n")[:len(points)]
    if len(names) != len(points):
        raise ScriptError(f"place_of_pose answered {len(names)} of {len(points)} points")
    return [None if n == "-" else n for n in names]


def score(truth, estimate, spread, args):
    at = dec = right = cw = 0
    for t, e, s in zip(truth, estimate, spread):
        if t is None:
            continue
        at += 1
        if e is None or not s <= args.decided_spread:
            continue
        dec += 1
        if e == t:
            right += 1
        elif s <= args.confident_spread:
            cw += 1
    return at, dec, right, cw


def summary_row(p, elapsed, step_ms=None):
    """(at a place, decided, right, confidently wrong, ms per scan of the whole commands, ms per
    scan timed as the filter's step or None) from `eval`'s JSON summary."""
    s = json.loads(p.stdout)
    truth = s["truth"]
    dec = truth["correct"] + truth["wrong"]
    return (truth["at_place"], dec, truth["correct"], truth["confidently_wrong"],
            1e3 * elapsed / s["frames"], step_ms)


def lplace_default_row(b, tools, log, wdir, repeats):
    """lplace with the defaults, as the README's buildings table: the log extracted without a
    config, the floor-plan map surveyed on it with DEFAULT_RULES (`lplace survey`, a one-off
    like the filter's map building, so not timed), the log evaluated with the surveyed map.
    Extraction and evaluation are timed `repeats` times and the median kept: one pass over a
    log of a few hundred scans takes a tenth of a second, where one busy moment of the host
    shows, while the filter's time is a mean over every step of every run. Timed too as the
    filter's step is (`examples/time_per_scan`: the log parsed before the clock starts, no
    JSON, no process start), the median of as many passes; its decisions must be eval's."""
    lplace, _, per_scan = tools
    plan = REPO / b["plan"]
    stream = wdir / "lplace.jsonl"
    surveyed = wdir / "surveyed.map"
    times = []
    for k in range(max(1, repeats)):
        t0 = time.perf_counter()
        frames = run([lplace, "extract", "--from", "carmen", log, "--map", plan], cwd=REPO).stdout
        extract_s = time.perf_counter() - t0
        stream.write_text(frames)
        if k == 0:
            run([lplace, "survey", "--map", plan, "--rules", REPO / DEFAULT_RULES, stream,
                 "-o", surveyed], cwd=REPO)
        t0 = time.perf_counter()
        p = run([lplace, "eval", stream, "--map", surveyed, "--rules", REPO / DEFAULT_RULES,
                 "--only-summary", "--summary", "json"], cwd=REPO)
        times.append(extract_s + time.perf_counter() - t0)
    step = run([per_scan, log, plan, surveyed, REPO / DEFAULT_RULES, str(max(1, repeats))],
               cwd=REPO).stdout.split()
    # `scans S decided D ms_per_scan M`
    figures = dict(zip(step[0::2], step[1::2]))
    decided = json.loads(p.stdout)["decided"]
    if int(figures.get("decided", -1)) != decided:
        raise ScriptError(f"{b['name']}: time_per_scan decided {figures.get('decided')} "
                          f"frames, eval {decided}")
    return summary_row(p, statistics.median(times), float(figures["ms_per_scan"]))


def lplace_intel_row(b, lplace, log):
    """lplace's `rules/intel.lpl` row: the building's map surveyed with RULES, extracted with
    the config it was surveyed with, evaluated with RULES and TRACKER."""
    t0 = time.perf_counter()
    frames = run([lplace, "extract", "--from", "carmen", log, "--map", REPO / b["map"],
                  "--config", REPO / b["config"]], cwd=REPO).stdout
    p = run([lplace, "eval", "-", "--map", REPO / b["map"], "--rules", REPO / RULES,
             "--tracker", REPO / TRACKER, "--only-summary",
             "--summary", "json"], input=frames, cwd=REPO)
    return summary_row(p, time.perf_counter() - t0)


def pct(a, b):
    return 100.0 * a / b if b else 0.0


# A run confidently wrong on more scans than this (percent of those at a place) is counted as
# one that locked onto a wrong pose.
LOCKED_WRONG_PCT = 5.0


def row(name, method, protocol, runs):
    """A Markdown row: the mean over runs, and the range when there are several; and how many
    runs locked onto a wrong pose."""
    def fig(vals, fmt):
        m = statistics.mean(vals)
        if len(vals) > 1 and max(vals) - min(vals) > 1e-9:
            return f"{fmt.format(m)} ({fmt.format(min(vals))}–{fmt.format(max(vals))})"
        return fmt.format(m)
    at = runs[0][0]
    decided = [pct(r[1], r[0]) for r in runs]
    right = [pct(r[2], r[1]) for r in runs]
    cw = [pct(r[3], r[0]) for r in runs]
    ms = [r[4] for r in runs]
    locked = sum(c > LOCKED_WRONG_PCT for c in cw)
    # lplace's own rows: the time as the filter's step is timed, then the whole commands'.
    step = [r[5] for r in runs if len(r) > 5 and r[5] is not None]
    time_cell = (f"{fig(step, '{:.3f}')} ms (whole commands {fig(ms, '{:.2f}')} ms)" if step
                 else f"{fig(ms, '{:.2f}')} ms")
    return (f"| {name} | {method} | {protocol} | {len(runs)} | {at} | {fig(decided, '{:.1f} %')}"
            f" | {fig(right, '{:.1f} %')} | {fig(cw, '{:.1f} %')} | {locked} | {time_cell} |")


# ---------------------------------------------------------------- main


def building(key, args, tools, work):
    b = BUILDINGS[key]
    log = data_dir() / b["log"]
    if not log.is_file():
        print(f"SKIP {b['name']}: {log} not found (set LPLACE_DATA)", file=sys.stderr)
        return []
    wdir = work / key
    wdir.mkdir(parents=True, exist_ok=True)
    scans = read_log(log)
    simplemap, rawlog = write_logs(b, scans, wdir)
    lookup = tools[1]
    truth = places_of(lookup, b["plan"], [(p[0], p[1]) for _, p, _, _ in scans])
    own = [(f"floor plan surveyed on the log, {DEFAULT_RULES}, the defaults",
            lplace_default_row(b, tools, log, wdir, args.lplace_repeats))]
    if b["map"]:
        own.append((f"surveyed map, {RULES}, grid tracker", lplace_intel_row(b, tools[0], log)))
    # All scored on the same scans: the extents looked up here must hold what extract labelled.
    at_place = sum(t is not None for t in truth)
    for protocol, figures in own:
        if figures[0] != at_place:
            raise ScriptError(f"{b['name']}: lplace ({protocol}) scores {figures[0]} scans at "
                              f"a place, the lookup finds {at_place}")
    rows = [row(b["name"], "lplace", protocol, [figures]) for protocol, figures in own]
    protocols = [("known first pose", args.known_particles, init_known(scans[0][1]))]
    protocols += [("no prior", n, init_uniform(scans)) for n in args.particles]
    for label, n, init in protocols:
        results = []
        for r in range(args.runs):
            tag = f"{label.replace(' ', '-')}-{n}-{r}"
            est, times = run_pf(b, simplemap, rawlog, wdir, tag, n, init)
            if len(est) != len(scans):
                raise ScriptError(f"{b['name']} {tag}: {len(est)} estimates for "
                                  f"{len(scans)} scans (see {wdir / tag}.txt)")
            where = places_of(lookup, b["plan"], [(x, y) for x, y, _ in est])
            at, dec, right, cw = score(truth, where, [s for _, _, s in est], args)
            ms = statistics.mean(times) if times else float("nan")
            results.append((at, dec, right, cw, ms))
            print(f"{b['name']} {tag}: {at} at a place, decided {dec}, right {right}, "
                  f"confidently wrong {cw}, {ms:.2f} ms/scan", file=sys.stderr)
        rows.append(row(b["name"], "MRPT pf-localization", f"{label}, {n:,} particles",
                        results))
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--buildings", default=",".join(BUILDINGS),
                    help="comma-separated: " + ", ".join(BUILDINGS))
    ap.add_argument("--particles", default="5000,40000",
                    help="particle counts of the no-prior runs (comma-separated)")
    ap.add_argument("--known-particles", type=int, default=5000,
                    help="particles of the run started at the known first pose")
    ap.add_argument("--runs", type=int, default=1, help="runs per protocol (MRPT seeds anew)")
    ap.add_argument("--lplace-repeats", type=int, default=5,
                    help="times lplace's defaults row is timed; the median is kept")
    ap.add_argument("--decided-spread", type=float, default=1.0)
    ap.add_argument("--confident-spread", type=float, default=0.5)
    ap.add_argument("--work", help="keep the intermediate files here (default: a temporary "
                    "directory, removed)")
    args = ap.parse_args()
    try:
        args.particles = [int(n) for n in args.particles.split(",") if n]
        keys = [k for k in args.buildings.split(",") if k]
        unknown = [k for k in keys if k not in BUILDINGS]
        if unknown:
            raise ScriptError(f"unknown building(s) {unknown}; known: {list(BUILDINGS)}")
        missing = [t for t in TOOLS if shutil.which(t) is None]
        if missing:
            raise ScriptError(f"{', '.join(missing)} not found: this script needs MRPT's "
                              "applications (Debian 12: apt-get install mrpt-apps, 2.5.8)")
        tools = cargo_targets()
        work = Path(args.work) if args.work else Path(tempfile.mkdtemp(prefix="mrpt-sbs-"))
        rows = []
        try:
            for k in keys:
                rows += building(k, args, tools, work)
        finally:
            if not args.work:
                shutil.rmtree(work, ignore_errors=True)
        if not rows:
            raise ScriptError(f"no building's log found under {data_dir()}")
    except (ScriptError, ValueError, OSError) as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    print("| building | method | protocol | runs | scans at a place | decided | right of decided "
          f"| confidently wrong | runs > {LOCKED_WRONG_PCT:g} % confidently wrong | time per scan |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    print("\n".join(rows))
    return 0


if __name__ == "__main__":
    sys.exit(main())
