"""Vigor VS simulation of the data-set instructions of 6-8, 6-10 ... 6-21 (targets/vs/tables.py,
ascii_codes.py, scale.py, timing.py): each case is the example printed on the instruction's
page, with its figures' values."""

from __future__ import annotations

from mlctool.targetapi import load_target
from vskit import run

VS = load_target("vs")




def run_period(il: str, stim: str, period_us: int, scans: int):
    """As run(), with a longer scan period (hour meters, 1 s timers)."""
    return run(il, stim, alarms=True, period_us=period_us, scans=scans)


# ------------------------------------------------------------------ 6-13

def test_wsum_sums_into_a_double_width_register():
    # FNC 140: WSUM D10 D100 K5 -> (D101, D100) = 655; DWSUM D0 D100 K4: 100000 ... 400000
    # -> (D103 ... D100) = 1000000
    run("LD X0\nWSUM D10 D100 K5\nLD X1\nDWSUM D0 D200 K4\n",
        "0ms D10=100 D11=110 D12=120 D13=140 D14=185 D0:d=100000 D2:d=200000 D4:d=300000 "
        "D6:d=400000 D101=7 D203=9\n10ms X0=1 X1=1\n"
        "10ms expect D100:d=655 D200:d=1000000 D202=0 D203=0\n"
        "20ms X0=0 D10=-1000 D11=-1000 D12=0 D13=0 D14=0\n30ms X0=1\n30ms expect D100:d=-2000")


def test_wtob_btow_split_and_pack_bytes():
    # FNC 141: WTOBP D10 D20 K5: bytes of D10-D12 (low first) into D20-D24, high bytes 0;
    # FNC 142: BTOWP D10 D20 K5: low bytes of D10-D14 into D20-D22, D22's high byte 0
    run("LDP X0\nWTOB D10 D20 K5\nLDP X1\nBTOW D30 D40 K5\nLDP X2\nWTOB D10 D50 K0\n",
        "0ms D10:h=H3412 D11:h=H7856 D12:h=HBC9A D20:h=HFFFF D24:h=HFFFF D25=7\n"
        "0ms D30:h=H4321 D31:h=H6543 D32:h=H8765 D33:h=HA987 D34:h=HCBA9 D42:h=HFFFF D50=5\n"
        "10ms X0=1 X1=1 X2=1\n"
        "10ms expect D20:h=H12 D21:h=H34 D22:h=H56 D23:h=H78 D24:h=H9A D25=7\n"
        "10ms expect D40:h=H4321 D41:h=H8765 D42:h=H00A9 D50=5")


def test_uni_dis_pack_and_split_digits():
    # FNC 143: UNIP D10 D20 K3: low 4 bits of D10-D12 -> D20 = 0321H (upper digit 0);
    # FNC 144: DISP D10 D20 K4: D10 = 1234H -> D20-D23 = 4, 3, 2, 1
    run("LDP X0\nUNI D10 D20 K3\nLDP X1\nDIS D30 D40 K4\n",
        "0ms D10:h=HFF1 D11:h=H2 D12:h=HA3 D20:h=HFFFF D30:h=H1234 D40:h=HFFF0\n10ms X0=1 X1=1\n"
        "10ms expect D20:h=H0321 D40=4 D41=3 D42=2 D43=1")


STUDENTS = "D0=1 D1=90 D2=75 D3=66 D4=2 D5=55 D6=65 D7=54 D8=3 D9=80 D10=98 D11=89 " \
           "D12=4 D13=70 D14=60 D15=99 D16=5 D17=95 D18=79 D19=75"


def test_sort2_rows_by_a_field_in_m1_scans():
    # FNC 148: SORT2 D0 K5 K4 D100 D200: 5 students (number, three marks) row after row;
    # D200 = 2 sorts on the first mark ascending (M9165 Off) in 5 scans, M9029 On one scan
    run("LD X0\nSORT2 D0 K5 K4 D100 D200\n",
        f"0ms {STUDENTS} D200=2\n10ms X0=1\n40ms expect D100=0 M9029=0\n"
        "50ms expect D100=2 D101=55 D104=4 D105=70 D108=3 D112=1 D116=5 D119=75 M9029=1\n"
        "60ms expect M9029=0\n"
        "70ms X0=0 M9165=1 D200=4\n80ms X0=1\n"
        "120ms expect D100=4 D103=99 D104=3 D108=5 D112=1 D116=2 D119=54 M9029=1")


