"""Timers (1.6, 2.2 TMR) and counters (1.7, 2.2 CNT/DCNT) on virtual time."""

from __future__ import annotations

from simkit import Bench, passed, simulate


def test_tmr_100ms_example_contact_at_preset():
    # 1.6.1: X0 On -> T0 counts in 100 ms units; T0 = K100 -> contact On; X0 Off -> value 0
    r = simulate("""
LD X0
TMR T0 K100
LD T0
OUT Y0
END""", """
0ms X0=1
9.99s expect T0=0 Y0=0 T0:w=99
10s expect T0=1 Y0=1 T0:w=100
12s expect T0=1 T0:w=100     # stops at the preset
12.5s X0=0
12.5s expect T0=0 T0:w=0 Y0=0
""")
    assert passed(r)


def test_tmr_10ms_base_and_d_preset():
    r = simulate("""
LD X0
TMR T200 D5
END""", """
0ms D5=25 X0=1
240ms expect T200=0 T200:w=24
250ms expect T200=1 T200:w=25
""")
    assert passed(r)


def test_timer_contact_before_tmr_sees_it_one_scan_later():
    # rule of docs/stimulus.md: the contact changes when TMR executes
    r = simulate("""
LD T0
OUT Y0
LD X0
TMR T0 K1
LD T0
OUT Y1
END""", "0ms X0=1\n100ms expect Y1=1 Y0=0\n110ms expect Y0=1")
    assert passed(r)


def test_timer_with_scan_period_not_dividing_base_keeps_remainder():
    # 30 ms scans: 100 ms of timing is complete at the scan starting at 120 ms
    r = simulate("LD X0\nTMR T0 K1\nEND", "scan 30ms\n0ms X0=1\n90ms expect T0=0\n120ms expect T0=1")
    assert passed(r)


def test_tmr_preset_k0_is_on_at_first_execution():
    b = Bench("LD X0\nTMR T0 K0\nEND")
    b.set("X0", 1)
    b.scan()
    assert b.get("T0") == 1


def test_cnt_manual_1_7_1_example():
    # X0 On: RST C0; X1 Off->On: +1; at K5 contact On and the value stays 5 until reset
    b = Bench("""
LD X0
RST C0
LD X1
CNT C0 K5
LD C0
OUT Y0
END""")
    for k in range(7):
        b.set("X1", 1)
        b.scan()
        b.set("X1", 0)
        b.scan()
        assert b.get("C0:w") == min(k + 1, 5)
    assert b.get("C0") == 1 and b.get("Y0") == 1
    b.set("X0", 1)
    b.scan()
    assert b.get("C0:w") == 0 and b.get("C0") == 0


def test_cnt_counts_edges_not_levels():
    b = Bench("LD X1\nCNT C1 K100\nEND")
    b.set("X1", 1)
    b.scan(10)
    assert b.get("C1:w") == 1


def test_cnt_k0_acts_like_k1_and_contact_is_set_at_end_of_scan():
    b = Bench("LD X1\nCNT C3 K0\nLD C3\nOUT Y0\nEND")
    b.set("X1", 1)
    b.scan()
    assert b.get("C3:w") == 1 and b.get("C3") == 1
    assert b.get("Y0") == 0  # the contact acts at the end of the scan (1.7 table)
    b.scan()
    assert b.get("Y0") == 1


def test_dcnt_wraps_and_counts_down_with_its_direction_relay():
    b = Bench("LD X1\nDCNT C64 K-5\nEND")
    b.set("C64:d", 2147483647)
    b.set("X1", 1)
    b.scan()
    assert b.get("C64:d") == -2147483648  # 1.7.1
    b.set("C64:d", 0)
    b.set("M2944", 1)  # C64 counts down while M2944 is On (1.1.2)
    for _ in range(5):
        b.set("X1", 0)
        b.scan()
        b.set("X1", 1)
        b.scan()
    assert b.get("C64:d") == -5 and b.get("C64") == 1
    b.set("X1", 0)
    b.scan()
    b.set("X1", 1)
    b.scan()
    assert b.get("C64:d") == -5  # stops at the preset


def test_counter_preset_from_d_register():
    b = Bench("LD X1\nCNT C5 D10\nEND")
    b.set("D10", 2)
    for _ in range(2):
        b.set("X1", 1)
        b.scan()
        b.set("X1", 0)
        b.scan()
    assert b.get("C5") == 1


def test_zrst_clears_timers_and_counters():
    b = Bench("LD X0\nTMR T1 K1\nLD X1\nCNT C1 K1\nLD X2\nZRST T0 T127\nZRST C0 C63\nEND")
    b.set("X0", 1)
    b.set("X1", 1)
    b.scan(12)
    assert b.get("T1") == 1 and b.get("C1") == 1
    b.set("X0", 0)
    b.set("X2", 1)
    b.scan()
    assert (b.get("T1"), b.get("T1:w"), b.get("C1"), b.get("C1:w")) == (0, 0, 0, 0)


def test_the_running_timers_not_seen_are_found_in_order():
    """scan._running_unseen (end_of_scan's skipped timers) against the plain loop it replaces."""
    import random

    from mlctool.sim.scan import _running_unseen

    rnd = random.Random(7)
    for size in (1, 8, 9, 256, 300):
        for _ in range(50):
            running = bytearray(rnd.getrandbits(1) for _ in range(size))
            seen = bytearray(rnd.getrandbits(1) for _ in range(size))
            assert _running_unseen(running, seen) == [n for n in range(size) if running[n] and not seen[n]]
