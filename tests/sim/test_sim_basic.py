"""Basic instructions (manual 2.2): contacts, blocks, stack, coils, edges, PLS/PLF, RST."""

from __future__ import annotations

import itertools

import pytest

from simkit import Bench, passed, simulate


def test_contacts_and_blocks_truth_tables():
    # 2.2 ANB figure: (X0+X2)*(X1+X3) -> Y0; ORB figure: (X0*X1)+(X2*X3) -> Y1; INV, LDI/ANI/ORI
    b = Bench("""
LD X0
OR X2
LD X1
OR X3
ANB
OUT Y0
LD X0
AND X1
LD X2
AND X3
ORB
OUT Y1
LDI X0
ANI X1
ORI X2
OUT Y2
LD X0
INV
OUT Y3
END""")
    for x in itertools.product((0, 1), repeat=4):
        for k, v in enumerate(x):
            b.set(f"X{k}", v)
        b.scan()
        x0, x1, x2, x3 = x
        assert b.get("Y0") == int((x0 or x2) and (x1 or x3))
        assert b.get("Y1") == int((x0 and x1) or (x2 and x3))
        assert b.get("Y2") == int((not x0 and not x1) or not x2)
        assert b.get("Y3") == int(not x0)


def test_mps_mrd_mpp_branch_outputs():
    b = Bench("""
LD X0
MPS
AND X1
OUT Y1
MRD
AND X2
OUT Y2
MPP
ANI X3
OUT Y3
END""")
    for x in itertools.product((0, 1), repeat=4):
        for k, v in enumerate(x):
            b.set(f"X{k}", v)
        b.scan()
        assert b.get("Y1") == int(x[0] and x[1])
        assert b.get("Y2") == int(x[0] and x[2])
        assert b.get("Y3") == int(x[0] and not x[3])


def test_set_rst_and_rst_clears_words_timers_counters():
    r = simulate("""
LD X0
SET Y0
MOV K99 D0
MOV K5 V1
TMR T3 K1000
CNT C2 K10
LD X1
RST Y0
RST D0
RST V1
RST T3
RST C2
END""", """
0ms X0=1
50ms X0=0
60ms expect Y0=1 D0=99 V1=5 C2=0 C2:w=1 T3:w=0
100ms X1=1
110ms expect Y0=0 D0=0 V1=0 C2:w=0
""")
    assert passed(r)


def test_double_coil_last_out_wins():
    r = simulate("""
LD X0
OUT Y0
LD X1
OUT Y0
END""", "0ms X0=1 X1=0\n10ms expect Y0=0\n20ms X0=0 X1=1\n30ms expect Y0=1")
    assert passed(r)


@pytest.mark.parametrize("instr,seq,expected", [
    ("LDP", [0, 1, 1, 0, 1], [0, 1, 0, 0, 1]),
    ("LDF", [1, 0, 0, 1, 0], [0, 1, 0, 0, 1]),
])
def test_edge_load_is_on_for_one_scan(instr, seq, expected):
    b = Bench(f"{instr} X0\nOUT Y0\nEND")
    got = []
    for v in seq:
        b.set("X0", v)
        b.scan()
        got.append(b.get("Y0"))
    # LDF: its memory starts Off, so the first scan (X0 already On) is no edge
    assert got == expected


def test_andp_andf_orp_orf_each_keep_their_own_memory():
    b = Bench("""
LD X1
ANDP X0
OUT Y0
LD X1
ANDF X0
OUT Y1
LDI X1
ORP X0
OUT Y2
LDI X1
ORF X0
OUT Y3
END""")
    b.set("X1", 1)
    rows = []
    for v in (0, 1, 1, 0, 0):
        b.set("X0", v)
        b.scan()
        rows.append(tuple(b.get(f"Y{k}") for k in range(4)))
    assert [r[0] for r in rows] == [0, 1, 0, 0, 0]
    assert [r[1] for r in rows] == [0, 0, 0, 1, 0]
    assert [r[2] for r in rows] == [0, 1, 0, 0, 0]
    assert [r[3] for r in rows] == [0, 0, 0, 1, 0]


def test_edge_contact_still_updates_memory_when_rung_already_off():
    # ANDP is evaluated even though X1 is Off, so the later edge is not "remembered" wrongly
    b = Bench("LD X1\nANDP X0\nOUT Y0\nEND")
    b.set("X0", 1)
    b.scan()  # X1 Off: ANDP sees X0 go On here
    b.set("X1", 1)
    b.scan()
    assert b.get("Y0") == 0


def test_edge_on_first_scan_when_contact_already_on():
    b = Bench("LDP X0\nOUT Y0\nEND")
    b.set("X0", 1)
    b.scan()
    assert b.get("Y0") == 1  # documented decision: edge memories start Off


def test_pls_plf_one_scan_pulse():
    # 2.2 PLS/PLF: X0 Off->On gives M0 one scan long; On->Off gives M1 one scan long
    b = Bench("LD X0\nPLS M0\nLD X0\nPLF M1\nEND")
    m0, m1 = [], []
    for v in (0, 1, 1, 1, 0, 0):
        b.set("X0", v)
        b.scan()
        m0.append(b.get("M0"))
        m1.append(b.get("M1"))
    assert m0 == [0, 1, 0, 0, 0, 0]
    assert m1 == [0, 0, 0, 0, 1, 0]


def test_nop_keeps_the_result():
    b = Bench("LD X0\nNOP\nOUT Y0\nEND")
    b.set("X0", 1)
    b.scan()
    assert b.get("Y0") == 1


def test_alt_toggles_every_scan_and_with_ldp_once_per_press():
    # 4.6 ALT example 1 (figure lost: the prose "X0 Off->On" needs LDP; ALT itself is continuous)
    b = Bench("LDP X0\nALT Y0\nLD X1\nALT Y1\nEND")
    b.set("X0", 1)
    b.set("X1", 1)
    seen0, seen1 = [], []
    for _ in range(3):
        b.scan()
        seen0.append(b.get("Y0"))
        seen1.append(b.get("Y1"))
    assert seen0 == [1, 1, 1]
    assert seen1 == [1, 0, 1]
    b.set("X0", 0)
    b.scan()
    b.set("X0", 1)
    b.scan()
    assert b.get("Y0") == 0
