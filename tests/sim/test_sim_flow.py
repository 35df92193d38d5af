"""Program flow (4.1): CJ, CALL/SRET, FEND, FOR/NEXT; faults, watchdog, power cycle."""

from __future__ import annotations

from mlctool.sim.scan import Fault
from simkit import Bench, passed, simulate


def test_cj_example_1_skips_the_middle_part():
    b = Bench("""
LD X0
CJ P1
LD X1
OUT Y1
LD X2
MOV K10 D0
P1:
LD X3
OUT Y3
END""")
    b.set("X1", 1)
    b.set("X2", 1)
    b.set("X3", 1)
    b.set("X0", 1)
    b.scan()
    assert (b.get("Y1"), b.get("D0"), b.get("Y3")) == (0, 0, 1)
    b.set("X0", 0)
    b.scan()
    assert (b.get("Y1"), b.get("D0"), b.get("Y3")) == (1, 10, 1)
    # jumped again: Y1 holds its state although X1 goes Off (4.1 API-00 item 2)
    b.set("X0", 1)
    b.set("X1", 0)
    b.scan()
    assert b.get("Y1") == 1


def test_cj_example_2_timers_keep_timing_counters_hold():
    # 4.1 API-00 example 2: while M0 jumps, a running T0 keeps timing and turns On; C0 holds
    prog = """
LD M0
CJ P1
LD M4
TMR T0 K10
LD M10
CNT C0 K100
LD M11
INC D0
P1:
END"""
    b = Bench(prog)
    b.set("M4", 1)
    b.set("M11", 1)
    b.scan()  # T0 starts; D0 = 1
    b.set("M0", 1)
    b.set("M4", 0)  # the rung goes Off inside the skipped region: T0 does not see it
    for k in range(120):
        b.set("M10", k % 2)
        b.scan()
    assert b.get("T0") == 1 and b.get("T0:w") == 10
    assert b.get("C0:w") == 0 and b.get("D0") == 1
    b.set("M0", 0)
    b.set("M10", 1)
    b.scan()
    assert b.get("C0:w") == 1  # counting resumes after the jump


def test_cj_with_index_modified_pointer():
    b = Bench("LD X0\nCJ P1V0\nLD X0\nMOV K1 D0\nP1:\nLD X0\nMOV K2 D1\nP2:\nLD X0\nMOV K3 D2\nEND")
    b.set("X0", 1)
    b.set("V0", 1)  # P1 + 1 = P2
    b.scan()
    assert (b.get("D0"), b.get("D1"), b.get("D2")) == (0, 0, 3)


def test_call_sret_and_nesting_example_2():
    # 4.1 API-02 example 2: X10 edge -> CALL P10, X11..X14 nest P11..P14; each SRET returns
    lines = ["LDP X10", "CALL P10", "LD X0", "OUT Y0", "FEND"]
    for p in range(10, 15):
        lines += [f"P{p}:", "LD X0", f"INC D{p}"]
        if p < 14:
            lines += [f"LD X{p + 1}", f"CALL P{p + 1}"]
        lines += ["SRET"]
    lines += ["END"]
    b = Bench("\n".join(lines))
    for x in (0, 10, 11, 12, 13, 14):
        b.set(f"X{x}", 1)
    b.scan()
    assert [b.get(f"D{p}") for p in range(10, 15)] == [1] * 5
    assert b.get("Y0") == 1
    b.scan()  # no edge on X10: nothing called
    assert b.get("D10") == 1


def test_sixth_call_level_is_not_executed_and_raises_an_alarm():
    lines = ["LD X0", "CALL P1", "FEND"]
    for p in range(1, 7):
        lines += [f"P{p}:", "LD X0", f"MOV K1 D{p}"]
        if p < 6:  # the last CALL indexed (V0 = 0): the checker's E307 follows written numbers only
            lines += ["LD X0", f"CALL P{p + 1}" + ("V0" if p == 5 else "")]
        lines += ["SRET"]
    r = simulate("\n".join(lines + ["END"]), "0ms X0=1\n0ms expect D5=1 D6=0\n0ms expect alarm CALL_NESTING")
    assert passed(r)
    assert [a.name for a in r.alarms] == ["CALL_NESTING"]


def test_unexpected_alarm_fails_the_run():
    r = simulate("LD X0\nDIV K10 D0 D2\nEND", "0ms X0=1 D2=7\n0ms expect D2=7")
    assert not r.failed and r.alarms[0].name == "MLC_ARITH_ERROR" and not r.ok


def test_for_next_example_1_runs_inner_body_12_times():
    b = Bench("""
FOR K3
LD X0
INC D0
FOR K4
LD X0
INC D1
NEXT
NEXT
END""")
    b.set("X0", 1)
    b.scan()
    assert (b.get("D0"), b.get("D1")) == (3, 12)


def test_for_count_below_one_runs_once_and_d_operand():
    b = Bench("FOR D5\nLD X0\nINC D0\nNEXT\nEND")
    b.set("X0", 1)
    b.set("D5", -3)
    b.scan()
    assert b.get("D0") == 1
    b.set("D5", 7)
    b.scan()
    assert b.get("D0") == 8


def test_for_example_3_cj_skips_the_innermost_loop():
    b = Bench("""
FOR K2
LD X0
INC D0
LD X1
CJ P0
FOR K3
LD X0
INC D1
NEXT
P0:
NEXT
END""")
    b.set("X0", 1)
    b.set("X1", 1)
    b.scan()
    assert (b.get("D0"), b.get("D1")) == (2, 0)
    b.set("X1", 0)
    b.scan()
    assert (b.get("D0"), b.get("D1")) == (4, 6)


def test_runaway_loop_stops_with_watchdog_fault_naming_the_line():
    r = simulate("P0:\nLD X0\nCJ P0\nEND", "0ms X0=1\n10ms expect Y0=0")
    assert r.fault is not None and "watchdog" in r.fault.message
    assert r.fault.line in (1, 2, 3) and r.fault.file.endswith("t.il")
    assert r.scans == 1 and not r.ok


def test_index_out_of_range_is_a_fatal_fault():
    b = Bench("LD X0\nMOV K1 D65535V0\nEND")
    b.set("X0", 1)
    b.set("V0", 1)
    try:
        b.scan()
    except Fault as f:
        assert "D65536" in f.message and f.step.ins.line == 2
    else:
        raise AssertionError("no fault")


def test_index_modification_manual_1_8_2_example():
    # V0 = 8, Z0 = 14: D5V0 = D13 is moved to D5Z0 = D19; and 3.4: K20V0 = K28
    b = Bench("""
LD X0
MOV K8 V0
MOV K14 Z0
MOV D5V0 D5Z0
MOV K20V0 D24
END""")
    b.set("D13", 1234)
    b.set("X0", 1)
    b.scan()
    assert (b.get("D19"), b.get("D24")) == (1234, 28)


def test_power_cycle_keeps_latched_areas_only():
    r = simulate("""
LD X0
MOV K7 D60000
MOV K8 D0
SET M60000
SET M0
SET Y0
END""", """
0ms X0=1
10ms X0=0
20ms power-cycle
20ms expect D60000=7 M60000=1 D0=0 M0=0 Y0=0 X0=0
""")
    assert passed(r)


def test_fend_inside_a_subroutine_is_a_fault():
    r = simulate("LD X0\nCALL P1\nFEND\nP1:\nFEND\nSRET\nEND", "0ms X0=1")
    assert r.fault is not None and "subroutine" in r.fault.message
