"""Issue 29: import defects seen on real exports, each held by a test that failed before the fix."""

from __future__ import annotations

from mlctool.imports import import_text
from mlctool.targetapi import load_target

VS = load_target("vs")


def _gx(rows: list[list[str]], cpu: str = "FXCPU FX3U/FX3UC", info: str = "PLC Information:") -> str:
    head = f'"MAIN"\n"{info}"\t"{cpu}"\n' \
        '"Step Number"\t"Line Statement"\t"Instruction"\t"I/O(Device)"\t"Blank"\t"PI Statement"\t"Note"\n'
    return head + "".join("\t".join(f'"{c}"' for c in (r + [""] * 7)[:7]) + "\n" for r in rows)


def test_w107_quotes_the_row_as_the_export_writes_it():
    """Before: `LD M9002` (the mapped device) and `OUT T0` without its K10 continuation."""
    text = _gx([["0", "", "LD", "M8002"], ["1", "", "OUT", "T0"], ["", "", "", "K10"], ["2", "", "END"]])
    out, _, diags = import_text("g.csv", text, VS)
    said = [d.message for d in diags if d.code == "W107"]
    assert said == ["row 4: LD M8002 is 1 steps in the export (step 0 to 1), 2 by target vs's step convention",
                    "row 5: OUT T0 K10 is 1 steps in the export (step 1 to 2), 3 by target vs's step convention"]
    assert "LD M9002" in out
