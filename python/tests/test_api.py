"""The Python API against the `lplace` binary on the office example, error cases, hostile input."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pyarrow as pa
import pytest

import lplace
from conftest import REPO, data_dir, degree, render_rows, run_cli

RECORDING = REPO / "recordings" / "office.jsonl"


def cli_eval(lplace_bin, stream, *extra, ok=(0,)):
    args = ["eval", "--format", "json", "--summary", "json", *extra]
    if stream is not None:
        args.insert(1, str(stream))
    r = run_cli(lplace_bin, args, ok=ok)
    return r.stdout, r.stderr


@pytest.mark.parametrize("extra", [[], ["--no-track"]])
def test_evaluate_bundled_recording_is_the_cli_byte_for_byte(lplace_bin, extra):
    stdout, stderr = cli_eval(lplace_bin, None, *extra)
    res = lplace.evaluate(None, tracker=False if extra else None)
    assert res.table.num_rows == 2500 and res.rejected == []
    assert render_rows(res.table.to_pylist()) == stdout
    assert res.summary == json.loads(stderr)
    # The same file by path, and by lines, gives the same table.
    by_path = lplace.evaluate(RECORDING, tracker=False if extra else None)
    lines = RECORDING.read_text().splitlines()
    by_lines = lplace.evaluate(lines, tracker=False if extra else None)
    assert by_path.table.equals(res.table) and by_lines.table.equals(res.table)


def test_evaluate_with_explicit_model_and_tracker_file(lplace_bin):
    m, r = REPO / "maps" / "office.map", REPO / "rules" / "office.lpl"
    cfg = REPO / "config" / "intel-tracker.ron"
    stdout, stderr = cli_eval(
        lplace_bin, RECORDING, "--map", str(m), "--rules", str(r), "--tracker", str(cfg)
    )
    res = lplace.evaluate(RECORDING, m, r, tracker=cfg)
    assert render_rows(res.table.to_pylist()) == stdout
    assert res.summary == json.loads(stderr)


def test_table_schema_and_nulls():
    t = lplace.evaluate(None).table
    assert t.schema == lplace.SCHEMA
    rows = t.to_pylist()
    for r in rows:
        # A row has either a place with its necessity, or a reason, never both.
        assert (r["place"] is None) == (r["necessity"] is None) == (r["reason"] is not None)
    assert {r["reason"] for r in rows if r["reason"]} <= set(lplace.REASONS)
    df = t.to_pandas()
    assert len(df) == 2500 and str(df["place"].dtype) == "category"


def test_iter_batches_equal_evaluate():
    whole = lplace.evaluate(None)
    b = lplace.iter_batches(None, batch_frames=333)
    tables = list(b)
    assert [t.num_rows for t in tables[:-1]] == [333] * (len(tables) - 1)
    assert pa.concat_tables(tables).equals(whole.table)
    assert b.summary() == whole.summary


def office_frame_p2():
    # The crate's own documented example (src/engine/mod.rs): beacon from 116° at 1.1 m,
    # walls North and East: place P2.
    return {
        "beacon_angle": (0.9, 116.0),
        "beacon_distance": (0.9, 1.1),
        "sonar_wall(North)": 0.8,
        "laser_wall(East)": 0.9,
    }


def test_step_dict_arrays_and_step_many_agree():
    e = lplace.Engine.office()
    d = e.step(office_frame_p2())
    assert d.place == "P2" and d.reason is None
    assert e.places[d.place_index] == "P2"
    assert 0.0 < d.necessity <= 1.0
    n = len(e.slots)
    deg, val = np.zeros(n), np.full(n, np.nan)
    deg[e.slot("beacon_angle")], val[e.slot("beacon_angle")] = 0.9, 116.0
    deg[e.slot("beacon_distance")], val[e.slot("beacon_distance")] = 0.9, 1.1
    deg[e.slot("sonar_wall", ["North"])] = 0.8
    deg[e.slot("laser_wall", ["East"])] = 0.9
    a = e.step(deg, val)
    assert (a.place, a.necessity, a.inconsistency) == (d.place, d.necessity, d.inconsistency)
    for name in ("support", "possibility", "necessities"):
        assert np.array_equal(getattr(a, name), getattr(d, name))
    # The place's necessity is the per-place array's entry (N(P2) in the distribution).
    assert d.necessities[d.place_index] == d.necessity
    empty = np.zeros(n)
    many = e.step_many(np.stack([deg, empty, deg]), np.stack([val, np.full(n, np.nan), val]))
    assert list(many["place"]) == [d.place_index, -1, d.place_index]
    assert many["necessity"][0] == d.necessity and math.isnan(many["necessity"][1])
    assert lplace.REASONS[many["reason"][1]] == e.step({}).reason
    assert many["possibility"].shape == (3, len(e.places))
    assert np.array_equal(many["necessities"][2], d.necessities)


def test_step_matches_cli_no_track_frame_by_frame(lplace_bin):
    """Python's step on each recorded frame (built here from the JSON, not by the crate's
    reader) gives the CLI's --no-track decision on that frame."""
    stdout, _ = cli_eval(lplace_bin, None, "--no-track")
    e = lplace.Engine.office()
    for line, want in zip(RECORDING.read_text().splitlines(), stdout.splitlines()):
        rec, want = json.loads(line), json.loads(want)
        frame = {}
        for p in rec["percepts"]:
            key = p["name"] + (f"({', '.join(p['args'])})" if p.get("args") else "")
            frame[key] = (p["degree"], p.get("value"))
        d = e.step(frame)
        assert d.place == want["place"]
        assert degree(d.inconsistency) == f"{want['inconsistency']:.4f}"
        if d.place is not None:
            assert degree(d.necessity) == f"{want['necessity']:.4f}"
        else:
            assert d.reason == want["reason"]