# ------------------------------------------------------------------ 6-19

def test_fdel_fins_table_entries():
    # FNC 210: FDELP D0 D2 D1, (D1) = K3: the 3rd entry of the table at D2 (count in D2)
    # moves to D0, the later ones move up, the count drops; FNC 211: FINSP D0 D2 D1 inserts
    run("LDP X0\nFDEL D0 D2 D1\nLDP X1\nFINS D0 D2 D1\nLDP X2\nFDEL D0 D2 K9\n",
        "0ms D1=3 D2=5 D3=10 D4=20 D5=30 D6=40 D7=50\n10ms X0=1\n"
        "10ms expect D0=30 D2=4 D3=10 D4=20 D5=40 D6=50\n"
        "20ms D0=99\n30ms X1=1\n30ms expect D2=5 D5=99 D6=40 D7=50\n40ms X2=1\n"
        "40ms expect D2=5 M9067=1 D9067=6706", alarms=True)


def test_pop_reads_the_last_entry():
    # FNC 212: POPP D0 D101 K10: D0 = 5 -> D101 = (D5), D0 = 4, then (D4), D0 = 3; pointer
    # 1 -> 0 turns M9020 On; pointer 0: nothing read, M9020 On
    run("LDP X0\nPOP D0 D101 K10\n",
        "0ms D0=5 D1=10 D2=20 D3=30 D4=40 D5=50\n10ms X0=1\n10ms expect D101=50 D0=4 M9020=0\n"
        "20ms X0=0\n30ms X0=1\n30ms expect D101=40 D0=3\n40ms X0=0 D0=1\n50ms X0=1\n"
        "50ms expect D101=10 D0=0 M9020=1\n60ms X0=0 M9020=0\n70ms X0=1\n"
        "70ms expect D101=10 D0=0 M9020=1")


def test_sfr_sfl_shift_one_word():
    # FNC 213/214: SFRP D0 K4 / SFLP D1 K4: 16 bits shifted 4 places, 0 in, the last bit
    # out to M9022
    run("LDP X0\nSFR D0 K4\nLDP X0\nSFL D1 K4\nLDP X1\nSFL D2 K4\n",
        "0ms D0:h=H1238 D1:h=HF234 D2:h=H0234\n10ms X0=1\n"
        "10ms expect D0:h=H0123 D1:h=H2340 M9022=1\n20ms X1=1\n20ms expect D2:h=H2340 M9022=0")


# ------------------------------------------------------------------ 6-11

def test_zpush_zpop_nest_index_registers():
    # FNC 102/103 example: D0 = 0; three ZPUSH save Z0-V7 at D1-D16, D17-D32, D33-D48
    # (D0 = 3); three ZPOP restore them in reverse order
    il = ("LDP X0\nMOV K0 D0\nMOV K1 Z0\nMOV K2 V7\nZPUSH D0\nMOV K11 Z0\nZPUSH D0\n"
          "MOV K21 Z0\nMOV K0 V7\nZPUSH D0\nMOV K99 Z0\n"
          "LDP X1\nZPOP D0\nMOV Z0 D100\nZPOP D0\nMOV Z0 D101\nZPOP D0\nMOV Z0 D102\nMOV V7 D103\n")
    run(il, "10ms X0=1\n10ms expect D0=3 D1=1 D16=2 D17=11 D33=21 D48=0 Z0=99\n"
            "20ms X1=1\n20ms expect D0=0 D100=21 D101=11 D102=1 D103=2")


# ------------------------------------------------------------------ 6-21

