"""`lplace.survey` against `lplace survey` on a simulated office run (ground truth from
`lplace simulate`), a hand-worked fit, error cases and hostile input."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

import lplace
from conftest import REPO, run_cli

MAP = REPO / "maps" / "office.map"
RULES = REPO / "rules" / "office.lpl"
TRACKER = REPO / "config" / "intel-tracker.ron"


@pytest.fixture(scope="module")
def sim_run(lplace_bin, tmp_path_factory) -> Path:
    """600 simulated frames on the bundled office map, each with its true place."""
    path = tmp_path_factory.mktemp("survey") / "sim.jsonl"
    run_cli(lplace_bin, ["simulate", "--steps", "600", "--seed", "7", "-o", str(path)])
    return path


def cli_survey(lplace_bin, stream, *extra, ok=(0,)):
    r = run_cli(
        lplace_bin,
        ["survey", "--map", str(MAP), "--rules", str(RULES), str(stream), *extra],
        ok=ok,
    )
    return r.stdout, r.stderr.decode()


def report_lines(res: lplace.SurveyResult) -> str:
    """The stderr `lplace survey` prints, rendered from the Python result."""
    out = []
    for row in res.table.to_pylist():
        warn = f"  WARNING: {row['warning']}" if row["warning"] else ""
        out.append(
            f"survey: {row['place']}: {row['scans']} scan(s), "
            f"median spread {row['spread']:.2f}{warn}\n"
        )
    if res.held_out is not None:
        out.append(f"survey: later visits (held out): {res.held_out['text']}\n")
    return "".join(out)


def labels_csv(stream: Path, out: Path) -> Path:
    """The run's truth as a `t,place` CSV, as a labelling tool would write it."""
    with out.open("w") as f:
        f.write("t,place\n")
        for line in stream.read_text().splitlines():
            r = json.loads(line)
            f.write(f"{r['t']},{(r.get('truth') or {}).get('place') or ''}\n")
    return out


@pytest.mark.parametrize(
    "extra, kwargs",
    [
        ([], {}),
        (["--fit", "first-visits"], {"fit": "first-visits"}),
        (
            ["--fit", "first-visits", "--tracker", str(TRACKER)],
            {"fit": "first-visits", "tracker": TRACKER},
        ),
        (
            ["--quantiles", "0.2", "0.7", "--min-scans", "100"],
            {"quantiles": (0.2, 0.7), "min_scans": 100},
        ),
    ],
)
def test_survey_is_the_cli_byte_for_byte(lplace_bin, sim_run, extra, kwargs):
    stdout, stderr = cli_survey(lplace_bin, sim_run, *extra)
    res = lplace.survey(sim_run, MAP, RULES, **kwargs)
    assert res.map_text.encode() == stdout
    assert report_lines(res) == stderr
    assert res.rejected == []
    assert res.table.schema == lplace.SURVEY_SCHEMA
    assert (res.held_out is not None) == (kwargs.get("fit") == "first-visits")
    if res.held_out is not None:
        h = res.held_out
        assert 0 < h["right"] <= h["decided"] <= h["at_place"]
        assert h["decided_rate"] == pytest.approx(h["decided"] / h["at_place"])
    # The same run given as lines gives the same map.
    by_lines = lplace.survey(sim_run.read_text().splitlines(), MAP, RULES, **kwargs)
    assert by_lines.map_text == res.map_text


def test_labels_from_csv_and_pairs_equal_the_cli(lplace_bin, sim_run, tmp_path):
    csv = labels_csv(sim_run, tmp_path / "labels.csv")
    # The frames' own truth is removed, so only the labels can place them.
    bare = tmp_path / "bare.jsonl"
    rows = [json.loads(line) for line in sim_run.read_text().splitlines()]
    bare.write_text("".join(json.dumps({k: v for k, v in r.items() if k != "truth"}) + "\n" for r in rows))
    stdout, stderr = cli_survey(lplace_bin, bare, "--labels", str(csv))
    by_csv = lplace.survey(bare, MAP, RULES, labels=csv)
    assert by_csv.map_text.encode() == stdout and report_lines(by_csv) == stderr
    pairs = [(r["t"], (r.get("truth") or {}).get("place")) for r in rows]
    by_pairs = lplace.survey(bare, MAP, RULES, labels=reversed(pairs))
    assert by_pairs.map_text == by_csv.map_text
    # With truth on the frames, the labels agree with it: the same map as without labels.
    assert by_csv.map_text == lplace.survey(sim_run, MAP, RULES).map_text


