"""Keypads, 7-segment displays and the printer output (6-9 FNC 70 TKY, 71 HKY, 74 SEGL,
77 PR): the pages' examples, the stimulus pressing the keys (X) while the Y lines scan."""

from __future__ import annotations

from vskit import run


def test_tky_page_example_keys_9_1_2_0_give_9120():
    # TKY X20 D0 M0 on X0: X20-X31 are the keys 0-9; M(k) On from key k until the next key,
    # M10 while a key is held; a key held keeps the others out; X0 Off: D0 kept, M0-M10 Off
    run("LD X0\nTKY X20 D0 M0\n",
        "0ms X0=1\n10ms X31=1\n10ms expect D0=9 M9=1 M10=1\n20ms X31=0\n20ms expect M9=1 M10=0\n"
        "30ms X21=1\n30ms expect D0=91 M1=1 M9=0\n40ms X22=1\n40ms expect D0=91 M2=0\n"
        "50ms X22=0 X21=0\n60ms X22=1\n60ms expect D0=912 M2=1 M1=0\n70ms X22=0\n"
        "80ms X20=1\n80ms expect D0=9120 M0=1\n90ms X0=0 X20=0\n90ms expect D0=9120 M0=0 M10=0\n"
        "100ms X0=1 X25=1\n100ms expect D0=1205 M5=1\n")  # the fifth digit pushes the 9 out


def test_dtky_keeps_eight_digits():
    run("LD X0\nDTKY X20 D0 M0\n",
        "0ms X0=1 X21=1\n10ms X21=0\n20ms X22=1\n30ms X22=0\n40ms X23=1\n40ms expect D0:d=123\n")


def test_hky_page_example_matrix_scan():
    # HKY X20 Y20 D0 M0: Y20-Y23 drive the rows, X20-X23 are the columns; a row is read the
    # scan after it went out (rows 0-3 read at 10, 30, 50, 70 ms of each 80 ms cycle); key 5
    # is row 1 column 1, A row 2 column 2 (function key: M0), 3 row 0 column 3; a key enters
    # after a cycle with no key held
    run("LD X0\nHKY X20 Y20 D0 M0\n",
        "0ms X0=1\n0ms expect Y20=1 Y21=0\n20ms expect Y21=1 Y20=0\n30ms X21=1\n40ms X21=0\n"
        "60ms expect M9029=0 D0=0\n70ms expect D0=5 M6=1 M9029=1 Y23=0\n80ms expect M9029=0 Y20=1\n"
        "150ms expect M6=0 D0=5\n210ms X22=1\n220ms X22=0\n230ms expect M0=1 M7=1 D0=5\n"
        "310ms expect M7=0\n330ms X23=1\n340ms X23=0\n390ms expect D0=53 M0=1 M7=0\n"
        "400ms X0=0\n400ms expect M0=0 D0=53 Y20=0 Y21=0\n")


def test_hky_hex_mode_with_m9167():
    # M9167 On: F (row 3 column 3) is a hex digit, not a function key
    run("LD X0\nHKY X20 Y20 D0 M0\n",
        "0ms X0=1 M9167=1\n10ms X21=1\n20ms X21=0\n70ms expect D0=1\n230ms X23=1\n"
        "230ms expect D0:h=H1F M0=0 M5=0 M6=1 M7=0\n240ms X23=0\n")


def test_segl_page_example_four_digits_in_12_scans():
    # SEGL D0 Y20 K0: Y20-Y23 BCD data, Y24 (10^0) ... Y27 (10^3) latch strobes; each digit
    # 3 scans (data out, strobe On twice); M9029 after the 12th scan
    run("LD X20\nSEGL D0 Y20 K0\n",
        "0ms D0=1234 X20=1\n0ms expect Y22=1 Y20=0 Y24=0\n10ms expect Y24=1 Y22=1\n"
        "20ms expect Y24=1\n30ms expect Y24=0 Y20=1 Y21=1 Y22=0 Y25=0\n40ms expect Y25=1\n"
        "100ms expect M9029=0\n110ms expect Y27=1 Y20=1 Y21=0 M9029=1\n"
        "120ms expect M9029=0 Y27=0 Y22=1\n130ms X20=0\n130ms expect Y20=0 Y22=0 Y24=0\n")


def test_segl_second_set_polarity_and_range():
    # n = 5: two sets (D1 on Y30-Y33), the strobe's level inverted
    run("LD X20\nSEGL D0 Y20 K5\n",
        "0ms D0=1 D1=8 X20=1\n0ms expect Y20=1 Y33=1 Y24=1 Y25=1\n10ms expect Y24=0 Y25=1\n")
    r = run("LD X20\nSEGL D0 Y20 K0\n", "0ms D0=10000 X20=1\n0ms expect M9067=1 Y24=0\n",
            alarms=True)
    assert r.alarms


def test_pr_page_example_eight_characters():
    # PR D0 Y20: "ABCDEFGH" in D0-D3 (low byte first), Y20-Y27 data, Y30 strobe, Y31 busy;
    # 3 scans a character; X20 Off in mid-output stops, On again starts from "A"
    run("LD X20\nPR D0 Y20\n",
        "0ms D0:h=H4241 D1:h=H4443 D2:h=H4645 D3:h=H4847\n10ms X20=1\n"
        "10ms expect Y20=1 Y26=1 Y21=0 Y30=0 Y31=1\n20ms expect Y30=1\n30ms expect Y30=0 Y20=1\n"
        "40ms expect Y21=1 Y20=0\n220ms expect K2Y20=72 Y31=1\n"
        "250ms expect Y31=0 K2Y20=0\n260ms expect Y31=0 M9029=0\n"
        "270ms X20=0\n280ms X20=1\n290ms X20=0\n290ms expect Y31=0 Y20=0\n"
        "300ms X20=1\n300ms expect Y20=1 Y26=1 Y31=1\n")


def test_pr_sixteen_character_mode_stops_at_nul():
    # M9027 On: up to 16 characters, 00H ends the text; M9029 when X20 goes Off after it
    run("LD X20\nPR D0 Y20\n",
        "0ms M9027=1 D0:h=H4241\n10ms X20=1\n40ms expect K2Y20=66\n70ms expect Y31=0\n"
        "100ms expect Y31=0 M9029=0\n110ms X20=0\n110ms expect M9029=1\n120ms expect M9029=0\n")
