"""A stimulus power cycle restarts the NC with the MLC (DECISION in model.py power_cycle: one
controller): AUTO, the program from its first block, nothing homed, the spindle stopped,
magazine 1 reset, the counters from 0; the axes stay where they are."""

from __future__ import annotations

from nc5kit import run

IL = "LD M31065\nOUT M21016\nLD X2\nOUT M21000\nLD X3\nOUT M21704\nLD X4\nMOV K7 D21000\nLDI X4\nMOV K0 D21000\nLD X5\nOUT M21320\nLD X6\nOUT M21064\n"


def test_a_power_cycle_restarts_the_nc_where_the_axes_are():
    run(IL, "model nc5 program=part.nc start=-1,0,0 home_speed=600\n"
            "0ms X4=1 X5=1\n300ms expect M31320=1 NC1.X.pos=0\n300ms X4=0 X5=0\n"
            "400ms X6=1\n420ms X6=0\n430ms expect D31038=2\n"
            "500ms X2=1 X3=1\n520ms X2=0\n990ms expect M31016=1 NC1.state=1 NC1.block=2 NC1.spindle.rpm=1000\n"
            "1000ms power-cycle\n1000ms expect M31016=0 M31000=0 D31038=0\n"  # the memory is cleared at once
            "1010ms expect M31016=0 NC1.state=0 NC1.block=0 M31000=1 M31320=0 D31038=1 D31036=17 "
            "NC1.X.pos=4800 NC1.spindle.rpm=0 D49100:d=0\n"
            "1100ms X2=1\n1120ms X2=0\n1500ms expect M31016=1 NC1.block=2 NC1.X.pos=8600\n",
        "S1000\nG01 X10. F600\nM30\n")
