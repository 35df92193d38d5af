"""Diagnostics: one problem at one place, with a stable code.

Every stage reports problems as `Diagnostic` values; the CLI renders them as text, JSON or
SARIF. Codes and their docs live in `mlctool.codes`.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace


@dataclass(frozen=True, slots=True)
class Span:
    """1-based line and column; end column is exclusive."""

    line: int
    col: int
    end_line: int
    end_col: int

    @staticmethod
    def at(line: int, col: int = 1, length: int = 1) -> Span:
        return Span(line, col, line, col + max(length, 1))


@dataclass(frozen=True, slots=True)
class Diagnostic:
    file: str
    span: Span
    severity: str  # "error" | "warning" | "note"
    code: str
    message: str
    notes: tuple[str, ...] = field(default=())

    def with_severity(self, severity: str) -> Diagnostic:
        return replace(self, severity=severity)

    def as_dict(self) -> dict:
        """As the JSON outputs write it (`mlc check --format json`, `mlc sim --json` warnings)."""
        return {"file": self.file, "line": self.span.line, "column": self.span.col,
                "end_line": self.span.end_line, "end_column": self.span.end_col, "severity": self.severity,
                "code": self.code, "message": self.message, **({"notes": list(self.notes)} if self.notes else {})}

    def sort_key(self):
        return (self.file, self.span.line, self.span.col, self.code, self.message)


# An input that cannot be read as a source: missing or refused (E100), binary (E101), not in
# an encoding we read (E102), too large (E104). Every command exits 2 on them
# (docs/reliability.md, "Exit codes"); errors in a source that could be read give 1.
UNREADABLE = frozenset({"E100", "E101", "E102", "E104", "E111"})  # E111: no source at all (a .stim, an object)


def unreadable(diags) -> bool:
    return any(d.code in UNREADABLE for d in diags)


class MlcError(Exception):
    """A failure that ends a command with a diagnostic (never a traceback)."""

    def __init__(self, diagnostic: Diagnostic, exit_code: int = 2):
        super().__init__(diagnostic.message)
        self.diagnostic = diagnostic
        self.exit_code = exit_code
        self.diagnostics: list[Diagnostic] = [diagnostic]  # all of them, when there are several
        self.lines: dict[str, list[str]] = {}  # the lines of the files they point into


def diag(file: str, span: Span, code: str, message: str, *notes: str) -> Diagnostic:
    """A diagnostic with the code's default severity."""
    from mlctool.codes import CODES

    return Diagnostic(file, span, CODES[code].severity, code, message, tuple(notes))


def fail(file: str, code: str, message: str, line: int = 1, col: int = 1, exit_code: int = 2):
    raise MlcError(diag(file, Span.at(line, col), code, message), exit_code)
