"""Vigor VS RS (6-10 FNC 80): non-protocol send on port CPn with the per-port flags M9100+
and registers D9100+; m counts bytes in both data modes (the page's timing diagrams).
Reception: tests/targets/vs/test_vs_sim_serial_receive.py."""

from __future__ import annotations

from test_vs_sim_fx import run

# the page's example: RS D0 D200 D100 D201 K1, the send request set by a pulse
PROGRAM = """
LD M9002
MOV K10 D200
MOV K5 D201
LD X20
RS D0 D200 D100 D201 K1
LDP X21
SET M9100
"""


def test_send_request_clears_after_the_transmission_time():
    # 16-bit mode: m = 10 bytes (D0-D4, two a word) at 9600 8N1 (10 bits a byte) take
    # 10.42 ms; the request set after RS at 10 ms is seen by RS at 20 ms; at 30 ms 9 bytes
    # are out: 1 left
    run(PROGRAM, "port CP1 baud=9600\n0ms X20=1\n10ms X21=1\n"
                 "10ms expect M9100=1 D9102=0\n"
                 "20ms expect M9100=1 D9102=10\n"
                 "30ms expect M9100=1 D9102=1\n"
                 "40ms expect M9100=0 D9102=0 M9101=0 D9101=0\n")


def test_eight_bit_mode_counts_bytes_and_nothing_is_received_without_a_peer():
    # M9161 On: one byte a word (D0-D9), 10 bytes at 19200 = 5.21 ms: done by the next scan
    run(PROGRAM.replace("LD M9002\n", "LD M9002\nSET M9161\n"),
        "0ms X20=1\n10ms X21=1\n20ms expect M9100=1 D9102=10\n"
        "30ms expect M9100=0 D9102=0\n500ms expect M9101=0 D9101=0 D100=0\n")


def test_condition_off_abandons_the_send():
    run(PROGRAM, "port CP1 baud=9600\n0ms X20=1\n10ms X21=1\n20ms expect D9102=10\n30ms X20=0\n"
                 "30ms expect M9100=1 D9102=0\n50ms expect M9100=1 D9102=0\n"
                 "60ms X20=1\n60ms expect D9102=10\n80ms expect M9100=0 D9102=0\n")
