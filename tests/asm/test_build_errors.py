"""`mlc build` on sources with errors exits 1 with the diagnostics, whatever it was asked to
write (issue 21 #8: a label out of range, P256 on NC5, crashed `build -o x.mlo`)."""

from __future__ import annotations

import pytest

from conftest import SAMPLES, run_mlc
from mlctool.targetapi import load_target

BAD = sorted((SAMPLES / "nc5" / "bad").glob("*.il"))
OUTPUTS = (["-o", "x.mlo"], ["-o", "x.mlx"], ["-c", "-o", "objs"])


def _label_past_the_range(target: str) -> str:
    p = load_target(target).devices["P"].hi + 1
    return f"LD X0\nCJ P{p}\nP{p}\nEND\n"


@pytest.mark.parametrize("target", ["nc5", "vs"])
@pytest.mark.parametrize("out", OUTPUTS, ids=lambda o: o[-1])
def test_label_out_of_range_is_an_error_not_a_crash(target, out, tmp_path):
    (tmp_path / "lab.il").write_text(_label_past_the_range(target), "utf-8")
    r = run_mlc("build", "--target", target, "lab.il", *out, cwd=tmp_path)
    assert r.code == 1, r.err
    assert "E205" in r.err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["lab.il"]  # nothing written


@pytest.mark.parametrize("path", BAD, ids=lambda p: p.name)
def test_every_bad_sample_builds_to_exit_1(path, tmp_path):
    for out in OUTPUTS:
        r = run_mlc("build", str(path), *[str(tmp_path / o) if o != "-o" and o != "-c" else o for o in out])
        assert r.code == 1, (out, r.err[-1500:])
