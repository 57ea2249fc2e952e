"""Stream evaluation, log extraction and map surveys: ``evaluate``, ``iter_batches``,
``extract``, ``survey``.

Each function calls the same Rust code as its command (``report::StreamRun`` for
``lplace eval``, ``survey::Survey`` for ``lplace survey``) and only shapes its columns here into
a ``pyarrow.Table``. Depends on the extension module
(``lplace._lplace``), numpy and pyarrow.
"""

from __future__ import annotations

import json
import os
from typing import Any, Dict, Iterable, Iterator, List, NamedTuple, Optional, Tuple, Union

import numpy as np
import pyarrow as pa

from lplace import _lplace
from lplace._lplace import Engine

#: A stream: a path, the bytes of a stream, or its lines.
StreamSource = Union[str, "os.PathLike[str]", bytes, Iterable[str], None]
#: ``None`` = track with the default configuration (as ``lplace eval``), ``False`` = no
#: tracking (``--no-track``), a path = a tracker configuration file (RON, ``--tracker``).
TrackerArg = Union[None, bool, str, "os.PathLike[str]"]

#: The columns of a decision table, in order.
SCHEMA = pa.schema(
    [
        ("line", pa.uint64()),
        ("t", pa.float64()),
        ("place", pa.dictionary(pa.int32(), pa.string())),
        ("necessity", pa.float64()),
        ("inconsistency", pa.float64()),
        ("reason", pa.dictionary(pa.int8(), pa.string())),
        ("truth", pa.dictionary(pa.int32(), pa.string())),
        ("truth_known", pa.bool_()),
    ]
)


class EvalResult(NamedTuple):
    """What ``evaluate`` returns."""

    #: One row per accepted frame (columns: see ``SCHEMA``).
    table: pa.Table
    #: ``lplace eval --summary json``, as a dict.
    summary: Dict[str, Any]
    #: One dict per rejected record: ``line``, ``column`` (or ``None``), ``kind``, ``message``.
    rejected: List[Dict[str, Any]]


def _engine(map: Any, rules: Any, engine: Optional[Engine]) -> Engine:
    if engine is not None:
        if map is not None or rules is not None:
            raise TypeError("give either engine= or map and rules, not both")
        return engine
    if map is None and rules is None:
        return Engine.office()
    if map is None or rules is None:
        raise TypeError("give both map and rules (or neither, for the bundled office)")
    return Engine.load(os.fspath(map), os.fspath(rules))


def _tracker(tracker: TrackerArg) -> Tuple[bool, Optional[str]]:
    if tracker is None or tracker is True:
        return True, None
    if tracker is False:
        return False, None
    with open(os.fspath(tracker), encoding="utf-8") as f:
        return True, f.read()


def _source(stream: StreamSource) -> Dict[str, Any]:
    if stream is None:
        return {"data": _lplace.OFFICE_RECORDING.encode()}
    if isinstance(stream, (str, os.PathLike)):
        return {"path": os.fspath(stream)}
    if isinstance(stream, (bytes, bytearray, memoryview)):
        return {"data": bytes(stream)}
    lines = []
    for line in stream:
        if not isinstance(line, str):
            raise TypeError(f"stream lines must be str, not {type(line).__name__}")
        lines.append(line.rstrip("\r\n"))
    return {"data": ("\n".join(lines) + "\n").encode()}


def _dictionary(codes: np.ndarray, names: List[str], index: pa.DataType) -> pa.Array:
    indices = pa.array(codes, type=index, mask=codes < 0)
    return pa.DictionaryArray.from_arrays(indices, pa.array(names, pa.string()))


def table_of(cols: Dict[str, Any], places: List[str]) -> pa.Table:
    """The decision table of a dict of columns from the extension."""
    arrays = [
        pa.array(cols["line"], pa.uint64()),
        pa.array(cols["t"], pa.float64(), from_pandas=True),
        _dictionary(cols["place"], places, pa.int32()),
        pa.array(cols["necessity"], pa.float64(), from_pandas=True),
        pa.array(cols["inconsistency"], pa.float64()),
        _dictionary(cols["reason"], list(_lplace.REASONS), pa.int8()),
        _dictionary(cols["truth"], places, pa.int32()),
        pa.array(cols["truth_known"], pa.bool_()),
    ]
    return pa.Table.from_arrays(arrays, schema=SCHEMA)


def rejections_of(cols: Dict[str, Any]) -> List[Dict[str, Any]]:
    """The rejected records of a dict of columns from the extension: ``line``, ``column``
    (``None`` when the problem has no column), ``kind`` and ``message`` (without position)."""
    lines = cols["rejected_line"]
    columns = cols.get("rejected_column", [None] * len(lines))
    return [
        {"line": line, "column": column, "kind": kind, "message": message}
        for line, column, kind, message in zip(
            lines, columns, cols["rejected_kind"], cols["rejected_message"]
        )
    ]


