"""docs/nc5-audit.md, section "Examples (chapter 6)", stays honest: one row per example
6.1-6.16, every row names tests that exist, a row of test_example names an example whose
sample exists, or says **pending** while it has none (and stops saying so once it has)."""

from __future__ import annotations

import re

from conftest import ROOT

AUDIT = ROOT / "docs" / "nc5-audit.md"
SECTION = "Examples (chapter 6)"
TEST_CELL = re.compile(r"`(tests/[\w/.-]+\.py)::(\w+)(?:\[([^\]]*)\])?`")


def section_rows() -> list[list[str]]:
    rows, inside = [], False
    for line in AUDIT.read_text(encoding="utf-8").splitlines():
        if line.startswith("## "):
            inside = line[3:].strip() == SECTION
        elif inside and line.startswith("|") and not line.startswith(("| ---", "| rows ")):
            rows.append([c.strip() for c in line.strip().strip("|").split("|")])
    return rows


def test_one_row_per_example():
    examples = [re.match(r"6\.(\d+) ", cells[0]) for cells in section_rows()]
    assert sorted(int(m[1]) for m in examples if m) == list(range(1, 17))


def test_every_row_names_tests_that_exist():
    missing = []
    for cells in section_rows():
        assert len(cells) == 5, f"{cells[:1]} has {len(cells)} cells, not 5"
        tests = TEST_CELL.findall(cells[4])
        assert tests, f"row {cells[0]!r} names no test as `path::name`"
        for path, name, case in tests:
            text = (ROOT / path).read_text(encoding="utf-8") if (ROOT / path).is_file() else ""
            if not re.search(rf"^\s*def {name}\(", text, re.M):
                missing.append(f"{path}::{name}")
            elif name == "test_example":  # parametrised over the samples present
                sample = sorted((ROOT / "samples" / "nc5").glob(f"man_6_{case.split('.')[1]}_*.il"))
                pending = "**pending**" in cells[1]
                if bool(sample) == pending:
                    missing.append(f"{path}::{name}[{case}] ({'pending with a sample' if pending else 'no sample'})")
    assert not missing, f"rows name tests that do not exist: {missing}"
