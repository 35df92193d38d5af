"""mlctool/commission/realtime.py: the live run's alarm memory (the servers: the other files)."""

from __future__ import annotations

import simkit
from mlctool.commission.realtime import LiveRun
from mlctool.sim.run.run import Simulation
from mlctool.sim.stimulus.stimulus import parse_stimulus_text
from mlctool.targetapi import load_target


def test_a_continuous_alarm_does_not_grow_the_machine_and_is_reported_once():
    """An operation error every scan appended one alarm a scan to the machine for as long as
    mlc run ran (no end trims it, as a batch run's end does): a live run keeps one per name,
    enough for `expect alarm`, and reports the first."""
    target = load_target("vs")
    image = simkit.image_of("LD M9000\nDIV K1 D1 D0\nEND", target=target)
    st, diags = parse_stimulus_text("t.stim", "scan 1ms\n400ms expect alarm MLC_ARITH_ERROR\n", target)
    assert not diags
    sim = Simulation(image, target, st, [], 1000, [], False)
    live = LiveRun(sim, speed=1000.0)
    stats = live.run(500)
    assert stats.scans == 500 and live.fault is None
    assert len(sim.m.alarms) == 1 and not sim.m.warnings
    [alarm] = live.reports.alarms()
    assert (alarm.name, alarm.scan) == ("MLC_ARITH_ERROR", 0)
    assert [(o.scan, o.failures) for o in live.outcomes] == [(400, [])]
