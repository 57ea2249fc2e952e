"""Exceptions raised by lplace.

``CheckError`` is defined here, in Python, so that it can carry attributes under the stable ABI;
the extension raises it when a map or rule file has errors.
"""

from __future__ import annotations

from typing import Any, Dict, List


class CheckError(Exception):
    """A map or rule file has errors.

    Attributes:
        path: the file the first error is in (as given, or ``<map>``/``<rules>`` for texts).
        line: 1-based line of the first error.
        column: 1-based column of the first error.
        message: every diagnostic rendered as plain text, as ``lplace check`` prints them.
        diagnostics: one dict per problem (``path``, ``line``, ``column``, ``severity``,
            ``message``, ``rendered``).
    """

    def __init__(
        self,
        message: str,
        path: str,
        line: int,
        column: int,
        diagnostics: List[Dict[str, Any]],
    ) -> None:
        super().__init__(message)
        self.message = message
        self.path = path
        self.line = line
        self.column = column
        self.diagnostics = diagnostics

    def __str__(self) -> str:
        return self.message
