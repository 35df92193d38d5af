"""Rendering diagnostics: text for people (rich), JSON and SARIF 2.1.0 for CI."""

from __future__ import annotations

import json
import os
import sys

from mlctool import __version__
from mlctool.codes import CODES
from mlctool.diagnostics import Diagnostic
from mlctool.syntax.source import display_width

_STYLE = {"error": "bold red", "warning": "bold yellow", "note": "bold cyan"}


def use_color(stream) -> bool:
    if os.environ.get("NO_COLOR"):
        return False
    if os.environ.get("FORCE_COLOR"):
        return True
    return hasattr(stream, "isatty") and stream.isatty()


def render_text(diags: list[Diagnostic], lines: dict[str, list[str]], stream=None) -> None:
    if not diags:
        return  # and rich is not even imported
    from rich.console import Console
    from rich.markup import escape

    stream = stream or sys.stderr
    console = Console(file=stream, no_color=not use_color(stream), highlight=False, soft_wrap=True,
                      force_terminal=use_color(stream), emoji=False)
    for d in diags:
        style = _STYLE.get(d.severity, "bold")
        console.print(f"[bold]{escape(d.file)}:{d.span.line}:{d.span.col}:[/bold] "
                      f"[{style}]{d.severity}[{escape(d.code)}][/{style}]: {escape(d.message)}")
        src = lines.get(d.file)
        if src and 1 <= d.span.line <= len(src):
            text = src[d.span.line - 1].replace("\t", " ")
            if len(text) > 200:
                text = text[:200] + " ..."
            end = min(d.span.end_col, len(text) + 1) if d.span.end_line == d.span.line else d.span.col + 1
            # columns count characters; the carets go by display width (Chinese names take two)
            lead = display_width(text[:d.span.col - 1])
            width = max(1, display_width(text[d.span.col - 1:end - 1]))
            console.print(f"  {d.span.line:>5} | {escape(text)}")
            console.print(f"        | {' ' * lead}[{style}]{'^' * width}[/{style}]")
        for n in d.notes:
            console.print(f"        = note: {escape(n)}")


def summary_line(errors: int, warnings: int) -> str:
    return f"{errors} error{'s' if errors != 1 else ''}, {warnings} warning{'s' if warnings != 1 else ''}"


def to_json(diags: list[Diagnostic]) -> str:
    data = {
        "diagnostics": [
            {"file": d.file, "line": d.span.line, "column": d.span.col, "end_line": d.span.end_line,
             "end_column": d.span.end_col, "severity": d.severity, "code": d.code, "message": d.message,
             **({"notes": list(d.notes)} if d.notes else {})}
            for d in diags
        ],
        "errors": sum(d.severity == "error" for d in diags),
        "warnings": sum(d.severity == "warning" for d in diags),
    }
    return json.dumps(data, indent=2, ensure_ascii=False) + "\n"


def to_sarif(diags: list[Diagnostic]) -> str:
    rules = [
        {"id": c.code, "name": c.code, "shortDescription": {"text": c.summary},
         "fullDescription": {"text": c.summary}, "help": {"text": c.doc},
         "defaultConfiguration": {"level": c.severity if c.severity in ("error", "warning") else "note"}}
        for c in CODES.values()
    ]
    index = {c: k for k, c in enumerate(CODES)}
    results = []
    for d in diags:
        results.append({
            "ruleId": d.code,
            "ruleIndex": index[d.code],
            "level": d.severity if d.severity in ("error", "warning") else "note",
            "message": {"text": d.message},
            "locations": [{"physicalLocation": {
                "artifactLocation": {"uri": d.file.replace(os.sep, "/"), "uriBaseId": "%SRCROOT%"},
                "region": {"startLine": d.span.line, "startColumn": d.span.col,
                           "endLine": d.span.end_line, "endColumn": max(d.span.end_col, d.span.col + 1)},
            }}],
        })
    doc = {
        "$schema": "https://json.schemastore.org/sarif-2.1.0.json",
        "version": "2.1.0",
        "runs": [{
            "tool": {"driver": {"name": "mlctool", "version": __version__, "semanticVersion": __version__,
                                "rules": rules}},
            "results": results,
            "columnKind": "unicodeCodePoints",
        }],
    }
    return json.dumps(doc, indent=2, ensure_ascii=False) + "\n"
