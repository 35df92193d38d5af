"""Ladder diagrams: IL rungs as series/parallel networks, laid out on a grid and rendered
as SVG, a self-contained HTML page, terminal text, or a simulation report (docs/ladder.md).

Belongs here: drawing and reporting programs as ladders. Does not belong here: checking
(check/) or running them (sim/).
"""

from __future__ import annotations

from mlctool.check import check_files
from mlctool.config import Config
from mlctool.diagnostics import Diagnostic
from mlctool.ladder.document import Sheet, build_sheet
from mlctool.targetapi import Target


def sheets_from_files(paths: list[str], target: Target, config: Config | None = None
                      ) -> tuple[list[Sheet], list[Diagnostic], dict[str, list[str]]]:
    """Check the sources; without errors, one Sheet per file (else no sheets)."""
    result = check_files(paths, target, config)
    if result.errors:
        return [], result.diagnostics, result.lines
    sheets = [build_sheet(m.path, m.instrs, result.lines, target) for m in result.modules]
    return sheets, result.diagnostics, result.lines
