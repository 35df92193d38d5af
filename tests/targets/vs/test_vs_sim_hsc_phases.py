"""Vigor VS high-speed counters with reset/start inputs, 2-phase and A/B phase (2-7-1 to
2-7-3, mode 1 assignment) and the hardware counters HHSC1/2 with DHHCMV (2-15-4, 6-16 FNC
189): the pages' examples on stimulus pulse trains and A/B pairs, counted analytically."""

from __future__ import annotations

from mlctool.sim.stimulus.stimulus import parse_stimulus_text
from vskit import VS, run


def test_one_phase_with_hardware_reset_c242():
    # 2-7-1: X20 drives M9242 (direction), X21 RST C242, X22 the software start, X2 counts,
    # X3 the hardware reset, preset D1:D0. A reset input On clears after the interval's
    # counts and holds 0 while the previous scan saw it On
    run("LD X20\nOUT M9242\nLD X21\nRST C242\nLD X22\nOUT C242 D0\n",
        "0ms D0:d=100 X22=1\n0ms X2 pulses 1kHz until 300ms\n90ms expect C242:d=90 C242=0\n"
        "100ms expect C242:d=100 C242=1\n150ms X3=1\n150ms expect C242:d=0 C242=0\n"
        "160ms expect C242:d=0\n170ms X3=0\n170ms expect C242:d=0\n180ms expect C242:d=10\n"
        "200ms X20=1\n200ms expect C242:d=30\n250ms expect C242:d=-20\n"
        "260ms X21=1\n260ms expect C242:d=0\n")


def test_one_phase_with_hardware_start_c244():
    # 2-7-1: C244 counts X0 only while X22 (software) and X6 (hardware start) are On; X1 resets
    run("LD X20\nOUT M9244\nLD X21\nRST C244\nLD X22\nOUT C244 K200\n",
        "0ms X22=1\n0ms X0 pulses 1kHz until 500ms\n50ms X6=1\n50ms expect C244:d=0\n"
        "100ms expect C244:d=50\n150ms X6=0\n200ms expect C244:d=100 C244=0\n"
        "250ms X6=1\n350ms expect C244:d=200 C244=1\n360ms X1=1\n360ms expect C244:d=0 C244=0\n")


def test_two_phase_c246_counts_up_and_down():
    # 2-7-2: X21 starts C246 (preset K-5), X0 rising +1, X1 rising -1, M9246 shows down;
    # contact On from -5 up
    run("LD X21\nOUT C246 K-5\nLD X20\nRST C246\n",
        "0ms X21=1\n0ms X0 pulses 1kHz until 100ms\n105ms X1 pulses 2kHz until 205ms\n"
        "100ms expect C246:d=99 C246=1 M9246=0\n150ms expect C246:d=8 C246=1 M9246=1\n"
        "160ms expect C246:d=-12 C246=0\n210ms expect C246:d=-101\n"
        "220ms X20=1\n220ms expect C246:d=0\n")


def test_two_phase_c248_hardware_reset():
    # 2-7-2: C248 on X3 (up) / X4 (down), X5 the hardware reset, preset D1:D0
    run("LD X21\nOUT C248 D0\n",
        "0ms X21=1 D0:d=50\n0ms X3 pulses 1kHz until 100ms\n60ms expect C248:d=60 C248=1\n"
        "70ms X5=1\n70ms expect C248:d=0 C248=0\n100ms X5=0\n120ms expect C248:d=0\n")


def test_ab_phase_c251_follows_the_encoder():
    # 2-7-3: A X0, B X1: A On and B rising +1, A On and B falling -1 (x1); `X0/X1 pulses
    # -500Hz` turns the other way; single trains on A and B are no pair and count nothing
    run("LD X21\nOUT C251 K-5\nLD X20\nRST C251\n",
        "0ms X21=1\n0ms X0/X1 pulses 1kHz until 100ms\n100ms X0/X1 pulses -500Hz until 300ms\n"
        "100ms expect C251:d=100 C251=1 M9251=0\n200ms expect C251:d=50 M9251=1\n"
        "300ms expect C251:d=0\n400ms X0 pulses 1kHz until 500ms\n400ms X1 pulses 1kHz until 500ms\n"
        "510ms expect C251:d=0\n")


def test_ab_phase_c255_reset_and_start_inputs():
    # 2-7-3: C255 on X3 (A) / X4 (B), X5 hardware reset, X7 hardware start, preset K-200
    run("LD X21\nOUT C255 K-200\n",
        "0ms X21=1\n0ms X3/X4 pulses -1kHz until 400ms\n100ms expect C255:d=0\n"
        "100ms X7=1\n200ms expect C255:d=-100 C255=1 M9255=1\n300ms X5=1\n300ms expect C255:d=0\n")


def test_ab_pair_syntax():
    _, diags = parse_stimulus_text("t.stim", "0ms X0/X1 pulses 1kHz\n10ms X3/X4 pulses -2kHz for 5ms", VS)
    assert not diags
    for bad, words in (("0ms X0/X0 pulses 1kHz", "two inputs"), ("0ms X0/Y1 pulses 1kHz", "inputs"),
                       ("0ms X0/ pulses 1kHz", "A/B pair"), ("0ms X0 pulses -1kHz", "frequency")):
        _, diags = parse_stimulus_text("t.stim", bad, VS)
        assert [d.code for d in diags] == ["E601"] and words in diags[0].message, (bad, diags)


