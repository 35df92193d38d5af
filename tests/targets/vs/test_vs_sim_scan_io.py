"""Scanning inputs MTR (6-7 FNC 52) and DSW (6-9 FNC 72): the pages' examples, the Y lines
driven scan by scan and the X switches the stimulus sets while a line is driven."""

from __future__ import annotations

from vskit import run


def test_mtr_page_example_two_rows_into_m0_m17():
    # MTR X20 Y20 M0 K2 on X0: Y20 drives row 0, read into M0-M7 the scan after; Y21 row 1
    # into M10-M17; M9029 On for the scan completing the last row; X0 Off: Y Off, M kept
    run("LD X0\nMTR X20 Y20 M0 K2\n",
        "0ms X0=1\n0ms expect Y20=1 Y21=0\n10ms X20=1 X27=1\n10ms expect M0=1 M7=1 M1=0 Y20=1\n"
        "20ms X20=0 X27=0 X22=1\n20ms expect Y20=0 Y21=1 M0=1 M10=0\n"
        "30ms expect M12=1 M10=0 M2=0 M9029=1 Y21=1\n40ms expect M9029=0 Y20=1 Y21=0\n"
        "50ms expect M2=1 M0=0\n60ms X0=0\n60ms expect Y20=0 Y21=0 M2=1 M12=1\n")


def test_dsw_page_example_reads_four_bcd_digits():
    # DSW X20 Y20 D0 K1: Y20 (10^0) ... Y23 (10^3) each On 0.1 s, X20-X23 the 8421 lines;
    # switches 1234: D0 = 1234 and M9029 after the 10^3 digit (at 400 ms)
    run("LD X0\nDSW X20 Y20 D0 K1\n",
        "0ms X0=1 X22=1\n0ms expect Y20=1\n100ms X22=0 X21=1 X20=1\n100ms expect Y21=1 Y20=0\n"
        "200ms X21=1 X20=0\n300ms X21=0 X20=1\n390ms expect D0=0\n"
        "400ms expect D0=1234 M9029=1 Y20=1 Y23=0\n410ms expect M9029=0\n"
        "410ms X0=0\n420ms expect Y20=0 D0=1234\n")


def test_dsw_second_set_and_a_digit_above_nine():
    r = run("LD X0\nDSW X20 Y20 D0 K2\n",
            "0ms X0=1 X25=1 X27=1\n400ms expect D1=0 M9067=1\n", alarms=True)
    assert r.alarms
    run("LD X0\nDSW X20 Y20 D0 K2\n", "0ms X0=1 X24=1 X20=1\n400ms expect D0=1111 D1=1111\n")