def test_check_error_carries_position():
    rules = lplace.OFFICE_RULES.splitlines()
    # Break one line by hand: an unknown predicate at a known line and column.
    target = next(i for i, l in enumerate(rules) if "|-" in l or "->" in l)
    rules.insert(target, "foo_bar(t) -> at_place(P_i);")
    with pytest.raises(lplace.CheckError) as ei:
        lplace.Engine.from_strings(lplace.OFFICE_MAP, "\n".join(rules), rules_name="x.lpl")
    err = ei.value
    assert err.path == "x.lpl"
    assert (err.line, err.column) == (target + 1, 1)
    assert err.diagnostics and err.diagnostics[0]["line"] == target + 1
    assert "x.lpl:" in str(err) and "error" in str(err)


def test_check_error_from_files(tmp_path):
    bad = tmp_path / "bad.map"
    bad.write_text("this is not a map\n")
    with pytest.raises(lplace.CheckError) as ei:
        lplace.Engine.load(bad, REPO / "rules" / "office.lpl")
    assert ei.value.path == str(bad) and ei.value.line == 1


def test_io_and_argument_errors(tmp_path):
    with pytest.raises(FileNotFoundError):
        lplace.Engine.load(tmp_path / "none.map", REPO / "rules" / "office.lpl")
    with pytest.raises(FileNotFoundError):
        lplace.evaluate(tmp_path / "none.jsonl")
    with pytest.raises(OSError):
        lplace.evaluate(tmp_path)
    with pytest.raises(TypeError):
        lplace.evaluate(None, REPO / "maps" / "office.map")
    with pytest.raises(ValueError):
        lplace.evaluate(None, format="xml")
    bad_tracker = tmp_path / "t.ron"
    bad_tracker.write_text("(no_such_field: 1)")
    with pytest.raises(ValueError):
        lplace.evaluate(None, tracker=bad_tracker)
    e = lplace.Engine.office()
    with pytest.raises(KeyError):
        e.slot("no_such_percept")
    with pytest.raises(KeyError):
        e.step({"sonar_wall(Up)": 0.5})
    with pytest.raises(KeyError):
        e.step({"sonar_wall(North": 0.5})
    with pytest.raises(TypeError):
        e.step({1: 0.5})
    with pytest.raises(ValueError):
        e.step({"sonar_wall(North)": (0.5, 1.0, 2.0)})
    with pytest.raises(ValueError):
        e.step(np.zeros(len(e.slots) + 1))
    with pytest.raises(TypeError):
        e.step(np.zeros(len(e.slots), dtype=np.float32))
    with pytest.raises(ValueError):
        e.step_many(np.zeros((4, len(e.slots) - 1)))
    with pytest.raises(ValueError):
        e.step_many(np.zeros((4, len(e.slots))), np.zeros((3, len(e.slots))))
    with pytest.raises((TypeError, ValueError)):
        e.step_many(np.zeros((4, 2 * len(e.slots)))[:, ::2])  # not C-contiguous


