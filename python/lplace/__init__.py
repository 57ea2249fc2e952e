"""lplace from Python: possibilistic place recognition for mobile robots.

The engine (``Engine``: load a map and a rule file, step frames), stream evaluation
(``evaluate`` → ``pyarrow.Table`` + summary, exactly as ``lplace eval``), CARMEN extraction
(``extract``, as ``lplace extract --from carmen``), map surveys (``survey``, as
``lplace survey``) and, in ``lplace.fleet``, one Ray task per log
with the decisions written to Parquet. All the work is done by the Rust crate; see the README's
Python section and ``docs/python.md``.
"""

from lplace._errors import CheckError
from lplace._eval import (
    SCHEMA,
    SURVEY_SCHEMA,
    Batches,
    EvalResult,
    Extraction,
    SurveyResult,
    evaluate,
    extract,
    iter_batches,
    rejection_text,
    survey,
)
from lplace._lplace import OFFICE_MAP, OFFICE_RECORDING, OFFICE_RULES, REASONS, Decision, Engine

__all__ = [
    "CheckError",
    "Decision",
    "Engine",
    "EvalResult",
    "Batches",
    "Extraction",
    "OFFICE_MAP",
    "OFFICE_RECORDING",
    "OFFICE_RULES",
    "REASONS",
    "SCHEMA",
    "SURVEY_SCHEMA",
    "SurveyResult",
    "evaluate",
    "extract",
    "iter_batches",
    "rejection_text",
    "survey",
]
