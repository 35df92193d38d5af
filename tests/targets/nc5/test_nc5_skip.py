"""The virtual NC skips the steps in which only time passes (model.py step(): the inputs are
those of its last full step and no event of its own is due) and catches up in closed form.
Skipping must change nothing: every scenario here runs with skipping and without
(NcModel.SKIP), traced (the model's signals read every scan, so every skipped step is
caught up at once) and untraced (caught up only at the next full step); the MLC program
counts, every scan, each NC -> MLC relay that is On and adds up the NC -> MLC registers, so
a value that differs in any one scan shows in its totals."""

from __future__ import annotations

import pytest
from nc5kit import NC5, outcome

from mlctool.debug.load import load_session
from mlctool.debug.session import BOUNDARY
from mlctool.sim.state import parse_device_name
from mlctool.targets.nc5.nc.model import NcModel

BITS = [*range(31000, 31008), *range(31016, 31025), 31064, 31065, 31066, 31272, 31320, 31336, 31352,
        31464, 31480, 31496, 31465, 31481, 31497, 31466, 31353, 31337, 31704, 31705, 31706]
WORDS = [31024, 31026, 31028, 31036, 31037, 31038, 31039, 31048, 31050, 31052, 49100, 49104, 49106]
WITNESS = "".join(f"LD M{b}\nINC D{500 + i}\n" for i, b in enumerate(BITS)) + \
    "LDI M0\n" + "".join(f"ADD D{w} D{600 + i} D{600 + i}\n" for i, w in enumerate(WORDS))
PANEL = """
LD X2
OUT M21000
LD X3
OUT M21001
LD X4
OUT M21004
LD M31064
OR M31065
OR M31066
AND X7
OUT M21016
LD X10
MOV K40 D21002
LD X11
MOV K0 D21002
LD X12
OUT M21704
"""
SCENARIOS = {
    "machining": (PANEL, "model nc5 program=part.nc spindle_ramp=300ms\n0ms X2=1 X7=1\n20ms X2=0\n"
                         "430ms X10=1\n900ms X10=0 X11=1\n1200ms X11=0\n1500ms X3=1\n1520ms X3=0\n"
                         "2000ms X2=1\n2020ms X2=0\n2500ms X12=1\n3000ms X7=0\n3100ms X7=1\n6000ms X4=1\n"
                         "6100ms X4=0\n6200ms X2=1\n6230ms X2=0\n9000ms expect M31016=0\n",
                  "G90 G01 X10. Y3.3 F600\nG04 P333\nS1500 M03\nG00 Z-7.777\nG91 G01 X-3.1 F77\n"
                  "T4\nM08\nG90 X0 Y0 Z0 F1000\nM30\n"),
    "manual": ("LD X2\nMOV K4 D21000\nLD X3\nMOV K6 D21000\nLD X4\nMOV K7 D21000\nLD X5\nMOV K3 D21000\n"
               "LD X6\nOUT M21384\nLD X7\nOUT M21401\nLD X10\nOUT M21320\nLD X11\nOUT M21007\n"
               "LDI M0\nDMOV K2345 D21014\nMOV K10 D21009\nMOV K1 D21008\n",
               "model nc5 start=-3,2,0 soft1_x=-5:4 hard_y=-1:5 mpg=D100 home_speed=333\n"
               "0ms X4=1\n10ms X10=1\n1000ms X4=0 X10=0 X2=1\n1100ms X6=1\n2500ms X6=0\n2600ms X7=1\n"
               "3000ms X7=0\n3000ms X2=0 X3=1\n3100ms X6=1\n3120ms X6=0\n3500ms X3=0 X5=1\n"
               "3600ms D100=7\n3700ms D100=-20\n3800ms D100=5\n4000ms X5=0 X2=1\n4100ms X7=1\n"
               "6000ms X7=0 X11=1\n6100ms X7=1\n6500ms X7=0\n7000ms expect M31000=0\n"),
    "axes": ("LDI M0\nMOV K4 D21000\nOUT M21256\nOUT M21292\nLD X3\nOUT M21385\nLD X4\nOUT M21432\n"
             "LD X5\nOUT M21448\nLD X6\nOUT M21416\n",
             "model nc5 axes=X,Y,Z,B sync_b=-Y\n0ms X4=1 D21256:f=7.777 D21288:f=333\n20ms X5=1 X3=1\n"
             "900ms X3=0\n2000ms X5=0\n2100ms X6=1 D21288:f=-123\n2200ms X5=1\n2700ms D21288:f=456\n"
             "3000ms X5=0\n3500ms expect M31432=1\n"),
    "spindle": ("LD X3\nOUT M21704\nLD X4\nOUT M21706\nLD X5\nOUT M21710\nDMOV K2400 D21024\n"
                "LD X6\nMOV K37 D21026\n",
                "model nc5 spindle_ramp=700ms orient_at=9000 orient_time=170ms\n0ms X3=1 X5=1\n"
                "1000ms X6=1\n1500ms X3=0 X4=1\n2200ms X4=0 X3=1\n3000ms X5=0\n4000ms expect M31705=1\n"),
}


def _runs(name: str, monkeypatch):
    il, stim, *part = SCENARIOS[name]
    results, full_steps = [], []
    step = NcModel._step

    def counted(self, *args):
        full_steps[-1] += 1
        step(self, *args)
    monkeypatch.setattr(NcModel, "_step", counted)
    for skip, trace in ((False, True), (True, True), (True, False)):
        monkeypatch.setattr(NcModel, "SKIP", skip)
        full_steps.append(0)
        r = outcome(WITNESS + il, stim, part[0] if part else None, trace=trace)
        assert r.fault is None
        results.append(r)
    assert full_steps[2] < full_steps[0] // 2  # (it does skip)
    return results


@pytest.mark.parametrize("name", sorted(SCENARIOS))
def test_skipping_steps_changes_nothing(name, monkeypatch):
    full, skipped, untraced = _runs(name, monkeypatch)
    assert skipped.trace == full.trace
    assert skipped.devices == full.devices == untraced.devices
    assert [o.failures for o in full.expectations] == [o.failures for o in untraced.expectations]
    witness = {k: v for k, v in full.devices.items() if k.startswith("D5") or k.startswith("D6")}
    assert any(witness.values())  # the scenario does something the witness sees


def test_the_debugger_going_back_sees_the_same_nc(tmp_path):
    """A checkpoint keeps the model with the machine; going back and replaying gives the values
    of the run forward, skipped steps and all."""
    (tmp_path / "m.il").write_text("LDI M0\nOUT M21012\nMOV K100 D21002\nLD X2\nOUT M21000\nEND\n", "utf-8")
    (tmp_path / "part.nc").write_text("G01 X10. F600\nG04 P250\nY5.\nM30\n", "utf-8")
    (tmp_path / "m.stim").write_text("model nc5 program=part.nc\n0ms X2=1\nrun 2s\n", "utf-8")
    s = load_session([str(tmp_path / "m.il")], str(tmp_path / "m.stim"), NC5, checkpoint_every=50)
    views = [parse_device_name(n, NC5) for n in ("NC1.X.pos", "NC1.Y.pos", "NC1.state", "M31464")]
    seen = {}
    for k in (37, 120, 163):
        s.goto((k, BOUNDARY))
        seen[k] = [v.read(s.m) for v in views]
    s.goto((170, BOUNDARY))
    for k in (163, 37, 120):
        s.goto((k, BOUNDARY))
        assert [v.read(s.m) for v in views] == seen[k], k
    assert seen[37][0] == 3600 and seen[163][1] == 3700  # X at 600 mm/min; Y after the dwell
