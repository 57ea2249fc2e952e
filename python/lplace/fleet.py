"""Fleet batch on Ray: one Ray task per log, each log's decisions streamed to Parquet.

``evaluate(paths, map, rules, out=…, address=None)`` starts (or joins) a Ray cluster, runs one
task per log, and returns the per-log summary table. Each task evaluates its log batch by batch
(``lplace.iter_batches``: the same loop as ``lplace eval``) and writes every batch as it comes
to ``OUT/log=NAME/part-0.parquet`` (hive partitioning, so pandas, Polars and Spark read the
folder back with a ``log`` column). A log that fails (unreadable, not a stream) is reported in
its row (``status = "failed"``, ``error``) and leaves no Parquet file; the batch goes on.
Rejected records are counted and listed per log (``rejected``, ``rejections``), never dropped.

Command line: ``python -m lplace.fleet LOG… --map M --rules R --out DIR [--address ADDR]``.

Depends on ``lplace`` (the engine and the batch reader), pyarrow and ray (imported when used).
"""

from __future__ import annotations

import argparse
import json
import os
import re
import sys
import time
from typing import Any, Dict, List, Optional, Sequence, Union

import pyarrow as pa
import pyarrow.parquet as pq

from lplace import _eval, _lplace
from lplace._errors import CheckError

#: The per-log summary table's columns.
SUMMARY_SCHEMA = pa.schema(
    [
        ("log", pa.string()),
        ("path", pa.string()),
        ("status", pa.string()),
        ("error", pa.string()),
        ("frames", pa.int64()),
        ("decided", pa.int64()),
        ("rejected", pa.int64()),
        ("accuracy", pa.float64()),
        ("confidently_wrong_rate", pa.float64()),
        ("seconds", pa.float64()),
        ("parquet", pa.string()),
        ("summary_json", pa.string()),
        (
            "rejections",
            pa.list_(
                pa.struct(
                    [
                        ("line", pa.uint64()),
                        ("column", pa.uint64()),
                        ("kind", pa.string()),
                        ("message", pa.string()),
                    ]
                )
            ),
        ),
    ]
)

_Path = Union[str, "os.PathLike[str]"]


def log_names(paths: Sequence[_Path]) -> List[str]:
    """One partition name per path: the file name without its extension, with characters
    other than letters, digits, ``.``, ``_`` and ``-`` replaced by ``_``; a repeated name gets
    ``~2``, ``~3``… in input order, so that no log overwrites another."""
    seen: Dict[str, int] = {}
    names = []
    for p in paths:
        base = os.path.basename(os.fspath(p))
        for ext in (".jsonl", ".json", ".csv"):
            if base.endswith(ext):
                base = base[: -len(ext)]
                break
        base = re.sub(r"[^A-Za-z0-9._-]", "_", base) or "log"
        n = seen.get(base, 0) + 1
        seen[base] = n
        names.append(base if n == 1 else f"{base}~{n}")
    return names


def _row(name: str, path: str) -> Dict[str, Any]:
    return {
        "log": name,
        "path": path,
        "status": "ok",
        "error": None,
        "frames": 0,
        "decided": 0,
        "rejected": 0,
        "accuracy": None,
        "confidently_wrong_rate": None,
        "seconds": 0.0,
        "parquet": None,
        "summary_json": None,
        "rejections": [],
    }


def evaluate_log(
    path: str,
    name: str,
    model: Dict[str, str],
    track: bool,
    tracker_ron: Optional[str],
    out: str,
    batch_frames: int = 65536,
    format: Optional[str] = None,
) -> Dict[str, Any]:
    """One log: decisions to ``out/log=NAME/part-0.parquet``, its summary row returned. Never
    raises for a bad log: the row says ``failed`` and why. (The body of each Ray task.)"""
    start = time.perf_counter()
    row = _row(name, path)
    part = os.path.join(out, f"log={name}")
    final = os.path.join(part, "part-0.parquet")
    # A leading underscore hides the file from pyarrow, pandas, Polars and Spark readers.
    tmp = os.path.join(part, "_part-0.parquet.partial")
    try:
        engine = _lplace.Engine.from_strings(
            model["map"], model["rules"], model["map_name"], model["rules_name"]
        )
        batches = _eval.Batches(
            _lplace.StreamBatches(
                engine, path=path, format=format, track=track, tracker=tracker_ron
            ),
            batch_frames,
        )
        os.makedirs(part, exist_ok=True)
        # Written under another name and renamed at the end, so that a log failing half way
        # leaves no partial file for readers of the folder to pick up.
        with pq.ParquetWriter(tmp, _eval.SCHEMA) as writer:
            for table in batches:
                writer.write_table(table)
        os.replace(tmp, final)
        summary = batches.summary()
        truth = summary.get("truth") or {}
        row.update(
            frames=summary["frames"],
            decided=summary["decided"],
            rejected=summary["rejected"],
            accuracy=truth.get("accuracy"),
            confidently_wrong_rate=truth.get("confidently_wrong_rate"),
            parquet=final,
            summary_json=json.dumps(summary, sort_keys=True),
            rejections=batches.rejected,
        )
    except Exception as e:  # noqa: BLE001 — the contract: a bad log fails its row, not the batch
        row.update(status="failed", error=f"{type(e).__name__}: {e}")
        # Neither a half-written file nor an earlier run's output may pass for this log's.
        for stale in (tmp, final):
            if os.path.exists(stale):
                os.remove(stale)
    row["seconds"] = time.perf_counter() - start
    return row


