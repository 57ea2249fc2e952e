"""lplace.fleet on a local Ray cluster (2 CPUs): 8 simulated logs, a log with rejected records
and a missing log, each log's Parquet output compared with the `lplace` binary on that log."""

from __future__ import annotations

import json
from pathlib import Path

import pyarrow.parquet as pq
import pytest

from conftest import REPO, render_rows, run_cli

ray = pytest.importorskip("ray")
from lplace import fleet  # noqa: E402  (after the skip: fleet needs ray)

SEEDS = range(1, 9)


@pytest.fixture(scope="module")
def cluster():
    ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False)
    yield
    ray.shutdown()


@pytest.fixture(scope="module")
def logs(lplace_bin, tmp_path_factory):
    d = tmp_path_factory.mktemp("logs")
    paths = []
    for s in SEEDS:
        r = run_cli(lplace_bin, ["simulate", "--seed", str(s), "--steps", "400"])
        p = d / f"robot-{s}.jsonl"
        p.write_bytes(r.stdout)
        paths.append(p)
    # A log with bad records in it: they are reported, the rest evaluated.
    lines = paths[0].read_text().splitlines()
    bad = d / "robot-bad.jsonl"
    bad.write_text("\n".join(lines[:10] + ["not json", '{"version":7,"percepts":[]}'] + lines[10:]) + "\n")
    paths.append(bad)
    return paths


def cli_eval(lplace_bin, path):
    """The CLI's decisions (stdout) and summary (the JSON after the rejections on stderr)."""
    r = run_cli(lplace_bin, ["eval", str(path), "--summary", "json"], ok=(0, 3))
    lines = r.stderr.decode().splitlines()
    start = lines.index("{")
    return r.stdout, json.loads("\n".join(lines[start:]))


def test_fleet_equals_cli_on_each_log(cluster, logs, lplace_bin, tmp_path):
    missing = tmp_path / "robot-missing.jsonl"
    out = tmp_path / "out"
    table = fleet.evaluate([*logs, missing], out=out)
    rows = table.to_pylist()
    assert [r["log"] for r in rows] == [p.stem for p in logs] + ["robot-missing"]
    failed = rows[-1]
    assert failed["status"] == "failed" and "FileNotFoundError" in failed["error"]
    assert not (out / "log=robot-missing").exists()
    for path, row in zip(logs, rows):
        assert row["status"] == "ok", row["error"]
        stdout, summary = cli_eval(lplace_bin, path)
        part = pq.read_table(out / f"log={path.stem}" / "part-0.parquet")
        assert render_rows(part.to_pylist()) == stdout, path
        assert json.loads(row["summary_json"]) == summary
        assert row["frames"] == summary["frames"] and row["rejected"] == summary["rejected"]
    bad = rows[len(logs) - 1]
    assert bad["rejected"] == 2
    assert [(r["line"], r["kind"]) for r in bad["rejections"]] == [(11, "malformed"), (12, "version")]


def test_parquet_reads_back_with_a_log_column(cluster, logs, tmp_path):
    pd = pytest.importorskip("pandas")
    out = tmp_path / "out"
    table = fleet.evaluate(logs[:3], out=out)
    df = pd.read_parquet(out)
    assert sorted(df["log"].astype(str).unique()) == sorted(p.stem for p in logs[:3])
    assert len(df) == sum(table.column("frames").to_pylist())


def test_module_entry_point(cluster, logs, tmp_path, capsys):
    out = tmp_path / "out"
    summary = tmp_path / "summary.parquet"
    rc = fleet.main([str(p) for p in logs[:2]] + ["--out", str(out), "--summary", str(summary)])
    assert rc == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[0].startswith("log,status,frames") and len(lines) == 3
    assert pq.read_table(summary).num_rows == 2
    assert fleet.main([str(logs[-1]), "--out", str(out)]) == 3
    assert fleet.main([str(tmp_path / "nope.jsonl"), "--out", str(out)]) == 4
    bad_rules = tmp_path / "bad.lpl"
    bad_rules.write_text("nonsense")
    office = str(REPO / "maps" / "office.map")
    argv = [str(logs[0]), "--out", str(out), "--map", office, "--rules", str(bad_rules)]
    assert fleet.main(argv) == 2


def test_log_names_are_unique_and_safe():
    names = fleet.log_names(["a/x.jsonl", "b/x.jsonl", "c/we ird=1.csv", "d/x.jsonl"])
    assert names == ["x", "x~2", "we_ird_1", "x~3"]
