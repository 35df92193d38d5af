"""`mlc sim` end to end: samples, exit codes, JSON, VCD (vcdvcd, vcd2fst), JUnit, errors."""

from __future__ import annotations

import json
import shutil
import subprocess
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from conftest import SAMPLES, run_mlc

NC5 = SAMPLES / "nc5"
SIM_SAMPLES = sorted(NC5.glob("sim_*.il")) + [NC5 / "conveyor.il"]
CONVEYOR = [str(NC5 / "conveyor.il"), "--stimulus", str(NC5 / "conveyor.stim")]


@pytest.mark.parametrize("il", SIM_SAMPLES, ids=lambda p: p.stem)
def test_each_sample_passes_check_and_its_stimulus(il):
    assert run_mlc("check", str(il)).code == 0
    r = run_mlc("sim", str(il), "--stimulus", str(il.with_suffix(".stim")))
    assert r.code == 0, r.err
    assert "0 failed" in r.out


def test_wrong_expectation_exits_1_with_a_clear_message(tmp_path):
    stim = tmp_path / "wrong.stim"
    stim.write_text((NC5 / "conveyor.stim").read_text() + "12s expect D0=4\n")
    r = run_mlc("sim", str(NC5 / "conveyor.il"), "--stimulus", str(stim))
    assert r.code == 1
    assert "error[E603]" in r.err and "D0 expected 4, actual 3" in r.err
    assert "at 12000 ms (scan 1200)" in r.err and "conveyor.il:" in r.err and "MOV C0 D0" in r.err


def test_json_shape(tmp_path):
    r = run_mlc("sim", *CONVEYOR, "--json", "--watch", "T0:w,D100")
    assert r.code == 0
    doc = json.loads(r.out)
    assert doc["time_ms"] == 13000 and doc["scans"] == 1300
    assert doc["expectations"] == {"passed": 7, "failed": 0, "failures": []}
    devices = doc["devices"]
    for name in ("X0", "Y0", "M0", "T0", "T0:w", "C0", "C0:w", "D0", "D100"):
        assert name in devices
    assert devices["D0"] == 0 or isinstance(devices["D0"], int)


def test_runs_are_deterministic_byte_for_byte(tmp_path):
    outs = []
    for k in range(2):
        vcd = tmp_path / f"run{k}.vcd"
        r = run_mlc("sim", *CONVEYOR, "--json", "--vcd", str(vcd))
        outs.append((r.out, vcd.read_bytes()))
    assert outs[0] == outs[1]
    assert b"$date" not in outs[0][1]


def test_vcd_read_back_with_an_independent_reader(tmp_path):
    vcdvcd = pytest.importorskip("vcdvcd")
    vcd = tmp_path / "c.vcd"
    assert run_mlc("sim", *CONVEYOR, "--vcd", str(vcd), "--watch", "Y0,X2,C0:w").code == 0
    data = vcdvcd.VCDVCD(str(vcd))
    assert "mlc.Y0" in data.signals and "mlc.C0_w" in data.signals
    y0 = data["mlc.Y0"]
    assert y0[0] == "1" and y0[1_500_000] == "1" and y0[2_000_000] == "0" and y0[3_000_000] == "1"
    assert int(data["mlc.C0_w"][7_000_000], 2) == 2
    assert data["mlc.C0_w"].size == "16" or int(data["mlc.C0_w"].size) == 16
    gtkw = (tmp_path / "c.gtkw").read_text()
    assert '[dumpfile] "c.vcd"' in gtkw and "mlc.Y0" in gtkw and "mlc.C0_w[15:0]" in gtkw
    assert "mlc.D0" not in gtkw  # only the watched signals


def test_vcd2fst_accepts_the_vcd(tmp_path):
    tool = shutil.which("vcd2fst")
    if tool is None:
        pytest.skip("vcd2fst (gtkwave) is not installed")
    vcd = tmp_path / "c.vcd"
    assert run_mlc("sim", *CONVEYOR, "--vcd", str(vcd)).code == 0
    done = subprocess.run([tool, str(vcd), str(tmp_path / "c.fst")], capture_output=True,
                          text=True, timeout=60)
    assert done.returncode == 0, done.stderr
    assert (tmp_path / "c.fst").stat().st_size > 0


