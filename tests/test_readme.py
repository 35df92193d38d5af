"""The README's example program and stimulus work as shown."""

from __future__ import annotations

import re

from tests.conftest import ROOT


def _blocks(text: str) -> list[str]:
    return re.findall(r"^```[a-z]*\n(.*?)^```", text, re.S | re.M)


def test_readme_example_runs(mlc, tmp_path):
    blocks = _blocks((ROOT / "README.md").read_text())
    program = next(b for b in blocks if "LD   START" in b)
    stimulus = next(b for b in blocks if "expect Y0=1" in b)
    (tmp_path / "motor.il").write_text(program)
    (tmp_path / "motor.stim").write_text(stimulus)
    assert mlc("check", "--werror", "motor.il", cwd=tmp_path).code == 0
    r = mlc("sim", "motor.il", "--stimulus", "motor.stim", cwd=tmp_path)
    assert r.code == 0, r.err
    assert "2 passed, 0 failed" in r.out or "expectations: 2 passed" in r.out
    assert "make demo" in (ROOT / "README.md").read_text().split("\n## ")[0]
