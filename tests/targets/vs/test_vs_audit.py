"""docs/vs-audit.md stays honest: every FNC of the VS instruction table has a row, every row
names a test that exists, and no section is left empty."""

import re
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[3]
AUDIT = ROOT / "docs" / "vs-audit.md"
TABLE = ROOT / "mlctool" / "targets" / "vs" / "instructions.toml"
# section heading -> the FNC numbers its rows must cover
SECTIONS = {
    "Basic instructions": range(0),
    "FNC 000-049": range(0, 50),
    "FNC 050-149": range(50, 150),
    "FNC 150-316": range(150, 317),
}
# Sections whose audit is still being written: their coverage is not yet asserted.
# Remove a section's line when its rows are complete.
IN_PROGRESS: set[str] = set()
TEST_CELL = re.compile(r"`(tests/[\w/.-]+\.py)::(\w+)(?:\[([^\]]*)\])?`")


def audit_rows():
    """(section heading, cells) for every data row of the page's tables."""
    section, rows = None, []
    for line in AUDIT.read_text(encoding="utf-8").splitlines():
        if line.startswith("## "):
            section = line[3:].strip()
        elif line.startswith("|") and not line.startswith("| ---") and not line.startswith("| page"):
            cells = [c.strip() for c in line.strip().strip("|").split("|")]
            rows.append((section, cells))
    return rows


def fnc_mnemonics():
    """{FNC number: mnemonic} of every application instruction of the target."""
    table = tomllib.loads(TABLE.read_text(encoding="utf-8"))
    return {entry["api"]: entry["names"][0] for entry in table["instr"] if "api" in entry}


def test_every_row_has_six_cells_and_a_test_that_exists():
    rows = audit_rows()
    missing = []
    for section, cells in rows:
        assert len(cells) == 6, f"{section}: row {cells} has {len(cells)} cells, not 6"
        tests = TEST_CELL.findall(cells[5])
        assert tests, f"{section}: row {cells[:3]} names no test as `path::name`"
        for path, name, case in tests:
            source = ROOT / path
            text = source.read_text(encoding="utf-8") if source.is_file() else ""
            if not re.search(rf"^\s*(async )?def {name}\(", text, re.M):
                missing.append(f"{path}::{name}")
            elif case and f'"{case}"' not in text:  # a parametrized case: its id is written in the file
                missing.append(f"{path}::{name}[{case}]")
    assert not missing, f"rows name tests that do not exist: {missing}"


@pytest.mark.parametrize("section", SECTIONS)
def test_every_fnc_page_of_a_section_has_a_row(section):
    if section in IN_PROGRESS:
        pytest.skip(f"audit of {section} in progress")
    rows = [cells for s, cells in audit_rows() if s and s.startswith(section)]
    assert rows, f"section {section!r} has no rows"
    covered = set()
    for cells in rows:
        covered.update(int(n) for n in re.findall(r"FNC\s*(\d+)", cells[0] + " " + cells[1]))
    missing = {n: m for n, m in fnc_mnemonics().items() if n in SECTIONS[section] and n not in covered}
    assert not missing, f"{len(missing)} FNC pages have no row in {section!r}: {sorted(missing.items())[:20]}"