def test_hostile_arrays_do_not_raise():
    e = lplace.Engine.office()
    n = len(e.slots)
    rows = np.array(
        [
            np.full(n, np.nan),
            np.full(n, np.inf),
            np.full(n, -np.inf),
            np.full(n, 1e308),
            np.full(n, -1e308),
            np.full(n, 5e-324),
        ]
    )
    out = e.step_many(rows, rows)
    assert np.all((out["inconsistency"] >= 0) & (out["inconsistency"] <= 1))
    for r in rows:
        d = e.step(r, r)
        assert 0.0 <= d.inconsistency <= 1.0
    assert e.step_many(np.zeros((0, n)))["place"].shape == (0,)


def test_hostile_stream_is_rejected_line_by_line_like_the_cli(lplace_bin, tmp_path):
    good = RECORDING.read_text().splitlines()[:50]
    bad = [
        "\x00\x01\x02 not json",
        "{" * 100_000,
        "x" * ((1 << 20) + 1),
        '{"version":1,"percepts":[{"name":"sonar_wall","args":["North"],"degree":"NaN"}]}',
        '{"version":1,"percepts":[{"name":"no_such","degree":0.5}]}',
        '{"version":1,"percepts":[{"name":"sonar_wall","args":["North"],"degree":7}]}',
        '{"version":99,"percepts":[]}',
        '{"version":1,"t":-1e9,"percepts":[]}',
        "[]",
        '{"version":1,"percepts":[{"name":"beacon_angle","value":1e999,"degree":0.5}]}',
    ]
    lines = good[:20] + bad + good[20:]
    path = tmp_path / "hostile.jsonl"
    path.write_bytes(("\n".join(lines) + "\n").encode("utf-8", errors="surrogateescape"))
    stdout, stderr = cli_eval(lplace_bin, path, ok=(3,))
    res = lplace.evaluate(path)
    assert render_rows(res.table.to_pylist()) == stdout
    cli_lines = [l for l in stderr.decode().splitlines() if l.startswith(str(path) + ":")]
    # The position is composed here from the fields, as a user would, and must read as the CLI's.
    ours = [
        f"{path}:{r['line']}"
        + ("" if r["column"] is None else f":{r['column']}")
        + f": {r['message']}"
        for r in res.rejected
    ]
    assert any(r["column"] is not None for r in res.rejected)
    assert ours == cli_lines and len(ours) == len(bad)
    assert res.summary["rejected"] == len(bad)
    assert sum(res.summary["rejected_by_kind"].values()) == len(bad)


def test_extract_small_carmen_log_like_the_cli(lplace_bin, tmp_path):
    d = data_dir()
    src = d / "carmen-corrected-logs" / "intel-corrected.log" if d else None
    if src is None or not src.is_file():
        pytest.skip("intel-corrected.log not found under $LPLACE_DATA or ../shared/data")
    head = tmp_path / "intel-head.log"
    with open(src, encoding="utf-8", errors="replace") as f:
        text = [next(f) for _ in range(4000)]
    text.insert(100, "FLASER 3 1.0\n")  # a malformed line: too short
    head.write_text("".join(text))
    m = REPO / "maps" / "intel.map"
    r = run_cli(lplace_bin, ["extract", "--from", "carmen", str(head), "--map", str(m)], ok=(3,))
    ext = lplace.extract(head, map=m)
    assert ("\n".join(ext.records) + "\n").encode() == r.stdout
    assert ext.frames == len(ext.records) > 0 and len(ext.malformed) == 1
    out = tmp_path / "intel.jsonl"
    ext2 = lplace.extract(head, map=m, out=out)
    assert ext2.records is None and out.read_bytes() == r.stdout
