"""Vigor VS simulation of the FX-family data instructions (mlctool/targets/vs/): each case is
the example printed on the instruction's page (manual ch. 6), with its figures' values."""

from __future__ import annotations

import pytest

from vskit import VS, run  # noqa: F401  (other test modules import run from here)

# ------------------------------------------------------------------ 6-5 rotation and shifts

def test_rcr_rcl_rotate_through_the_carry():
    # FNC 32/33 example: RCRP D0 K4 / RCLP D1 K4 on X20/X21, 16 bits plus M9022 as one ring
    run("LDP X20\nRCR D0 K4\nLDP X21\nRCL D1 K4\nLD X22\nDRCR D2 K1\n",
        "0ms D0:h=H1234 D1:h=H1234 M9022=1\n10ms X20=1\n10ms expect D0:h=H9123 M9022=0\n"
        "20ms X20=0 X21=1 M9022=1\n20ms expect D1:h=H2348 M9022=1\n"
        "30ms X21=0 D2:d=1 M9022=0\n40ms X22=1\n40ms expect D2:d=0 M9022=1\n"
        "50ms expect D2:d=H80000000 M9022=0")


def test_sftr_sftl_bit_shift_registers():
    # FNC 34/35 example: SFTRP X0 M0 K16 K4 moves M0-M15 right 4, X0-X3 into M12-M15;
    # SFTLP X0 M0 K16 K4 moves them left 4, X0-X3 into M0-M3
    run("LDP X20\nSFTR X0 M0 K16 K4\nLDP X21\nSFTL X0 M20 K16 K4\n",
        "0ms K4M0=H1234 K4M20=H1234 K1X0=H9\n10ms X20=1 X21=1\n"
        "10ms expect K4M0=H9123 K4M20=H2349")


def test_wsfr_wsfl_word_shift_registers():
    # FNC 36 example: WSFRP D100 D0 K12 K3: D3-D11 -> D0-D8, D100-D102 -> D9-D11;
    # FNC 37 example: WSFLP K1X20 K1Y20 K4 K1: nibbles of Y20-Y37 move up, X20-X23 into Y20-Y23
    run("LDP X0\nWSFR D100 D0 K12 K3\nLDP X0\nWSFL K1X20 K1Y20 K4 K1\n",
        "0ms D3=3 D11=11 D100=100 D101=101 D102=102 K4Y20=H4321 K1X20=H7\n10ms X0=1\n"
        "10ms expect D0=3 D8=11 D9=100 D10=101 D11=102 K4Y20=H3217")


def test_sfwr_sfrd_fifo():
    # FNC 38/39 examples: SFWRP D100 D0 K10 writes at D0+1 after D0 +1; SFRDP D0 D101 K10
    # reads D1, shifts D2-D9 down, D0 -1; full file -> M9022, empty file -> M9020
    run("LDP X20\nSFWR D100 D0 K3\nLDP X21\nSFRD D0 D101 K3\n",
        "0ms D100=7\n10ms X20=1\n10ms expect D0=1 D1=7\n20ms X20=0 D100=8\n30ms X20=1\n"
        "30ms expect D0=2 D2=8 M9022=0\n40ms X20=0\n50ms X20=1\n50ms expect D0=2 M9022=1\n"
        "60ms X21=1\n60ms expect D101=7 D1=8 D0=1 M9020=0\n70ms X21=0\n80ms X21=1\n"
        "80ms expect D101=8 D0=0 M9020=1\n90ms X21=0 D101=0\n100ms X21=1\n100ms expect D101=0 M9020=1")


# ------------------------------------------------------------------ 6-3, 6-6 data

def test_smov_bcd_and_hex_modes():
    # FNC 13 example: SMOV D0 K3 K2 D1 K2: digits 3-2 of D0 to digits 2-1 of D1 (BCD)
    run("LD X20\nSMOV D0 K3 K2 D1 K2\nLD X21\nSMOV D2 K4 K1 D3 K4\n",
        "0ms D0=1234 D1=5678 D2:h=HABCD D3:h=H0123 M9168=0\n10ms X20=1\n10ms expect D1=5623\n"
        "20ms X20=0 X21=1 M9168=1\n20ms expect D3:h=HA123")
    r = run("LD X20\nSMOV D0 K3 K2 D1 K2\n", "0ms D0=-1 X20=1\n0ms expect M9067=1 D9067=6706 M9004=1",
            alarms=True)
    assert r.alarms[0].name == "OPERATION_ERROR"