def test_junit_one_case_per_expectation_line(tmp_path):
    stim = tmp_path / "s.stim"
    stim.write_text("0ms X0=1\n1s expect T0=1\n2s expect Y9=1\n")
    prog = tmp_path / "p.il"
    prog.write_text("LD X0\nTMR T0 K10\nEND\n")
    xml = tmp_path / "out.xml"
    r = run_mlc("sim", str(prog), "--stimulus", str(stim), "--junit", str(xml))
    assert r.code == 1
    suite = ET.parse(xml).getroot().find("testsuite")
    cases = suite.findall("testcase")
    assert [c.get("name").split(":")[0] for c in cases] == ["line 2", "line 3"]
    assert cases[0].find("failure") is None and cases[1].find("failure") is not None
    assert suite.get("failures") == "1"


def test_works_from_a_linked_image(tmp_path):
    mlx = tmp_path / "conveyor.mlx"
    assert run_mlc("build", str(NC5 / "conveyor.il"), "-o", str(mlx)).code == 0
    a = run_mlc("sim", str(mlx), "--stimulus", str(NC5 / "conveyor.stim"), "--json")
    b = run_mlc("sim", *CONVEYOR, "--json")
    assert a.code == 0 and a.out == b.out


def test_a_linked_image_runs_on_the_target_it_was_built_for(tmp_path):
    vs = SAMPLES / "vs"
    mlx = tmp_path / "t.mlx"
    assert run_mlc("build", "--target", "vs", str(vs / "traffic_light.il"), "-o", str(mlx)).code == 0
    (tmp_path / "mlc.toml").write_text('target = "nc5"\n')  # the object wins over the project
    stim = ["--stimulus", str(vs / "traffic_light.stim")]
    r = run_mlc("sim", "t.mlx", *stim, "--json", cwd=tmp_path)
    assert r.code == 0, r.err
    assert r.out == run_mlc("sim", "--target", "vs", str(vs / "traffic_light.il"), *stim, "--json").out
    assert run_mlc("sim", "--target", "vs", "t.mlx", *stim, cwd=tmp_path).code == 0
    r = run_mlc("sim", "--target", "nc5", "t.mlx", *stim, cwd=tmp_path)
    assert r.code == 2 and "t.mlx was built for target vs, not nc5" in r.err


@pytest.mark.parametrize("args,code,text", [
    (["--until", "1s", "--scans", "3"], 2, "not both"),
    (["--scan-time", "fast"], 2, "not a time"),
    (["--watch", "Q9"], 2, "E602"),
])
def test_usage_errors_exit_2(args, code, text):
    r = run_mlc("sim", str(NC5 / "conveyor.il"), *args)
    assert r.code == code and text in r.err


@pytest.mark.parametrize("content,expect", [
    (b"0ms X0=7\n", "s.stim:1:5: error[E601]"),
    (b"\n0ms Q0=1\n", "s.stim:2:5: error[E602]"),
    (b"\x00\x01\x02junk", "E101"),
    (b"\xff\xfe\xfa not utf", "E10"),
    (b"model belt motor=Y0\n", "unknown device model"),
    (b"model conveyor motor=Y0 sensor=X2 travel=1s\n", "needs every"),
    (b"model conveyor motor=Y0 sensor=X2 travel=1s every=1s speed=3\n", "no parameter 'speed'"),
])
def test_bad_stimulus_is_a_diagnostic_not_a_traceback(tmp_path, content, expect):
    stim = tmp_path / "s.stim"
    stim.write_bytes(content)
    r = run_mlc("sim", str(NC5 / "conveyor.il"), "--stimulus", str(stim), cwd=tmp_path)
    assert r.code == 2 and expect in r.err and "Traceback" not in r.err


def test_missing_inputs_exit_2(tmp_path):
    assert run_mlc("sim", str(tmp_path / "nope.il")).code == 2
    r = run_mlc("sim", str(NC5 / "conveyor.il"), "--stimulus", str(tmp_path / "nope.stim"))
    assert r.code == 2 and "E100" in r.err


def test_program_fault_exits_1_naming_step_and_line(tmp_path):
    prog = tmp_path / "loop.il"
    prog.write_text("P0:\nLD X0\nCJ P0\nEND\n")
    stim = tmp_path / "s.stim"
    stim.write_text("0ms X0=1\n")
    r = run_mlc("sim", str(prog), "--stimulus", str(stim), "--watchdog", "1000", "--json")
    assert r.code == 1
    fault = json.loads(r.out)["fault"]
    assert "watchdog" in fault["message"] and fault["line"] in (1, 2, 3)
    assert "error[E604]" in r.err and "step" in r.err


def test_unwritable_vcd_is_e605_and_nothing_partial(tmp_path):
    (tmp_path / "blocker").write_text("a file where the folder would be\n")
    target = tmp_path / "blocker" / "x.vcd"
    r = run_mlc("sim", *CONVEYOR, "--vcd", str(target))
    assert r.code == 2 and "E605" in r.err
    assert not Path(target).exists()
