"""The virtual NC's modes and part-program run (manual 5.3.1, 5.3.2, 6.1, 6.2, 5.3.15):
mode feedback, cycle start, feed hold, single block, optional stop, block skip, dry run,
overrides, M02/M30, reset, emergency stop, part counter. Timings follow from the program:
X10 at F600 is 1 s."""

from __future__ import annotations

from nc5kit import run

START = """
LD X2
OUT M21000
LD X3
OUT M21001
LD X4
OUT M21004
LD X5
OUT M21013
"""
LINE = "G90 G01 X10. F600\nM30\n"


def test_mode_feedback_follows_4ms_after_the_register():
    """6.1: "NC 系統約 4 ms 內會發出對應的【模式回授】"; DECISION (notes #1): M3x000-M3x007."""
    run("", "scan 1ms\nmodel nc5\n0ms expect M31000=1 NC1.mode=0\n10ms D21000=4\n"
            "13ms expect M31004=0 M31000=1\n14ms expect M31004=1 M31000=0 NC1.mode=4 M22292=0\n"
            "20ms D21000=9\n40ms expect M31004=1 NC1.mode=4\n")  # 9: no mode, nothing changes


def test_cycle_start_runs_the_program_to_m30():
    r = run(START, "model nc5 program=part.nc\n0ms X2=1\n20ms X2=0\n"
                   "500ms expect M31016=1 NC1.X.pos=5000 NC1.state=1 NC1.block=1 NC1.feed=600 M31464=1 M31480=1\n"
                   "1010ms expect M31016=0 M31023=1 M31021=1 M31022=0 NC1.X.pos=10000 NC1.state=6 "
                   "D49100:d=1 M31464=0\n", LINE)
    assert r.devices["NC1.X.pos"] == 10000


def test_cycle_start_outside_auto_or_mdi_does_nothing():
    run(START, "model nc5 program=part.nc\n0ms D21000=4\n50ms X2=1\n100ms expect M31016=0 NC1.X.pos=0\n"
               "100ms D21000=2 X2=0\n150ms X2=1\n500ms expect M31016=1\n", LINE)  # MDI runs it (6.2)


def test_feed_hold_keeps_the_position_and_cycle_start_resumes():
    run(START, "model nc5 program=part.nc\n0ms X2=1\n20ms X2=0\n300ms X3=1\n320ms X3=0\n"
               "310ms expect M31017=1 M31016=1 NC1.state=2 NC1.X.pos=3000\n"
               "800ms expect NC1.X.pos=3000 M31017=1\n800ms X2=1\n"  # held: nothing moves
               # the held time is not travelled: 7 mm to go at 10 um/ms from 800 ms
               "1000ms expect NC1.X.pos=5000\n1490ms expect NC1.X.pos=9900\n"
               "1500ms expect NC1.X.pos=10000 M31017=0 M31023=1\n", LINE)


def test_overrides_change_the_speed_at_once():
    """6.2: D2x002 is F's percentage, 0-150, and acts at once; 6.6: D2x004 on G00."""
    run(START + "LD X6\nMOV K50 D21002\nLD X7\nMOV K200 D21002\n",
        "model nc5 program=part.nc\n0ms X2=1 X6=1\n20ms X2=0\n500ms expect NC1.X.pos=2500 NC1.feed=300\n"
        "500ms X6=0 X7=1\n700ms expect NC1.X.pos=5500 NC1.feed=900\n", LINE)  # 200 % -> 150 %
    run(START + "LD X6\nMOV K25 D21004\n", "model nc5 program=part.nc rapid=6000\n0ms X2=1 X6=1\n"
        "20ms X2=0\n1000ms expect NC1.X.pos=25000 NC1.feed=1500\n", "G00 X100.\n")


def test_single_block_stops_after_each_block():
    part = "G01 X1. F600\nX2.\nM30\n"
    run(START + "LD X6\nOUT M21008\n",
        "model nc5 program=part.nc\n0ms X2=1 X6=1\n20ms X2=0\n"
        "200ms expect NC1.X.pos=1000 M31024=1 M31016=0 NC1.state=3 NC1.block=1\n"
        "200ms X2=1\n220ms X2=0\n400ms expect NC1.X.pos=2000 M31024=1\n400ms X6=0 X2=1\n"
        "500ms expect M31024=0 M31023=1\n", part)