def test_mean_drops_the_remainder():
    # FNC 45 example: (150 + 200 + 88 + 100 + 100) / 5 = 127, remainder 3 dropped
    run("LD X20\nMEAN D0 D10 K5\nDMEAN D20 D30 K2\n",
        "0ms D0=150 D1=200 D2=88 D3=100 D4=100 D20:d=100000 D22:d=-3\n10ms X20=1\n"
        "10ms expect D10=127 D30:d=49998")


def test_sqr_flags_and_negative():
    # FNC 48: result truncated, M9021 when a fraction dropped, M9020 when 0
    run("LD X20\nSQR D0 D1\nDSQR D2 D4\n", "0ms D0=10 D2:d=1000000 X20=1\n"
        "0ms expect D1=3 D4:d=1000 M9021=0\n10ms D2:d=0\n10ms expect D4:d=0 M9020=1\n"
        "20ms D0=17 D2:d=16\n20ms expect D1=4 M9021=0")
    run("LD X20\nSQR D0 D1\n", "0ms D0=-4 X20=1\n0ms expect D1=0 M9067=1", alarms=True)


def test_ans_anr_alarm_steps():
    # FNC 46/47 example: ANS T0 K15 S900 (X20 and X21 On 1.5 s), ANRP on X0 resets the
    # lowest alarm; M9049 On: M9048 and D9049 monitor (6-6 ANS application example)
    run("LD M9000\nOUT M9049\nLD X20\nAND X21\nANS T0 K15 S900\nLD X22\nANS T1 K5 S901\n"
        "LD X0\nANRP\nLD X1\nANR\n",
        "0ms X20=1 X21=1\n1s X21=0\n1s expect S900=0 T0:w=0\n1.1s X21=1\n2.5s expect S900=0\n"
        "2.6s expect S900=1 M9048=1 D9049=900\n2.7s X20=0 X22=1\n2.7s expect S900=1 T0:w=0\n"
        "3.3s expect S901=1\n3.4s X0=1\n3.4s expect S900=0 S901=1 D9049=901\n3.5s X0=0\n"
        "3.6s X0=1 X22=0\n3.6s expect S901=0 M9048=0")


# ------------------------------------------------------------------ 6-8 SER, SORT

def test_ser_search():
    # FNC 61 example: 10 values, S2 = 100: 4 equal, first 0, last 8, min at 5, max at 9;
    # ties of the minimum take the larger index
    run("LD X20\nSER D0 D10 D20 K10\nDSER D40 D60 D70 K3\n",
        "0ms D0=100 D1=111 D2=100 D3=98 D4=123 D5=66 D6=100 D7=95 D8=100 D9=210 D10=100 "
        "D40:d=70000 D42:d=-5 D44:d=70000 D60:d=70000\n10ms X20=1\n"
        "10ms expect D20=4 D21=0 D22=8 D23=5 D24=9 D70:d=2 D72:d=0 D74:d=2 D76:d=1 D78:d=2")


def test_sort_takes_m1_scans():
    # FNC 69 example: 5 records x 4 fields (number, Chinese, maths, English), sorted on the
    # field D200 = 2: numbers 2 4 1 5 3; M9029 On for one scan when done
    table = ("D0=1 D1=2 D2=3 D3=4 D4=5 D5=80 D6=65 D7=90 D8=75 D9=80 D10=70 D11=70 D12=65 "
             "D13=90 D14=85 D15=75 D16=90 D17=80 D18=65 D19=95 D200=2")
    run("LD X20\nSORT D0 K5 K4 D100 D200\n",
        f"0ms {table}\n10ms X20=1\n40ms expect D100=0 M9029=0\n50ms expect D100=2 D101=4 D102=1 "
        "D103=5 D104=3 D105=65 D106=75 D107=80 D108=80 D109=90 D110=70 D111=90 D112=70 "
        "D113=85 D114=65 D115=90 D116=65 M9029=1\n60ms expect M9029=0")


