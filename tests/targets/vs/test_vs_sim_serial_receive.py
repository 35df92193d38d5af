"""Vigor VS RS (6-10 FNC 80) reception and the serial stimulus lines (docs/stimulus.md
"Serial ports"): `port CPn ...` settings (7-3-8: start/end characters, time-out) and
`TIME CPn receive ...` bytes; the page's timing diagrams with K5/K10 and STX/ETX."""

from __future__ import annotations

import pytest

from mlctool.sim.stimulus.stimulus import parse_stimulus_text
from vskit import VS, image_of, run, simulate

# the page's diagrams: RS D0 K5 D100 K10 K1 on X20; the program moves a message away and
# resets M9101 with a pulse (the page: do not reset it continuously)
PROGRAM = """
LD X20
RS D0 K5 D100 K10 K1
LDP M9101
BMOV D100 D300 K5
MOV D9101 D310
LDP X21
RST M9101
"""
PORT = "port CP1 start=H02 end=H03 timeout=50ms\n"


def test_sixteen_bit_message_between_start_and_end_characters():
    # 16-bit mode: D100 low, D100 high, D101 low ...; STX and ETX are not stored or counted;
    # 6 bytes at 19200 8N1 take 3.1 ms: the scan at 30 ms takes them
    run(PROGRAM, PORT + "0ms X20=1\n20ms CP1 receive H02 \"ABCD\" H03\n"
                 "20ms expect M9101=0 D9101=0\n"
                 "30ms expect M9101=1 D9101=4 D100:h=H4241 D101:h=H4443 D102=0\n"
                 "40ms expect D300:h=H4241 D301:h=H4443 D310=4\n")


def test_eight_bit_message_ends_at_n_bytes_and_the_rest_is_lost():
    # M9161 On: one byte a word; n = 3 ends the message, "DE" arrive while M9101 is On
    run(PROGRAM.replace("K10 K1", "K3 K1").replace("LD X20\n", "LD M9002\nSET M9161\nLD X20\n"),
        "0ms X20=1\n20ms CP1 receive \"ABCDE\"\n"
        "30ms expect M9101=1 D9101=3 D100=65 D101=66 D102=67 D103=0\n"
        "40ms X21=1\n50ms expect M9101=0 D9101=0\n"
        "60ms CP1 receive \"Z\"\n70ms expect M9101=0 D9101=1 D100=90 D101=66\n")


def test_a_gap_longer_than_the_time_out_ends_the_message_with_m9102():
    # no end character arrives: 50 ms after the last byte M9102 and M9101 turn On (6-10 3);
    # resetting M9101 resets M9102 (seen by the next RS) and reception starts over
    run(PROGRAM, PORT + "0ms X20=1\n20ms CP1 receive H02 \"XY\"\n"
                 "70ms expect M9101=0 M9102=0 D9101=2 D100:h=H5958\n"
                 "80ms expect M9101=1 M9102=1 D9101=2\n"
                 "90ms X21=1\n100ms expect M9101=0 M9102=0 D9101=0\n"
                 "100ms CP1 receive H02 \"Q\" H03\n110ms expect M9101=1 M9102=0 D9101=1 D100=81\n")


def test_bytes_before_the_start_character_are_dropped():
    run(PROGRAM, PORT + "0ms X20=1\n20ms CP1 receive \"zz\" H02 \"OK\" H03\n"
                 "30ms expect M9101=1 D9101=2 D100:h=H4B4F\n")


def test_a_message_split_over_scans_and_the_count_following_it():
    # 9600 baud: 1.04 ms a byte; 20 bytes from 20 ms arrive until 40.8 ms: 9 by 30 ms, and
    # n = 10 ends the message at the 10th byte before the end character comes
    run(PROGRAM, "port CP1 baud=9600 end=H0D\n0ms X20=1\n20ms CP1 receive \"ABCDEFGHIJKLMNOPQRS\" 13\n"
                 "30ms expect M9101=0 D9101=9\n40ms expect M9101=1 D9101=10\n"
                 "40ms expect D104:h=H4A49\n")


def test_nothing_is_received_with_n_zero_or_the_condition_off():
    run(PROGRAM.replace("K10 K1", "K0 K1"), "0ms X20=1\n20ms CP1 receive \"AB\"\n"
                                             "1s expect M9101=0 D9101=0 D100=0\n")
    run(PROGRAM, "20ms CP1 receive \"AB\"\n30ms X20=1\n1s expect M9101=0 D9101=0 D100=0\n")


def test_send_frames_with_the_start_and_end_characters():
    # 16-bit mode, m = K5: STX D0L D0H D1L D1H D2L ETX (the page's diagram), D9102 counts
    # the 5 data bytes only
    il = "LD X20\nRS D0 K5 D100 K10 K1\nLDP X21\nSET M9100\nEND"
    stim = (PORT + "0ms X20=1 D0:h=H3231 D1:h=H3433 D2:h=H3635\n10ms X21=1\n"
            "20ms expect M9100=1 D9102=5\n30ms expect M9100=0 D9102=0\n")
    image = image_of(il)
    sim_run = simulate(image, stim)
    assert not sim_run.failed, sim_run.failed
    from mlctool.sim.hardware import seriallink
    from mlctool.sim.run.run import Simulation
    st, _ = parse_stimulus_text("t.stim", stim, VS)
    sim = Simulation(image, VS, st, [], 10_000, [], False)
    sim.run(3)
    assert seriallink.port(sim.m, "CP1").exchanges[-1].request == b"\x0212345\x03"


@pytest.mark.parametrize("line, col, message", [
    ("20ms CP9 receive H41", 6, "ports are CP1"),
    ("20ms CP1 receive H100", 18, "0-255"),
    ("20ms CP1 receive", 10, "expected `CPn receive"),
    ('20ms CP1 receive "A B"', 18, "no spaces"),
    ("#3 CP1 receive 65", 1, "at a time"),
    ("port CP1 baud=1234", 10, "one of 300"),
    ("port CP1 parity=mark", 10, "none, even or odd"),
    ("port CP1 stop=2", 10, "port settings are"),
    ("port CP1 station=255", 10, "0-254"),
    ("port CP1\nport CP1 end=H0D", 6, "one `port` line per port"),
])
def test_bad_serial_stimulus_lines_are_diagnosed(line, col, message):
    _, diags = parse_stimulus_text("t.stim", line + "\n", VS)
    assert [(d.code, d.span.line, d.span.col) for d in diags] == [("E601", line.count("\n") + 1, col)]
    assert message in diags[0].message


def test_mlc_sim_reports_a_bad_receive_line(tmp_path, mlc):
    (tmp_path / "p.il").write_text("LD X20\nRS D0 K5 D100 K10 K1\nEND\n", encoding="utf-8")
    (tmp_path / "p.stim").write_text("0ms X20=1\n20ms CP1 receive HZZ\n", encoding="utf-8")
    r = mlc("sim", "--target", "vs", str(tmp_path / "p.il"), "--stimulus", str(tmp_path / "p.stim"))
    assert r.code == 2 and "p.stim:2:18: error[E601]" in r.err and "Traceback" not in r.out + r.err
