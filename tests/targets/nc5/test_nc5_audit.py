"""docs/nc5-audit.md stays honest: every row names tests that exist, the sections the page
promises are there and not empty, and every row of the signal table (signals.tsv) lies in a
row group of the 5.2 sections."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from mlctool.targets.nc5 import signals as nc5

ROOT = Path(__file__).resolve().parents[3]
AUDIT = ROOT / "docs" / "nc5-audit.md"
SECTIONS = ["5.1 Numbering, channels, ranges", "5.2.1 Special M, MLC -> NC", "5.2.1 Special M, NC -> MLC",
            "5.2.2 Special D", "5.3.1-5.3.15 Function groups", "5.3.16-5.3.19 HMI points and registers",
            "5.3.20 EtherCAT", "Where the names appear"]
TEST_CELL = re.compile(r"`(tests/[\w/.-]+\.py)::(\w+)(?:\[([^\]]*)\])?`")
PATTERN = re.compile(r"\b([MD][0-9x]{5})(?:-([MD][0-9x]{5}))?\b")


def audit_rows() -> list[tuple[str, list[str]]]:
    """(section heading, cells) of every data row of the page's tables."""
    section, rows = "", []
    for line in AUDIT.read_text("utf-8").splitlines():
        if line.startswith("## "):
            section = line[3:].strip()
        elif line.startswith("|") and not line.startswith(("| ---", "| rows ")):
            rows.append((section, [c.strip() for c in line.strip().strip("|").split("|")]))
    return rows


def test_every_row_has_five_cells_and_tests_that_exist():
    missing = []
    rows = audit_rows()
    assert rows
    for section, cells in rows:
        assert len(cells) == 5, f"{section}: {cells[:2]} has {len(cells)} cells, not 5"
        assert cells[2] and cells[3], f"{section}: {cells[0]} says nothing of where or what was decided"
        tests = TEST_CELL.findall(cells[4])
        assert tests, f"{section}: row {cells[0]!r} names no test as `path::name`"
        for path, name, case in tests:
            text = (ROOT / path).read_text("utf-8") if (ROOT / path).is_file() else ""
            if not re.search(rf"^\s*(async )?def {name}\(", text, re.M) or (case and f'"{case}"' not in text):
                missing.append(f"{path}::{name}")
    assert not missing, f"rows name tests that do not exist: {missing}"


@pytest.mark.parametrize("section", SECTIONS)
def test_every_promised_section_has_rows(section):
    assert any(s == section for s, _ in audit_rows()), f"no rows under ## {section}"


def _key(pattern: str) -> tuple[str, str]:
    """Patterns compare within one kind, direction and channel form (M2x000 .. M2x726)."""
    return pattern[:2] + ("x" if "x" in pattern else "0") + str(pattern.find("x")), pattern


def test_every_row_of_the_signal_table_lies_in_a_row_group():
    groups = []
    for section, cells in audit_rows():
        if section.startswith("5.2"):
            for first, last in PATTERN.findall(cells[0]):
                groups.append((first, last or first))
    loose = []
    for s in nc5.rows():
        k = _key(s.device)
        if not any(_key(a)[0] == k[0] and a <= s.device <= b and _key(b)[0] == k[0] for a, b in groups):
            loose.append(s.device)
    assert not loose, f"{len(loose)} rows of signals.tsv in no row group of docs/nc5-audit.md: {loose[:10]}"


def test_every_decision_of_the_table_is_on_the_page():
    """Each DECISION beside rows of signals.tsv is stated on the page: the first row it is
    beside is named in a decision cell that says DECISION."""
    said = " ".join(cells[3] for _, cells in audit_rows() if "DECISION" in cells[3])
    first: dict[str, str] = {}
    for s in nc5.rows():
        if s.decision:
            first.setdefault(s.decision, s.device)
    assert len(first) >= 10
    silent = sorted(device for device in first.values() if not re.search(rf"\b{device}\b", said))
    assert not silent, f"decisions of signals.tsv the page does not state: {silent}"