# ------------------------------------------------------------------ 6-17 block instructions

def test_block_add_sub_and_overlap():
    # FNC 192/193 examples: BK+P D0 D10 D20 K5, S2 = K100, DBK+ with n in (D101, D100) = 3
    run("LD X0\nBK+P D0 D10 D20 K5\nBK- D0 K100 D30 K2\nDBK+ D40 D50 D60 D100\nDBK- D40 K1 D70 K1\n",
        "0ms D0=-1 D1=2 D4=32767 D10=-10 D11=3 D14=1 D40:d=70000 D44:d=-1 D50:d=1 D54:d=1 "
        "D100:d=3\n10ms X0=1\n10ms expect D20=-11 D21=5 D24=-32768 D30=-101 D31=-98 "
        "D60:d=70001 D64:d=0 D70:d=69999 M9022=0")
    run("LD X0\nBK+ D0 D10 D3 K5\n", "0ms X0=1\n0ms expect M9067=1", alarms=True)


@pytest.mark.parametrize("line, bits", [
    ("BKCMP= D0 D10 M0 K5", "10100"), ("BKCMP> D0 D10 M0 K5", "01000"),
    ("BKCMP< D0 D10 M0 K5", "00011"), ("BKCMP<> D0 D10 M0 K5", "01011"),
    ("BKCMP<= D0 D10 M0 K5", "10111"), ("BKCMP>= D0 D10 M0 K5", "11100"),
])
def test_block_compare(line, bits):
    # FNC 194-199 example: BKCMP=P D0 D10 M0 K5, result bits M0-M4; M9090 when all On; the
    # 32-bit form with a constant S1 against (D21, D20), (D23, D22)
    mnemonic = line.split()[0]
    expect = " ".join(f"M{k}={b}" for k, b in enumerate(bits))
    run(f"LD X0\n{line}\nD{mnemonic} K7 D20 M10 K2\n",
        "0ms D0=5 D1=9 D2=-3 D3=1 D4=2 D10=5 D11=8 D12=-3 D13=4 D14=6 D20:d=7 D22:d=7\n"
        f"10ms X0=1\n10ms expect {expect} M9090={1 if mnemonic in ('BKCMP=', 'BKCMP<=', 'BKCMP>=') else 0}")


# ------------------------------------------------------------------ 6-12 floats

def test_float_family():
    # FNC 111-135 pages: EZCP zones, EBCD 1.234e2 -> 1234 x 10^-1, EBIN 2345 x 10^5,
    # EXP 2.1, LOGE 10, LOG10 20, ESQR, ENEG, SIN 45 deg, COS, TAN, ASIN 0.8660254,
    # ACOS 0.5, ATAN 1.732051 (all 1.047198)
    run("""
LD X0
DEZCP E1 E2 D0 M0
DEZCP E5 E2 D2 M3
DEBCD E123.4 D10
DEBIN D12 D14
DEXP E2.1 D16
DLOGE E10 D18
DLOG10 E20 D20
DESQR E16 D22
DEMOV E-123.45 D24
DENEG D24
DSIN E0.785398 D26
DCOS E0 D28
DTAN E0.785398 D30
DASIN E0.8660254 D32
DACOS E0.5 D34
DATAN E1.732051 D36
""", "0ms D0:f=1.5 D2:f=5 D12=2345 D13=5 X0=1\n0ms expect M0=0 M1=1 M2=0 M3=0 M4=1 M5=0 "
         "D10=1234 D11=-1 D14:f=234500000 D16:f=8.16616..8.16618 D18:f=2.302584..2.302586 "
         "D20:f=1.301029..1.301031 D22:f=4 D24:f=123.45 D26:f=0.707106..0.707108 D28:f=1 "
         "D30:f=0.999999..1.000001 D32:f=1.047197..1.047199 D34:f=1.047197..1.047199 "
         "D36:f=1.047197..1.047199 M9020=0")


@pytest.mark.parametrize("line", ["DLOGE E0 D0", "DLOG10 E-1 D0", "DESQR E-4 D0", "DASIN E1.5 D0",
                                  "DACOS E-2 D0", "DEXP E100 D0"])
