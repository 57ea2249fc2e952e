"""Shared helpers: the `lplace` binary (the reference every test compares with) and a renderer
of decision rows in the exact text `lplace eval --format json` writes."""

from __future__ import annotations

import math
import os
import subprocess
from pathlib import Path
from typing import Any, Dict, List, Optional, Sequence

import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[2]


def data_dir() -> Optional[Path]:
    """$LPLACE_DATA, else ../shared/data beside the repository; None when absent."""
    env = os.environ.get("LPLACE_DATA")
    p = Path(env) if env else REPO.parent / "shared" / "data"
    return p if p.is_dir() else None


@pytest.fixture(scope="session")
def lplace_bin() -> Path:
    """The CLI binary: $LPLACE_BIN (must exist when set, as in CI), else target/release/lplace."""
    env = os.environ.get("LPLACE_BIN")
    if env:
        p = Path(env)
        assert p.is_file(), f"LPLACE_BIN={env} does not exist"
        return p
    p = REPO / "target" / "release" / "lplace"
    if not p.is_file():
        pytest.skip("no lplace binary: run `cargo build --release` or set LPLACE_BIN")
    return p


def run_cli(binary: Path, args: Sequence[str], ok=(0,)) -> subprocess.CompletedProcess:
    r = subprocess.run([str(binary), *args], capture_output=True, cwd=REPO)
    assert r.returncode in ok, (r.returncode, r.stderr.decode(errors="replace"))
    return r


def rust_float(x: float) -> str:
    """Rust's `{}` for an f64: the shortest round-trip digits, never an exponent, `1` for 1.0."""
    return np.format_float_positional(x, unique=True, trim="-")


def degree(x: float) -> str:
    """The CLI's 4-decimal degree: round half away from zero of clamp(x) * 10000."""
    y = min(max(x, 0.0), 1.0) * 10000.0
    fl = math.floor(y)
    v = fl + 1 if y - fl >= 0.5 else fl
    return f"{v // 10000}.{v % 10000:04d}"


def render_rows(rows: List[Dict[str, Any]]) -> bytes:
    """Decision rows (as `table.to_pylist()` gives them) in `lplace eval --format json` text."""
    out = []
    for r in rows:
        s = '{"line":' + str(r["line"])
        if r["t"] is not None:
            s += ',"t":' + rust_float(r["t"])
        if r["place"] is not None:
            s += ',"place":"' + r["place"] + '","necessity":' + degree(r["necessity"])
        else:
            s += ',"place":null,"reason":"' + r["reason"] + '"'
        s += ',"inconsistency":' + degree(r["inconsistency"])
        if r["truth_known"]:
            s += ',"truth":' + ("null" if r["truth"] is None else '"' + r["truth"] + '"')
        out.append(s + "}\n")
    return "".join(out).encode()
