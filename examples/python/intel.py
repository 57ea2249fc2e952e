"""The Intel Research Lab run from Python, notebook style (each block a cell; not run in CI).

1. extract the CARMEN log into a percept stream (``lplace.extract`` = ``lplace extract``);
2. evaluate it with the metric grid tracker (``lplace.evaluate`` = ``lplace eval``);
3. plot the decided place's necessity and Inc over time with matplotlib;
4. score the place-level trajectory (each decided frame at its place's pose) against the
   corrected poses with evo (TUM files, ``evo_ape``).

    pip install . matplotlib evo pandas
    python examples/python/intel.py [LOG]   # default ../shared/data/carmen-corrected-logs/...

Writes intel-necessity.png, intel-est.tum, intel-ref.tum in the current folder.
"""

# %% 1. Extract
import json
import os
import subprocess
import sys
from pathlib import Path

import lplace

REPO = Path(__file__).resolve().parents[2]
DATA = Path(os.environ.get("LPLACE_DATA", REPO.parent / "shared" / "data"))
LOG = Path(sys.argv[1]) if len(sys.argv) > 1 else DATA / "carmen-corrected-logs" / "intel-corrected.log"
MAP, RULES = REPO / "maps" / "intel.map", REPO / "rules" / "intel.lpl"

ext = lplace.extract(LOG, map=MAP, config=REPO / "config" / "intel.ron")
print(f"{ext.frames} frames from {ext.lines} log lines; {len(ext.malformed)} malformed")

# %% 2. Evaluate (the grid tracker of the README's Intel table)
res = lplace.evaluate(ext.records, MAP, RULES, tracker=REPO / "config" / "intel-tracker.ron")
truth = res.summary["truth"]
decided_at_place = truth["correct"] + truth["wrong"]
print(
    f"decided {res.summary['decided']} of {res.summary['frames']} frames; "
    f"right {truth['correct'] / max(decided_at_place, 1):.1%} of the decisions at a place; "
    f"confidently wrong {truth['confidently_wrong_rate']:.2%} of the frames at a place"
)
df = res.table.to_pandas()

# %% 3. Plot necessity and Inc over time
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

fig, ax = plt.subplots(figsize=(11, 3.5))
ax.plot(df["t"] - df["t"].iloc[0], df["necessity"], ".", ms=2, label="N(decided place)")
ax.plot(df["t"] - df["t"].iloc[0], df["inconsistency"], lw=0.6, label="Inc")
ax.set_xlabel("time (s)")
ax.set_ylim(0, 1.02)
ax.legend(loc="lower right")
ax.set_title("Intel lab: necessity of each decision (gaps: disoriented)")
fig.tight_layout()
fig.savefig("intel-necessity.png", dpi=120)

# %% 4. Score with evo: decided frames at their place's pose, against the corrected pose
engine = lplace.Engine.load(MAP, RULES)
poses = dict(zip(engine.places, engine.place_poses))
records = {i + 1: json.loads(line) for i, line in enumerate(ext.records)}
with open("intel-est.tum", "w") as est, open("intel-ref.tum", "w") as ref:
    for row in df.itertuples():
        rec = records[row.line]
        pose = (rec.get("truth") or {}).get("pose")
        if row.place is None or not isinstance(row.place, str) or pose is None:
            continue
        x, y = poses[row.place]
        est.write(f"{row.t:.6f} {x} {y} 0 0 0 0 1\n")
        ref.write(f"{row.t:.6f} {pose[0]} {pose[1]} 0 0 0 0 1\n")
# evo's scripts sit beside this interpreter in a venv, which need not be on PATH.
beside = Path(sys.executable).parent / "evo_ape"
evo_ape = str(beside) if beside.exists() else "evo_ape"
subprocess.run([evo_ape, "tum", "intel-ref.tum", "intel-est.tum"], check=True)