def test_float_domain_errors(line):
    run(f"LD X0\n{line}\n", "0ms X0=1\n0ms expect M9067=1 D0=0", alarms=True)


# ------------------------------------------------------------------ 6-18 strings

def test_str_val_formats():
    # FNC 200: D10 = 8, D11 = 2, D20 = -12345 -> "-  123.45"; 32-bit D10 = 13, D11 = 8,
    # -123450 -> "-  0.00123450" (13 characters); FNC 201 reads them back
    run("LD X0\nSTR D10 D20 D0\nDSTR D30 D40 D50\nVAL D0 D60 D62\nDVAL D50 D64 D66\n",
        "0ms D10=8 D11=2 D20=-12345 D30=13 D31=8 D40:d=-123450 X0=1\n"
        "0ms expect D0:h=H202D D1:h=H3231 D2:h=H2E33 D3:h=H3534 D4:h=0 "
        "D50:h=H202D D51:h=H3020 D52:h=H302E D53:h=H3130 D54:h=H3332 D55:h=H3534 D56:h=H0030 "
        "D60=8 D61=2 D62=-12345 D64=13 D65=8 D66:d=-123450")
    run("LD X0\nSTR D10 D20 D0\n", "0ms D10=3 D20=123 X0=1\n0ms expect M9067=1", alarms=True)


STRINGS = '$MOV "I LIKE VIGOR" D0\n$MOV "VIGOR" D100\n'


def test_concat_len_right_left():
    # FNC 202-205 examples on "I LIKE VIGOR": $+ " I LIKE " "VIGOR"; LEN 12; RIGHT 5; LEFT 6
    run(f'LD X0\n{STRINGS}$+ "I LIKE " D100 D20\nLEN D0 D30\nRIGHT D0 D40 K5\nLEFT D0 D50 K6\n'
        '$+ D0 D100 D0\n',
        "0ms X0=1\n0ms expect D20:h=H2049 D21:h=H494C D22:h=H454B D23:h=H5620 D24:h=H4749 "
        "D25:h=H524F D26:h=0 D30=12 D40:h=H4956 D41:h=H4F47 D42:h=H0052 D50:h=H2049 "
        "D51:h=H494C D52:h=H454B D53:h=0 M9067=1", alarms=True)


def test_midr_midw_instr():
    # FNC 206-208 examples: MIDR from 3, 4 chars "LIKE" / -1 "LIKE VIGOR"; MIDW "LOVE168"
    # 4 chars at 3 -> "I LOVE VIGOR", all at 8 -> "I LIKE LOVE1"; INSTR "VIGOR" from 3 -> 8
    run(f'LD X0\n{STRINGS}$MOV "LOVE168" D110\nMIDR D0 D10 D200\nMIDR D0 D20 D202\n'
        'MIDW D110 D0 D204\n$MOV "I LIKE VIGOR" D30\nMIDW D110 D30 D206\n'
        '$MOV "I LIKE VIGOR" D60\nINSTR D100 D60 D40 K3\nINSTR "LIKE" D60 D41 K5\n'
        'INSTR "LIKE" D60 D42 K1\n',
        "0ms D200=3 D201=4 D202=3 D203=-1 D204=3 D205=4 D206=8 D207=-1 X0=1\n"
        "0ms expect D10:h=H494C D11:h=H454B D12=0 D20:h=H494C D21:h=H454B D22:h=H5620 "
        "D23:h=H4749 D24:h=H524F D25=0 D0:h=H2049 D1:h=H4F4C D2:h=H4556 "
        "D33:h=H4C20 D34:h=H564F D35:h=H3145 D36=0 D40=8 D41=0 D42=3")


def test_string_without_terminator_is_an_operation_error():
    run("LD X0\nLEN R23999 D0\n", "0ms R23999:h=H4141 X0=1\n0ms expect M9067=1 D0=0", alarms=True)


# ------------------------------------------------------------------ 6-14 clock

