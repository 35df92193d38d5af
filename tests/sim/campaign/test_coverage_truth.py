"""Coverage counts what executed (mlctool/sim/campaign/coverage.py), per target: a coil or application
instruction when its condition is On, a multi-input instruction (FBs HSPSO, FUN147) when any
input is On, an unconditional one (FBs MPARA) in every scan, a P-suffix form (VS MOVP) in the
scans it executed, timers and counters in the scans their condition was On."""

from __future__ import annotations

from pathlib import Path

import pytest

from mlctool.asm import program_from_paths
from mlctool.sim.campaign.coverage import Probe, report
from mlctool.sim.run.run import Simulation, plan_scans
from mlctool.sim.stimulus.stimulus import parse_stimulus_text
from mlctool.targetapi import load_target


def hits(tmp_path: Path, target_name: str, il: str, stim: str) -> dict[str, int]:
    """mnemonic and first operand ("TMR T0") -> hits in one run with a coverage probe."""
    target = load_target(target_name)
    src = tmp_path / "p.il"
    src.write_text(il.strip() + "\n")
    image, diags, _ = program_from_paths([str(src)], target)
    assert image is not None, [d.message for d in diags]
    st, problems = parse_stimulus_text("t.stim", stim, target)
    assert not problems, [d.message for d in problems]
    probe = Probe(len(image.instrs))
    period = st.scan_us or 10_000
    Simulation(image, target, st, [], period, [], trace=False, probe=probe).run(plan_scans(st, period, None, None))
    out: dict[str, int] = {}
    for step in report(image, probe).steps:
        ins = image.instrs[[i.addr for i in image.instrs].index(step["addr"])]
        out.setdefault(" ".join((ins.mnemonic, *ins.texts[:1])), step["hits"])
    return out


# X0 On in scans 0-9 of 30 (10 ms scans); X1 rises three times
STIM = """
scan 10ms
0ms X0=1 X1=1
20ms X1=0
40ms X1=1
60ms X1=0
80ms X1=1
100ms X0=0 X1=0
run 300ms
"""


def test_nc5_timer_and_counter_count_the_scans_their_condition_was_on(tmp_path):
    h = hits(tmp_path, "nc5", "LD X0\nTMR T0 K50\nLD X1\nCNT C0 K3\nEND", STIM)
    assert h["TMR T0"] == 10
    assert h["CNT C0"] == 6  # X1 On in scans 0-1, 4-5, 8-9


def test_vs_out_timer_counter_and_reset(tmp_path):
    h = hits(tmp_path, "vs", "LD X0\nOUT T0 K10\nLD X1\nOUT C0 K3\nLDI X0\nRST C0\nLD X1\nMOVP K1 D0\nEND", STIM)
    assert h["OUT T0"] == 10 and h["OUT C0"] == 6
    assert h["RST C0"] == 20  # X0 Off in scans 10-29
    assert h["MOVP K1"] == 3  # executed on each of the three rising edges, not in every On scan


FBS = """
LD M1924
MPARA K0 R2000
LD X0
LD X1
LD X2
HSPSO K0 R5000 R2100
LD X0
LD X1
LD X2
MHSPO K0 R6000 R2200
END
"""


@pytest.mark.parametrize("stim, hspso", [(STIM, 10), (STIM.replace("X0=1", "X0=0"), 6)],
                         ids=["EN", "PAU only"])
def test_fbs_multi_input_instructions_count_any_input_and_mpara_every_scan(tmp_path, stim, hspso):
    h = hits(tmp_path, "fbs", FBS, stim)
    assert h["MPARA K0"] == 30  # 11.6 FUN141: executed whether EN is 0 or 1 (M1924: first scan only)
    # EN (X0) On in 10 scans; without EN, PAU (X1) On in 6: the last input (ABT, X2) never is
    assert h["HSPSO K0"] == hspso and h["MHSPO K0"] == hspso
