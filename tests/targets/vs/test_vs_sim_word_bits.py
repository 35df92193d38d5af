"""Vigor VS bit-of-word operands D.b / R.b (3-1, 5-1) at run time: contacts (LD/AND/OR and
their edge forms), OUT, SET and RST touch one bit of the word and leave the others."""

from __future__ import annotations

from test_vs_sim_fx import run


def test_out_writes_one_bit_and_keeps_the_rest():
    il = """
LD M9002
MOV H00F0 D0
LD X0
OUT D0.5
OUT D0.F
LD D0.F
OUT Y0
"""
    # bit 5 is On in 00F0H: OUT with X0 Off clears only it; On sets bits 5 and 15 (sign)
    run(il, "0ms expect D0=H00D0 Y0=0\n10ms X0=1\n10ms expect D0=-32528 Y0=1\n"
            "20ms X0=0\n20ms expect D0=H00D0 Y0=0\n")


def test_set_and_rst_change_only_their_bit():
    il = """
LD M9002
MOV K-1 R5
LD X1
SET D1.0
LD X2
RST R5.3
LD R5.3
OUT Y1
"""
    run(il, "0ms expect R5=-1 Y1=1 D1=0\n10ms X1=1 X2=1\n10ms expect D1=1 R5=-9 Y1=0\n"
            "20ms X1=0 X2=0\n20ms expect D1=1 R5=-9\n")


def test_edge_and_series_contacts_read_the_bit():
    il = """
LD M9000
MOV D10 D2
LDP D2.2
INC D20
LD D2.2
ANI D2.3
OUT Y2
LDF D2.2
INC D21
"""
    run(il, "0ms D10=4\n0ms expect D20=1 Y2=1 D21=0\n10ms expect D20=1\n"
            "20ms D10=12\n20ms expect Y2=0 D20=1\n30ms D10=0\n30ms expect D21=1 D20=1\n")
