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


def test_check_reports_a_fun147_axis_in_p_r_mode_at_its_travel(tmp_path):
    """11.6, FUN147: "務必設定 Pulse Output 之工作模式 ... 為 U/D 或 A/B 等二種模式之一": a LIN/LINE
    travel that drives an axis mlc.toml sets to P/R is E236 at that operand; blank and ADR 0 do
    not drive it (ABS 0 does: it moves to 0); FUN140 (.pos) may drive a P/R axis."""
    from conftest import run_mlc

    (tmp_path / "mlc.toml").write_text('target = "fbs"\nsources = []\npulse_modes = ["U/D", "P/R", "A/B"]\n',
                                       "utf-8")
    (tmp_path / "ok.mpos").write_text("001 SPD 5000\n LIN ADR,500,0,300, ,Ut\n GOTO NEXT\n"
                                      "002 SPD 5000\n LINE ADR,500, ,300,200,Ut\n MEND\n", "utf-8")
    (tmp_path / "ok.pos").write_text("001 SPD 1000\n DRV ADR,+,1000,Ps\n MEND\n", "utf-8")
    r = run_mlc("check", "ok.mpos", "ok.pos", cwd=tmp_path)
    assert r.code == 0, r.err
    (tmp_path / "bad.mpos").write_text("001 SPD 5000\n LIN ADR,500,400, , ,Ut\n GOTO NEXT\n"
                                       "002 SPD 5000\n LINE ABS,500,0, , ,Ut\n MEND\n", "utf-8")
    r = run_mlc("check", "bad.mpos", cwd=tmp_path)
    assert r.code == 1 and "Traceback" not in r.err
    assert "bad.mpos:2:14: error[E236]" in r.err and "bad.mpos:5:15: error[E236]" in r.err, r.err
    assert r.err.count("E236") == 2 and "Ps1" in r.err
    (tmp_path / "mlc.toml").write_text('target = "fbs"\nsources = []\n', "utf-8")  # the default: U/D
    assert run_mlc("check", "bad.mpos", cwd=tmp_path).code == 0