def test_scl_scl2_scale_by_a_table():
    # FNC 259 example: 3200-28800 from the analog module -> 0-4000 (0.1 mm): D0 = 16000 ->
    # D1 = 2000; 3201 -> 0.15625 -> 0 (half-up); outside the table: 6706.
    # FNC 269 SCL2: the same table as points, X1..Xn, Y1..Yn
    run("LD X0\nSCL D0 D1000 D1\nLD X0\nSCL2 D0 D1100 D2\n",
        "0ms D1000=2 D1001=3200 D1002=0 D1003=28800 D1004=4000\n"
        "0ms D1100=2 D1101=3200 D1102=28800 D1103=0 D1104=4000\n"
        "0ms D0=16000 X0=1\n0ms expect D1=2000 D2=2000\n10ms D0=3204\n10ms expect D1=1 D2=1\n"
        "20ms D0=28800\n20ms expect D1=4000\n30ms D0=100 D1=7\n30ms expect D1=7 M9067=1 D9067=6706",
        alarms=True)


def test_dabin_binda_ascii_numbers():
    # FNC 260: DABIN D0 D10: "-12589" (2DH 31H 32H 35H 38H 39H) -> D10 = -12589;
    # FNC 261: BINDA D10 D0: 125 -> 20H 20H 20H 31H 32H 35H then 0000H (M9091 Off)
    run("LD X0\nDABIN D0 D10\nLD X1\nBINDA D20 D30\nLD X2\nDBINDA D40 D50\n",
        "0ms D0:h=H312D D1:h=H3532 D2:h=H3938 D20=125 D33=7 D40:d=-12 D55:h=HFFFF\n"
        "10ms X0=1 X1=1 X2=1\n10ms expect D10=-12589 D30:h=H2020 D31:h=H3120 D32:h=H3532 D33=0\n"
        "10ms expect D50:h=H202D D53:h=H2020 D54:h=H3120 D55:h=H0032\n"
        "20ms X0=0 D0:h=H3141\n30ms X0=1\n30ms expect D10=-12589 M9067=1", alarms=True)


# ------------------------------------------------------------------ 6-10, 6-16, 6-9

def test_asci_hex_ccd_crc():
    # FNC 82: ASCI D0 D100 K8: D0 = 4567H, D1 = 89ABH -> "89AB4567"; FNC 83 HEX back;
    # FNC 188: CRC D0 D100 K7 of 01H 03H 04H EDH 85H A3H 28H = 58A6H (M9161 On: A6H, 58H);
    # FNC 84: CCD: sum and horizontal parity
    run("LD X0\nASCI D0 D100 K8\nLD X0\nHEX D100 D10 K8\nLD X1\nCRC D20 D200 K7\n"
        "LD X2\nCRC D30 D210 K7\nLD X0\nCCD D20 D220 K7\n",
        "0ms D0:h=H4567 D1:h=H89AB D20:h=H0301 D21:h=HED04 D22:h=HA385 D23:h=H0028\n"
        "0ms D30=1 D31=3 D32=4 D33=H00ED D34=H0085 D35=H00A3 D36=H0028\n"
        "10ms X0=1 X1=1\n10ms expect D100:h=H3938 D101:h=H4241 D102:h=H3534 D103:h=H3736 "
        "D10:h=H4567 D11:h=H89AB D200:h=H58A6 D220=581 D221:h=HE5\n"
        "20ms X1=0 M9161=1 X2=1\n20ms expect D210:h=HA6 D211:h=H58")


def test_asc_letters_into_registers():
    # FNC 76: ASC ABCDEFGH D0 (written "ABCDEFGH" in IL): 41H 42H ... two a word; fewer
    # than 8 letters are filled up with spaces (20H), always 4 words
    run('LD X0\nASC "ABCDEFGH" D0\nLD X1\nASC "AB" D10\n',
        "10ms X0=1 X1=1 D12=5 D14=5\n10ms expect D0:h=H4241 D1:h=H4443 D3:h=H4847 D10:h=H4241 "
        "D11:h=H2020 D12:h=H2020 D13:h=H2020 D14=5")


