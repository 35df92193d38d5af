"""NC1.feed is the path speed in force: 0 while the program waits at an M/S/T code or dwells
after its motion ended, not the last block's speed (found by the chapter-6 samples: the mill's
M09 wait showed the rapid speed it had ended with)."""

from __future__ import annotations

from nc5kit import run

START = "LD X2\nOUT M21000\n"


def test_feed_is_zero_while_waiting_at_a_code_after_a_move():
    run(START, "model nc5 program=part.nc\n0ms X2=1\n20ms X2=0\n"
               "500ms expect NC1.feed=600 NC1.state=1\n"
               "1200ms expect NC1.X.pos=10000 NC1.state=4 M31064=1 NC1.feed=0\n",
        "G01 X10. F600\nM08\nM30\n")


def test_feed_is_zero_during_a_dwell():
    run(START, "model nc5 program=part.nc\n0ms X2=1\n20ms X2=0\n"
               "1100ms expect NC1.X.pos=10000 NC1.block=2 NC1.feed=0 M31016=1\n"
               "1700ms expect M31023=1\n",
        "G01 X10. F600\nG04 P500\nM30\n")
