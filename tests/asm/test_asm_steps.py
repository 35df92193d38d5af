"""Step counts of built programs against the manual's own tables (2.1 basic, 3.1 application).

The expected totals are computed here from the manual text and the sources, without the
assembler: a tiny IL reader, the 2.1 / 3.1 step columns, and the project's documented "1~2"
rule (target.toml `short_operand`: 1 step in the ordinary device ranges, else 2).
"""

from __future__ import annotations

import json
import re
import tomllib
from pathlib import Path

import pytest

from conftest import ROOT, SAMPLES, run_mlc

MANUAL = ROOT.parent / "shared" / "manuals" / "000_a33d4a328dc57a96.txt"
TARGET_TOML = ROOT / "mlctool" / "targets" / "nc5" / "target.toml"
PROJECT = SAMPLES / "project"

pytestmark = pytest.mark.skipif(not MANUAL.is_file(), reason=f"manual text not found at {MANUAL}")


def _section(lines, start, end):
    i = next(k for k, x in enumerate(lines) if x.strip() == start)
    j = next(k for k in range(i + 1, len(lines)) if lines[k].strip().startswith(end))
    return lines[i:j]


@pytest.fixture(scope="module")
def manual_steps() -> dict[str, str]:
    """mnemonic -> steps as printed ('1', '3', '1~2', ...)."""
    lines = MANUAL.read_text("utf-8").split("\n")
    steps = {}
    for x in _section(lines, "## 2.1 基本指令一覽表", "## 2.2 基本指令說明"):
        f = x.split("\t")
        if len(f) == 5 and re.fullmatch(r"[A-Z]+", f[0]):
            steps[f[0]] = f[4].strip()
    for x in _section(lines, "### 3.1 應用指令一覽表", "### 3.2"):
        f = [c.strip() for c in x.split("\t")]
        k = next((i for i, c in enumerate(f) if re.fullmatch(r"\d\d", c)), None)
        if k is None or len(f) < k + 7:
            continue
        _api, n16, n32, _count, _func, s16, s32 = f[k:k + 7]
        for name, s in ((n16, s16), (n32, s32)):
            if name not in ("-", "–", ""):
                steps.setdefault(name, s)
    assert steps["LD"] == "1~2" and steps["DMOV"] == "6" and steps["DVRT"] == "134"
    return steps


def expected_steps(path: Path, steps: dict[str, str]) -> list[int]:
    """Steps of each statement of an IL file, from the manual's tables."""
    short = tomllib.loads(TARGET_TOML.read_text("utf-8"))["short_operand"]
    symbols: dict[str, str] = {}
    out = []
    for line in path.read_text("utf-8").splitlines():
        words = [w for w in re.split(r"[\s,]+", re.split(r";|//", line)[0]) if w]
        if words and words[0].isdigit():
            words = words[1:]
        if not words:
            continue
        if words[0].lower() == ".define":
            symbols[words[1].upper()] = words[2]
            continue
        if words[0].startswith("."):
            continue
        if words[0].endswith(":") or re.fullmatch(r"[Pp]\d+", words[0]):
            out.append(int(steps["P"]))
            continue
        s = steps[words[0].upper()]
        if s == "1~2":
            m = re.fullmatch(r"([A-Z])(\d+)", symbols.get(words[1].upper(), words[1]).upper())
            lo, hi = short.get(m[1], (0, -1))
            s = "1" if lo <= int(m[2]) <= hi else "2"
        out.append(int(s))
    return out


def _objdump(path) -> dict:
    r = run_mlc("objdump", "--json", str(path))
    assert r.code == 0, r.err
    return json.loads(r.out)


def test_project_total_matches_manual(tmp_path, manual_steps):
    out = tmp_path / "p.mlx"
    sources = ["src/conveyor.il", "src/pickplace.il"]
    r = run_mlc("build", *sources, "-o", str(out), cwd=PROJECT)
    assert r.code == 0, r.err
    doc = _objdump(out)
    per_file = {s: expected_steps(PROJECT / s, manual_steps) for s in sources}
    expected = sum(sum(v) for v in per_file.values())  # the main module has its own FEND
    assert doc["total_steps"] == expected
    for s in sources:
        got = [i["steps"] for i in doc["instructions"] if i["file"] == s]
        assert got == per_file[s], s
    # addresses are the running sum of steps
    addr = 0
    for i in doc["instructions"]:
        assert i["addr"] == addr
        addr += i["steps"]


@pytest.mark.parametrize("path", sorted((SAMPLES / "nc5").glob("*.il")), ids=lambda p: p.name)
def test_sample_steps_match_manual(tmp_path, manual_steps, path):
    out = tmp_path / "x.mlo"
    r = run_mlc("build", str(path), "-o", str(out))
    if r.code == 1:
        pytest.skip(f"{path.name} does not build alone: {r.err.splitlines()[0]}")
    assert r.code == 0, r.err
    doc = _objdump(out)
    assert [i["steps"] for i in doc["instructions"]] == expected_steps(path, manual_steps)
    assert doc["total_steps"] == sum(expected_steps(path, manual_steps))