def _model(map: Optional[_Path], rules: Optional[_Path]) -> Dict[str, str]:
    if map is None and rules is None:
        return {
            "map": _lplace.OFFICE_MAP,
            "rules": _lplace.OFFICE_RULES,
            "map_name": "maps/office.map",
            "rules_name": "rules/office.lpl",
        }
    if map is None or rules is None:
        raise TypeError("give both map and rules (or neither, for the bundled office)")
    with open(os.fspath(map), encoding="utf-8") as f:
        map_text = f.read()
    with open(os.fspath(rules), encoding="utf-8") as f:
        rules_text = f.read()
    model = {
        "map": map_text,
        "rules": rules_text,
        "map_name": os.fspath(map),
        "rules_name": os.fspath(rules),
    }
    # Checked once here, so that a broken model fails the call rather than every task.
    _lplace.Engine.from_strings(
        model["map"], model["rules"], model["map_name"], model["rules_name"]
    )
    return model


def evaluate(
    paths: Sequence[_Path],
    map: Optional[_Path] = None,
    rules: Optional[_Path] = None,
    *,
    out: _Path = "lplace-fleet",
    tracker: _eval.TrackerArg = None,
    address: Optional[str] = None,
    num_cpus: Optional[int] = None,
    runtime_env: Optional[Dict[str, Any]] = None,
    batch_frames: int = 65536,
    format: Optional[str] = None,
) -> pa.Table:
    """Evaluates every log on Ray, one task per log; returns the per-log summary table.

    Args:
        paths: the logs (percept streams, JSONL or CSV). On a cluster every node must see them
            at these paths (a shared file system), and ``out`` likewise.
        map, rules: the map and rule files (read here and shipped to the tasks as text); both
            ``None`` for the bundled office example.
        out: the output folder; log ``NAME`` goes to ``out/log=NAME/part-0.parquet``.
        tracker: as in ``lplace.evaluate`` (``None`` default tracking, ``False`` none, a path).
        address: a Ray cluster's address (``"ray://head:10001"``, ``"auto"``); ``None`` starts a
            local Ray (with ``num_cpus`` workers) unless one is already running in this process.
        runtime_env: passed to ``ray.init`` (e.g. ``{"pip": ["lplace"]}`` for a cluster whose
            nodes do not have the package).
        batch_frames: rows per Parquet write (memory per task stays about this many rows).

    Returns:
        One row per log, in input order (``SUMMARY_SCHEMA``): ``status`` is ``ok`` or
        ``failed`` (with ``error``); ``rejected`` and ``rejections`` list rejected records.

    Raises:
        CheckError: the map or rule file has errors (before any task runs).
    """
    import ray

    model = _model(map, rules)
    track, ron = _eval._tracker(tracker)
    out_dir = os.path.abspath(os.fspath(out))
    os.makedirs(out_dir, exist_ok=True)
    if not ray.is_initialized():
        kwargs: Dict[str, Any] = {"address": address, "include_dashboard": False}
        if address is None and num_cpus is not None:
            kwargs["num_cpus"] = num_cpus
        if runtime_env is not None:
            kwargs["runtime_env"] = runtime_env
        ray.init(**kwargs)
    task = ray.remote(num_cpus=1, max_retries=0)(evaluate_log)
    strs = [os.path.abspath(os.fspath(p)) for p in paths]
    names = log_names(strs)
    refs = [
        task.remote(p, n, model, track, ron, out_dir, batch_frames, format)
        for p, n in zip(strs, names)
    ]
    rows = []
    for p, n, ref in zip(strs, names, refs):
        try:
            rows.append(ray.get(ref))
        except Exception as e:  # a task that died (worker lost) fails its log, not the batch
            row = _row(n, p)
            row.update(status="failed", error=f"{type(e).__name__}: {e}")
            rows.append(row)
    return pa.Table.from_pylist(rows, schema=SUMMARY_SCHEMA)


def main(argv: Optional[Sequence[str]] = None) -> int:
    """``python -m lplace.fleet``: exit 0, 3 when some record was rejected, 4 when some log
    failed, 2 when the map or rules have errors."""
    ap = argparse.ArgumentParser(
        prog="python -m lplace.fleet",
        description="Evaluate percept logs on Ray, one task per log; decisions to Parquet.",
    )
    ap.add_argument("logs", nargs="+", help="percept streams (JSONL or CSV)")
    ap.add_argument("--map", help="map file (default: the bundled office)")
    ap.add_argument("--rules", help="rule file (default: the bundled office)")
    ap.add_argument("--out", default="lplace-fleet", help="output folder (default lplace-fleet)")
    ap.add_argument("--address", help="Ray cluster address (default: a local Ray)")
    ap.add_argument("--num-cpus", type=int, help="workers of the local Ray")
    ap.add_argument("--tracker", help="tracker configuration (RON)")
    ap.add_argument("--no-track", action="store_true", help="decide frame by frame")
    ap.add_argument("--summary", help="also write the summary table to this Parquet file")
    args = ap.parse_args(argv)
    tracker: _eval.TrackerArg = False if args.no_track else args.tracker
    try:
        table = evaluate(
            args.logs,
            args.map,
            args.rules,
            out=args.out,
            tracker=tracker,
            address=args.address,
            num_cpus=args.num_cpus,
        )
    except CheckError as e:
        print(e, file=sys.stderr)
        return 2
    cols = ["log", "status", "frames", "decided", "rejected", "accuracy", "seconds", "error"]
    print(",".join(cols))
    for r in table.select(cols).to_pylist():
        print(",".join("" if r[c] is None else str(r[c]) for c in cols))
    for r in table.to_pylist():
        for rej in r["rejections"]:
            print(_eval.rejection_text(r["path"], rej), file=sys.stderr)
    if args.summary:
        pq.write_table(table, args.summary)
    if "failed" in table.column("status").to_pylist():
        return 4
    return 3 if sum(table.column("rejected").to_pylist()) > 0 else 0


if __name__ == "__main__":
    sys.exit(main())
