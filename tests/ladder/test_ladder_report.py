"""`mlc sim --report` and `mlc test`'s failure page: every expectation with its result, the
page opening at the first failing one and marking it on the waveforms and the ladder, time
in seconds; and the lighting rule (ladder/lighting.py) shared with the live monitor."""

from __future__ import annotations

import json
import re

from mlctool.check import check_texts
from mlctool.debug.load import load_session
from mlctool.debug.web import Monitor
from mlctool.ladder.report import ScanLamps, _ticks, default_waves
from mlctool.program import Image
from mlctool.sim.run.run import Simulation
from mlctool.sim.stimulus.stimulus import load_stimulus, parse_stimulus_text
from mlctool.syntax.source import SourceText
from mlctool.targetapi import load_target
from tests.ladder.test_ladder_network import NC5

VS = load_target("vs")


def page_data(page: str) -> dict:
    return json.loads(re.search(r'<script type="application/json" id="power">(.*?)</script>', page).group(1))


def test_report_on_the_conveyor_sample(mlc, tmp_path):
    out = tmp_path / "r.html"
    args = ("sim", "samples/nc5/conveyor.il", "--stimulus", "samples/nc5/conveyor.stim", "--report", str(out))
    r = mlc(*args)
    assert r.code == 0, r.err
    page = out.read_text("utf-8")
    assert page.count('<div class="rung"') == 9
    data = page_data(page)
    assert data["scans"] == 1300 and len(data["deltas"]) == 1300 and data["period_us"] == 10_000
    assert data["start"] == 1299 and data["failing"] == []  # all held: opens at the last scan
    assert '<input id="scan" type="range" min="0" max="1299" value="1299"' in page
    # every check of the 7 expect lines is a row (2 + 5 + 2 + 2 + 1 + 5 + 2), all held
    assert page.count('<tr class="pass"') == 19 and '<tr class="fail"' not in page
    assert re.search(r'<tr class="pass" data-scan="200"><td>10</td><td>2 s</td><td>200</td><td>C0:w</td>'
                     r'<td>1</td><td>1</td><td>held', page)
    assert re.search(r">Y0</text>", page) and 'class="bit"' in page and 'class="bus"' in page
    assert ">0 s</text>" in page and ">12 s</text>" in page  # the time axis is in seconds
    assert not re.search(r'(src|href)="(https?:)?//', page)
    first = page
    assert mlc(*args).code == 0 and out.read_text("utf-8") == first  # deterministic


def test_a_failing_report_opens_at_and_marks_the_first_failure(mlc, tmp_path):
    stim = tmp_path / "bad.stim"
    text = open("samples/nc5/conveyor.stim", encoding="utf-8").read()
    stim.write_text(text.replace("3s      expect Y0=1 M1=0", "3s      expect Y0=0 M1=0")
                    .replace("7s      expect C0:w=2", "7s      expect C0:w=5"))
    out = tmp_path / "r.html"
    r = mlc("sim", "samples/nc5/conveyor.il", "--stimulus", str(stim), "--report", str(out))
    assert r.code == 1
    page = out.read_text("utf-8")
    data = page_data(page)
    assert data["start"] == 300  # the first failing expectation's scan
    assert '<input id="scan" type="range" min="0" max="1299" value="300"' in page
    assert re.search(r'<tr class="fail" data-scan="300" id="first-failure"><td>11</td><td>3 s</td><td>300</td>'
                     r'<td>Y0</td><td>0</td><td>1</td><td>FAILED<div class="why">last written by '
                     r'samples/nc5/conveyor.il:38: OUT MOTOR', page)
    assert page.count('<tr class="fail"') == 2 and page.count('<tr class="pass"') == 17
    assert re.search(r'id="failure"><b>First failure</b>: line 11, at 3 s \(scan 300\): Y0 expected 0, actual 1', page)
    assert '<a href="#f0-s23">the rung that writes Y0</a>' in page  # LD RUNNING / ANI BUSY / OUT MOTOR
    # the failing devices' waves first, each failure ringed at its scan
    names = re.findall(r'<text x="142" y="\d+" text-anchor="end">([^<.]+)</text>', page)
    assert names[:2] == ["Y0", "C0:w"]
    assert page.count('<g class="failmark">') == 2 and "line 13: C0:w expected 5, actual 2" in page
    # marked on the ladder: the elements naming Y0 (OUT MOTOR) and C0 (ANI PARTS, CNT PARTS,
    # LD PARTS, RST PARTS, MOV C0 D0)
    assert data["failing"] == [3, 12, 13, 16, 19, 21]


