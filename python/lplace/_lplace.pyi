"""Type stubs of the extension module (Rust, PyO3). Use it through ``lplace``."""

import os
from typing import Any, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

REASONS: List[str]
OFFICE_MAP: str
OFFICE_RULES: str
OFFICE_RECORDING: str

_Path = Union[str, "os.PathLike[str]"]
_Frame = Dict[str, Union[float, Tuple[float, Optional[float]]]]

class Decision:
    """The outcome of one step."""

    @property
    def place(self) -> Optional[str]:
        """The chosen place's name, ``None`` when disoriented."""
    @property
    def place_index(self) -> Optional[int]:
        """The chosen place's index into ``Engine.places``."""
    @property
    def necessity(self) -> Optional[float]:
        """The chosen place's necessity, ``None`` when disoriented."""
    @property
    def inconsistency(self) -> float:
        """``Inc = 1 − max π``."""
    @property
    def reason(self) -> Optional[str]:
        """Why no place was chosen (an entry of ``REASONS``), ``None`` when one was."""
    @property
    def support(self) -> npt.NDArray[np.float64]:
        """Per-place support, in ``Engine.places`` order."""
    @property
    def possibility(self) -> npt.NDArray[np.float64]:
        """Per-place possibility Π."""
    @property
    def necessities(self) -> npt.NDArray[np.float64]:
        """Per-place necessity N."""

class Engine:
    """A loaded, compiled map and rule file."""

    @staticmethod
    def load(map_path: _Path, rules_path: _Path) -> "Engine":
        """Loads, checks and compiles; ``CheckError`` on diagnostics, ``OSError`` on I/O."""
    @staticmethod
    def from_strings(
        map_text: str, rules_text: str, map_name: str = "<map>", rules_name: str = "<rules>"
    ) -> "Engine":
        """Loads from texts; ``CheckError`` names them ``map_name`` / ``rules_name``."""
    @staticmethod
    def office() -> "Engine":
        """The bundled office example."""
    @property
    def places(self) -> List[str]:
        """Place names, in the order of the per-place arrays."""
    @property
    def place_poses(self) -> List[Tuple[float, float]]:
        """Each place's ``(x, y)`` in the map frame, metres."""
    @property
    def slots(self) -> List[str]:
        """Percept instances ``name(args…)`` in slot order."""
    def slot(self, name: str, args: Sequence[str] = ...) -> int:
        """The slot of ``name(args…)``; ``KeyError`` when not declared."""
    def step(
        self,
        frame: Union[_Frame, npt.NDArray[np.float64]],
        values: Optional[npt.NDArray[np.float64]] = None,
    ) -> Decision:
        """Steps a dict frame ``{"sonar_wall(North)": 0.8, "beacon_angle": (0.9, 116.0)}`` or a
        float64 array of degrees per slot (with an optional array of values, NaN = none)."""
    def step_many(
        self,
        degrees: npt.NDArray[np.float64],
        values: Optional[npt.NDArray[np.float64]] = None,
    ) -> Dict[str, npt.NDArray[Any]]:
        """Steps every row of an ``(n_frames, n_slots)`` C-contiguous float64 array (GIL
        released). Keys: ``place`` (int64, -1 disoriented), ``necessity`` (NaN disoriented),
        ``inconsistency``, ``reason`` (int8 into ``REASONS``, -1 decided), and
        ``(n_frames, n_places)`` ``support``, ``possibility``, ``necessities``."""

class StreamBatches:
    places: List[str]
    def __init__(
        self,
        engine: Engine,
        path: Optional[_Path] = None,
        data: Optional[bytes] = None,
        format: Optional[str] = None,
        track: bool = True,
        tracker: Optional[str] = None,
    ) -> None: ...
    def next_batch(self, max_frames: int) -> Optional[Dict[str, Any]]: ...
    def summary_json(self) -> str: ...

def evaluate_columns(
    engine: Engine,
    path: Optional[_Path] = None,
    data: Optional[bytes] = None,
    format: Optional[str] = None,
    track: bool = True,
    tracker: Optional[str] = None,
    read_ahead: bool = True,
) -> Dict[str, Any]: ...
def extract_carmen(
    log: _Path,
    map_path: Optional[_Path] = None,
    config: Optional[str] = None,
    out: Optional[_Path] = None,
) -> Dict[str, Any]: ...
def survey_run(
    map_path: Optional[_Path] = None,
    rules_path: Optional[_Path] = None,
    path: Optional[_Path] = None,
    data: Optional[bytes] = None,
    labels_path: Optional[_Path] = None,
    labels_rows: Optional[List[Tuple[float, Optional[str]]]] = None,
    first_visits: bool = False,
    tracker: Optional[str] = None,
    lo: float = 0.1,
    hi: float = 0.9,
    min_scans: int = 10,
) -> Dict[str, Any]:
    """``lplace survey`` (use ``lplace.survey``): ``map_text``, report columns ``place``,
    ``scans``, ``spread``, ``warning``, ``held_out`` and the ``rejected_*`` lines."""

def rust_loop_ns(
    engine: Engine,
    degrees: npt.NDArray[np.float64],
    values: Optional[npt.NDArray[np.float64]] = None,
    outputs: bool = True,
) -> int:
    """Benchmark reference timed inside Rust, nanoseconds for all rows: ``step_many``'s loop
    (``outputs``), or the bare per-row step that one ``Engine.step`` wraps."""