def rejection_text(path: Any, r: Dict[str, Any]) -> str:
    """A rejection as the command line prints it: ``PATH:LINE: what`` or
    ``PATH:LINE:COLUMN: what``."""
    at = f"{r['line']}" if r.get("column") is None else f"{r['line']}:{r['column']}"
    return f"{path}:{at}: {r['message']}"


def evaluate(
    stream: StreamSource,
    map: Union[str, "os.PathLike[str]", None] = None,
    rules: Union[str, "os.PathLike[str]", None] = None,
    tracker: TrackerArg = None,
    *,
    engine: Optional[Engine] = None,
    format: Optional[str] = None,
    read_ahead: bool = True,
) -> EvalResult:
    """Evaluates a percept stream as ``lplace eval`` does: the same decisions, the same summary.

    Args:
        stream: a path (``.csv`` is read as CSV, anything else as JSON Lines), the bytes of a
            stream, an iterable of its lines, or ``None`` for the bundled office recording.
        map, rules: the map and rule files; both ``None`` for the bundled office example.
        tracker: ``None`` tracks with the default configuration (as ``lplace eval``), ``False``
            decides frame by frame (``--no-track``), a path reads a tracker configuration (RON).
        engine: an already loaded ``Engine`` instead of ``map`` and ``rules``.
        format: ``"jsonl"`` or ``"csv"`` to override the guess from the path.
        read_ahead: parse on a second thread when the machine has a second core (as the CLI).

    Returns:
        ``EvalResult(table, summary, rejected)``: a ``pyarrow.Table`` with one row per accepted
        frame (``line, t, place, necessity, inconsistency, reason, truth, truth_known``; place,
        reason and truth are dictionary-encoded strings; necessity is null when disoriented),
        the summary dict, and the rejected records (each reported, none dropped silently).

    Raises:
        CheckError: the map or rule file has errors.
        OSError: a file cannot be read.
        ValueError: a bad tracker configuration or format.
    """
    eng = _engine(map, rules, engine)
    track, ron = _tracker(tracker)
    cols = _lplace.evaluate_columns(
        eng, **_source(stream), format=format, track=track, tracker=ron, read_ahead=read_ahead
    )
    return EvalResult(
        table_of(cols, cols["places"]),
        json.loads(cols["summary_json"]),
        rejections_of(cols),
    )


class Batches:
    """A stream evaluated batch by batch (see ``iter_batches``); ``summary()`` after the end."""

    def __init__(self, inner: Any, batch_frames: int = 65536) -> None:
        self._inner = inner
        self._size = max(1, int(batch_frames))
        self.places: List[str] = inner.places
        self.rejected: List[Dict[str, Any]] = []

    def __iter__(self) -> Iterator[pa.Table]:
        while True:
            cols = self._inner.next_batch(self._size)
            if cols is None:
                return
            self.rejected.extend(rejections_of(cols))
            if len(cols["line"]):
                yield table_of(cols, self.places)

    def summary(self) -> Dict[str, Any]:
        """The summary of what has been read so far."""
        result: Dict[str, Any] = json.loads(self._inner.summary_json())
        return result


def iter_batches(
    stream: StreamSource,
    map: Union[str, "os.PathLike[str]", None] = None,
    rules: Union[str, "os.PathLike[str]", None] = None,
    tracker: TrackerArg = None,
    *,
    engine: Optional[Engine] = None,
    format: Optional[str] = None,
    batch_frames: int = 65536,
) -> Batches:
    """Like ``evaluate``, but yields ``pyarrow.Table`` batches of at most ``batch_frames`` rows,
    so that memory stays flat on any length (``lplace.fleet`` writes each to Parquet). Read on
    the calling thread. Rejections collect in ``.rejected``; ``.summary()`` at the end."""
    eng = _engine(map, rules, engine)
    track, ron = _tracker(tracker)
    inner = _lplace.StreamBatches(eng, **_source(stream), format=format, track=track, tracker=ron)
    return Batches(inner, batch_frames)


class Extraction(NamedTuple):
    """What ``extract`` returns."""

    #: The percept stream's JSON lines (``None`` when written to ``out``).
    records: Optional[List[str]]
    #: Frames written (one per laser scan after the first odometry).
    frames: int
    #: Log lines read, FLASER scans, ODOM readings.
    lines: int
    lasers: int
    odoms: int
    #: One message per malformed log line (skipped; ``lplace extract`` prints them on stderr).
    malformed: List[str]


def extract(
    log: Union[str, "os.PathLike[str]"],
    map: Union[str, "os.PathLike[str]", None] = None,
    config: Union[str, "os.PathLike[str]", None] = None,
    out: Union[str, "os.PathLike[str]", None] = None,
) -> Extraction:
    """Turns a CARMEN log into a percept stream, as ``lplace extract --from carmen`` does (the
    same JSON lines, byte for byte).

    Args:
        log: the CARMEN text log (FLASER, ODOM, PARAM lines).
        map: a ``.map`` whose place extents give each frame's true place.
        config: the extractor parameters (RON file); without it the travelling settings of
            ``lplace extract`` without ``--config`` (compass on; the map's ``axis`` gives the axis).
        out: write the stream to this file instead of returning its lines.

    MRCLAM directories (``--from mrclam``) are not wrapped yet.
    """
    cfg = None
    if config is not None:
        with open(os.fspath(config), encoding="utf-8") as f:
            cfg = f.read()
    d = _lplace.extract_carmen(
        os.fspath(log),
        map_path=None if map is None else os.fspath(map),
        config=cfg,
        out=None if out is None else os.fspath(out),
    )
    return Extraction(
        d["records"], d["frames"], d["lines"], d["lasers"], d["odoms"], d["malformed"]
    )


