"""The virtual NC's axes (5.3.3-5.3.6, 6.3-6.7, 6.9): jog, rapid, incremental jog, handwheel,
homing and its three flags, axis lock, soft limits and their release, hardware limits."""

from __future__ import annotations

from nc5kit import run

JOG = "LD X3\nOUT M21384\nLD X4\nOUT M21400\nLD X5\nOUT M21352\n"


def test_jog_only_in_jog_mode_at_d2x006_percent():
    """6.4: jog +/- while the mode is JOG; DECISION (notes #9): D2x006 is a percentage (0-100)
    of N2.030 (jog_max) in JOG."""
    run(JOG, "model nc5 jog_max=600\n0ms X3=1\n500ms expect NC1.X.pos=0 M31464=0\n"
             "500ms D21000=4\n1000ms expect NC1.X.pos=2500 M31464=1 M31480=1 M31496=0 NC1.X.speed=300\n"
             "1000ms X3=0 X4=1\n1200ms expect NC1.X.pos=1500 M31496=1 NC1.X.speed=-300\n"
             "1200ms X5=1\n1400ms expect NC1.X.pos=1500 M31464=0\n")  # locked (6.4)
    run(JOG, "model nc5 jog_max=1000\n0ms D21000=4 X3=1\n3000ms expect NC1.X.pos=25000\n")  # 8.33 um/step


def test_rapid_mode_moves_at_the_rapid_override():
    run(JOG, "model nc5 rapid=6000\n0ms D21000=5 X3=1\n1000ms expect NC1.X.pos=100000\n")


def test_incremental_jog_moves_d2x014_once_per_press():
    """6.5: each press moves D2x014 x 0.001 mm (N1.001), 32-bit."""
    run(JOG + "LDI M0\nDMOV K70000 D21014\n",
        "model nc5 jog_max=4200\n0ms D21000=6\n20ms X3=1\n3000ms expect NC1.X.pos=70000 M31464=0\n"
        "3000ms X3=0 X4=1\n3010ms X4=0\n3020ms X4=1\n5000ms expect NC1.X.pos=0\n")


def test_handwheel_moves_the_selected_axis_by_its_pulses():
    """6.3: a pulse moves 0.001 mm x D2x009 on the axis D2x008 (0 X, 1 Y, 2 Z)."""
    run("", "model nc5 mpg=D100\n0ms D21000=3 D21009=10 D21008=1\n20ms D100=25\n"
            "50ms expect NC1.Y.pos=250 NC1.X.pos=0\n60ms D21009=100 D100=20\n80ms expect NC1.Y.pos=-250\n"
            "100ms D21000=4 D100=100\n150ms expect NC1.Y.pos=-250\n")  # only in MPG mode


def test_homing_in_home_mode_and_its_three_flags():
    """6.7: M2x320 in HOME mode; M3x336 done (Off once moved by hand), M3x320 ever homed (kept),
    M3x352 at the origin (machine 0; DECISION: only once homed)."""
    run(JOG + "LD X6\nOUT M21320\n",
        "model nc5 start=-30,0,0 home_speed=3000\n0ms X6=1\n200ms expect NC1.X.pos=-30000\n"
        "200ms D21000=7 X6=0\n210ms X6=1\n"
        "500ms expect NC1.X.pos=-15500 M31336=0 M31320=0\n"
        "900ms expect NC1.X.pos=0 M31336=1 M31320=1 M31352=1 M31321=0 M31353=0\n"
        "900ms D21000=4 X3=1\n1000ms expect M31336=0 M31320=1 M31352=0\n")


def test_soft_limits_once_homed_and_their_release():
    """6.9: the first soft limit stops the program (an alarm, checked before the move); its
    release (M2x368+) switches to the second; before homing there is none."""
    il = "LD X2\nOUT M21000\nLD X4\nOUT M21004\nLD X7\nOUT M21370\nLD M31064\nOUT M21016\n"
    part = "G90 G00 Z-50.\nM90\nG00 Z134.\nM30\n"
    soft = "model nc5 program=part.nc soft1_z=-500:70 soft2_z=-500:140 rapid=60000\n"
    run(il, soft + "0ms X2=1\n1000ms expect NC1.Z.pos=134000 M31023=1\n", part)  # not homed
    homed = soft + "0ms D21000=7 M21322=1\n10ms expect M31322=1\n20ms D21000=0 M21322=0\n30ms X2=1\n"
    run(il, homed + "1000ms expect NC1.Z.pos=-50000 NC1.alarm=1 NC1.state=7 M31016=0\n"
                    "1000ms X4=1\n1020ms expect NC1.alarm=0 NC1.state=0\n", part)
    run(il, homed + "0ms X7=1\n1000ms expect NC1.Z.pos=134000 NC1.alarm=0 M31023=1\n", part)


def test_hardware_limit_stops_until_released():
    run(JOG + "LD X6\nOUT M21007\nLD X2\nOUT M21004\n",
        "model nc5 hard_x=-10:5 jog_max=600\n0ms D21000=4 X3=1\n1000ms expect NC1.X.pos=5000 NC1.alarm=0\n"
        "1100ms expect NC1.X.pos=5000 NC1.alarm=2\n1100ms X3=0 X4=1\n1300ms expect NC1.X.pos=5000\n"
        "1300ms X6=1\n1500ms expect NC1.X.pos=4000\n1500ms X2=1\n1520ms expect NC1.alarm=0\n")