def test_optional_stop_block_skip_and_m00():
    part = "M01\n/G01 X5. F600\nG01 Y1. F600\nM00\nY2.\nM02\n"
    il = START + "LD X6\nOUT M21009\nLD X7\nOUT M21010\n"
    # M01 passes without M2x009; '/' runs without M2x010; M00 stops (DECISION notes #33: M3x016
    # and M3x017 Off)
    run(il, "model nc5 program=part.nc\n0ms X2=1\n20ms X2=0\n"
            "1000ms expect NC1.X.pos=5000\n1200ms expect NC1.Y.pos=1000 NC1.state=5 M31016=0 M31017=0\n"
            "1300ms X2=1\n1500ms expect NC1.Y.pos=2000 M31022=1 M31023=0 M31021=1 NC1.state=6\n", part)
    run(il, "model nc5 program=part.nc\n0ms X2=1 X6=1 X7=1\n20ms X2=0\n"
            "100ms expect NC1.state=5 NC1.block=1\n100ms X2=1\n"
            "300ms expect NC1.X.pos=0 NC1.Y.pos=1000\n", part)


def test_dry_run_takes_d2x006_as_the_feed():
    """5.2.2 D2x006: "此特 D 若設為 50，則表示為 F50 (mm/min)"."""
    run(START + "LD X6\nOUT M21005\nMOV K1200 D21006\n",
        "model nc5 program=part.nc\n0ms X2=1 X6=1\n20ms X2=0\n500ms expect NC1.X.pos=10000\n", LINE)


def test_reset_stops_and_rewinds_and_says_done():
    run(START, "model nc5 program=part.nc\n0ms X2=1\n20ms X2=0\n300ms X4=1\n"
               "300ms expect M31019=0\n310ms expect M31016=0 NC1.state=0 M31019=0\n320ms expect M31019=1\n"
               "400ms X4=0\n420ms expect M31019=0\n420ms X2=1\n"
               "1000ms expect NC1.X.pos=8800\n1200ms expect NC1.X.pos=10000\n", LINE)  # from the top again


def test_emergency_stop_stops_everything():
    run(START, "model nc5 program=part.nc\n0ms X2=1\n20ms X2=0\n300ms X5=1\n"
               "310ms expect M31018=1 M31016=0 M31272=0\n600ms expect NC1.X.pos=3000\n"
               "600ms X5=0\n610ms expect M31018=0 M31272=1\n", LINE)


def test_a_mode_change_ends_running_and_pauses():
    """6.2 (e): switching the mode while the program runs drops M3x016."""
    run(START, "model nc5 program=part.nc\n0ms X2=1\n20ms X2=0\n300ms D21000=4\n"
               "320ms expect M31016=0 M31017=1 NC1.state=2 NC1.X.pos=3000\n320ms D21000=0\n400ms X2=1\n"
               "600ms expect NC1.X.pos=5000\n1200ms expect NC1.X.pos=10000\n", LINE)  # (the held time not travelled)


def test_a_servo_off_axis_holds_the_block():
    run(START + "LD X6\nOUT M21272\n",
        "model nc5 program=part.nc\n0ms X2=1 X6=1\n20ms X2=0\n500ms expect NC1.X.pos=0 M31272=0 M31016=1\n"
        "500ms X6=0\n1000ms expect NC1.X.pos=5000\n", LINE)


def test_machining_times_and_counter_accumulate():
    run(START, "model nc5 program=part.nc\n0ms X2=1\n20ms X2=0\n1100ms X2=1\n1200ms X2=0\n"
               "2200ms expect D49100:d=2 D49104:d=2 D49106:d=1 NC1.X.pos=20000\n",
        "G91 G01 X10. F600\nM30\n")  # 5.3.15: a part at each M30, times in s
