"""Stream evaluation and log extraction: ``evaluate``, ``iter_batches``, ``extract``.

Each function steps frames through the same Rust loop as ``lplace eval`` (``report::StreamRun``)
and only shapes its columns here into a ``pyarrow.Table``. Depends on the extension module
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
    #: One dict per rejected record: ``line``, ``kind``, ``message``.
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
    """The rejected records of a dict of columns from the extension."""
    return [
        {"line": line, "kind": kind, "message": message}
        for line, kind, message in zip(
            cols["rejected_line"], cols["rejected_kind"], cols["rejected_message"]
        )
    ]


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
        config: the extractor parameters (RON file); built-in defaults without it.
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


def survey(*args: Any, **kwargs: Any) -> Any:
    """Not available yet: ``lplace survey`` is being built as a command first; this will wrap it
    once it exists. Raises ``NotImplementedError``."""
    raise NotImplementedError(
        "lplace.survey: the `lplace survey` command does not exist yet in this version"
    )
