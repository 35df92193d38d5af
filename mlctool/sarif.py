"""SARIF 2.1.0 for CI (GitHub code scanning and other SARIF viewers).

Decisions (docs/check.md "Output"):
- Artifact URIs are relative to the repository root, the git top level found upward from the
  current folder (else the current folder), named `%SRCROOT%` in `originalUriBaseIds`, and
  percent-encoded (RFC 3986: a blank is `%20`, a Chinese name is its UTF-8 bytes). A file
  outside that root gets an absolute `file:` URI.
- `invocations` records the exit code; `executionSuccessful` is false only when the check
  could not run over its inputs (exit 2: unreadable input, usage), since finding errors is a
  successful check.
- Each rule's `helpUri` is the code's row in docs/check.md of the release's tag:
  `DOCS_URL` + `check.md#e201` (lower-case code; the table row carries that anchor).
"""

from __future__ import annotations

import json
import os
from pathlib import Path
from urllib.parse import quote

from mlctool import __version__
from mlctool.codes import CODES
from mlctool.diagnostics import Diagnostic

# The one place naming where the documentation is published (a fork changes this line).
DOCS_URL = f"https://github.com/mlctool/mlctool/blob/v{__version__}/docs/"
SRCROOT = "%SRCROOT%"


def help_uri(code: str) -> str:
    return f"{DOCS_URL}check.md#{code.lower()}"


def repository_root(start: str | None = None) -> Path:
    """The git top level above `start` (a `.git` folder, or a `.git` file in a worktree),
    else `start` itself; found without running git."""
    here = Path(start or os.getcwd()).resolve()
    for folder in (here, *here.parents):
        if (folder / ".git").exists():
            return folder
    return here


def artifact_location(path: str, root: Path) -> dict:
    full = Path(os.path.abspath(path))
    try:
        rel = full.relative_to(root)
    except ValueError:
        return {"uri": full.as_uri()}
    return {"uri": quote(rel.as_posix(), safe="/"), "uriBaseId": SRCROOT}


def _level(severity: str) -> str:
    return severity if severity in ("error", "warning") else "note"


def to_sarif(diags: list[Diagnostic], exit_code: int = 0, root: Path | None = None) -> str:
    root = root or repository_root()
    rules = [
        {"id": c.code, "name": c.code, "shortDescription": {"text": c.summary},
         "fullDescription": {"text": c.summary}, "help": {"text": c.doc}, "helpUri": help_uri(c.code),
         "defaultConfiguration": {"level": _level(c.severity)}}
        for c in CODES.values()
    ]
    index = {c: k for k, c in enumerate(CODES)}
    results = []
    for d in diags:
        results.append({
            "ruleId": d.code,
            "ruleIndex": index[d.code],
            "level": _level(d.severity),
            "message": {"text": d.message},
            "locations": [{"physicalLocation": {
                "artifactLocation": artifact_location(d.file, root),
                "region": {"startLine": d.span.line, "startColumn": d.span.col,
                           "endLine": d.span.end_line, "endColumn": max(d.span.end_col, d.span.col + 1)},
            }}],
        })
    doc = {
        "$schema": "https://json.schemastore.org/sarif-2.1.0.json",
        "version": "2.1.0",
        "runs": [{
            "tool": {"driver": {"name": "mlctool", "version": __version__, "semanticVersion": __version__,
                                "informationUri": f"{DOCS_URL}check.md", "rules": rules}},
            "invocations": [{"executionSuccessful": exit_code != 2, "exitCode": exit_code}],
            "originalUriBaseIds": {SRCROOT: {"uri": root.as_uri().rstrip("/") + "/"}},
            "results": results,
            "columnKind": "unicodeCodePoints",
        }],
    }
    return json.dumps(doc, indent=2, ensure_ascii=False) + "\n"
