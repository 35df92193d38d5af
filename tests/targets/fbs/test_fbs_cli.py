"""mlc check / build / objdump on FBs positioning files and the fbs target (real CLI)."""

from __future__ import annotations

import json
import subprocess
from pathlib import Path

from conftest import MLC_COMMAND

ROOT = Path(__file__).resolve().parents[3]
SAMPLES = ROOT / "samples" / "fbs"


def mlc(*args: str, cwd=ROOT) -> subprocess.CompletedProcess:
    cmd = MLC_COMMAND
    return subprocess.run([*cmd, *args], cwd=cwd, capture_output=True, text=True, timeout=120)


def test_check_all_samples_and_the_il_program():
    files = [str(p) for p in sorted(SAMPLES.glob("*.*pos"))]
    assert len(files) >= 10
    r = mlc("check", *files)
    assert r.returncode == 0, r.stderr
    r = mlc("check", "--target", "fbs", str(SAMPLES / "home_and_run.il"))
    assert r.returncode == 0, r.stderr


def test_check_reports_codes_with_line_and_column(tmp_path):
    p = tmp_path / "bad.pos"
    p.write_text("001 SPD 0\n DRV ABS,+,1,Ut\n MEND\n", "utf-8")
    r = mlc("check", "--format", "json", str(p))
    assert r.returncode == 1
    got = {(d["code"], d["line"], d["column"]) for d in json.loads(r.stdout)["diagnostics"]}
    assert got == {("F031", 1, 9), ("F043", 2, 10)}
    assert "Traceback" not in r.stderr


def test_build_objdump_round_trip(tmp_path):
    src = SAMPLES / "man_program_format.pos"
    for ext in ("json", "csv"):
        out = tmp_path / f"t.{ext}"
        assert mlc("build", str(src), "-o", str(out), "--sr", "R5000").returncode == 0
        text = mlc("objdump", str(out))
        assert text.returncode == 0 and text.stdout.startswith("; FUN140 HSPSO table at R5000: 4 steps, 38")
        back = tmp_path / f"back_{ext}.pos"
        back.write_text(text.stdout, "utf-8")
        again = tmp_path / f"again.{ext}"
        assert mlc("build", str(back), "-o", str(again), "--sr", "R5000").returncode == 0
        assert again.read_bytes() == out.read_bytes()


def test_bad_requests_and_images(tmp_path):
    src = str(SAMPLES / "man_drvc.pos")
    assert mlc("build", src, "-o", str(tmp_path / "x.mlx")).returncode == 2
    assert mlc("build", src, "-o", str(tmp_path / "x.json"), "--sr", "R4000").returncode == 2
    bad = tmp_path / "bad.csv"
    bad.write_text("register,value,hex\nR0,1,0001\nR1,1,0001\n", "utf-8")
    r = mlc("objdump", str(bad))
    assert r.returncode == 2 and "F034" in r.stderr and "Traceback" not in r.stderr