def test_rnd_is_the_pages_generator_from_seed_1():
    # FNC 184: (D9161, D9160) = K1 at power-on, x = x * 1103515245 + 12345, D = (x >> 16) & 7FFFH
    run("LDP X0\nRND D0\n",
        "0ms expect D9160=1\n10ms X0=1\n10ms expect D0=16838\n20ms X0=0\n30ms X0=1\n"
        "30ms expect D0=5758\n40ms X0=0\n40ms power-cycle\n40ms expect D9160=1")


def test_duty_scan_pulses_keep_running_when_off():
    # FNC 186: DUTY K10 K5 M9330: On 10 scans, Off 5, counted in D9330; Off does not stop it
    run("LD X0\nDUTY K10 K5 M9330\n",
        "10ms X0=1\n10ms expect M9330=1 D9330=0\n100ms expect M9330=1 D9330=9\n"
        "110ms expect M9330=0 D9330=10\n150ms expect M9330=0 D9330=14\n160ms expect M9330=1 D9330=0\n"
        "170ms X0=0\n270ms expect M9330=0 D9330=11")


# ------------------------------------------------------------------ 6-8

def test_ttmr_teaching_timer():
    # FNC 64: TTMR D0 K1: X20 On 5 s -> D1 = 5, D0 = 50; Off: D1 = 0, D0 kept
    run_period("LD X20\nTTMR D0 K1\n",
               "0ms X20=1\n5s expect D1=5 D0=50\n5.5s X20=0\n5.5s expect D1=0 D0=50", 100_000, 60)


def test_stmr_off_delay_one_shots_and_flasher():
    # FNC 65: STMR T0 K20 Y20: Y20 off-delay, Y21 one shot after Off, Y22 one shot at On,
    # Y23 On 2 s after On, Off 2 s after Off; the page's flasher X20 AND NOT M3 -> M1/M2
    run_period("LD X20\nSTMR T0 K20 Y20\nLD X21\nANI M3\nSTMR T1 K10 M0\n",
               "0ms X20=1 X21=1\n0ms expect Y20=1 Y21=0 Y22=1 Y23=0 M2=1\n"
               "1.9s expect Y22=1 Y23=0\n2s expect Y22=0 Y23=1 T0:w=20\n"
               "3s X20=0\n3s expect Y20=1 Y21=1 Y22=0 Y23=1\n4.9s expect Y20=1 Y21=1\n"
               "5s expect Y20=0 Y21=0 Y23=0\n"
               "1.5s expect M1=1 M2=0\n2.5s expect M1=0 M2=1\n3.5s expect M1=1 M2=0", 100_000, 60)


def test_ramp_in_scans():
    # FNC 67: RAMP D0 D1 D2 K500 (10 -> 110 in 500 scans of 10 ms); M9026 Off repeats
    run("LD X20\nRAMP D0 D1 D2 K500\n",
        "0ms D0=10 D1=110\n0ms X20=1\n0ms expect D2=10 D3=1\n2.49s expect D2=60 D3=250\n"
        "4.98s expect D2=109 D3=499 M9029=0\n4.99s expect D2=10 D3=0 M9029=1\n5s expect D3=1 M9029=0\n"
        "5.5s X20=0\n5.5s expect D3=0")


def test_ramp_once_holds_the_end():
    run("LD X20\nRAMP D0 D1 D2 K4\n",
        "0ms D0=100 D1=20 M9026=1 X20=1\n20ms expect D2=40 D3=3\n30ms expect D2=20 D3=4 M9029=1\n"
        "60ms expect D2=20 D3=4 M9029=0")


def test_absd_cam_zones():
    # FNC 62: ABSD D0 C0 M0 K4: C0 against (D0, D1) ... (D6, D7) -> M0-M3; Off keeps them
    run("LD X20\nABSD D0 C0 M0 K4\nLD X21\nOUT C0 K32767\n",
        "0ms D0=40 D1=100 D2=120 D3=210 D4=140 D5=200 D6=240 D7=280 X20=1\n"
        "10ms X21=1\n10ms expect C0:w=1 M0=0 M1=0 M2=0 M3=0\n"
        "20ms X21=0\n30ms C0:w=150\n30ms expect M0=0 M1=1 M2=1 M3=0\n"
        "40ms X20=0 C0:w=50\n40ms expect M0=0 M1=1 M2=1")


