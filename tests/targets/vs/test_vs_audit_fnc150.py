"""docs/vs-audit.md, section "FNC 150-316": one case per rule the VS manual's pages state
(chapter 6-14 ... 6-21, FNC 160-280, and 8-3, FNC 300-316), each named by its row's id.

Two tables: STATIC (what `mlc check` says: a program that keeps the rule is clean, one that
breaks it gets the code) and RUNS (the simulator: the page's example or the rule's case,
with its expected devices, flags and error registers M9067/D9067 = 6706 in the stimulus)."""

from __future__ import annotations

import pytest

import vskit


def program(lines: str) -> str:
    """`lines` (';' between instructions) under LD X0, then END; the rule's line is line 2."""
    body = lines.replace(";", "\n")
    head = "" if body.split()[0].startswith(("LD", "AND", "OR")) else "LD X0\n"
    tail = "OUT Y0\n" if body.split()[0].startswith(("LD", "AND", "OR")) else ""
    return f"{head}{body}\n{tail}END\n"


# (good, bad, code, line of the bad instruction): `good` keeps the rule and has no error and
# not the code; `bad` breaks it and gets `code` at that line.
STATIC = [
    # ---- 6-14 calendar
    pytest.param("TCMP K23 K59 K59 D0 M0", "TCMP K24 K0 K0 D0 M0", "E206", 2, id="FNC160-S1-hour"),
    pytest.param("TCMP K0 K0 K0 D0 M0", "TCMP K8 K60 K0 D0 M0", "E206", 2, id="FNC160-S2-minute"),
    pytest.param("TCMP K0 K0 K0 D0 M0", "TCMP K8 K0 K-1 D0 M0", "E206", 2, id="FNC160-S3-second"),
    pytest.param("TCMP K8 K30 K20 D0 M0", "TCMP K8 K30 K20 R23998 M0", "E208", 2, id="FNC160-S-3-words"),
    pytest.param("TZCP D0 D10 D20 Y375", "TZCP D0 D10 D20 Y376", "E208", 2, id="FNC161-D-3-bits"),
    pytest.param("TADD D0 D10 D20", "TADD D0 D10 R23998", "E208", 2, id="FNC162-3-words"),
    pytest.param("TSUB R23997 D10 D20", "TSUB R23998 D10 D20", "E208", 2, id="FNC163-3-words"),
    pytest.param("TRD D0", "TRD R23995", "E208", 2, id="FNC166-7-words"),
    pytest.param("TWR D0", "TWR R23994", "E208", 2, id="FNC167-7-words"),
    # ---- 6-15
    pytest.param("HOUR K1000 D7000 Y0", "HOUR K1000 R23999 Y0", "E208", 2, id="FNC169-D1-2-words"),
    pytest.param("DHOUR K1000 R23997 Y0", "DHOUR K1000 R23998 Y0", "E208", 2, id="FNC169-D1-3-words"),
    pytest.param("HOUR K1000 D7000 Y0", "HOUR K1000 D100 Y0", "W241", 2, id="FNC169-D1-latched"),
    pytest.param("TFT D0 K32767 M0", "TFT D0 K-5 M0", "W221", 2, id="FNC176-preset-0-32767"),
    pytest.param("TFH D0 K0 M0", "TFH D0 K-1 M0", "W221", 2, id="FNC177-preset-0-32767"),
    pytest.param("TFK D0 K100 M0", "TFK D0 K-100 M0", "W221", 2, id="FNC178-preset-0-32767"),
    # ---- 6-16
    pytest.param("DUTY K10 K5 M9334", "DUTY K10 K5 M9335", "E205", 2, id="FNC186-D-M9330-M9334"),
    pytest.param("DUTY K10 K5 M9330;DUTY K1 K1 M9331", "DUTY K10 K5 M9330;LD X1;DUTY K1 K1 M9330",
                 "E240", 4, id="FNC186-D-once"),
    pytest.param("DUTY K0 K0 M9330", "DUTY K-1 K5 M9330", "E206", 2, id="FNC186-n-not-negative"),
    pytest.param("CRC D0 D100 K256", "CRC D0 D100 K257", "E206", 2, id="FNC188-n-1-256"),
    pytest.param("CRC K4M0 D100 K2", "CRC K2M0 D100 K1", "E207", 2, id="FNC188-K4-source"),
    pytest.param("CRC D0 K4Y0 K2", "CRC D0 K3Y0 K1", "E207", 2, id="FNC188-K4-destination"),
    pytest.param("DHHCMV D9226 D0", "HHCMV D9226 D0", "E201", 2, id="FNC189-32-bit-only"),
    pytest.param("DHHCMV D9226 D0Z1", "DHHCMV D9226Z1 D0", "E209", 2, id="FNC189-no-index"),
    # ---- 6-17
    pytest.param("BK+ D0 D10 D20 K5", "BK+ D0 D10 D20 K5", "E901", 2, id="FNC192-VS3-only"),
    pytest.param("BK+ D0 D10 D20 K5", "BK+ D0 D10 D3 K5", "W240", 2, id="FNC192-overlap"),
    pytest.param("DBK- D0 K100 D20 K5", "DBK- D0 D8 D20 K5", "W240", 2, id="FNC193-overlap"),
    pytest.param("BK+ D0 D10 R23995 K5", "BK+ D0 D10 R23996 K5", "E208", 2, id="FNC192-n-points"),
    pytest.param("DBK- D0 D20 R23990 K5", "DBK- D0 D20 R23991 K5", "E208", 2, id="FNC193-2n-registers-32"),
    pytest.param("BKCMP= D0 D10 M0 K5", "BKCMP= D0 D10 M8188 K5", "E205", 2, id="FNC194-D-n-bits"),
    pytest.param("DBKCMP> K5 R23990 M0 K5", "DBKCMP> K5 R23991 M0 K5", "E208", 2, id="FNC195-S2-2n-registers"),
    pytest.param("BKCMP< D0 D10 M0 K5", "BKCMP< R23996 D10 M0 K5", "E208", 2, id="FNC196-S1-n-points"),
    pytest.param("BKCMP<> D0 D10 M0 K1", "BKCMP<> D0 R23999 M0 K2", "E208", 2, id="FNC197-S2-n-points"),
    pytest.param("BKCMP<= D0 D10 Y370 K8", "BKCMP<= D0 D10 Y371 K8", "E208", 2, id="FNC198-D-n-bits"),
    pytest.param("BKCMP>= D0 D10 S4091 K5", "BKCMP>= D0 D10 S4092 K5", "E208", 2, id="FNC199-D-n-bits"),
    # ---- 6-18
    pytest.param('$+ "ABCDEFGHIJKLMNOPQRSTUVWXYZ012345" D0 D100',
                 '$+ "ABCDEFGHIJKLMNOPQRSTUVWXYZ0123456" D0 D100', "E203", 2, id="FNC202-32-characters"),
    pytest.param("RIGHT D0 D40 K0", "RIGHT D0 D40 K-1", "E206", 2, id="FNC204-n-not-negative"),
    pytest.param("LEFT D0 D40 K5", "LEFT D0 D40 K-2", "E206", 2, id="FNC205-n-not-negative"),
    # ---- 6-19
    pytest.param("FDEL D50 D0 K1", "FDEL D50 D0 K0", "E206", 2, id="FNC210-n-above-0"),
    pytest.param("FINS K99 D0 K1", "FINS K99 D0 K0", "E206", 2, id="FNC211-n-above-0"),
    pytest.param("POP D0 D101 K512", "POP D0 D101 K1", "E206", 2, id="FNC212-n-2-512"),
    pytest.param("SFRP D0 K15", "SFRP D0 K16", "E206", 2, id="FNC213-n-0-15"),
    pytest.param("SFLP D1 K0", "SFLP D1 K-1", "E206", 2, id="FNC214-n-0-15"),
    # ---- 6-20
    pytest.param("LDD<> C235 K10", "LD<> C235 K10", "E211", 1, id="FNC228-32-bit-counter"),
    # ---- 6-21
    pytest.param("DABIN D0 D10", "DABIN R23998 D10", "E208", 2, id="FNC260-S-3-words"),
    pytest.param("DDABIN R23994 D10", "DDABIN R23995 D10", "E208", 2, id="FNC260-S-6-words-32"),
    pytest.param("BINDA D10 D0", "BINDA D10 R23997", "E208", 2, id="FNC261-D-4-words"),
    pytest.param("DBINDA D10 R23994", "DBINDA D10 R23995", "E208", 2, id="FNC261-D-6-words-32"),
    pytest.param("DHSCT D0 K16 C235 Y4 K16", "DHSCT D0 K17 C235 Y4 K3", "E206", 2, id="FNC280-m-1-16"),
    pytest.param("DHSCT D0 K6 C235 Y4 K1", "DHSCT D0 K6 C235 Y4 K0", "E206", 2, id="FNC280-n-1-16"),
    pytest.param("DHSCT D0 K6 C255 Y4 K3", "DHSCT D0 K6 C234 Y4 K3", "E205", 2, id="FNC280-S2-C235-C255"),
    pytest.param("DHSCT R23952 K16 C235 Y4 K3", "DHSCT R23953 K16 C235 Y4 K3", "E208", 2, id="FNC280-S1-3m-registers"),
    pytest.param("DHSCT D0 K6 C235 Y4 K3", "DHSCT D0 K6 C235 Y4 K3;LD X1;DHSCT D20 K6 C236 Y10 K3",
                 "E904", 4, id="FNC280-once"),
    pytest.param("DHSCT D0 K6 C235 Y4 K3", "HSCT D0 K6 C235 Y4 K3", "E201", 2, id="FNC280-32-bit-only"),
    # ---- 8-3 positioning
    pytest.param("DZRN K50000 K1000 Y3 Y7", "DZRN K50000 K1000 Y4 Y7", "E205", 2, id="FNC300-D1-Y0-Y3"),
    pytest.param("DZRN K50000 K1000 Y0 M10", "DZRN K50000 K1000 Y0 Y10", "E205", 2, id="FNC300-D2-Y0-Y7"),
    pytest.param("JOGF K100 K1000 Y0 Y4", "JOGF K100 K1000 X0 Y4", "E210", 2, id="FNC301-D1-Y"),
    pytest.param("JOGR K100 K1000 Y1 Y5", "JOGR K100 K1000 Y1 Y10", "E205", 2, id="FNC302-D2-Y0-Y7"),
    pytest.param("DDRVR K1000 K500 Y2 Y6", "DDRVR K1000 K500 Y6 Y6", "E205", 2, id="FNC303-D1-Y0-Y3"),
    pytest.param("DDRVA K1000 K500 Y0 Y4", "DDRVA K1000 K500 Y0 Y20", "E205", 2, id="FNC304-D2-Y0-Y7"),
    pytest.param("DV2R D10 D20 Y0 Y4", "DV2R R23999 D20 Y0 Y4", "E208", 2, id="FNC305-S1-S2-2-devices"),
    pytest.param("DDV2A D10 D20 Y0 Y4", "DDV2A D10 R23997 Y0 Y4", "E208", 2, id="FNC306-S-2-pairs"),
    pytest.param("DDVIT K1000 K500 Y0 Y4", "DDVIT K1000 K500 Y4 Y4", "E205", 2, id="FNC307-D1-Y0-Y3"),
    pytest.param("DV2I D10 D20 Y0 Y4", "DV2I D10 R23999 Y0 Y4", "E208", 2, id="FNC308-S2-2-devices"),
    pytest.param("DDVSR K1000 K500 Y0 Y4", "DDVSR K1000 K500 Y0 Y10", "E205", 2, id="FNC309-D2-Y0-Y7"),
    pytest.param("DDVSA K1000 K500 Y3 Y7", "DDVSA K1000 K500 Y7 Y7", "E205", 2, id="FNC310-D1-Y0-Y3"),
    pytest.param("DPLSV K1000 Y0 Y4", "DPLSV K1000 Y4 Y4", "E205", 2, id="FNC311-D1-Y0-Y3"),
    pytest.param("DTBL Q0 D100 Y0 Y4", "DTBL Q0 R23997 Y0 Y4", "E208", 2, id="FNC312-S2-4-words"),
    pytest.param("DABS X0 M0 D0", "DABS X0 M0 D0;LD X1;DABS X4 M10 D10", "E904", 4, id="FNC313-once"),
    pytest.param("DABS X0 M0 D0", "DABS X0 M8190 D0", "E205", 2, id="FNC313-D1-3-bits"),
    pytest.param("DABS X374 M0 D0", "DABS X376 M0 D0", "E208", 2, id="FNC313-S-3-bits"),
    pytest.param("MPG K3 D100 Y0 Y4", "MPG K4 D100 Y0 Y4", "E206", 2, id="FNC314-S1-0-3"),
    pytest.param("MPG K0 D100 Y0 Y4", "MPG K0 R23998 Y0 Y4", "E208", 2, id="FNC314-S2-3-words"),
    pytest.param("LIR D1000 K1", "LIR D1000 K2", "E206", 2, id="FNC315-D-0-1"),
    pytest.param("DLIA R23982 K0", "DLIA R23983 K0", "E208", 2, id="FNC316-S-18-words"),
]


