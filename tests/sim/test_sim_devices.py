"""Device models: the conveyor example on the scan loop's virtual clock."""

from __future__ import annotations

from mlctool.devices.base import ModelIO
from mlctool.devices.registry import MODELS
from mlctool.sim.state import Machine
from simkit import NC5, passed, simulate


def test_conveyor_moves_parts_only_while_the_motor_runs():
    model = MODELS["conveyor"]({"motor": "Y0", "sensor": "X0", "travel": "100ms",
                                "every": "1s", "window": "20ms", "count": "D5"}, NC5)
    m = Machine(NC5, 0)
    io = ModelIO(m)
    seen = []
    for k in range(30):
        m.bits["Y"][0] = 1 if k >= 5 else 0  # as if the scan at 40 ms switched the motor on
        model.step(io, k * 10_000, 10_000)
        seen.append(m.bits["X"][0])
    # a model sees the outputs of the previous scan, in effect since that scan (40 ms): the
    # part loaded at 0 ms has 100 ms of travel at 140 ms and covers the sensor until 160 ms
    assert [k for k, v in enumerate(seen) if v] == [14, 15]
    assert m.words["D"][5] == 1


def test_conveyor_attached_from_a_stimulus_file_drives_the_program():
    r = simulate("LD X0\nCNT C0 K10\nLDI M9\nOUT Y0\nEND", """
model conveyor motor=Y0 sensor=X0 travel=200ms every=500ms window=50ms
0ms     expect X0=0
200ms   expect X0=1 C0:w=1
250ms   expect X0=0
2.2s    expect C0:w=5
""")
    assert passed(r)
    assert "X0" in r.devices and "Y0" in r.devices