def test_incd_relative_cam():
    # FNC 63: INCD D0 C0 M0 K5, D0-D4 = 30 40 10 50 20: C0 counts the program's pulses (M9012
    # 100 ms clock), M0 ... M4 in turn, M9029 after a cycle; X20 Off clears C0, C1, M0-M4
    run("LD M9012\nOUT C0 K32767\nLD X20\nINCD D0 C0 M0 K5\n",
        "0ms D0=30 D1=40 D2=10 D3=50 D4=20 X20=1\n10ms expect M0=1 C1:w=0\n"
        "3.5s expect M0=0 M1=1 C1:w=1\n15.5s expect M0=1 M4=0 C1:w=0\n"
        "16s X20=0\n16s expect C0:w=0 C1:w=0 M0=0")


# ------------------------------------------------------------------ 6-15, 6-2

def test_hour_meter_counts_hours_with_seconds_below():
    # FNC 169: HOUR K1000 D7000 Y0: D7000 hours, D7001 seconds; Y0 at 1000 h, even with X0 Off
    run_period("LD X0\nHOUR K1000 D7000 Y0\n",
               "0ms D7000=999 D7001=3590 X0=1\n9s expect D7000=999 D7001=3599 Y0=0\n"
               "10s expect D7000=1000 D7001=0 Y0=1\n12s X0=0\n20s expect D7000=1000 D7001=1 Y0=1",
               1_000_000, 25)


def test_tft_tfh_tfk_register_timers():
    # FNC 176-178: TFT D0 K100 M0 (10 ms), TFH D10 K100 M10 (100 ms), TFK D20 K2 M20 (1 s);
    # Off clears the value and the contact; WDT (FNC 7) changes nothing
    run("LD X0\nTFT D0 K100 M0\nLD X0\nTFH D10 K100 M10\nLD X0\nTFK D20 K2 M20\nWDT\n",
        "0ms X0=1\n990ms expect D0=99 M0=0 D10=9 D20=0\n1s expect D0=100 M0=1 M20=0\n"
        "2s expect D20=2 M20=1 D0=100\n9.99s expect M10=0\n10s expect D10=100 M10=1\n"
        "10.5s X0=0\n10.5s expect D0=0 M0=0 D10=0 M10=0 D20=0 M20=0")


# ------------------------------------------------------------------ 6-12

def test_destr_deval_float_strings():
    # FNC 116: DESTR D20 D10 D0: -1.23456, decimal form, 8 characters, 4 decimals ->
    # "- 1.2346" + 0000H; exponent form 11 characters, 3 decimals: 123.4567 -> "  1.235E+02";
    # FNC 117: DEVAL D0 D100 of "- 0123.4567" -> -123.456 (6 digits kept)
    run("LD X0\nDESTR D20 D10 D0\nLD X1\nDESTR D22 D13 D30\nLD X2\nDEVAL D40 D100\n",
        "0ms D20:f=-1.23456 D10=0 D11=8 D12=4 D22:f=123.4567 D13=1 D14=11 D15=3\n"
        "0ms D40:h=H202D D41:h=H3130 D42:h=H3332 D43:h=H342E D44:h=H3635 D45:h=H0037\n"
        "10ms X0=1 X1=1 X2=1\n10ms expect D0:h=H202D D1:h=H2E31 D2:h=H3332 D3:h=H3634 D4=0\n"
        "10ms expect D30:h=H2020 D31:h=H2E31 D32:h=H3332 D33:h=H4535 D34:h=H302B D35:h=H0032\n"
        "10ms expect D100:f=-123.456 M9020=0")


# ------------------------------------------------------------------ 6-7

def test_ref_reff_are_accepted_without_effect():
    # FNC 50/51: REF X0 K8, REF Y0 K8, REFF K1 run (no E905) and change nothing; the program
    # around them still sees the stimulus's inputs
    run("LD X0\nREF X0 K8\nLD X0\nREF Y0 K8\nLD X0\nREFF K1\nLD X0\nOUT Y1\n",
        "10ms X0=1\n10ms expect Y1=1 Y0=0")
