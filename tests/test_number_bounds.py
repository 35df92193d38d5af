"""Numbers of 4,301 digits or more (issue 21 #9) hit Python's int-conversion limit: every
entry point bounds digit counts first (mlctool/limits.py, 20 digits) and says so with a
diagnostic at the number, never a crash."""

from __future__ import annotations

import pytest

from conftest import SAMPLES, run_mlc
from mlctool.limits import MAX_DIGITS

HUGE = "1" * 5000
LIMIT = f"at most {MAX_DIGITS}"

IL = {
    "device number": f"LD X{HUGE}\nOUT Y0\nEND\n",
    "label operand": f"LD X0\nCJ P{HUGE}\nEND\n",
    "label line": f"LD X0\nOUT Y0\nP{HUGE}\nEND\n",
    "label line with colon": f"LD X0\nOUT Y0\nP{HUGE}:\nEND\n",
    "step number": f"{HUGE} LD X0\n1 OUT Y0\n2 END\n",
    "constant": f"LD X0\nMOV K{HUGE} D0\nEND\n",
    "timer preset": f"LD X0\nOUT T0 K{HUGE}\nEND\n",
    "export": f".export P{HUGE}\nLD X0\nOUT Y0\nEND\n",
    "define": f".define A D{HUGE}\nLD X0\nOUT Y0\nEND\n",
}


@pytest.mark.parametrize("case", sorted(IL))
@pytest.mark.parametrize("target", ["nc5", "vs"])
def test_il_number_too_long(case, target, tmp_path):
    (tmp_path / "t.il").write_text(IL[case], "utf-8")
    for cmd in ("check", "ladder", "fmt"):
        r = run_mlc(cmd, "--target", target, "t.il", cwd=tmp_path) if cmd != "fmt" else \
            run_mlc("fmt", "t.il", cwd=tmp_path)
        assert r.code == 1, (cmd, r.err[-800:])
    r = run_mlc("check", "--target", target, "t.il", cwd=tmp_path)
    assert "E103" in r.err and LIMIT in r.err


POS = {
    "step label": f"{HUGE} SPD 100\n DRV ADR + 100 Ut\n MEND\n",
    "speed": f"001 SPD {HUGE}\n DRV ADR + 100 Ut\n MEND\n",
    "goto": f"001 SPD 100\n DRV ADR + 100 Ut\n GOTO {HUGE}\n MEND\n",
    "register": f"001 SPD 100\n DRV ADR + 100 Ut\n WAIT R{HUGE}\n MEND\n",
}


@pytest.mark.parametrize("case", sorted(POS))
def test_positioning_number_too_long(case, tmp_path):
    (tmp_path / "p.pos").write_text(POS[case], "utf-8")
    r = run_mlc("check", "--target", "fbs", "p.pos", cwd=tmp_path)
    assert r.code == 1, r.err[-800:]
    assert "F034" in r.err and LIMIT in r.err


STIM = {
    "time": f"{HUGE}ms X0=1\n",
    "relative time": f"10ms X0=1\n+{HUGE}ms X0=0\n",
    "scan number": f"#{HUGE} X0=1\n",
    "device number": f"10ms X{HUGE}=1\n",
    "value": f"10ms D0={HUGE}\n",
    "expected value": f"10ms expect D0={HUGE}\n",
    "run time": f"run {HUGE}ms\n",
    "run scans": f"run #{HUGE}\n",
    "scan period": f"scan {HUGE}ms\n",
}


@pytest.mark.parametrize("case", sorted(STIM))
def test_stimulus_number_too_long(case, tmp_path):
    (tmp_path / "t.il").write_text("LD X0\nOUT Y0\nEND\n", "utf-8")
    (tmp_path / "t.stim").write_text(STIM[case], "utf-8")
    r = run_mlc("sim", "t.il", "--stimulus", "t.stim", cwd=tmp_path)
    assert r.code == 2, r.err[-800:]
    assert "E601" in r.err and LIMIT in r.err


def test_until_too_long(tmp_path):
    (tmp_path / "t.il").write_text("LD X0\nOUT Y0\nEND\n", "utf-8")
    r = run_mlc("sim", "t.il", "--until", f"{HUGE}ms", cwd=tmp_path)
    assert r.code == 2 and LIMIT in r.err, r.err[-800:]


def test_duration_too_long():
    r = run_mlc("device", "serve", "xc100", "--tcp", "127.0.0.1:1", "--duration", f"{HUGE}s")
    assert r.code == 2 and "E801" in r.err and LIMIT in r.err, r.err[-800:]