def test_ab_pair_levels_are_a_quarter_period_apart():
    # the scans see A and B: at 40 Hz (25 ms) A On 0-12.5 ms, B On 6.25-18.75 ms
    run("LD X0\nOUT Y0\nLD X1\nOUT Y1\n",
        "0ms X0/X1 pulses 40Hz until 1s\n0ms expect Y0=1 Y1=0\n10ms expect Y0=1 Y1=1\n"
        "20ms expect Y0=0 Y1=0\n30ms expect Y0=1 Y1=0\n")


def test_dhhcmv_and_hardware_counter_modes():
    # 2-15-4 / 6-16 FNC 189 example: X10 sets HHSC1 to A/B x1 (MOVP K4 D9224), DHHCMV D9226 D0
    # reads it at once, DHHCMVP K0 D9226 clears it, DHHCMVP K1000 D9230 writes the set value;
    # HHSC2 in mode 3 (2-phase X3 up, X4 down; the 2 kHz train's first edge at 100 ms counts
    # before the 100 ms scan) read with DHHCMV D9228 D2; then mode 6 (x4)
    run("LDI X10\nMOVP K0 D9224\nLD X10\nMOVP K4 D9224\nLD X12\nMOV K6 D9224\n"
        "LD M9000\nMOV K3 D9225\nLD M9000\nDHHCMV D9226 D0\nLD X11\nDHHCMVP K0 D9226\n"
        "LD M9002\nDHHCMVP K1000 D9230\nLD M9000\nDHHCMV D9228 D2\nLD M9000\nDHHCMV K70000 D20\n",
        "0ms X10=1\n0ms X0/X1 pulses 1kHz until 1s\n"
        "0ms X3 pulses 1kHz until 100ms\n0ms X4 pulses 500Hz until 100ms\n"
        "100ms expect D0:d=100 D9226:d=100 D9230:d=1000 M9196=0 D2:d=49 M9197=0 D20:d=70000\n"
        "100ms X4 pulses 2kHz until 150ms\n"
        "150ms X11=1\n150ms expect D0:d=150 D9226:d=0\n200ms expect D0:d=50 D2:d=-50 M9197=1\n"
        "300ms X10=0 X12=1\n400ms expect D0:d=550 D9226:d=550\n")


# ------------------------------------------------------------------ 6-9 / 6-10 I/O conversions

def test_segd_decodes_to_seven_segments():
    # 6-9 FNC 73 example: SEGD D0 K2Y20 on X20: the low 4 bits of D0 as segments a-g on Y20-Y27;
    # a word destination keeps its high byte
    run("LD X20\nSEGD D0 K2Y20\nLD X20\nSEGD D1 D2\n",
        "0ms D0:h=H1237 D1=11 D2:h=HAB00\n10ms X20=1\n10ms expect K2Y20=39 D2:h=HAB7C\n"
        "20ms D0=8\n20ms expect K2Y20=127\n")


def test_prun_copies_in_octal():
    # 6-10 FNC 81 example: PRUN K4X20 K4M0 on X0 (X20-X27 -> M0-M7, X30-X37 -> M10-M17, M8/M9
    # unchanged), PRUNP K4M0 K4Y20 on X1 (back, M8/M9 skipped)
    run("LD X0\nPRUN K4X20 K4M0\nLDP X1\nPRUN K4M0 K4Y20\n",
        "0ms M8=1 M9=1 X20=1 X27=1 X30=1 X37=1\n10ms X0=1\n"
        "10ms expect M0=1 M7=1 M10=1 M17=1 M8=1 M9=1 M1=0 M11=0\n"
        "20ms X1=1\n20ms expect Y20=1 Y27=1 Y30=1 Y37=1 Y21=0 Y31=0 Y26=0 Y36=0\n")


def test_dhsct_page_example_table_of_six_rows():
    # 6-21 FNC 280's program: C235 counts X0 0-1000 round (DHSCR K1000 C235 C235); the table
    # D0-D17 (100 -> H1, 200 -> H6, 300 -> HA, 400 -> HC, 500 -> H8, 600 -> H5) drives Y4-Y7
    # at each value reached; D9162 the row, M9162 one scan after the last row
    il = ("LD M9002\nMOV H5 K1Y4\nLD M9000\nOUT C235 K1000\nDHSCR K1000 C235 C235\n"
          "DHSCT D0 K6 C235 Y4 K4\n")
    table = " ".join(f"D{3 * k}:d={100 * (k + 1)} D{3 * k + 2}={v}"
                     for k, v in enumerate((1, 6, 10, 12, 8, 5)))
    run(il, f"0ms {table}\n0ms expect K1Y4=5 D9162=0\n5ms X0 pulses 1kHz until 2000ms\n"
            "100ms expect K1Y4=5 D9162=0\n110ms expect K1Y4=1 D9162=1\n250ms expect K1Y4=6 D9162=2\n"
            "350ms expect K1Y4=10\n450ms expect K1Y4=12\n550ms expect K1Y4=8 D9162=5\n"
            "600ms expect M9162=0\n610ms expect K1Y4=5 D9162=0 M9162=1\n620ms expect M9162=0\n"
            "1150ms expect K1Y4=1 D9162=1 C235:d=146\n")


def test_dhsct_off_clears_the_row_counter_keeps_outputs():
    il = "LD M9000\nOUT C235 K1000\nLD X10\nDHSCT D0 K2 C235 Y4 K2\n"
    run(il, "0ms D0:d=10 D2=3 D3:d=20 D5=0 X10=1\n5ms X0 pulses 1kHz until 500ms\n"
            "10ms expect Y4=0 D9162=0\n20ms X10=0\n20ms expect D9162=0 Y4=1 Y5=1\n"
            "60ms expect Y4=1 Y5=1 D9162=0\n")  # 10 reached at 14 ms; 20 (at 24 ms) no more