def test_default_waves_are_the_scenario_and_the_axis_not_constant_registers():
    """FBs: the axis registers (position, frequency, ...) and what the stimulus names, not
    the 32 parameter registers the program only loads once, nor a :d view and its halves."""
    fbs = load_target("fbs")
    r = module_for(fbs, open("samples/fbs/home_and_run.il", encoding="utf-8").read(), "home_and_run.il")
    st, _ = load_stimulus("samples/fbs/home_and_run.stim", fbs)
    sim = Simulation(Image("fbs", r.modules[0].instrs), fbs, st, [], 10_000, [], True)
    result = sim.run(80)
    names = [v.name for v in default_waves(sim, result, [], 80)]
    assert names[:4] == ["X10", "M1992", "Y0", "Y1"]  # the stimulus's devices, in its order
    assert "R4088:d" in names and "R4080:d" in names  # axis 0's position and frequency
    assert len(names) <= 24 and len(set(names)) == len(names)
    assert "R4088" not in names and "R4089" not in names  # no halves of a :d view shown
    assert not [n for n in names if n.startswith("R20")]  # the constant parameter block


def module_for(target, text: str, path: str):
    r = check_texts([SourceText(path, text)], target)
    assert not r.errors, r.diagnostics
    return r


def test_ticks_are_round_seconds():
    assert _ticks(13.0) == [0, 2, 4, 6, 8, 10, 12]
    assert _ticks(0.08) == [0, 0.01, 0.02, 0.03, 0.04, 0.05, 0.06, 0.07, 0.08]
    assert _ticks(8.5) == [0, 1, 2, 3, 4, 5, 6, 7, 8]


# ------------------------------------------------------------------ the lighting rule

def lit_by_scan(text: str, target, stim: str, scans: int) -> list[set[int]]:
    r = module_for(target, text, "t.il")
    st, diags = parse_stimulus_text("t.stim", stim, target)
    assert not diags, diags
    sim = Simulation(Image(target.name, r.modules[0].instrs), target, st, [], 10_000, [], False)
    lamps = ScanLamps(sim, {"t.il": text.splitlines()})
    sim.run(scans)
    return [set(x) for x in lamps.on]


def test_contacts_light_by_their_condition_coils_by_their_device():
    # 0 LD X0, 1 ANI X1, 2 OUT Y0, 3 LDP X2, 4 OUT Y1, 5 LD> D0 K1, 6 RST Y0 (a coil), 7 END
    text = "LD X0\nANI X1\nOUT Y0\nLDP X2\nSET Y1\nLD> D0 K1\nRST Y0\nEND\n"
    states = lit_by_scan(text, NC5, "0ms X0=1 X2=1\n10ms X1=1\n20ms D0=5 X1=0\n", 3)
    # scan 0: X0 On, X1 Off (ANI lit), Y0 On (both its coils lit: OUT and RST show Y0);
    # LDP X2 lit while X2 is On, SET Y1 lit as Y1 is On
    assert states[0] == {0, 1, 2, 3, 4, 6}
    assert states[1] == {0, 3, 4}  # X1 On: ANI open, Y0 Off
    assert states[2] == {0, 1, 3, 4, 5}  # D0 > 1: the comparison holds; RST Y0 left Y0 Off


def test_coils_of_an_inactive_step_are_not_lit_though_their_device_is_on():
    """VS step ladder: Y0 driven in S20 and in S21; while S21 is active, S20's OUT Y0 is not
    lit (the issue's smaller cut), S21's is; the state boxes light by their step."""
    # 0 LD X0, 1 SET S20, 2 STL S20, 3 OUT Y0, 4 LD X1, 5 SET S21, 6 STL S21, 7 OUT Y0, 8 RET, 9 END
    text = "LD X0\nSET S20\nSTL S20\nOUT Y0\nLD X1\nSET S21\nSTL S21\nOUT Y0\nRET\nEND\n"
    states = lit_by_scan(text, VS, "0ms X0=1\n10ms X0=0\n20ms X1=1\n30ms X1=0\n", 5)
    assert {2, 3} <= states[0] and 7 not in states[0]  # S20 active: its box and coil
    assert {6, 7} <= states[3] and not {2, 3} & states[3]  # S21 active, Y0 On: S20's coil dark


def test_the_monitor_and_the_report_light_the_same_elements(tmp_path):
    """One rule for both: at every scan boundary the live monitor's `on` is the report's
    sample at the end of the scan before."""
    text = "LD X0\nSET S20\nSTL S20\nOUT Y0\nLDP X1\nSET S21\nSTL S21\nOUT Y0\nLD= D0 K2\nOUT Y2\nRET\n" \
           "LD X2\nOR Y3\nANI X3\nOUT Y3\nEND\n"
    stim = "0ms X0=1 X2=1\n10ms X0=0\n20ms X1=1 D0=2\n40ms X3=1 X1=0\n"
    (tmp_path / "p.il").write_text(text)
    (tmp_path / "p.stim").write_text(stim + "run 60ms\n")
    report = lit_by_scan(text, VS, stim, 6)
    session = load_session([str(tmp_path / "p.il")], str(tmp_path / "p.stim"), VS)
    monitor = Monitor(session)
    for k in range(6):
        session.step_scan()
        assert set(monitor.state()["on"]) == report[k], k
    assert report[0] != report[3]  # the run does change what is lit