@pytest.mark.parametrize("good, bad, code, line", STATIC)
def test_static_rule(good, bad, code, line):
    model = "VS1" if code == "E901" else "VS3"
    clean = vskit.check_codes(program(good), "VS3")
    assert not [c for c, _ in clean if c.startswith("E") or c == code], clean
    found = vskit.check_codes(program(bad), model)
    assert (code, line) in found, found


def run(il: str, stim: str) -> None:
    vskit.run(il, stim, alarms=True)


OP_ERROR = "M9067=1 D9067=6706"
NO_ERROR = "M9067=0"

# (program, stimulus with its expectations)
RUNS = [
    # ---- 6-14 FNC 160 TCMP K8 K30 K20 D0 M0 (the page's program, X20 its condition)
    pytest.param("LD X20\nTCMP K8 K30 K20 D0 M0\n",
                 "0ms D0=7 X20=1\n0ms expect M0=1 M1=0 M2=0\n10ms D0=8 D1=30 D2=20\n"
                 "10ms expect M0=0 M1=1 M2=0\n20ms D2=21\n20ms expect M0=0 M1=0 M2=1 " + NO_ERROR,
                 id="FNC160-page-example"),
    pytest.param("LD X20\nTCMP K8 K30 K20 D0 M0\n",
                 "0ms D0=9 X20=1\n0ms expect M2=1\n10ms X20=0 D0=7\n10ms expect M0=0 M2=1",
                 id="FNC160-off-keeps-results"),
    pytest.param("LD X20\nTCMP K8 K30 K20 D0 M0\n",
                 "0ms D0=9 X20=1\n0ms expect M2=1\n10ms D1=60\n10ms expect M2=1 " + OP_ERROR,
                 id="FNC160-bad-time-op-error"),
    # FNC 161 TZCP D0 D10 D20 M0
    pytest.param("LD X20\nTZCP D0 D10 D20 M0\n",
                 "0ms D0=8 D10=9 D20=7 X20=1\n0ms expect M0=1 M1=0 M2=0\n10ms D20=8 D21=30\n"
                 "10ms expect M0=0 M1=1 M2=0\n20ms D20=9 D21=0 D22=1\n20ms expect M1=0 M2=1",
                 id="FNC161-page-example"),
    pytest.param("LD X20\nTZCP D0 D10 D20 M0\n",
                 "0ms D0=10 D10=9 D20=10 X20=1\n0ms expect M0=0 M1=1 M2=0\n10ms D20=9 D21=30\n"
                 "10ms expect M0=1 M1=0 M2=0\n20ms D20=10 D22=1\n20ms expect M2=1 M1=0",
                 id="FNC161-S1-above-S2-both-limits"),
    pytest.param("LD X20\nTZCP D0 D10 D20 M0\n", "0ms D10=24 X20=1\n0ms expect M1=0 " + OP_ERROR,
                 id="FNC161-bad-time-op-error"),
    # FNC 162 TADD D0 D10 D20: 8:30:00 + 6:35:30, 8:25:30 + 20:10:20 = 4:35:50 with M9022
    pytest.param("LD X20\nTADD D0 D10 D20\n",
                 "0ms D0=8 D1=30 D10=6 D11=35 D12=30 X20=1\n0ms expect D20=15 D21=5 D22=30 M9022=0\n"
                 "10ms D1=25 D2=30 D10=20 D11=10 D12=20\n10ms expect D20=4 D21=35 D22=50 M9022=1 M9020=0",
                 id="FNC162-page-example-carry"),
    pytest.param("LD X20\nTADD D0 D10 D20\n", "0ms D0=12 D10=12 X20=1\n0ms expect D20=0 M9020=1 M9022=1",
                 id="FNC162-zero-flag"),
    pytest.param("LD X20\nTADD D0 D10 D20\n", "0ms D20=5 D2=60 X20=1\n0ms expect D20=5 " + OP_ERROR,
                 id="FNC162-bad-time-op-error"),
    # FNC 163 TSUB: 18:28:50 - 8:40:20 = 9:48:30; 6:30:20 - 20:20:10 = 10:10:10 with M9021
    pytest.param("LD X20\nTSUB D0 D10 D20\n",
                 "0ms D0=18 D1=28 D2=50 D10=8 D11=40 D12=20 X20=1\n0ms expect D20=9 D21=48 D22=30 M9021=0\n"
                 "10ms D0=6 D1=30 D2=20 D10=20 D11=20 D12=10\n10ms expect D20=10 D21=10 D22=10 M9021=1",
                 id="FNC163-page-example-borrow"),
    pytest.param("LD X20\nTSUB D0 D10 D20\n", "0ms D0=8 D10=8 X20=1\n0ms expect D20=0 M9020=1 M9021=0",
                 id="FNC163-zero-flag"),
    pytest.param("LD X20\nTSUB D0 D10 D20\n", "0ms D20=5 D10=-1 X20=1\n0ms expect D20=5 " + OP_ERROR,
                 id="FNC163-bad-time-op-error"),
    # FNC 164 HTOS D0 D10: 3:15:48 = 11748 s; DHTOSP 40:21:33 = 145293 s; 16-bit hours 0-4
    pytest.param("LD X0\nHTOS D0 D10\nDHTOSP D20 D30\n",
                 "0ms D0=3 D1=15 D2=48 D20=40 D21=21 D22=33 X0=1\n0ms expect D10=11748 D30:d=145293 " + NO_ERROR,
                 id="FNC164-page-examples"),
    pytest.param("LD X0\nHTOS D0 D10\n", "0ms D0=5 D10=7 X0=1\n0ms expect D10=7 " + OP_ERROR,
                 id="FNC164-16-bit-hours-0-4"),
    pytest.param("LD X0\nDHTOS D0 D10\n", "0ms D0=32767 D1=59 D2=59 X0=1\n0ms expect D10:d=117964799 "
                 + NO_ERROR + "\n10ms D1=60\n10ms expect " + OP_ERROR, id="FNC164-32-bit-hours-0-32767"),
    # FNC 165 STOH D10 D20: 11748 -> 3:15:48; DSTOHP 145293 -> 40:21:33; S 0-32767 / 0-117,964,799
    pytest.param("LD X0\nSTOH D10 D20\nDSTOHP D30 D40\n",
                 "0ms D10=11748 D30:d=145293 X0=1\n0ms expect D20=3 D21=15 D22=48 D40=40 D41=21 D42=33",
                 id="FNC165-page-examples"),
    pytest.param("LD X0\nSTOH D10 D20\n", "0ms D10=-1 D20=9 X0=1\n0ms expect D20=9 " + OP_ERROR,
                 id="FNC165-16-bit-range"),
    pytest.param("LD X0\nDSTOH D10 D20\n", "0ms D10:d=117964800 D20=9 X0=1\n0ms expect D20=9 " + OP_ERROR,
                 id="FNC165-32-bit-range"),
    # FNC 166 TRD D0: year, month, day, hour, minute, second, weekday (0 Sunday) = D9018 ... D9019
    pytest.param("LD X20\nTRD D0\n",
                 "0ms X20=1\n0ms expect D0=2000 D1=1 D2=1 D6=6\n10ms D9018=2024 D9017=2 D9016=29 "
                 "D9015=23 D9014=59 D9013=58\n10ms expect D0=2024 D1=2 D2=29 D3=23 D4=59 D5=58 D6=4",
                 id="FNC166-fields-and-order"),
    # FNC 167 TWR D0: the same order; a field outside its range is an operation error
    pytest.param("LD X20\nTWR D10\nLD M9000\nTRD D0\n",
                 "0ms D10=2030 D11=6 D12=15 D13=12 D14=30 D15=0 D16=6 X20=1\n"
                 "0ms expect D9018=2030 D9017=6 D9016=15 D9015=12 D9014=30 D0=2030 " + NO_ERROR,
                 id="FNC167-writes-the-calendar"),
    pytest.param("LD X20\nTWR D10\n", "0ms D10=2024 D11=13 D12=1 X20=1\n0ms expect " + OP_ERROR,
                 id="FNC167-month-13-op-error"),
    pytest.param("LD X20\nTWR D10\n", "0ms D10=2024 D11=1 D12=1 D16=7 X20=1\n0ms expect " + OP_ERROR,
                 id="FNC167-weekday-7-op-error"),
    pytest.param("LD X20\nTWR D10\n", "0ms D10=2100 D11=1 D12=1 X20=1\n0ms expect " + OP_ERROR,
                 id="FNC167-year-2000-2099"),
    # ---- 6-15 FNC 169 HOUR K1000 D7000 Y0: hours in D7000, seconds below the hour in D7001
    pytest.param("LD X0\nHOUR K1000 D7000 Y0\n",
                 "0ms D7000=999 D7001=3598 X0=1\n0ms expect Y0=0\n2s expect D7000=1000 D7001=0 Y0=1\n"
                 "3s X0=0\n5s expect D7000=1000 D7001=0 Y0=1\n6s D7000=10\n6s expect Y0=0",
                 id="FNC169-page-example-holds-when-off"),
    pytest.param("LD X0\nHOUR K1000 D7000 Y0\n",
                 "0ms D7000=32767 D7001=3598 X0=1\n3s expect D7000=32767 D7001=0 Y0=1",
                 id="FNC169-stops-at-the-largest-value"),
    pytest.param("LD X0\nHOUR K1000 D7000 Y0\nHOUR K1000 D100 Y1\n",
                 "0ms D7000=5 D7001=10 D100=5 D101=10 X0=1\n990ms expect D7000=5 D100=5\n1s power-cycle\n"
                 "1s expect D7000=5 D7001=10 D100=0 D101=0", id="FNC169-general-D1-cleared-at-power-off"),
    # FNC 170 GRY D0 K4Y20, FNC 171 GBIN K4X20 D0: 6513 <-> Gray H15C9
    pytest.param("LD X20\nGRY D0 K4Y20\n", "0ms D0=6513 X20=1\n0ms expect K4Y20=H15C9 " + NO_ERROR,
                 id="FNC170-page-example"),
    pytest.param("LD X20\nGRY D0 K4Y20\n", "0ms D0=-1 X20=1\n0ms expect K4Y20=0 " + OP_ERROR,
                 id="FNC170-negative-op-error"),
    pytest.param("LD X0\nGBIN K4X20 D0\n", "0ms K4X20=H15C9 X0=1\n0ms expect D0=6513 " + NO_ERROR,
                 id="FNC171-page-example"),
    pytest.param("LD X0\nGBIN K4X20 D0\n", "0ms K4X20=H8000 D0=3 X0=1\n0ms expect D0=3 " + OP_ERROR,
                 id="FNC171-negative-op-error"),
    # FNC 176-178 TFT/TFH/TFK D0 K100 M0: 10 ms / 100 ms / 1 s units, Off clears
    pytest.param("LD X0\nTFT D0 K100 M0\n",
                 "0ms X0=1\n990ms expect D0=99 M0=0\n1000ms expect D0=100 M0=1\n1010ms X0=0\n"
                 "1010ms expect D0=0 M0=0", id="FNC176-page-example"),
    pytest.param("LD X0\nTFT D0 D10 M0\n", "0ms D10=-5 X0=1\n0ms expect M0=1 D0=0",
                 id="FNC176-preset-outside-0-32767-is-0"),
    pytest.param("LD X0\nTFH D0 K100 M0\n",
                 "scan 100ms\n0ms X0=1\n9.9s expect D0=99 M0=0\n10s expect D0=100 M0=1\n10.1s X0=0\n"
                 "10.1s expect D0=0 M0=0", id="FNC177-page-example"),
    pytest.param("LD X0\nTFK D0 K100 M0\n",
                 "scan 1s\n0ms X0=1\n99s expect D0=99 M0=0\n100s expect D0=100 M0=1\n101s X0=0\n"
                 "101s expect D0=0 M0=0", id="FNC178-page-example"),
    # ---- 6-16 FNC 184 RND (the page's program: a seed kept in D7000 loaded at STOP->RUN)
    pytest.param("LD M9002\nDMOV D7000 D9160\nLDP X10\nRND D10\n",
                 "0ms expect D9160=0\n10ms X10=1\n10ms expect D10=0 " + NO_ERROR + "\n"
                 "20ms X10=0 D9160=1 D9161=0\n30ms X10=1\n30ms expect D10=16838",
                 id="FNC184-page-example-formula"),
    pytest.param("LDP X10\nRND D10\n", "0ms expect D9160=1\n10ms X10=1\n10ms expect D10=16838",
                 id="FNC184-seed-1-at-power-on"),
    pytest.param("LDP X10\nRND D10\n", "0ms D9161=H8000 D10=5 X10=1\n0ms expect D10=5 " + OP_ERROR,
                 id="FNC184-negative-seed-op-error"),
    # FNC 186 DUTY K10 K5 M9330
    pytest.param("LD X0\nDUTY K10 K5 M9330\n",
                 "10ms X0=1\n10ms expect M9330=1 D9330=0\n100ms expect M9330=1 D9330=9\n"
                 "110ms expect M9330=0 D9330=10\n160ms expect M9330=1 D9330=0\n170ms X0=0\n"
                 "270ms expect M9330=0 D9330=11", id="FNC186-page-example-runs-on-when-off"),
    pytest.param("LD X0\nDUTY K0 K5 M9331\nDUTY K3 K0 M9332\n",
                 "0ms X0=1\n0ms expect M9331=0 M9332=1\n100ms expect M9331=0 M9332=1",
                 id="FNC186-n1-0-off-n2-0-on"),
    pytest.param("LD X0\nDUTY D0 K5 M9330\n", "0ms D0=-1 X0=1\n0ms expect M9330=0 " + OP_ERROR,
                 id="FNC186-negative-n-op-error"),
    pytest.param("LD X0\nDUTY K10 K5 M9330\n",
                 "0ms X0=1\n30ms expect D9330=3\n40ms X0=0\n50ms X0=1\n50ms expect D9330=0 M9330=1",
                 id="FNC186-rising-edge-restarts-count"),
    # FNC 188 CRC D0 D100 K7: 01H 03H 04H EDH 85H A3H 28H -> 58A6H (16-bit mode: two bytes a
    # word, low first; M9161 On: one byte a word, result low/high byte into D100/D101)
    pytest.param("LD X20\nCRC D0 D100 K7\n",
                 "0ms D0=H0301 D1=HED04 D2=HA385 D3=H28 X20=1\n0ms expect D100:h=H58A6",
                 id="FNC188-16-bit-mode"),
    pytest.param("LD M9000\nOUT M9161\nLD X20\nCRC D0 D100 K7\n",
                 "0ms D0=1 D1=3 D2=4 D3=HED D4=H85 D5=HA3 D6=H28 X20=1\n0ms expect D100=HA6 D101=H58",
                 id="FNC188-8-bit-mode-M9161"),
    pytest.param("LD X20\nCRC D0 D100 D10\n", "0ms D10=0 D100=5 X20=1\n0ms expect D100=5 " + OP_ERROR,
                 id="FNC188-n-0-op-error"),
    # ---- 6-17 FNC 192/193 BK+P D0 D10 D20 K5 (wraps, no flags), overlap, constant S2
    pytest.param("LD X0\nBK+P D0 D10 D20 K5\n",
                 "0ms D0=32767 D10=1 D1=2 D11=3 X0=1\n0ms expect D20=-32768 D21=5 M9022=0 M9020=0 " + NO_ERROR,
                 id="FNC192-page-example-no-flags"),
    pytest.param("LD X0\nBK+ D0 K100 D20 K2\nDBK+ D40 D50 D60 D100\n",
                 "0ms D0=1 D1=2 D40:d=70000 D44:d=5 D50:d=1 D54:d=1 D100:d=3 X0=1\n"
                 "0ms expect D20=101 D21=102 D60:d=70001 D64:d=6", id="FNC192-constant-S2-and-32-bit-n"),
    pytest.param("LD X0\nBK+ D0 D10 D3 K5\n", "0ms D3=9 X0=1\n0ms expect D3=9 " + OP_ERROR,
                 id="FNC192-overlap-op-error"),
    pytest.param("LD X0\nBK+ D0 D10 D20 D100\n", "0ms D100=0 D20=4 X0=1\n0ms expect D20=4 " + OP_ERROR,
                 id="FNC192-n-below-1-op-error"),
    pytest.param("LD X0\nBK-P D0 D10 D20 K5\n",
                 "0ms D0=-32768 D10=1 D1=9 D11=4 X0=1\n0ms expect D20=32767 D21=5 M9021=0 " + NO_ERROR,
                 id="FNC193-page-example-no-flags"),
    pytest.param("LD X0\nBK- D0 D2 D4 K3\n", "0ms X0=1\n0ms expect " + OP_ERROR,
                 id="FNC193-overlap-op-error"),
    # FNC 194-199 BKCMP=P D0 D10 M0 K5 and each relation; M9090 On when every result is On
    pytest.param("LD X0\nBKCMP=P D0 D10 M0 K5\n",
                 "0ms D0=5 D1=9 D10=5 D11=8 X0=1\n0ms expect M0=1 M1=0 M2=1 M3=1 M4=1 M9090=0\n"
                 "10ms X0=0 D11=9\n20ms X0=1\n20ms expect M1=1 M9090=1", id="FNC194-page-example-M9090"),
    pytest.param("LD X0\nBKCMP> D0 D10 M0 K2\nDBKCMP> K7 D20 M10 K2\n",
                 "0ms D0=5 D1=9 D10=4 D11=9 D20:d=6 D22:d=6 X0=1\n0ms expect M0=1 M1=0 M10=1 M11=1 M9090=1",
                 id="FNC195-greater-constant-S1"),
    pytest.param("LD X0\nBKCMP< D0 D10 M0 K2\n", "0ms D0=3 D1=9 D10=4 D11=9 X0=1\n0ms expect M0=1 M1=0 M9090=0",
                 id="FNC196-less"),
    pytest.param("LD X0\nBKCMP<> D0 D10 M0 K2\n", "0ms D0=3 D1=9 D10=4 D11=8 X0=1\n0ms expect M0=1 M1=1 M9090=1",
                 id="FNC197-not-equal"),
    pytest.param("LD X0\nBKCMP<= D0 D10 M0 K2\n", "0ms D0=4 D1=9 D10=4 D11=8 X0=1\n0ms expect M0=1 M1=0 M9090=0",
                 id="FNC198-less-or-equal"),
    pytest.param("LD X0\nBKCMP>= K5 D10 M0 K2\n", "0ms D10=5 D11=4 X0=1\n0ms expect M0=1 M1=1 M9090=1",
                 id="FNC199-greater-or-equal"),
    # ---- 6-18 strings
    pytest.param("LD X0\nSTR D10 D20 D0\n",
                 "0ms D10=8 D11=2 D20=-12345 X0=1\n0ms expect D0:h=H202D D1:h=H3231 D2:h=H2E33 "
                 "D3:h=H3534 D4=0 " + NO_ERROR, id="FNC200-page-example"),
    pytest.param("LD X0\nSTR D10 D20 D0\n", "0ms D10=3 D20=123 X0=1\n0ms expect " + OP_ERROR,
                 id="FNC200-does-not-fit-op-error"),
    pytest.param("LD X0\nSTR D10 D20 D0\n", "0ms D10=9 D11=0 D20=1 X0=1\n0ms expect " + OP_ERROR,
                 id="FNC200-total-digits-2-8"),
    pytest.param("LD X0\nDSTR D10 D20 D0\n", "0ms D10=13 D11=11 D20:d=1 X0=1\n0ms expect " + OP_ERROR,
                 id="FNC200-32-bit-decimals-0-10"),
    pytest.param("LD X0\nSTR D10 D20 D0\nVAL D0 D30 D32\n",
                 "0ms D10=8 D11=2 D20=-12345 X0=1\n0ms expect D30=8 D31=2 D32=-12345 " + NO_ERROR,
                 id="FNC201-reads-str-back"),
    pytest.param('LD X0\n$MOV "12A" D0\nVAL D0 D30 D32\n', "0ms X0=1\n0ms expect " + OP_ERROR,
                 id="FNC201-not-a-number-op-error"),
    pytest.param('LD X0\n$+ "AB" "CDE" D0\n', "0ms X0=1\n0ms expect D0:h=H4241 D1:h=H4443 D2:h=H45",
                 id="FNC202-concatenates-with-terminator"),
    pytest.param("LD X0\n$+ D0 D10 D20\n", "0ms D0=0 D10=0 D20=HFFFF X0=1\n0ms expect D20=0",
                 id="FNC202-both-empty-0000H"),
    pytest.param('LD X0\n$MOV "AB" D0\n$+ D0 D0 D0\n', "0ms X0=1\n0ms expect " + OP_ERROR,
                 id="FNC202-same-device-op-error"),
    pytest.param('LD X0\n$MOV "I LIKE VIGOR" D0\nLEN D0 D30\n', "0ms X0=1\n0ms expect D30=12",
                 id="FNC203-length"),
    pytest.param("LD M9000\nMOV K0 Z0\nFOR K40\nLD M9000\nFMOV H4141 R0Z0 K512\nADD Z0 K512 Z0\nNEXT\n"
                 "LD M9000\nMOV K0 R16384\nLD X0\nLEN R0 D0\nLEN R16385 D1\n",
                 "0ms D0=5 X0=1\n0ms expect D0=5 D1=8190 " + OP_ERROR, id="FNC203-over-32767-characters-op-error"),
    pytest.param("LD X0\nLEN R23999 D0\n", "0ms R23999:h=H4141 X0=1\n0ms expect D0=0 " + OP_ERROR,
                 id="FNC203-no-terminator-op-error"),
    pytest.param('LD X0\n$MOV "I LIKE VIGOR" D0\nRIGHT D0 D40 K5\nRIGHT D0 D50 K0\n',
                 "0ms D50=7 X0=1\n0ms expect D40:h=H4956 D41:h=H4F47 D42:h=H52 D50=0", id="FNC204-page-example-n-0"),
    pytest.param('LD X0\n$MOV "VIGOR" D0\nRIGHT D0 D40 K6\n', "0ms X0=1\n0ms expect " + OP_ERROR,
                 id="FNC204-n-past-the-string-op-error"),
    pytest.param('LD X0\n$MOV "I LIKE VIGOR" D0\nLEFT D0 D50 K6\n',
                 "0ms X0=1\n0ms expect D50:h=H2049 D51:h=H494C D52:h=H454B D53=0", id="FNC205-page-example"),
    pytest.param('LD X0\n$MOV "VIGOR" D0\nLEFT D0 D50 D10\n', "0ms D10=-1 X0=1\n0ms expect " + OP_ERROR,
                 id="FNC205-negative-n-op-error"),
    pytest.param('LD X0\n$MOV "I LIKE VIGOR" D0\nMIDR D0 D10 D200\nMIDR D0 D20 D202\n',
                 "0ms D200=3 D201=4 D202=3 D203=-1 X0=1\n0ms expect D10:h=H494C D11:h=H454B D12=0 "
                 "D20:h=H494C D24:h=H524F D25=0", id="FNC206-page-example-minus-1-to-the-end"),
    pytest.param('LD X0\n$MOV "VIGOR" D0\nMIDR D0 D10 D200\n', "0ms D10=7 D200=1 D201=0 X0=1\n0ms expect D10=7 "
                 + NO_ERROR, id="FNC206-count-0-not-executed"),
    pytest.param('LD X0\n$MOV "VIGOR" D0\nMIDR D0 D10 D200\n', "0ms D200=4 D201=3 X0=1\n0ms expect " + OP_ERROR,
                 id="FNC206-outside-the-string-op-error"),
    pytest.param('LD X0\n$MOV "I LIKE VIGOR" D0\n$MOV "LOVE168" D110\nMIDW D110 D0 D204\n',
                 "0ms D204=3 D205=4 X0=1\n0ms expect D0:h=H2049 D1:h=H4F4C D2:h=H4556", id="FNC207-page-example"),
    pytest.param('LD X0\n$MOV "I LIKE VIGOR" D30\n$MOV "LOVE168" D110\nMIDW D110 D30 D206\n',
                 "0ms D206=8 D207=-1 X0=1\n0ms expect D33:h=H4C20 D34:h=H564F D35:h=H3145 D36=0",
                 id="FNC207-minus-1-whole-S1-only-what-fits"),
    pytest.param('LD X0\n$MOV "VIGOR" D0\n$MOV "AB" D110\nMIDW D110 D0 D204\n',
                 "0ms D204=9 D205=1 X0=1\n0ms expect " + OP_ERROR, id="FNC207-position-outside-op-error"),
    pytest.param('LD X0\n$MOV "VIGOR" D100\n$MOV "I LIKE VIGOR" D60\nINSTR D100 D60 D40 K3\n'
                 'INSTR D100 D60 D41 K0\n',
                 "0ms D41=9 X0=1\n0ms expect D40=8 D41=9 " + NO_ERROR, id="FNC208-page-example-n-0-not-executed"),
    pytest.param('LD X0\n$MOV "VIGOR" D100\n$MOV "ABC" D60\nINSTR D100 D60 D40 K5\n',
                 "0ms X0=1\n0ms expect " + OP_ERROR, id="FNC208-n-past-S2-op-error"),
    pytest.param('LD X0\n$MOV "VIGOR" D0\n', "0ms D2=HFFFF X0=1\n0ms expect D0:h=H4956 D1:h=H4F47 D2:h=H52",
                 id="FNC209-odd-length-00H"),
    pytest.param("LD X0\n$MOV R23999 D0\n", "0ms R23999:h=H4141 X0=1\n0ms expect " + OP_ERROR,
                 id="FNC209-no-terminator-op-error"),
    # ---- 6-19 FNC 210 FDEL / 211 FINS / 212 POPP D0 D101 K10 / 213-214 SFRP D0 K4, SFLP D1 K4
    pytest.param("LD X0\nFDELP D50 D0 K2\n", "0ms D0=3 D1=10 D2=20 D3=30 X0=1\n0ms expect D50=20 D0=2 D1=10 D2=30",
                 id="FNC210-deletes-entry-n"),
    pytest.param("LD X0\nFDELP D50 D0 K4\n", "0ms D0=3 D50=7 X0=1\n0ms expect D50=7 D0=3 " + OP_ERROR,
                 id="FNC210-n-1-to-count-op-error"),
    pytest.param("LD X0\nFINSP K99 D0 K4\n", "0ms D0=3 D1=10 D2=20 D3=30 X0=1\n0ms expect D0=4 D4=99",
                 id="FNC211-n-count-plus-1"),
    pytest.param("LD X0\nFINSP K99 D0 D20\n", "0ms D0=3 D20=0 X0=1\n0ms expect D0=3 " + OP_ERROR,
                 id="FNC211-n-0-op-error"),
    pytest.param("LD X0\nPOPP D0 D101 K10\n",
                 "0ms D0=2 D1=11 D2=22 X0=1\n0ms expect D101=22 D0=1 M9020=0\n10ms X0=0\n20ms X0=1\n"
                 "20ms expect D101=11 D0=0 M9020=1\n30ms X0=0 D101=5\n40ms X0=1\n40ms expect D101=5 D0=0 M9020=1",
                 id="FNC212-page-example-pointer-0-M9020"),
    pytest.param("LD X0\nSFRP D0 K4\nSFLP D1 K4\n",
                 "0ms D0=HFF08 D1=H1FFF X0=1\n0ms expect D0:h=H0FF0 D1:h=HFFF0 M9022=1",
                 id="FNC213-214-page-examples-carry"),
    pytest.param("LD X0\nSFRP D0 K4\n", "0ms D0=H0007 X0=1\n0ms expect D0=0 M9022=0",
                 id="FNC213-last-bit-out-0"),
    pytest.param("LD X0\nPOP D0 D101 K3\n", "0ms D0=5 D101=7 X0=1\n0ms expect D101=7 D0=5 " + OP_ERROR,
                 id="FNC212-pointer-past-the-file-op-error"),
    pytest.param("LD X0\nSFR D0 K0\n", "0ms D0=H00F1 M9022=1 X0=1\n0ms expect D0=H00F1 M9022=1 " + NO_ERROR,
                 id="FNC213-n-0-nothing-moves"),
    # ---- 6-20 comparison contacts: the page's program
    pytest.param("LD= K100 D0\nAND X0\nOUT Y0\nLD X1\nANDD<> C235 K10\nORD<= D100 D200\nOUT Y1\n",
                 "0ms D0=100 X0=1 X1=1\n0ms expect Y0=1 Y1=1\n10ms D0=99 C235:d=10 D100:d=70000 "
                 "D200:d=69999\n10ms expect Y0=0 Y1=0\n20ms D200:d=70000\n20ms expect Y1=1",
                 id="FNC224-page-example"),
    # ---- 6-21 FNC 256-258 examples; S1 > S2: an operation error (DECISION)
    pytest.param("LD X0\nLIMIT K500 K1000 D0 D1\nBAND K-5000 K5000 D0 D2\nZONE K-5000 K5000 D0 D3\n",
                 "0ms X0=1 D0=300\n0ms expect D1=500 D2=0 D3=5300\n10ms D0=-6000\n"
                 "10ms expect D1=500 D2=-1000 D3=-11000\n20ms D0=7000\n20ms expect D1=1000 D2=2000 D3=12000\n"
                 "30ms D0=0\n30ms expect D3=0 D2=0 " + NO_ERROR, id="FNC256-258-page-examples"),
    pytest.param("LD X0\nLIMIT K1000 K500 D0 D1\n", "0ms D0=700 D1=3 X0=1\n0ms expect D1=3 " + OP_ERROR,
                 id="FNC256-S1-above-S2-op-error"),
    pytest.param("LD X0\nBAND K5000 K-5000 D0 D1\n", "0ms D0=700 D1=3 X0=1\n0ms expect D1=3 " + OP_ERROR,
                 id="FNC257-S1-above-S2-op-error"),
    pytest.param("LD X0\nZONE K-100 K100 D0 D1\nDZONE K-100 K100 D10 D12\n",
                 "0ms D0=32700 D10:d=2147483600 X0=1\n0ms expect D1=-32736 D12:d=-2147483596 " + NO_ERROR,
                 id="FNC258-wraps-no-flags"),
    # FNC 259 SCL D0 D1000 D10: (D1000) points, then X1, Y1, X2, Y2 ...; round half up
    pytest.param("LD X0\nSCL D0 D1000 D10\n",
                 "0ms D1000=3 D1001=0 D1002=0 D1003=10 D1004=100 D1005=20 D1006=105 D0=5 X0=1\n"
                 "0ms expect D10=50\n10ms D0=15\n10ms expect D10=103 " + NO_ERROR, id="FNC259-interpolates-half-up"),
    pytest.param("LD X0\nSCL D0 D1000 D10\n",
                 "0ms D1000=3 D1001=0 D1002=0 D1003=10 D1004=100 D1005=10 D1006=200 D0=10 X0=1\n"
                 "0ms expect D10=200", id="FNC259-same-X-takes-point-2"),
    pytest.param("LD X0\nSCL D0 D1000 D10\n",
                 "0ms D1000=2 D1001=10 D1002=0 D1003=0 D1004=100 D0=5 D10=7 X0=1\n0ms expect D10=7 " + OP_ERROR,
                 id="FNC259-X-not-ascending-6706"),
    pytest.param("LD X0\nDSCL D0 D1000 D10\n",
                 "0ms D1000:d=2 D1002:d=0 D1004:d=0 D1006:d=70000 D1008:d=100 D0:d=5 X0=1\n0ms expect "
                 + OP_ERROR,
                 id="FNC259-points-65535-apart-6706"),
    pytest.param("LD X0\nSCL D0 D1000 D10\n",
                 "0ms D1000=2 D1001=0 D1002=0 D1003=10 D1004=100 D0=11 X0=1\n0ms expect " + OP_ERROR,
                 id="FNC259-S1-outside-the-table-6706"),
    # FNC 269 SCL2: points, X1 .. Xn, Y1 .. Yn
    pytest.param("LD X0\nSCL2 D0 D1000 D10\n",
                 "0ms D1000=2 D1001=0 D1002=10 D1003=0 D1004=100 D0=5 X0=1\n0ms expect D10=50 " + NO_ERROR
                 + "\n10ms D0=12\n10ms expect " + OP_ERROR, id="FNC269-table-layout-and-6706"),
    # FNC 260 DABIN D0 D10: "-  125"; 20H, 00H, 30H read as 0; another character: op error
    pytest.param("LD X0\nDABIN D0 D10\n", "0ms D0=H202D D1=H3120 D2=H3532 X0=1\n0ms expect D10=-125 "
                 + NO_ERROR, id="FNC260-page-example"),
    pytest.param("LD X0\nDABIN D0 D10\n", "0ms D0=H412D D1=H3120 D2=H3532 D10=4 X0=1\n0ms expect D10=4 "
                 + OP_ERROR, id="FNC260-bad-character-op-error"),
    pytest.param("LD X0\nDDABIN D0 D10\n",
                 "0ms D0=H322D D1=H3431 D2=H3437 D3=H3338 D4=H3436 D5=H0038 X0=1\n0ms expect D10:d=-2147483648 "
                 + NO_ERROR + "\n10ms D1=H3232 D2=H3232 D3=H3232 D4=H3232 D5=H3232\n10ms expect D10:d=-2147483648 "
                 + OP_ERROR, id="FNC260-32-bit-range"),
    # FNC 261 BINDA D10 D0: 125 -> " " "  125" + 0000H (M9091 Off) / nothing (M9091 On)
    pytest.param("LD X0\nBINDA D10 D0\n", "0ms D10=125 D3=HFFFF X0=1\n0ms expect D0:h=H2020 D1:h=H3120 "
                 "D2:h=H3532 D3=0", id="FNC261-page-example-M9091-off"),
    pytest.param("LD X0\nDBINDA D10 D0\n", "0ms D10:d=-123456789 X0=1\n0ms expect D0:h=H202D D1:h=H3231 "
                 "D2:h=H3433 D3:h=H3635 D4:h=H3837 D5:h=H0039", id="FNC261-32-bit-last-high-byte-00H"),
    pytest.param("LD M9000\nOUT M9091\nLD X0\nBINDA D10 D0\n", "0ms D10=-125 D3=7 X0=1\n0ms expect "
                 "D0:h=H202D D1:h=H3120 D2:h=H3532 D3=7", id="FNC261-M9091-on-no-terminator"),
    # ---- 8-3 positioning (no ramps: D9343 = D9344 = 0)
    pytest.param("LD M0\nJOGF K9000 K1000 Y0 Y4\n",
                 "0ms D9343=0 D9344=0 M0=1\n4.9s expect D9354:d=1\n5.1s expect D9354:d=90..110 D9350:d=1000",
                 id="FNC301-S1-above-5000-is-5000"),
    pytest.param("LD M0\nJOGR K-5 K1000 Y0 Y4\n", "0ms D9343=0 D9344=0 M0=1\n100ms expect D9354:d=-110..-90 Y4=0",
                 id="FNC302-S1-below-0-is-0"),
    pytest.param("LD M0\nDDRVR K100000 K10 Y0 Y4\n", "0ms D9343=0 D9344=0 D9342=100 M0=1\n"
                 "100ms expect D9350:d=100", id="FNC303-speed-below-bias-is-bias"),
    pytest.param("LD M0\nDDRVR K100000 K900000 Y0 Y4\n", "0ms D9343=0 D9344=0 D9340:d=20000 M0=1\n"
                 "100ms expect D9350:d=20000", id="FNC303-speed-above-max-is-max"),
    pytest.param("LD M0\nDDRVR K100 K1000 Y0 Y4\n", "0ms D9343=0 D9344=0 M0=1\n90ms expect M9342=0 M9340=1\n"
                 "110ms expect M9342=1 D9354:d=100\n200ms M0=0\n200ms expect M9342=0 M9340=0",
                 id="FNC303-done-M9342-until-off-busy-M9340"),
    pytest.param("LD M0\nLIR D1000 K0\n", "0ms D1000=500 D1001=100 D1002=300 D1003=4000 D1004=3000 M0=1\n"
                 "0ms expect Y0=0 " + OP_ERROR, id="FNC315-bias-above-run-speed-op-error"),
    pytest.param("LD M0\nDDRVA K1000 K1000 Y0 Y4\n", "0ms D9343=0 D9344=0 D9348=2000 M0=1\n"
                 "100ms expect D9350:d=2000\n", id="FNC304-override-D9348"),
    pytest.param("LD M0\nDDRVA K1000 K1000 Y0 Y4\n", "0ms D9343=0 D9344=0 D9348=0 M0=1\n"
                 "100ms expect D9350:d=1000\n", id="FNC304-override-outside-1-30000-is-1000"),
]


