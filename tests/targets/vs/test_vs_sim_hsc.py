"""Vigor VS software high-speed counters on stimulus pulse trains (2-7, 6-7 FNC 53-56):
the pages' examples, counted analytically (docs/vs.md "High-speed counters")."""

from __future__ import annotations

from mlctool.sim.stimulus.stimulus import parse_stimulus_text
from vskit import VS, run


def test_pulse_train_syntax_errors_are_e601_with_columns():
    cases = {
        "0ms X0 pulses fast until 1s": (1, 15, "frequency"),
        "0ms Y0 pulses 1kHz": (1, 5, "inputs"),
        "0ms X0 pulses 1kHz until": (1, 20, "expected"),
        "0ms X0 pulses 1kHz after 1s": (1, 20, "expected"),
        "1s X0 pulses 1kHz until 500ms": (1, 25, "end after"),
        "#5 X0 pulses 1kHz": (1, 1, "scan number"),
    }
    for text, (line, col, words) in cases.items():
        _, diags = parse_stimulus_text("t.stim", text, VS)
        assert [(d.code, d.span.line, d.span.col) for d in diags] == [("E601", line, col)], text
        assert words in diags[0].message, (text, diags[0].message)
    _, diags = parse_stimulus_text("t.stim", "0ms X0 pulses 2.5kHz for 10ms\n20ms X1 pulses 0Hz", VS)
    assert not diags


def test_dhscs_sets_y0_at_200_counting_up_and_down():
    # 6-7 FNC 53 example: OUT C235 K5000 on M9000, DHSCS K200 C235 Y0 on X20; Y0 On when C235
    # goes 199 -> 200 or 201 -> 200, held On. X0 at 1 kHz: the edge at 0 ms comes before the
    # coil's first scan; edges 1..199 ms leave 199, the one at 200 ms makes 200
    run("LD M9000\nOUT C235 K5000\nLD X20\nDHSCS K200 C235 Y0\n",
        "0ms X20=1\n0ms X0 pulses 1kHz until 500ms\n190ms expect C235:d=190 Y0=0\n"
        "200ms expect C235:d=200 Y0=1\n500ms expect C235:d=499 C235=0\n"
        "550ms Y0=0 M9235=1\n600ms X0 pulses 1kHz for 300ms\n"
        "890ms expect C235:d=208 Y0=0\n900ms expect C235:d=199 Y0=1\n")


def test_dhscr_self_reset_and_counter_contact():
    # 6-7 FNC 54 example: OUT C235 K100, DHSCR K200 C235 C235: contact On at 100, at 200 the
    # counter resets itself (0, contact Off) and counts on; at 30 kHz 300 edges a scan cross
    # 200 within the scan
    run("LD M9000\nOUT C235 K100\nLD M9000\nDHSCR K200 C235 C235\n"
        "LD M9000\nOUT C236 K100\nLD M9000\nDHSCR K200 C236 Y1\n",
        "0ms X0 pulses 1kHz until 1.5s\n0ms X1 pulses 30kHz until 1s\n0ms Y1=1\n"
        "90ms expect C235:d=90 C235=0\n100ms expect C235=1\n190ms expect C235:d=190 C235=1\n"
        "200ms expect C235:d=0 C235=0\n250ms expect C235:d=50\n1.01s expect C235:d=10\n"
        "10ms expect C236:d=300 Y1=0\n1s expect C236:d=29999 C236=1\n")


def test_self_reset_many_cycles_in_one_scan():
    # 100 kHz with a 200 reset point: 1000 edges per 10 ms scan = 5 cycles skipped whole
    run("LD M9000\nOUT C237 K150\nLD M9000\nDHSCR K200 C237 C237\n",
        "0ms X2 pulses 100kHz until 1s\n10ms expect C237:d=0\n15ms expect C237:d=0\n"
        "990ms expect C237:d=0\n2s expect C237:d=199 C237=1\n")


def test_dhsz_zone_and_counter_direction_relay():
    # 6-7 FNC 55: DHSZ K100 K200 C236 M0: M0 below, M1 inside, M2 above (judged at counts)
    run("LD M9000\nOUT C236 K1000\nLD M9000\nDHSZ K100 K200 C236 M0\n",
        "0ms X1 pulses 1kHz until 400ms\n50ms expect M0=1 M1=0 M2=0\n150ms expect M0=0 M1=1\n"
        "250ms expect M1=0 M2=1\n400ms M9236=1\n410ms X1 pulses 1kHz until 600ms\n"
        "600ms expect C236:d=209 M1=0 M2=1\n610ms X1 pulses 1kHz until 620ms\n"
        "620ms expect C236:d=199 M1=1\n")


def test_spd_counts_pulses_per_window():
    # 6-7 FNC 56: SPD X2 K100 D0: D0 pulses in the last 100 ms, D1 so far, D2 ms left
    run("LD X20\nSPD X2 K100 D0\n",
        "0ms X20=1\n0ms X2 pulses 2kHz\n50ms expect D0=0 D1=100 D2=50\n100ms expect D0=200 D1=0 D2=100\n"
        "150ms expect D0=200 D1=100\n200ms X2 pulses 500Hz\n300ms expect D0=50\n"
        "310ms X20=0\n400ms expect D0=50\n")


def test_pulse_train_drives_the_input_level():
    # 50 % duty: at 40 Hz the input is On for 12.5 ms of each 25 ms; scans see it at their start
    run("LD X3\nOUT Y3\n", "0ms X3 pulses 40Hz until 50ms\n0ms expect Y3=1\n10ms expect Y3=1\n"
        "20ms expect Y3=0\n30ms expect Y3=1\n50ms expect Y3=0\n")


def test_the_edge_at_the_enabling_scan_is_not_counted_whatever_the_start():
    """Issue 29: 1 kHz on X2 from 0 ms gave C237 = 249, from 5 ms 250. DECISION (docs/vs.md):
    counting starts with the coil's first execution, after the scan's input refresh, so the
    edge at that scan's instant is before it. The rule is one: a counter enabled at 20 ms by
    X10 misses the 20 ms edge of a train already running, and counts a train from 25 ms whole."""
    prog = "LD M9000\nOUT C237 K100000\nLD X10\nOUT C235 K100000\n"
    run(prog, "0ms X2 pulses 1kHz until 250ms\n300ms expect C237:d=249\n")
    run(prog, "5ms X2 pulses 1kHz until 255ms\n300ms expect C237:d=250\n")
    run(prog, "0ms X0 pulses 1kHz until 250ms\n20ms X10=1\n300ms expect C235:d=229\n")
    run(prog, "20ms X10=1\n25ms X0 pulses 1kHz until 275ms\n300ms expect C235:d=250\n")
