"""`mlc sim --report`: the page for a sample with a stimulus, and the per-scan power trace."""

from __future__ import annotations

import json
import re

from mlctool.ladder.report import PowerProbe
from mlctool.program import Image
from mlctool.sim.run import Simulation
from mlctool.sim.scan import run_scan
from mlctool.sim.stimulus import Stimulus
from tests.ladder.test_ladder_network import NC5, module


def test_report_on_the_conveyor_sample(mlc, tmp_path):
    out = tmp_path / "r.html"
    args = ("sim", "samples/nc5/conveyor.il", "--stimulus", "samples/nc5/conveyor.stim", "--report", str(out))
    r = mlc(*args)
    assert r.code == 0, r.err
    page = out.read_text("utf-8")
    assert page.count('<div class="rung"') == 9
    data = json.loads(re.search(r'<script type="application/json" id="power">(.*?)</script>', page).group(1))
    assert data["scans"] == 1300 and len(data["deltas"]) == 1300 and data["period_us"] == 10_000
    assert '<input id="scan" type="range" min="0" max="1299"' in page
    assert re.search(r">Y0</text>", page) and 'class="bit"' in page and 'class="bus"' in page
    assert not re.search(r'(src|href)="(https?:)?//', page)
    first = page
    assert mlc(*args).code == 0 and out.read_text("utf-8") == first  # deterministic


def scan_states(text: str, inputs: list[str]) -> list[set[int]]:
    """inputs: per scan, X0 X1 X2 X3 as a string of bits."""
    r = module(text)
    assert not r.errors, r.diagnostics
    trace = PowerProbe(10_000)
    sim = Simulation(Image("nc5", r.modules[0].instrs), NC5, Stimulus("<none>", []), [], 10_000, [], False,
                     probe=trace)
    for k, xs in enumerate(inputs):
        sim.m.now_us = k * 10_000
        for n, v in enumerate(xs):
            sim.m.bits["X"][n] = int(v)
        run_scan(sim.prog, sim.m)
    return [trace.on.get(k, set()) for k in range(len(inputs))]


def test_power_trace_marks_conducting_contacts_and_driven_outputs():
    # 0 LD X0, 1 ANI X1, 2 OUT Y0, 3 LDP X2, 4 OUT Y1, 5 LD X3, 6 CJ P1, 7 LD X0, 8 OUT Y2, 9 P1, 10 END
    text = "LD X0\nANI X1\nOUT Y0\nLDP X2\nOUT Y1\nLD X3\nCJ P1\nLD X0\nOUT Y2\nP1\nEND"
    states = scan_states(text, ["1000", "1110", "0010", "1001"])
    assert states[0] == {0, 1, 2, 7, 8}  # X1 Off: ANI conducts; no edge on X2
    assert states[1] == {0, 3, 4, 7, 8}  # X1 On breaks Y0; the X2 edge drives Y1 for one scan
    assert states[2] == {1}  # X0 Off, X1 Off, X2 held: no edge
    assert states[3] == {0, 1, 2, 5, 6}  # CJ taken: the rung at 7-8 is not executed


def test_power_trace_shows_no_driven_output_in_an_off_mc_block():
    """VS 3-6: the output of a rung inside an Off MC block is not lit even when an OR branch's
    contact conducts (the contact itself is lit: it is closed, like a PLC monitor shows it)."""
    from vskit import VS, image_of
    # 0 LD M100, 1 MC N0, 2 LD X0, 3 OR X1, 4 OUT Y0, 5 MCR N0, 6 END
    trace = PowerProbe(10_000)
    sim = Simulation(image_of("LD M100\nMC N0\nLD X0\nOR X1\nOUT Y0\nMCR N0\nEND"), VS,
                     Stimulus("<none>", []), [], 10_000, [], False, probe=trace)
    for k, m100 in enumerate((0, 1)):
        sim.m.now_us = k * 10_000
        sim.m.bits["X"][1] = 1
        sim.m.bits["M"][100] = m100
        run_scan(sim.prog, sim.m)
    assert trace.on.get(0, set()) == {3}  # X1 closed; MC, Y0 not driven
    assert trace.on.get(1, set()) == {0, 1, 3, 4}