def test_scans_too_long(tmp_path):
    (tmp_path / "t.il").write_text("LD X0\nOUT Y0\nEND\n", "utf-8")
    r = run_mlc("sim", "t.il", "--scans", HUGE, cwd=tmp_path)
    assert r.code == 2 and "internal error" not in r.err


def test_twenty_digits_still_read(tmp_path):
    """The bound is on digits, not values: 20 digits reach the usual range checks."""
    (tmp_path / "t.il").write_text(f"LD X{'9' * MAX_DIGITS}\nOUT Y0\nEND\n", "utf-8")
    r = run_mlc("check", "t.il", cwd=tmp_path)
    assert r.code == 1 and "E103" not in r.err and ("E205" in r.err or "E203" in r.err), r.err


@pytest.mark.parametrize("name,text", [
    ("image.csv", f"register,value\nR0,{HUGE}\n"),
    ("image.json", '{"format": "mlc-fbs-image", "words": [' + HUGE + "]}"),
])
def test_register_image_number_too_long(name, text, tmp_path):
    """FBs register images (objdump, --table) are read with json/int: bounded first."""
    (tmp_path / name).write_text(text, "utf-8")
    r = run_mlc("objdump", name, cwd=tmp_path)
    assert r.code == 2 and LIMIT in r.err and "internal error" not in r.err, r.err[-800:]


@pytest.mark.parametrize("option", [
    ["--until", f"{HUGE}ms"], ["--max-wall", f"{HUGE}s"], ["--scan-time", f"{HUGE}ms"],
    ["--vcd", "o.vcd", "--pulse-window", f"{HUGE}ms..{HUGE}ms"], ["--watch", f"D{HUGE}"],
])
def test_sim_option_number_too_long(option, tmp_path):
    (tmp_path / "t.il").write_text("LD X0\nOUT Y0\nEND\n", "utf-8")
    r = run_mlc("sim", "t.il", *option, cwd=tmp_path)
    assert r.code == 2 and LIMIT in r.err and "internal error" not in r.err, r.err[-800:]


def test_tcp_port_too_long():
    r = run_mlc("device", "serve", "xc100", "--tcp", f"127.0.0.1:{HUGE}")
    assert r.code == 2 and "E801" in r.err and "internal error" not in r.err, r.err[-800:]
    assert len(r.err) < 400  # the option is shown clipped


def test_mlc_toml_number_too_long(tmp_path):
    """tomllib converts integers itself: past 4,300 digits it raises ValueError, which is
    reported as E110 at the number."""
    (tmp_path / "mlc.toml").write_text(f'target = "nc5"\ncapacity = {HUGE}\n', "utf-8")
    (tmp_path / "t.il").write_text("LD X0\nOUT Y0\nEND\n", "utf-8")
    r = run_mlc("check", "t.il", cwd=tmp_path)
    assert r.code == 2 and "mlc.toml:2:12: error[E110]" in r.err and LIMIT in r.err, r.err[-800:]


def test_fbs_table_register_too_long(tmp_path):
    """The SR of `--table SR=FILE` and `build --sr` (FBs): a register name, bounded."""
    pos = SAMPLES / "fbs" / "home.pos"
    r = run_mlc("sim", "--target", "fbs", str(SAMPLES / "fbs" / "home_and_run.il"),
                "--table", f"R{HUGE}={pos}", cwd=tmp_path)
    assert r.code == 2 and "internal error" not in r.err and len(r.err) < 600, r.err[-800:]
    r = run_mlc("build", "--target", "fbs", str(pos), "-o", "t.json", "--sr", f"R{HUGE}", cwd=tmp_path)
    assert r.code == 2 and "internal error" not in r.err and len(r.err) < 600, r.err[-800:]


@pytest.mark.parametrize("line", [
    "port CP1 baud=²", "port CP1 station=²", "model vsplc link=CP1 station=²",
    "model xc100 link=CP1 station=²", f"port CP1 baud={HUGE}",
])
def test_stimulus_settings_take_ascii_digits_only(line, tmp_path):
    """str.isdigit() takes "²", which int() refuses: settings are read with limits.is_decimal."""
    (tmp_path / "t.il").write_text("LD X0\nOUT Y0\nEND\n", "utf-8")
    (tmp_path / "t.stim").write_text(line + "\n", "utf-8")
    r = run_mlc("sim", "--target", "vs", "t.il", "--stimulus", "t.stim", cwd=tmp_path)
    assert r.code == 2 and "E601" in r.err and "internal error" not in r.err, r.err[-800:]