def test_virtual_calendar_trd_twr():
    # FNC 166/167: TRD D0 reads year..second, weekday; the calendar starts at 2000-01-01
    # 00:00:00 (a Saturday) and runs on virtual time; TWR and stimulus writes set it
    run("LD X20\nTRD D0\nLD X21\nTWR D10\n",
        "0ms X20=1\n0ms expect D0=2000 D1=1 D2=1 D3=0 D4=0 D5=0 D6=6 D9019=6\n"
        "61s expect D4=1 D5=1 D9013=1 D9014=1\n"
        "70s D10=2024 D11=2 D12=29 D13=23 D14=59 D15=58 D16=4 X21=1\n70.01s X21=0\n"
        "72s expect D0=2024 D1=3 D2=1 D3=0 D4=0 D5=0 D6=5\n"
        "80s D9018=2099 D9017=12 D9016=31\n80s expect D0=2099 D1=12 D2=31 D9018=2099")
    run("LD X21\nTWR D10\n", "0ms D10=2024 D11=2 D12=30 X21=1\n0ms expect M9067=1", alarms=True)


def test_time_compare_add_sub_convert():
    # FNC 160-165 examples: TCMP K8 K30 K20 D0 M0; TZCP; TADD 8:30:00 + 6:35:30 = 15:05:30,
    # 8:25:30 + 20:10:20 = 4:35:50 with M9022; TSUB 18:28:50 - 8:40:20 = 9:48:30,
    # 6:30:20 - 20:20:10 = 10:10:10 with M9021; HTOS 3:15:48 = 11748 s, DHTOS 40:21:33 = 145293
    run("""
LD X20
TCMP K8 K30 K20 D0 M0
TZCP D10 D13 D0 M3
TADD D20 D23 D26
TSUB D30 D33 D36
TADD D40 D43 D46
TSUB D50 D53 D56
HTOS D60 D63
DHTOS D64 D68
STOH D63 D70
DSTOH D68 D73
""", "0ms D0=8 D1=30 D2=21 D10=8 D11=0 D12=0 D13=9 D14=0 D15=0 D20=8 D21=30 D23=6 D24=35 "
     "D25=30 D30=18 D31=28 D32=50 D33=8 D34=40 D35=20 D40=8 D41=25 D42=30 D43=20 D44=10 "
     "D45=20 D50=6 D51=30 D52=20 D53=20 D54=20 D55=10 D60=3 D61=15 D62=48 D64=40 D65=21 "
     "D66=33 X20=1\n0ms expect M0=0 M1=0 M2=1 M3=0 M4=1 M5=0 D26=15 D27=5 D28=30 D36=9 "
     "D37=48 D38=30 D46=4 D47=35 D48=50 D56=10 D57=10 D58=10 D63=11748 D68:d=145293 "
     "D70=3 D71=15 D72=48 D73=40 D74=21 D75=33 M9021=1 M9022=0")
    run("LD X20\nTADD D40 D43 D46\n", "0ms D40=8 D41=25 D42=30 D43=20 D44=10 D45=20 X20=1\n"
        "0ms expect D46=4 D47=35 D48=50 M9022=1 M9020=0")


# ------------------------------------------------------------------ 6-15, 6-21 conversions

def test_gry_gbin_gray_code():
    # FNC 170/171 examples: GRY D0 K4Y20, GBIN K4X20 D0 (1234 <-> Gray H06BB)
    run("LD X0\nGRY D0 K4Y20\nLD X1\nGBIN K4X20 D1\n",
        "0ms D0=1234 K4X20=H06BB X0=1 X1=1\n0ms expect K4Y20=H06BB D1=1234\n")


def test_limit_band_zone_curves():
    # FNC 256-258 examples: LIMIT K500 K1000 D0 D1, BAND K-5000 K5000 D0 D1, ZONE K-5000 K5000 D0 D1
    run("LD X0\nLIMIT K500 K1000 D0 D1\nBAND K-5000 K5000 D0 D2\nZONE K-5000 K5000 D0 D3\n",
        "0ms X0=1 D0=300\n0ms expect D1=500 D2=0 D3=5300\n10ms D0=-6000\n"
        "10ms expect D1=500 D2=-1000 D3=-11000\n20ms D0=7000\n20ms expect D1=1000 D2=2000 D3=12000\n"
        "30ms D0=0\n30ms expect D3=0 D2=0\n")