class SurveyResult(NamedTuple):
    """What ``survey`` returns."""

    #: The map text with the fitted parameters written in (``lplace survey``'s output).
    map_text: str
    #: One row per fitted place (columns: see ``SURVEY_SCHEMA``), places in name order.
    table: pa.Table
    #: With ``fit="first-visits"``: the score of the written map on the later visits
    #: (``at_place``, ``decided``, ``right``, ``confidently_wrong``, their rates, and ``text``,
    #: the line ``lplace survey`` prints); ``None`` with ``fit="all"``.
    held_out: Optional[Dict[str, Any]]
    #: One dict per rejected stream line: ``line``, ``column`` (or ``None``), ``kind``, ``message``.
    rejected: List[Dict[str, Any]]


#: The columns of a survey's per-place table, in order.
SURVEY_SCHEMA = pa.schema(
    [
        ("place", pa.string()),
        ("scans", pa.uint64()),
        ("spread", pa.float64()),
        ("warning", pa.string()),
    ]
)

#: Ground truth: a CSV ``t,place`` file, or ``(t, place)`` pairs (``place`` ``None`` between
#: places).
LabelsArg = Union[str, "os.PathLike[str]", Iterable[Tuple[float, Optional[str]]], None]


def survey(
    stream: StreamSource,
    map: Union[str, "os.PathLike[str]", None] = None,
    rules: Union[str, "os.PathLike[str]", None] = None,
    *,
    labels: LabelsArg = None,
    fit: str = "all",
    tracker: Union[str, "os.PathLike[str]", None] = None,
    quantiles: Tuple[float, float] = (0.1, 0.9),
    min_scans: int = 10,
) -> SurveyResult:
    """Fits each place's expected percept values from a run with ground truth and writes them
    into the map, as ``lplace survey`` does (the same map text, byte for byte).

    Args:
        stream: the survey run's percept stream (JSON Lines): a path, its bytes, an iterable of
            its lines, or ``None`` for the bundled office recording.
        map, rules: the map to fill in and the rules saying which percepts feed which place
            parameters; both ``None`` for the bundled office example.
        labels: the ground truth, when the frames carry no ``truth.place``: a CSV ``t,place``
            path (``--labels``) or ``(t, place)`` pairs; each frame takes the label nearest in
            time, within 0.5 s.
        fit: ``"all"`` (every frame with a place) or ``"first-visits"`` (each place's first
            visit; the later visits are scored with the map so written).
        tracker: tracker configuration file (RON) for the held-out score of first visits.
        quantiles: ``(lo, hi)``, the quantiles of a place's readings bounding its range.
        min_scans: places fitted from fewer frames get a warning.

    Returns:
        ``SurveyResult(map_text, table, held_out, rejected)``.

    Raises:
        CheckError: the map or rules do not parse, or (first visits) the written map does not
            load with the rules.
        OSError: a file cannot be read.
        ValueError: bad quantiles, labels, tracker configuration or ``fit``; rules that link no
            percept with a place parameter; a fitted place the map does not declare.
    """
    if fit not in ("all", "first-visits"):
        raise ValueError(f'fit must be "all" or "first-visits", not {fit!r}')
    lo, hi = (float(q) for q in quantiles)
    if (map is None) != (rules is None):
        raise TypeError("give both map and rules (or neither, for the bundled office)")
    label_args: Dict[str, Any] = {}
    if isinstance(labels, (str, os.PathLike)):
        label_args["labels_path"] = os.fspath(labels)
    elif labels is not None:
        label_args["labels_rows"] = [
            (float(t), None if p is None else str(p)) for t, p in labels
        ]
    ron = None
    if tracker is not None:
        with open(os.fspath(tracker), encoding="utf-8") as f:
            ron = f.read()
    d = _lplace.survey_run(
        map_path=None if map is None else os.fspath(map),
        rules_path=None if rules is None else os.fspath(rules),
        **_source(stream),
        **label_args,
        first_visits=fit == "first-visits",
        tracker=ron,
        lo=lo,
        hi=hi,
        min_scans=int(min_scans),
    )
    table = pa.Table.from_arrays(
        [
            pa.array(d["place"], pa.string()),
            pa.array(d["scans"], pa.uint64()),
            pa.array(d["spread"], pa.float64()),
            pa.array(d["warning"], pa.string()),
        ],
        schema=SURVEY_SCHEMA,
    )
    return SurveyResult(d["map_text"], table, d["held_out"], rejections_of(d))
