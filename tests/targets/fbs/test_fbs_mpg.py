"""FUN148 MPG in `mlc sim --target fbs`: the manual's handwheel example 1 (X32 Ps0, X34-X36
multiplier 1/10/100 in D700, D701 = 1, DD600 = 200 kHz, P4 200 kHz, P8 30 ms), axis sharing
with FUN140, lost pulses, R4020 inhibit. Handwheel: HSC0's current value DR4096 (docs/fbs.md)."""

from __future__ import annotations

from test_fbs_sim import ok, run

PARAMS = """
LD M1924
MOV K1 R2000
MOV K2000 R2001
DMOV K2000 R2002
MOV K3 R2004
DMOV K200000 R2005
DMOV K500 R2007
MOV K1000 R2009
MOV K30 R2011
MOV K256 R2012
MOV K-1 R2019
MOV K-1 R2020
MOV K1 R2023
LD M1924
MPARA K0 R2000
LD M1924
DMOV K200000 D600
MOV K1 D701
"""
HANDWHEEL = PARAMS + """
LD X34
MOV K1 D700
LD X35
MOV K10 D700
LD X36
MOV K100 D700
LD X32
AND M100
MPG K0 K0 D600 D700 R3000
OUT M30
LD M0
LD M10
LD M11
HSPSO K0 R5000 R2100
END
"""
TABLE = {"R5000": "001 SPD 10000\n DRV ADR,+,2000,Ps\n MEND\n"}


def test_manual_example_1_multipliers_and_direction():
    stim = """scan 10ms
0ms     X32=1 M100=1 X34=1
20ms    R4096:d=100                 # 100 handwheel pulses before the 50 ms sample
60ms    expect R4088:d=100          # x1: 100 pulses, output within 10 ms at up to 200 kHz
100ms   expect R4088:d=100 M30=0 M1992=1 R4072:d=0 R3000=100 R3003=0
110ms   X34=0 X35=1 R4096:d=150     # x10: 50 counts -> 500 pulses
200ms   expect R4088:d=600
210ms   R4096:d=140                 # turned back 10 counts: 100 reverse pulses
260ms   expect R4088:d=500 Y1=0 Y0=0
300ms   expect R4088:d=500
310ms   X35=0 X36=1 D701=3 R4096:d=141   # 1 x 100 / 3 = 33, remainder 1 carried
400ms   expect R4088:d=533 R3002=1
410ms   R4096:d=143                 # 2 x 100 + 1 = 201 / 3 = 67
500ms   expect R4088:d=600 R3002=0
510ms   M100=0 R4096:d=200          # EN Off: no sampling
600ms   expect R4088:d=600 M30=0
"""
    assert ok(run(HANDWHEEL, stim, TABLE))


def test_pulses_not_output_by_the_next_sample_are_lost():
    stim = """scan 10ms
0ms     X32=1 M100=1 X36=1
20ms    R4096:d=10 D600:d=1000      # x100 at only 1 kHz:                 # 1000 pulses asked for one 50 ms interval
60ms    expect M30=1 M1992=0 Y0=1 Y1=0   # being output (U/D: Y0 forward), the axis is held
100ms   expect M30=0 M1992=1
"""
    r = run(HANDWHEEL, stim, TABLE)
    assert ok(r)
    pos, lost = r.devices["R4088:d"], r.devices["R3003"]
    assert 0 < pos < 60 and pos + lost == 1000, (pos, lost)


def test_shares_the_axis_with_fun140():
    stim = """scan 10ms
0ms     X32=1 M100=1 X34=1 M0=1     # FUN140 takes Ps0 first: 2000 pulses at 10 kHz
20ms    R4096:d=100
60ms    expect M30=0 M1992=0        # sampled while FUN140 holds the axis: no output
400ms   expect R4088:d=2000 M1992=1 M1996=1
410ms   M0=0 R4096:d=300 D600:d=5000   # handwheel again: 200 pulses at 5 kHz (40 ms)
460ms   M0=1                        # FUN140 EN while FUN148 outputs: it waits ...
470ms   expect M30=1 M1992=0 M1996=1 M20=0
480ms   expect R4088:d=2100..2199 M20=0
800ms   expect R4088:d=4200 M1996=1 R2101=16385   # ... then runs its table: 2000 more
"""
    assert ok(run(HANDWHEEL, stim, TABLE))


def test_r4020_inhibits_one_direction():
    stim = """scan 10ms
0ms     X32=1 M100=1 X34=1 R4020=H5501     # Ps0 forward inhibited
20ms    R4096:d=100
100ms   expect R4088:d=0 M30=0
110ms   R4096:d=40                  # reverse is allowed
200ms   expect R4088:d=-60
210ms   R4020=H0001 R4096:d=50      # high byte not 55H: no inhibit
300ms   expect R4088:d=-50
"""
    assert ok(run(HANDWHEEL, stim, TABLE))