def test_hand_worked_fit(tmp_path):
    # Ten frames at P0 with beacon angles 10, 20, …, 100 and distances 1.0, 1.1, …, 1.9.
    # Nearest rank: lo = v[⌊0.1·9⌋] = v[0], hi = v[⌊0.9·9⌋] = v[8]: A = 10 .. 90, L = 1.0 .. 1.8.
    lines = []
    for k in range(10):
        rec = {
            "version": 1,
            "t": k * 0.1,
            "percepts": [
                {"name": "beacon_angle", "value": 10.0 * (k + 1), "degree": 1.0},
                {"name": "beacon_distance", "value": 1.0 + 0.1 * k, "degree": 1.0},
            ],
            "truth": {"place": "P0"},
        }
        lines.append(json.dumps(rec))
    res = lplace.survey(lines, MAP, RULES)
    old = "param A = 204.0; param L = 4.92;\n}"
    assert lplace.OFFICE_MAP.count(old) == 1
    # The ranges replace the values; the count of scans goes before P0's closing brace.
    new = "param A = 10.00 .. 90.00; param L = 1.00 .. 1.80;\n param scans = 10; }"
    want = lplace.OFFICE_MAP.replace(old, new)
    assert res.map_text == want
    # The spread is the median of the widths {80, 0.8}: index 2 // 2 = 1 of the sorted pair.
    assert res.table.to_pylist() == [
        {"place": "P0", "scans": 10, "spread": pytest.approx(80.0), "warning": None}
    ]
    few = lplace.survey(lines, MAP, RULES, min_scans=11).table.column("warning").to_pylist()
    assert few == ["few scans, the fit is unreliable"]
    # Bundled office map and rules when neither is given.
    assert lplace.survey(lines).map_text == want


def test_bad_map_is_a_check_error_with_position(lplace_bin, sim_run, tmp_path):
    bad = tmp_path / "bad.map"
    bad.write_text("map m;\nplace P0 at (0, ;\n")
    r = run_cli(
        lplace_bin,
        ["survey", "--map", str(bad), "--rules", str(RULES), str(sim_run)],
        ok=(2,),
    )
    with pytest.raises(lplace.CheckError) as ei:
        lplace.survey(sim_run, bad, RULES)
    e = ei.value
    assert e.path == str(bad) and e.line == 2
    # The CLI's rendering names the same position (`bad.map:LINE:COLUMN`).
    assert f"{bad}:{e.line}:{e.column}" in r.stderr.decode()


def test_argument_and_data_errors(lplace_bin, sim_run, tmp_path):
    with pytest.raises(ValueError, match="quantiles"):
        lplace.survey(sim_run, MAP, RULES, quantiles=(0.9, 0.1))
    with pytest.raises(ValueError, match="fit must be"):
        lplace.survey(sim_run, MAP, RULES, fit="some")
    no_links = tmp_path / "none.lpl"
    no_links.write_text("percept w(value, time);\n")
    with pytest.raises(ValueError, match="nothing to fit"):
        lplace.survey(sim_run, MAP, no_links)
    bad_csv = tmp_path / "bad.csv"
    bad_csv.write_text("t,place\n1.0,P0\nsoon,P1\n")
    with pytest.raises(ValueError, match=r"bad\.csv:3: expected `t,place`"):
        lplace.survey(sim_run, MAP, RULES, labels=bad_csv)
    with pytest.raises(OSError):
        lplace.survey(tmp_path / "absent.jsonl", MAP, RULES)
    with pytest.raises(TypeError):
        lplace.survey(sim_run, MAP)


def test_hostile_stream_is_rejected_line_by_line_like_the_cli(lplace_bin, sim_run, tmp_path):
    good = sim_run.read_text().splitlines()[:200]
    hostile = [
        "{",
        "[1, 2, 3]",
        '{"version": 999}',
        '{"t": "soon"}',
        '{"percepts": [{"name": "beacon_angle", "value": 1e308, "degree": 1}],'
        ' "truth": {"place": "P0"}}',
        '{"percepts": [{"name": "beacon_angle", "value": null, "degree": 7}],'
        ' "truth": {"place": "P1"}}',
        "[" * 10000 + "]" * 10000,
        "x" * 100000,
        "\u00e9\u0000\ufffd",
    ]
    lines = [x for pair in zip(good, hostile + [""] * len(good)) for x in pair]
    path = tmp_path / "hostile.jsonl"
    path.write_text("\n".join(lines) + "\n")
    stdout, stderr = cli_survey(lplace_bin, path, ok=(3,))
    res = lplace.survey(path, MAP, RULES)
    assert res.map_text.encode() == stdout
    # Every rejection the CLI printed, with its line, column, kind and message: the survey
    # reads with the stream reader of `evaluate`, so the position is composed the same way.
    printed = [ln for ln in stderr.splitlines() if ln.startswith(str(path))]
    assert printed == [
        f"{path}:{r['line']}"
        + ("" if r["column"] is None else f":{r['column']}")
        + f": {r['message']}"
        for r in res.rejected
    ]
    assert any(r["column"] is not None for r in res.rejected)
    kinds = {r["kind"] for r in res.rejected}
    assert len(res.rejected) >= 6 and kinds <= {"malformed", "version", "degree_out_of_range"}
    # A place the map does not declare cannot be written: an error, never a partial map.
    unlabelled = '{"t": 0, "percepts": [{"name": "beacon_angle", "value": 1, "degree": 1}]}'
    with pytest.raises(ValueError, match="Nowhere"):
        lplace.survey([unlabelled], MAP, RULES, labels=[(0.0, "Nowhere")])
    # Bytes that are not UTF-8 are a rejected record, as in `evaluate`, not a crash.
    res = lplace.survey(b"\xff\xfe{}\n", MAP, RULES)
    assert [r["line"] for r in res.rejected] == [1]
