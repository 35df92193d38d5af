"""MLC axes (5.3.9, 6.14): M2x432+ makes the axis the MLC's once it stands still (M3x432+);
position mode moves to D2x256+ (float mm, M2x464+ incremental) at D2x288+ (float mm/min) on
the trigger's rising edge, then M3x448+; speed mode turns at D2x288+ while the trigger is On;
the speed acts at once, the target at the next edge; the program leaves an MLC axis alone."""

from __future__ import annotations

from nc5kit import run


def test_position_mode_absolute_then_incremental():
    run("", "model nc5\n0ms M21432=1 D21256:f=25.5 D21288:f=600\n"
            "20ms expect M31432=1 M31448=0\n20ms M21448=1\n"  # switched; 600 mm/min = 10 um/ms
            # the step of 30 ms sees the trigger and moves the interval since the last (as a jog)
            "1030ms expect NC1.X.pos=10100 M31464=1 M31480=1 M31448=0 NC1.X.speed=600\n"
            "2600ms expect NC1.X.pos=25500 M31448=1 M31464=0\n"
            "2600ms M21448=0 M21464=1 D21256:f=-5.5\n2620ms M21448=1\n"
            "2700ms D21288:f=1200\n"  # the speed acts at once
            "3100ms expect NC1.X.pos=20000 M31448=1 M31496=0\n")


def test_speed_mode_turns_while_triggered_and_stops():
    run("", "model nc5\n0ms M21433=1 M21417=1 D21290:f=-1200\n20ms M21449=1\n"
            "1030ms expect NC1.Y.pos=-20200 M31449=1 M31497=1 NC1.Y.speed=-1200\n"
            "1030ms M21449=0\n1100ms expect NC1.Y.pos=-20200 M31449=0 M31465=0\n")


def test_the_switch_waits_for_the_axis_to_stand_still_and_the_program_leaves_it():
    run("LD X2\nOUT M21000\nLD X3\nOUT M21432\n",
        "model nc5 program=part.nc\n0ms X2=1\n100ms X3=1\n"
        "500ms expect M31432=0 NC1.X.pos=5000\n"  # X still moving for the program
        "1100ms expect M31432=1 NC1.X.pos=10000\n"
        "1100ms X2=0\n1120ms X2=1\n1300ms expect NC1.X.pos=10000 NC1.Y.pos=1800\n",
        "G90 G01 X10. F600\nM00\nX0 Y5.\nM30\n")