@pytest.mark.parametrize("il, stim", RUNS)
def test_run_rule(il, stim):
    run(il, stim)


# FNC 224-246: each comparison contact, 16- and 32-bit, as a load, a series and a parallel
# contact (the page's table; 32-bit written LDD= ...)
COMPARE = {224: "LD=", 225: "LD>", 226: "LD<", 228: "LD<>", 229: "LD<=", 230: "LD>=",
           232: "AND=", 233: "AND>", 234: "AND<", 236: "AND<>", 237: "AND<=", 238: "AND>=",
           240: "OR=", 241: "OR>", 242: "OR<", 244: "OR<>", 245: "OR<=", 246: "OR>="}
_REL = {"=": lambda a, b: a == b, ">": lambda a, b: a > b, "<": lambda a, b: a < b,
        "<>": lambda a, b: a != b, "<=": lambda a, b: a <= b, ">=": lambda a, b: a >= b}


@pytest.mark.parametrize("fnc", sorted(COMPARE), ids=[f"FNC{n}" for n in sorted(COMPARE)])
def test_comparison_contacts(fnc):
    name = COMPARE[fnc]
    stem = name.rstrip("=<>")
    rel = name[len(stem):]
    d_form = f"{stem}D{rel}"
    circuit = {"LD": f"{name} D0 D1\nOUT Y0\n{d_form} D10 D12\nOUT Y1\n",
               "AND": f"LD X0\n{name} D0 D1\nOUT Y0\nLD X0\n{d_form} D10 D12\nOUT Y1\n",
               "OR": f"LD X1\n{name} D0 D1\nOUT Y0\nLD X1\n{d_form} D10 D12\nOUT Y1\n"}[stem]
    stim = ["0ms X0=1"]
    for k, (a, b) in enumerate([(5, 5), (5, 6), (6, 5), (-1, 1)]):
        big = 70000 * (a if a else 1)
        wide = (big, 70000 * b)
        stim.append(f"{10 * k}ms D0={a} D1={b} D10:d={wide[0]} D12:d={wide[1]}")
        stim.append(f"{10 * k}ms expect Y0={int(_REL[rel](a, b))} Y1={int(_REL[rel](*wide))}")
    run(circuit, "\n".join(stim))
