"""samples/nc5: the manual's example programs pass `mlc check`; the illegal samples in
samples/nc5/bad fail with the codes, lines and columns their first line expects.

These run the real CLI (a few subprocesses); the per-rule tests are in test_check_rules.py.
"""

from __future__ import annotations

import json
import re
import subprocess
from pathlib import Path

import pytest

from conftest import MLC_COMMAND

ROOT = Path(__file__).resolve().parents[1]
SAMPLES = ROOT / "samples" / "nc5"
MAN = sorted(SAMPLES.glob("man_*.il"))
BAD = sorted((SAMPLES / "bad").glob("*.il"))
EXPECT = re.compile(r"^;\s*expect:\s*((?:[EW]\d{3}\s+\d+:\d+\s*)+)$")


def mlc(*args: str) -> subprocess.CompletedProcess:
    cmd = MLC_COMMAND
    return subprocess.run([*cmd, *args], cwd=ROOT, capture_output=True, text=True, timeout=120)


def expected(path: Path) -> set[tuple[str, int, int]]:
    first = path.read_text("utf-8").split("\n", 1)[0]
    m = EXPECT.match(first)
    assert m, f"{path.name}: first line must be '; expect: CODE LINE:COL ...'"
    items = re.findall(r"([EW]\d{3})\s+(\d+):(\d+)", m[1])
    return {(c, int(line), int(col)) for c, line, col in items}


def test_there_are_samples():
    assert len(MAN) >= 25 and len(BAD) >= 10
    sections = {p.name.split("_")[1] for p in MAN}
    assert sections >= {"1", "2", "3", "4", "6"}


@pytest.mark.parametrize("path", MAN, ids=lambda p: p.name)
def test_manual_sample_header(path):
    lines = path.read_text("utf-8").split("\n")
    # a header comment citing the manual section the file name names
    sec = ".".join(path.stem.split("_")[1:3])
    assert lines[0].startswith("; Manual ") and sec in lines[0], lines[0]


def test_manual_samples_pass_together():
    """The acceptance command: `mlc check samples/nc5/*.il` exits 0."""
    files = [str(p.relative_to(ROOT)) for p in sorted(SAMPLES.glob("*.il"))]
    r = mlc("check", *files)
    assert r.returncode == 0, r.stderr[-3000:]


def test_each_manual_sample_is_clean():
    """Each manual sample on its own: no errors, and no warnings unless suppressed in place."""
    r = mlc("check", "--format", "json", *[str(p.relative_to(ROOT)) for p in MAN])
    assert r.returncode == 0, r.stdout[-3000:]
    # checked together they are one program: cross-module double coils are expected, nothing else
    data = json.loads(r.stdout)
    others = [d for d in data["diagnostics"] if not (d["code"] == "W401" and "is also driven at" in d["message"]
                                                      and d["message"].split(" at ")[1].split(":")[0] != d["file"])]
    assert others == [], others


@pytest.mark.parametrize("path", BAD, ids=lambda p: p.name)
def test_bad_sample(path):
    want = expected(path)
    r = mlc("check", "--format", "json", str(path.relative_to(ROOT)))
    assert r.returncode == 1, (r.returncode, r.stderr)
    data = json.loads(r.stdout)
    got = {(d["code"], d["line"], d["column"]) for d in data["diagnostics"]}
    assert want <= got, f"missing {sorted(want - got)}; got {sorted(got)}"
    errors = {(d["code"], d["line"], d["column"]) for d in data["diagnostics"] if d["severity"] == "error"}
    assert errors == {w for w in want if w[0].startswith("E")}, f"unexpected errors {sorted(errors - want)}"
    for d in data["diagnostics"]:
        assert d["message"].strip(), d  # every diagnostic says something


def test_bad_sample_text_output():
    path = SAMPLES / "bad" / "zrst_mixed_counters.il"
    r = mlc("check", str(path.relative_to(ROOT)))
    assert r.returncode == 1
    assert "zrst_mixed_counters.il:4:9: error[E214]" in r.stderr
    assert "cannot mix 16-bit and 32-bit counters" in r.stderr


def test_warnings_exit_zero_unless_werror(tmp_path):
    src = tmp_path / "w.il"
    src.write_text("LD X0\nOUT Y0\nLD X1\nOUT Y0\nEND\n")
    assert mlc("check", str(src)).returncode == 0
    assert mlc("check", "--werror", str(src)).returncode == 1
    (tmp_path / "mlc.toml").write_text('[severity]\nW401 = "off"\n')
    r = mlc("check", "--werror", "--config", str(tmp_path / "mlc.toml"), str(src))
    assert r.returncode == 0, r.stderr
