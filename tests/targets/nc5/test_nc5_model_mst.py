"""The virtual NC's M/S/T handshake (5.3.10, 6.8), first spindle (5.3.13, 6.10, 6.11) and tool
magazine 1 (5.3.14, 6.13)."""

from __future__ import annotations

from nc5kit import run

START = "LD X2\nOUT M21000\n"
# 6.8's flow: the flag up -> the MLC's work (here: X6) -> M2x016 -> the flag down
FINISH = "LD M31064\nOR M31065\nOR M31066\nAND X6\nOUT M21016\n"


def test_m_s_t_codes_wait_for_the_finish_signal():
    part = "S1200 M03 T5\nG01 X1. F600\nM30\n"
    run(START + FINISH, "model nc5 program=part.nc\n0ms X2=1\n"
        "100ms expect M31064=1 M31065=1 M31066=1 D31048=3 D31050:d=1200 D31052=5 D31037=5 "
        "D31024:d=1200 NC1.state=4 M31016=1 NC1.X.pos=0\n"
        "500ms expect M31064=1 NC1.X.pos=0\n500ms X6=1\n"  # nothing goes on without the finish
        "520ms expect M31064=0 M31065=0 M31066=0 D31048=3\n"  # the data stay
        "700ms expect NC1.X.pos=1000 M31023=1\n", part)


def test_m00_m01_m02_m30_raise_no_m_flag():
    """5.2.1 M3x064: "M 碼不包含 M00、M01、M02、M30、M98、M99"."""
    run(START + FINISH + "LD M31064\nSET M100\n", "model nc5 program=part.nc\n0ms X2=1 X6=1\n"
        "100ms expect M100=0 NC1.state=5\n100ms X2=0\n110ms X2=1\n200ms expect M100=0 M31022=1\n",
        "M00\nM01\nM02\n")


def test_a_held_finish_does_not_pass_the_next_code():
    """DECISION: the NC raises a code only once M2x016 is Off, so two codes in a row are
    each seen by the MLC (a finish held On would pass the second unseen)."""
    run(START + "LD M31064\nAND= D31048 K8\nSET M100\nLD M31064\nAND= D31048 K9\nSET M101\n"
        "LD X6\nOUT M21016\n",
        "model nc5 program=part.nc\n0ms X2=1\n100ms expect M100=1 M101=0\n100ms X6=1\n"
        "300ms expect M101=0 M31064=0\n300ms X6=0\n400ms expect M101=1 M31064=1 D31048=9\n",
        "M08\nM09\nM30\n")


def test_t_codes_outside_the_magazine_and_two_t_words():
    """6.8: only a T of N0.1402's tools raises M3x066; DECISION (notes #18): of two T words
    the last counts."""
    run(START + FINISH, "model nc5 program=part.nc tools=8\n0ms X2=1 X6=1\n"
        "300ms expect M31023=1 D31052=7 D31039=-2\n", "T9\nT3 T7\nM30\n")
    run(START + FINISH, "model nc5 program=part.nc magazine=0\n0ms X2=1 X6=1\n"
        "100ms expect NC1.alarm=3 NC1.state=7 M31066=0 D31052=0 M31016=0\n", "T3\nM30\n")


def test_spindle_ramps_to_speed_with_the_override():
    il = "LD X3\nOUT M21704\nLD X4\nOUT M21705\nLD X5\nMOV K50 D21026\n"
    run(START + FINISH + il,
        "model nc5 program=part.nc spindle_max=6000 spindle_ramp=1s\n0ms X2=1 X6=1\n"
        "100ms expect D31024:d=3000 M31705=1 M31704=1\n100ms X3=1\n"  # S3000, stopped: at its 0
        "300ms expect NC1.spindle.rpm=1200 D31026:d=1200 M31704=0 M31705=0 NC1.spindle.cmd=3000\n"
        "700ms expect NC1.spindle.rpm=3000 M31704=1\n700ms X5=1\n"
        "1000ms expect NC1.spindle.rpm=1500 NC1.spindle.cmd=1500 M31704=1\n"
        "1000ms X3=0\n1300ms expect NC1.spindle.rpm=0 M31705=1 M31704=1\n"
        "1300ms X4=1\n1400ms expect NC1.spindle.rpm=-600 D31026:d=600\n",
        "S3000\nM30\n")


def test_spindle_speed_from_d2x024_and_orientation():
    il = "LD X3\nOUT M21704\nLD X4\nOUT M21706\nLD X5\nOUT M21710\nDMOV K2400 D21024\n"
    run(il, "model nc5 spindle_ramp=0s orient_at=9000 orient_time=100ms\n0ms X3=1 X5=1\n"
            "50ms expect NC1.spindle.rpm=2400 D31024:d=2400 D31026:d=2400\n"
            "100ms X3=0 X4=1\n150ms expect M31706=0\n250ms expect M31706=1 D31028:d=9000 NC1.spindle.angle=9000\n"
            "250ms X3=1 X4=0\n270ms expect M31706=0\n")


def test_gear_select_is_shown():
    run("LD X3\nMOV K3 D21027\n", "model nc5\n0ms X3=1\n20ms expect NC1.spindle.gear=3\n")


def test_magazine_forward_reverse_exchange_reset():
    """6.13: forward adds one to the standby pot (max -> 1), reverse takes one (1 -> max),
    exchange swaps the spindle's tool and the standby pot's; D3x039 counts the way to the
    commanded tool (5.2.1: forward -1). A reset puts tool first+k in pot k+1, the spindle's
    the highest + 1 (N0.1400 = 1), standby pot N0.1404."""
    il = START + FINISH + "LD X3\nOUT M21064\nLD X4\nOUT M21065\nLD X5\nOUT M21066\nLD X7\nOUT M21067\n"
    run(il, "model nc5 program=part.nc tools=16 first_tool=3 standby_pot=2\n"
            "0ms expect D31036=19 D31038=2 D31037=0\n0ms X2=1 X6=1\n"
            "100ms expect D31052=10 D31037=10 D31039=6\n"  # tool 10 in pot 8: 8 - 2
            "100ms X3=1\n120ms X3=0\n140ms expect D31038=3 D31039=5\n"
            "140ms X4=1\n160ms X4=0\n180ms expect D31038=2 D31039=6\n"
            "180ms X5=1\n200ms X5=0\n220ms expect D31036=4\n"  # pot 2 held tool 4
            "220ms X7=1\n240ms X7=0\n260ms expect D31036=19 D31038=2 D31037=0\n",
        "T10\nM30\n")
    run(il, "model nc5 program=part.nc tools=4\n0ms X4=1\n20ms expect D31038=4\n"  # 1 -> max
            "20ms X4=0 X2=1 X6=1\n100ms expect D31039=-1\n", "T3\nM30\n")  # tool 3 in pot 3, standby 4
