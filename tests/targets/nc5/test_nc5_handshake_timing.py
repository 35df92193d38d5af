"""The time the NC waits at an M/S/T code goes to waiting: the next block moves from the step
that sees M2x016 On, not from the step the code was raised (a bug of the first model gave the
waited interval to the next block's motion)."""

from __future__ import annotations

from nc5kit import run


def test_the_block_after_a_waited_code_moves_from_the_finish():
    # M08 raised at the step of 10 ms; the MLC answers in the scan of 200 ms, the NC sees it at
    # 210 ms; X10 at F600 is 10 um/ms: 90 ms later 0.9 mm
    run("LDI M0\nOUT M21000\nLD M31064\nAND X1\nOUT M21016\n",
        "model nc5 program=part.nc\n200ms X1=1\n"
        "300ms expect NC1.X.pos=900 NC1.block=2\n", "M08\nG01 X10. F600\nM30\n")
