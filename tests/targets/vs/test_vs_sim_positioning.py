"""Positioning ZRN, DRVR, DRVA, DVIT, PLSV, DTBL, DABS, MPG, LIR, LIA (8-3 FNC 300-316) on virtual time:
each page's example with the axis parameters of 8-1-1 (D9340 max speed, D9343/D9344 ramps,
D9348 override), the present position D9355:D9354, the flags M9340 busy, M9341 outputting,
M9342 done, M9343 abnormal end, M9344 home done, a level per scan on the pulse pin and the
direction pin D2. Numbers worked out by hand from the trapezoid (never counted per pulse)."""

from __future__ import annotations

import contextlib

from vskit import VS, run


@contextlib.contextmanager
def form(**values):
    """The editor's positioning parameter form (target.toml [positioning]) for one test."""
    table = VS.settings["positioning"]
    old = {k: table[k] for k in values}
    table.update(values)
    try:
        yield
    finally:
        table.update(old)


def test_drva_page_example_trapezoid_to_the_absolute_position():
    # 8-3 FNC 304: DDRVA D10 D20 Y0 Y4, M0 On: to D11:D10 at D21:D20 Hz. Max 10 kHz, ramps
    # 100 ms: 100000 Hz/s; 10000 pulses at 10 kHz: 500 up, 9000 cruising (0.9 s), 500 down
    run("LD M0\nDDRVA D10 D20 Y0 Y4\n",
        "0ms D9340:d=10000 D10:d=10000 D20:d=10000\n10ms M0=1\n"
        "10ms expect M9340=1 M9341=1 Y4=1 D9354:d=0\n60ms expect D9354:d=125\n"
        "110ms expect D9354:d=500 D9350:d=10000\n610ms expect D9354:d=5500\n"
        "1060ms expect D9354:d=9875 M9342=0\n"
        "1110ms expect D9354:d=10000 M9342=1 M9341=0 Y0=0 D9350:d=0 M9340=1\n"
        "1200ms M0=0\n1200ms expect M9342=0 M9340=0\n"
        # back to 4000: 6000 toward the decreasing position, Y4 Off
        "1300ms D10:d=4000 M0=1\n1300ms expect Y4=0\n1400ms expect D9354:d=9500\n"
        "2000ms expect D9354:d=4000 M9342=1\n")


def test_drva_condition_off_decelerates_without_done_and_speed_changes_replan():
    # Off at 610 ms (5500, 10 kHz): a 100 ms ramp down, 500 more pulses, M9342 stays Off;
    # M9340 holds the axis until it stands still
    run("LD M0\nDDRVA K10000 D20 Y0 Y4\n",
        "0ms D9340:d=10000 D20:d=10000 M0=1\n600ms M0=0\n650ms expect D9354:d=5875 M9340=1\n"
        "700ms expect D9354:d=6000 M9340=0 M9342=0 M9343=0 M9341=0\n")
    # the override D9348 may change while running: 50.0 % from 600 ms halves the speed
    run("LD M0\nDDRVA K100000 K10000 Y0 Y4\n",
        "0ms D9340:d=10000 D9343=0 D9344=0 M0=1\n600ms D9348=500\n"
        "600ms expect D9354:d=6000 D9350:d=5000\n800ms expect D9354:d=7000\n")


def test_m9346_cuts_a_decelerating_stop_under_way():
    # 8-2 M9346 "會立即停止輸出脈衝" also while a decelerating stop ramps down (docs/vs.md
    # DECISION: M9343 as that stop set it). DDRVA as above: Off at 600 ms (5500, 10 kHz), 50 ms
    # into the 100 ms ramp 10000 x 0.05 - 100000 x 0.05^2 / 2 = 375 more (5875); M9346 there:
    # no more pulses (the ramp would have run to 6000); the condition is Off: released, no M9343
    run("LD M0\nDDRVA K10000 D20 Y0 Y4\n",
        "0ms D9340:d=10000 D20:d=10000 M0=1\n600ms M0=0\n650ms M9346=1\n"
        "650ms expect D9354:d=5875 D9350:d=0 M9341=0 Y0=0 M9340=0 M9343=0 M9342=0\n"
        "800ms expect D9354:d=5875 M9340=0 M9343=0\n")
    # DPLSV 10 kHz: 500 on the ramp up, 4500 at 500 ms; M9345 ramps down (abnormal end);
    # 40 ms into it 400 - 80 = 320 more (4820); M9346 then: stopped at once, M9343 On, the
    # axis held until the condition goes Off (the ramp would have ended at 5000)
    run("LD M0\nDPLSV K10000 Y0 Y4\n",
        "0ms D9340:d=10000 M0=1\n500ms M9345=1\n500ms expect D9354:d=4500\n540ms M9346=1\n"
        "540ms expect D9354:d=4820 D9350:d=0 M9341=0 M9343=1 M9340=1 M9342=0\n"
        "700ms expect D9354:d=4820 M9343=1 M9340=1\n800ms M0=0\n"
        "800ms expect D9354:d=4820 M9340=0 M9343=0\n")
    # JOGF's short press: the one pulse's move runs on after the Off; ramps 32000 ms (312.5
    # Hz/s): a triangle peaking at sqrt(312.5) Hz after 56.6 ms, 0.39 of the pulse at 50 ms,
    # 0.56 at 60 ms; M9346 there: the pulse never goes out (it would at 113 ms)
    run("LD M0\nJOGF K300 K1000 Y0 Y4\n",
        "0ms D9340:d=10000 D9343=32000 D9344=32000 M0=1\n50ms M0=0\n"
        "50ms expect D9354:d=0 M9340=1\n60ms M9346=1\n"
        "60ms expect D9354:d=0 M9341=0 M9340=0\n200ms expect D9354:d=0 M9343=0 M9342=0\n")


def test_drvr_relative_move_direction_pin_level_and_immediate_stop():
    # 8-3 FNC 303: DDRVR K-3000 K1000 Y1 Y5 on axis Y1 (registers +20): no ramps (0 ms),
    # 1000 Hz toward the decreasing position from 0; a period is 1 ms, so every 10 ms scan
    # sees the first half of a period (Y1 On)
    run("LD M1\nDDRVR K-3000 K1000 Y1 Y5\n",
        "0ms D9363=0 D9364=0 M1=1\n0ms expect M9360=1 Y5=0\n"
        "1s expect D9374:d=-1000 Y1=1 D9370:d=1000\n3s expect D9374:d=-3000 M9362=1 Y1=0\n"
        "3100ms M1=0\n3200ms M1=1\n3700ms M9366=1\n"
        "3700ms expect D9374:d=-3500 M9363=1 M9362=0 M9361=0\n4s expect D9374:d=-3500\n")


def test_drvr_16_bit_form_on_axis_y2():
    # DRVR K100 K1000 Y2 M10: axis Y2 (registers +40), the direction on a relay
    run("LD M0\nDRVR K100 K1000 Y2 M10\n",
        "0ms D9383=0 D9384=0 M0=1\n50ms expect D9394:d=50 M10=1 M9380=1\n"
        "100ms expect D9394:d=100 M9382=1\n")


def test_plsv_page_example_speed_changes_and_off_decelerates():
    # 8-3 FNC 311: DPLSV D0 Y0 Y4, D0 80000 -> 120000 -> 40000 (the page's chart); max 200 kHz,
    # ramps 100 ms: 2 MHz/s. 0-40 ms up (1600), +80000 x 60 ms = 6400 at 100 ms; up to 120000
    # in 20 ms (+2000), 18000 at 200 ms; down to 40000 in 40 ms (+3200), 23600 at 300 ms; Off:
    # 20 ms down to 0 (+400)
    run("LD M0\nDPLSV D0 Y0 Y4\n",
        "0ms D0:d=80000 M0=1\n0ms expect Y4=1 M9341=1\n40ms expect D9354:d=1600 D9350:d=80000\n"
        "100ms D0:d=120000\n100ms expect D9354:d=6400\n120ms expect D9354:d=8400\n"
        "200ms D0:d=40000\n200ms expect D9354:d=18000\n240ms expect D9354:d=21200\n"
        "300ms M0=0\n300ms expect D9354:d=23600 M9340=1\n310ms expect D9354:d=23900\n"
        "320ms expect D9354:d=24000 M9340=0 M9341=0 M9342=0\n")
    # a negative speed runs toward the decreasing position (Y4 Off); M9345 stops it slowly
    # and ends it abnormally
    run("LD M0\nPLSV K-5000 Y0 Y4\n",
        "0ms D9343=0 D9344=0 M0=1\n0ms expect Y4=0\n1s expect D9354:d=-5000\n1s M9345=1\n"
        "1s expect M9343=1 M9341=0\n")


def test_dv2r_page_example_two_speeds():
    # 8-3 FNC 305: DV2R D10 D20 Y0 Y4: D10 = 1000 pulses at D20 = 5000 Hz, then D11 = 2000 at
    # D21 = 2000 Hz. Ramps 100 kHz/s: 125 up in 50 ms, the first part ends at 225 ms; down to
    # 2000 Hz in 30 ms (105), 1875 cruising (937.5 ms), 20 on the last 20 ms: done at 1212.5 ms
    run("LD M0\nDV2R D10 D20 Y0 Y4\n",
        "0ms D9340:d=10000 D10=1000 D11=2000 D20=5000 D21=2000 M0=1\n200ms expect D9354:d=875\n"
        "250ms expect D9350:d=2500\n260ms expect D9354:d=1115 D9350:d=2000\n"
        "1000ms expect D9354:d=2595 M9342=0\n1220ms expect D9354:d=3000 M9342=1 M9341=0\n")


def test_dv2a_absolute_two_speeds_and_a_second_target_behind_the_first():
    # 8-3 FNC 306: DDV2A D10 D20 Y0 Y4 from 500: to 1500 at 5000 Hz, then to 3500 at 2000 Hz
    # (the DV2R case's travels)
    run("LD M0\nDDV2A D10 D20 Y0 Y4\n",
        "0ms D9340:d=10000 D9354:d=500 D10:d=1500 D12:d=3500 D20:d=5000 D22:d=2000\n10ms M0=1\n"
        "1230ms expect D9354:d=3500 M9342=1\n")
    # 16-bit form: the second target 1000 lies behind the first 1500: operation error
    run("LD M0\nDV2A D10 D20 Y0 Y4\n",
        "0ms D10=1500 D11=1000 D20=5000 D21=2000 M0=1\n10ms expect M9340=0 M9067=1\n",
        alarms=True)


def test_jogf_page_example_short_press_one_pulse_long_press_runs_on():
    # 8-3 FNC 301: JOGF K300 D20 Y0 Y4, D20 = 1000 Hz, ramps 100 kHz/s (max 10 kHz). On for
    # 100 ms < 300 ms: one pulse; On from 200 ms: one pulse, then at 500 ms on at 1000 Hz
    # (5 on the 10 ms ramp, +490 by 1000 ms); Off: a 10 ms ramp down (+5)
    run("LD M0\nJOGF K300 D20 Y0 Y4\n",
        "0ms D9340:d=10000 D20=1000 M0=1\n0ms expect Y4=1 M9340=1\n"
        "50ms expect D9354:d=1 M9341=1\n100ms M0=0\n100ms expect D9354:d=1 M9340=0 M9342=0\n"
        "200ms M0=1\n490ms expect D9354:d=2 M9341=1\n1000ms expect D9354:d=497\n1000ms M0=0\n"
        "1010ms expect D9354:d=502 M9340=0 M9342=0 M9343=0\n")
    # 8-3 FNC 302: JOGR toward the decreasing position, D2 Off; S1 above 5000 is 5000
    run("LD M0\nJOGR K9000 K1000 Y1 Y5\n",
        "0ms D9363=0 D9364=0 M0=1\n0ms expect Y5=0\n4990ms expect D9374:d=-1\n"
        "6s expect D9374:d=-1001\n")


def test_dvit_page_example_travel_after_the_interrupt():
    # 8-3 FNC 307: DVIT D10 D20 Y0 Y4, interrupt X0 (parameter form): 5000 Hz until X0 rises
    # at 500 ms (125 on the ramp + 5000 x 0.45 s = 2375), then D10 = 1000 more: 875 cruising
    # (175 ms), 125 on the 50 ms ramp down: done at 725 ms on 3375
    run("LD M0\nDVIT D10 D20 Y0 Y4\n",
        "0ms D9340:d=10000 D10=1000 D20=5000 M0=1\n400ms expect D9354:d=1875 M9342=0\n"
        "500ms X0=1\n500ms expect D9354:d=2375\n700ms expect D9354:d=3343\n"
        "730ms expect D9354:d=3375 M9342=1 M9341=0\n")
    # M9350 On: the falling edge interrupts; a negative travel runs the other way
    run("LD M0\nDVIT K-100 K1000 Y0 Y4\n",
        "0ms D9343=0 D9344=0 M9350=1 X0=1 M0=1\n200ms X0=0\n200ms expect D9354:d=-200 Y4=0\n"
        "300ms expect D9354:d=-300 M9342=1\n")
    # b12 INT N/C (input polarity, 2-17-9 BFM#115): the contact opening is the signal's
    # rising edge (M9350 Off), its closing the falling one (M9350 On)
    with form(input_polarity=[0x1000, 0, 0, 0]):
        run("LD M0\nDVIT K-100 K1000 Y0 Y4\n",
            "0ms D9343=0 D9344=0 X0=1 M0=1\n100ms expect D9354:d=-100\n200ms X0=0\n"
            "200ms expect D9354:d=-200 Y4=0\n300ms expect D9354:d=-300 M9342=1\n")
        run("LD M0\nDVIT K100 K1000 Y0 Y4\n",
            "0ms D9343=0 D9344=0 M9350=1 M0=1\n200ms X0=1\n200ms expect D9354:d=200\n"
            "300ms expect D9354:d=300 M9342=1\n")
    # without an interrupt signal in the form: operation error, not executed
    with form(interrupt=["", "", "", ""]):
        run("LD M0\nDVIT K100 K1000 Y0 Y4\n", "0ms M0=1\n10ms expect M9340=0 M9067=1\n",
            alarms=True)


def test_dv2i_page_example_speed_change_then_interrupt():
    # 8-3 FNC 308: DV2I D10 D20 Y0 Y4, speed change X10, interrupt X0, no ramps: 1000 Hz to
    # 200 ms, X10: 3000 Hz, X0 at 400 ms (800), then D10 = 300 more at 3000 Hz: done at 500 ms
    run("LD M0\nDV2I D10 D20 Y0 Y4\n",
        "0ms D9343=0 D9344=0 D10=300 D20=1000 D21=3000 M0=1\n200ms X10=1\n"
        "200ms expect D9354:d=200 D9350:d=3000\n400ms X0=1\n400ms expect D9354:d=800 M9342=0\n"
        "500ms expect D9354:d=1100 M9342=1\n")


def test_dvsr_dvsa_page_examples_the_interrupt_ramps_down_and_completes():
    # 8-3 FNC 309: DVSR D10 D20 Y0 Y4, 10000 pulses at 5000 Hz; X0 rises at 500 ms (2375):
    # a 50 ms ramp down (+125), M9342 On
    run("LD M0\nDVSR D10 D20 Y0 Y4\n",
        "0ms D9340:d=10000 D10=10000 D20=5000 M0=1\n500ms X0=1\n500ms expect D9354:d=2375\n"
        "550ms expect D9354:d=2500 M9342=1 M9341=0\n1s expect D9354:d=2500\n")
    # 8-3 FNC 310: DDVSA K3000 ... without the interrupt it ends on the position (650 ms)
    run("LD M0\nDDVSA K3000 K5000 Y0 Y4\n",
        "0ms D9340:d=10000 M0=1\n600ms expect D9354:d=2875 M9342=0\n"
        "650ms expect D9354:d=3000 M9342=1\n")
    # 16-bit DVSA toward the decreasing position, the falling edge (M9350 On) stops it
    run("LD M0\nDVSA K-1000 K1000 Y0 Y4\n",
        "0ms D9343=0 D9344=0 M9350=1 X0=1 M0=1\n300ms X0=0\n"
        "300ms expect D9354:d=-300 M9342=1 Y4=0\n")


def test_zrn_page_example_dog_rear_edge_homing():
    # 8-3 FNC 300: DZRN K50000 K1000 Y0 Y4, DOG X10, toward the decreasing position (Y4 Off).
    # Ramps 2 MHz/s: 625 pulses to 50 kHz (25 ms); DOG front at 200 ms (9375): down to the
    # creep speed 1000 in 24.5 ms (624.75), then 1000 Hz; DOG rear at 500 ms: stop at once,
    # the origin value D9347:D9346 becomes the position, M9344 and M9342 On
    run("LD M0\nDZRN K50000 K1000 Y0 Y4\n",
        "0ms D9346:d=100 M9344=0 M0=1\n0ms expect Y4=0 M9340=1\n200ms X10=1\n"
        "200ms expect D9354:d=-9375\n490ms expect D9354:d=-10265 D9350:d=1000 M9344=0\n"
        "500ms X10=0\n500ms expect D9354:d=100 M9344=1 M9342=1 M9341=0 Y0=0\n"
        "600ms M0=0\n600ms expect M9342=0 M9344=1 M9340=0\n700ms M0=1\n700ms expect M9344=0\n")


def test_zrn_page_example_mode_dog_rear_counting_pg0():
    # 8-3 FNC 300 as the page sets it: "DOG rear edge, count PG0" with DOG X10, PG0 X0, CLR
    # Y10, zero signals 2. No ramps: 5000 Hz to DOG (100 ms, 500), 1000 Hz creep; DOG rear at
    # 200 ms (600); PG0 edges at 205 and 215 ms: the zero at 215 ms (615 pulses out)
    with form(home_mode="dog_rear_pg0", clr=["Y10", "", "", ""]):
        run("LD M0\nDZRN K50000 K1000 Y0 Y4\n",
            "0ms D9340:d=5000 D9343=0 D9344=0 D9346:d=-5 M0=1\n100ms X10=1\n200ms X10=0\n"
            "200ms expect D9354:d=-600\n205ms X0 pulses 100Hz\n210ms expect D9354:d=-610 M9344=0\n"
            "220ms expect D9354:d=-5 M9344=1 M9342=1 Y10=1 Y0=0\n240ms expect Y10=0\n")
    # "DOG front edge, count PG0": counting from the DOG's front edge (100 ms): PG0 edges at
    # 110 and 120 ms of the train running since 0 ms
    with form(home_mode="dog_front_pg0"):
        run("LD M0\nDZRN K5000 K1000 Y0 Y4\n",
            "0ms D9343=0 D9344=0 M0=1\n0ms X0 pulses 100Hz\n100ms X10=1\n"
            "110ms expect M9344=0 D9354:d=-510\n120ms expect M9344=1 D9354:d=0\n")


def test_zrn_clr_signal_data_set_mode_and_stop_relay():
    with form(clr=["Y10", "", "", ""]):
        # DOG already On at the start: creep at once (DECISION); CLR Y10 On for 20 ms
        run("LD M0\nZRN K5000 K1000 Y0 Y4\n",
            "0ms D9343=0 D9344=0 X10=1 M0=1\n90ms expect D9354:d=-90\n100ms X10=0\n"
            "100ms expect Y10=1 D9354:d=0 M9344=1\n110ms expect Y10=1\n120ms expect Y10=0\n")
    with form(home_mode="data_set"):
        run("LD M0\nZRN K5000 K1000 Y0 Y4\n",
            "0ms D9354:d=777 D9346:d=5 M0=1\n0ms expect D9354:d=5 M9344=1 M9342=1 M9341=0\n")
    # the immediate stop relay before the zero: abnormal end, no home done
    run("LD M0\nZRN K5000 K1000 Y0 Y4\n",
        "0ms D9343=0 D9344=0 M0=1\n100ms M9346=1\n100ms expect M9343=1 M9344=0 D9354:d=-500\n")


def test_a_busy_axis_refuses_a_second_positioning_instruction():
    # M9340 On: DRVA on the same axis is not executed while PLSY holds Y0
    run("LD M0\nPLSY K1000 K0 Y0\nLD M1\nDDRVA K5000 K1000 Y0 Y4\n",
        "0ms M0=1 M1=1\n100ms expect D9352:d=100 D9354:d=0\n")


DTBL_SINGLE = """.table Q0 DTBL K5000 K800 K-1 K2
.table Q0 DTBL K10000 K1200 K100 K2
.table Q0 DTBL K0 K0 K-1 K0
LD M0
DTBL Q0 D100 Y0 Y4
"""


def test_dtbl_page_example_single_absolute_steps_after_m_code_and_end():
    # 8-3 FNC 312, the page's single-step example: to 5000 at 800 Hz, to 10000 at 1200 Hz with
    # the AFTER m code 100, END. No ramps. Each move waits for M9347 OFF -> ON: 5000 / 800 Hz
    # = 6.25 s from 10 ms; then 5000 / 1200 Hz from 6.5 s: done at 10666.7 ms, M9029 one scan
    run(DTBL_SINGLE,
        "0ms D9343=0 D9344=0 D101=0 M0=1\n0ms expect D9349=-1 M9341=0\n10ms M9347=1\n20ms M9347=0\n"
        "3000ms expect D9354:d=2392 D100=0 M9341=1\n"
        "6300ms expect D9354:d=5000 M9342=1 D100=1 D9349=-1 M9341=0 M9340=1\n"
        "6500ms M9347=1\n6500ms expect M9342=0\n6600ms M9347=0\n10660ms expect M9342=0\n"
        "10670ms expect D9354:d=10000 D9349=100 M9348=1 M9342=1 M9029=1 D100=2\n"
        "10680ms expect M9029=0\n11000ms M9347=1\n11000ms expect M9342=0 D9354:d=10000\n"
        "11100ms M9349=1\n11100ms expect D9349=-1 M9348=0\n"
        "11200ms M0=0\n11200ms expect M9340=0 M9342=0\n")


def test_dtbl_continuous_relative_steps_hand_over_with_m_codes():
    # 8-3 FNC 312, continuous relative (command 3): 2000 at 1800 Hz, 1000 at 1200 Hz, D11:D10 =
    # 3000 at D21:D20 = 600 Hz without stopping; WITH m codes (>= 10000) at each step's start.
    # 1121.1 ms, 1954.4 ms, 6954.4 ms; the last row (0 pulses, m code 10002), then END
    run(""".table Q1 DTBL K2000 K1800 K10000 K3
.table Q1 DTBL K1000 K1200 K10001 K3
.table Q1 DTBL D10 D20 K-1 K3
.table Q1 DTBL K0 K0 K10002 K3
.table Q1 DTBL K0 K0 K-1 K0
LD M0
DTBL Q1 D100 Y0 Y4
""",
        "0ms D9343=0 D9344=0 D10:d=3000 D20:d=600 M0=1\n10ms M9347=1\n"
        "1000ms expect D9354:d=1782 D9349=10000 M9348=1 D100=0\n"
        "1200ms expect D9350:d=1200 D9349=10001 D100=1\n"
        # a row without an m code leaves the pending one (DECISION)
        "2000ms expect D9354:d=3027 D9350:d=600 D100=2 D9349=10001 M9342=0\n"
        "6950ms expect D9354:d=5997 M9029=0\n"
        "6960ms expect D9354:d=6000 D9349=10002 M9342=1 M9029=1\n")


def test_dtbl_pending_m_code_start_step_jmp_and_bad_tables():
    # a pending m code refuses the start signal; M9349 clears it, the next edge starts.
    # Start step D101 = 1 (the second row); JMP (5) back to row 1
    run(""".table Q2 DTBL K100 K1000 K5 K1
.table Q2 DTBL K100 K1000 K7 K1
.table Q2 DTBL K1 K0 K-1 K5
LD M0
DTBL Q2 D100 Y0 Y4
""",
        "0ms D9343=0 D9344=0 D101=1 M0=1\n0ms expect D100=1\n10ms M9347=1\n"
        "200ms expect D9354:d=100 D9349=7 D100=1 M9342=1\n200ms M9347=0\n300ms M9347=1\n"
        "400ms expect D9354:d=100 M9342=0\n400ms M9349=1 M9347=0\n400ms expect D9349=-1\n"
        "500ms M9347=1\n700ms expect D9354:d=200\n")
    # M9347 already On at the start is no edge (DECISION); the immediate stop relay: abnormal
    # end, the table stays stopped until the condition goes Off
    run(DTBL_SINGLE,
        "0ms D9343=0 D9344=0 M9347=1 M0=1\n100ms expect D9354:d=0\n100ms M9347=0\n110ms M9347=1\n"
        "1000ms M9346=1\n1000ms expect M9343=1 D9354:d=712\n"
        "1100ms M9346=0 M9347=0\n1200ms M9347=1\n1300ms expect D9354:d=712 M9341=0 M9340=1\n")
    # no rows for the table, a JMP loop, a step past the table: operation errors, no traceback
    for table, start in (("", 0), (".table Q3 DTBL K0 K0 K-1 K5\n", 0),
                         (".table Q3 DTBL K0 K0 K-1 K0\n", 4)):
        run(table + "LD M0\nDTBL Q3 D100 Y0 Y4\n", f"0ms D101={start} M0=1\n"
            "10ms expect M9067=1 M9341=0 D9354:d=0\n", alarms=True)


def _abs_servo(value: int, check_offset: int = 0) -> str:
    """The servo's side of the ABS transfer as a stimulus: 16 transfers of 2 bits (low first),
    3 of the checksum, each: bits on X10/X11 and ready X12 On at 100 + 40k ms, Off 20 ms later."""
    data = value & 0xFFFFFFFF
    twos = [data >> (2 * k) & 3 for k in range(16)]
    check = (sum(twos) + check_offset) & 0x3F
    twos += [check >> (2 * k) & 3 for k in range(3)]
    return "".join(f"{100 + 40 * k}ms X10={b & 1} X11={b >> 1} X12=1\n{120 + 40 * k}ms X12=0\n"
                   for k, b in enumerate(twos))


def test_dabs_page_example_reads_the_servo_position():
    # 8-3 FNC 313: DABS X10 Y10 D9352, M0 a normally-on contact: SERVO ON Y10 and ABS mode
    # Y11 On, request Y12 On until ready; 19 transfers; the last (820 ms) writes D9353:D9352
    # and M9029 On for one scan, ABS mode Off
    il = "LD M0\nDABS X10 Y10 D9352\n"
    run(il, "0ms M0=1\n0ms expect Y10=1 Y11=1 Y12=1\n100ms expect Y12=0\n120ms expect Y12=1\n"
        + _abs_servo(-123457) + "810ms expect D9352:d=0 M9029=0\n"
        "820ms expect D9352:d=-123457 M9029=1 Y10=1 Y11=0 Y12=0\n830ms expect M9029=0\n"
        "900ms M0=0\n900ms expect Y10=0 Y11=0\n")
    # a wrong checksum: operation error, D2 unchanged; the condition Off interrupts a read
    run(il, "0ms M0=1\n" + _abs_servo(5000, 1) + "830ms expect D9352:d=0 M9067=1 M9029=0\n",
        alarms=True)
    # S or D1 whose 3 points pass the device range: E208 when written so (test_vs_audit_fnc150
    # FNC313-D1-3-bits), an operation error when an index takes it there, no traceback
    run("LD M9000\nMOV K8 Z0\nLD M0\nDABS X366Z0 Y10 D9352\n", "0ms M0=1\n0ms expect M9067=1 Y10=0\n",
        alarms=True)
    run(il, "0ms M0=1\n" + _abs_servo(5000) + "300ms M0=0\n300ms expect Y10=0 Y11=0 Y12=0\n"
        "310ms M0=1\n900ms expect D9352:d=0 Y11=1\n")


def test_mpg_page_example_handwheel_gear_and_axis_choice():
    # 8-3 FNC 314, the page's program: response 5 ms, gear D101/D102 by the x1/x10/x100 switches
    # X11-X13, Z0 by the XY switch X10, MPG on X7; A/B on X3/X4 (S1 = K1). 100 Hz from 100 ms
    # (x1 counting: one input pulse a cycle, at 102.5, 112.5 ... ms) seen 5 ms late
    il = """LD M9002
MOV K5 D100
MOV K1 D102
LD X10
MOV K0 Z0
LDI X10
MOV K1 Z0
LD X11
MOVP K1 D101
LD X12
MOVP K10 D101
LD X13
MOVP K100 D101
LD X7
MPG K1 D100 Y0Z0 Y4Z0
"""
    run(il, "0ms X10=1 X12=1 X7=1\n100ms X3/X4 pulses 100Hz until 600ms\n"
        "300ms expect D9354:d=200 Y4=1 Y0=1 M9341=1 M9340=1 D9350:d=1000 D9374:d=0\n"
        # x1 from the 400 ms scan: it applies to the input the execution sees (up to 395 ms,
        # since 385 ms: 392.5 ... 592.5, 21 pulses 1:1) after the 29 pulses at x10
        "400ms X12=0 X11=1\n700ms expect D9354:d=311 M9341=0 D9350:d=0 Y0=0\n"
        # turning back (B leads): D2 Off, the position counts down
        "800ms X3/X4 pulses -200Hz until 900ms\n1000ms expect D9354:d=291 Y4=0\n"
        # Off with the wheel still (speed 0): the decelerating stop ends at once, released in
        # the same scan; then the Y axis (Z0 = 1)
        "1000ms X7=0\n1000ms expect M9340=0 M9343=0 M9342=0\n"
        "1100ms X10=0 X7=1\n1100ms X3/X4 pulses 100Hz until 1200ms\n"
        "1300ms expect D9374:d=10 D9354:d=291 M9360=1\n")
    # S1 from a register outside 0-3: operation error, not executed
    run("LD M0\nMPG D0 D100 Y0 Y4\n", "0ms D0=4 M0=1\n10ms expect M9067=1 M9340=0\n",
        alarms=True)


MPG = "LD M0\nMPG K1 D100 Y0 Y4\n"
# gear 10:1, response 5 ms; the axis: max 1000 Hz, bias 200 Hz, deceleration 1000 ms, so the
# ramp rate is (1000 - 200) / 1 s = 800 Hz/s. A/B on X3/X4 at 100 Hz from 100 ms (x1: one
# input pulse a cycle, at 102.5, 112.5 ... ms, seen 5 ms late): each 10 ms scan puts out 10
# pulses, 1000 Hz; the 500 ms scan sees 40 input pulses (up to 492.5 ms): 400 out
MPG_RAMP = "0ms D100=5 D101=10 D102=1 D9340:d=1000 D9342=200 D9344=1000 M0=1\n"


def test_mpg_condition_off_ramps_down_from_the_output_speed():
    # 8-3 FNC 314 "當條件接點于脈衝輸出中變為OFF時，會做減速停止": from 1000 Hz at 500 ms down
    # to the bias 200 Hz in 1 s, (1000 + 200) / 2 x 1 s = 600 pulses more: 1000 at 1500 ms.
    # At 1000 ms: 600 Hz, 1000 x 0.5 - 800 x 0.5^2 / 2 = 400 (800); at 1250 ms: 400 Hz,
    # 750 - 225 = 525 (925). The wheel still turning is no longer followed; M9340 holds the
    # axis until the ramp ends, then neither M9342 nor M9343
    run(MPG, MPG_RAMP + "100ms X3/X4 pulses 100Hz until 2000ms\n"
        "300ms expect D9354:d=200 D9350:d=1000\n500ms M0=0\n"
        "500ms expect D9354:d=400 D9350:d=1000 M9341=1 M9340=1 Y0=1\n"
        "1000ms expect D9354:d=800 D9350:d=600 M9341=1 M9340=1 Y0=1 Y4=1\n"
        "1250ms expect D9354:d=925 D9350:d=400\n1490ms expect M9340=1 M9341=1\n"
        "1500ms expect D9354:d=1000 D9350:d=0 M9341=0 M9340=0 M9342=0 M9343=0 Y0=0\n"
        "2100ms expect D9354:d=1000\n")
    # B leads: the ramp runs the way the output went (D2 Off, the position down)
    run(MPG, MPG_RAMP + "100ms X3/X4 pulses -100Hz until 2000ms\n500ms M0=0\n"
        "1000ms expect D9354:d=-800 Y4=0\n1500ms expect D9354:d=-1000 M9340=0\n")
    # no deceleration time (D9344 = 0): the stop is at once, released in the Off scan
    run(MPG, MPG_RAMP + "0ms D9344=0\n100ms X3/X4 pulses 100Hz until 2000ms\n500ms M0=0\n"
        "500ms expect D9354:d=400 M9340=0 M9341=0\n600ms expect D9354:d=400\n")


def test_mpg_stop_relays_decelerate_or_stop_at_once_and_end_the_instruction():
    # M9345 (8-2, the positioning pages: "當M9345為ON時，會減速停止輸出脈衝。停止信號解除後，必須
    # 重新啟動指令，才能輸出脈衝"): the ramp of the Off test, then an abnormal end (M9343) with the
    # axis held; M9345 Off does not resume following, the condition's OFF -> ON does (the 10
    # input pulses 1902.5 ... 1992.5 ms: 100 more)
    run(MPG, MPG_RAMP + "100ms X3/X4 pulses 100Hz until 2000ms\n500ms M9345=1\n"
        "1000ms expect D9354:d=800 D9350:d=600 M9343=0 M9340=1\n"
        "1500ms expect D9354:d=1000 D9350:d=0 M9341=0 M9343=1 M9342=0 M9340=1 Y0=0\n"
        "1600ms M9345=0\n1700ms expect D9354:d=1000 M9343=1 M9340=1\n"
        "1800ms M0=0\n1800ms expect M9343=0 M9340=0\n1900ms M0=1\n"
        "2100ms expect D9354:d=1100 M9340=1 M9343=0\n")
    # M9346: at once, the pulses up to the scan that sees it went out (400); abnormal end
    run(MPG, MPG_RAMP + "100ms X3/X4 pulses 100Hz until 2000ms\n500ms M9346=1\n"
        "500ms expect D9354:d=400 D9350:d=0 M9341=0 M9343=1 M9340=1 Y0=0\n"
        "700ms expect D9354:d=400\n")
    # M9346 during the condition-Off ramp ends it at once (800 at 1000 ms), released
    run(MPG, MPG_RAMP + "100ms X3/X4 pulses 100Hz until 2000ms\n500ms M0=0\n1000ms M9346=1\n"
        "1000ms expect D9354:d=800 M9340=0 M9343=0\n1200ms expect D9354:d=800\n")


def test_mpg_ramp_stops_at_once_on_the_limit_ahead():
    # a limit switch ahead stops MPG's output at once, its ramp too: LSF X21 On at 1000 ms (800
    # out, as the Off test) holds back the ramp's pulses after that scan; released then
    with form(lsf=["X21", "", "", ""]):
        run(MPG, MPG_RAMP + "100ms X3/X4 pulses 100Hz until 2000ms\n500ms M0=0\n1000ms X21=1\n"
            "1000ms expect D9354:d=800\n1010ms expect D9354:d=800 M9340=0 M9343=0\n"
            "1200ms expect D9354:d=800\n")


def test_lir_page_example_straight_line_both_axes_arrive_together():
    # 8-3 FNC 315: LIR D1000 K0 from (2000, 1000): bias 1000, run 3000, 300 ms, travel
    # (4000, 3000), length 5000: X bias 800 run 2400, Y 600 / 1800 (D1005-D1008). X ramps 480
    # pulses each way and cruises 3040 (1.2667 s): both arrive at 1876.7 ms. The axis
    # parameters (max 10 kHz here) and the override do not apply
    run("LD M0\nLIR D1000 K0\n",
        "0ms D9340:d=10000 D9348=500 D9354:d=2000 D9374:d=1000 D1000=1000 D1001=3000 D1002=300\n"
        "0ms D1003=4000 D1004=3000\n10ms M0=1\n"
        "10ms expect D1005=800 D1006=2400 D1007=600 D1008=1800 Y4=1 Y5=1 M9340=1 M9360=1\n"
        "310ms expect D9354:d=2480 D9374:d=1360 D9350:d=2400 D9370:d=1800\n"
        "1870ms expect D9354:d=5994 M9342=0 M9341=1\n"
        "1880ms expect D9354:d=6000 D9374:d=4000 M9342=1 M9362=1 M9341=0 M9361=0\n"
        "1900ms M0=0\n1900ms expect M9340=0 M9360=0 M9342=0\n")
    # both travels 0: not executed; the bias vector speed above the run one: operation error
    run("LD M0\nLIR D0 K0\n", "0ms D1=1000 M0=1\n10ms expect M9340=0 M9360=0 M9067=0\n")
    run("LD M0\nLIR D0 K0\n", "0ms D0=2000 D1=1000 D3=5 M0=1\n10ms expect M9340=0 M9067=1\n",
        alarms=True)


def test_lia_page_example_absolute_on_y2_y3_and_stops():
    # 8-3 FNC 316: DLIA D1000 K1 (32-bit pairs): Y2/Y3 with Y6/Y7 from (1000, 500) to (-2000,
    # 4500): travel (-3000, 4000), no ramps, run 5000: X 3000 Hz backward (Y6 Off), Y 4000 Hz
    run("LD M0\nDLIA D1000 K1\n",
        "0ms D9394:d=1000 D9414:d=500 D1002:d=5000 D1006:d=-2000 D1008:d=4500 M0=1\n"
        "0ms expect Y6=0 Y7=1 D1012:d=3000 D1016:d=4000\n500ms expect D9394:d=-500 D9414:d=2500\n"
        "1000ms expect D9394:d=-2000 D9414:d=4500 M9382=1 M9402=1\n")
    # the Y axis's immediate stop relay stops both at once: abnormal end, no done
    run("LD M0\nLIR D1000 K0\n",
        "0ms D1001=5000 D1003=3000 D1004=4000 M0=1\n500ms M9366=1\n"
        "500ms expect D9354:d=1500 D9374:d=2000 M9343=1 M9363=1 M9342=0 M9341=0\n"
        "700ms expect D9354:d=1500\n")
    # the condition Off ramps both down over the ramp time (200 ms: X 3000 -> 0 Hz, +300)
    run("LD M0\nLIR D1000 K0\n",
        "0ms D1001=5000 D1002=200 D1003=6000 D1004=8000 M0=1\n1000ms M0=0\n"
        "1000ms expect D9354:d=2700\n1200ms expect D9354:d=3000 D9374:d=4000 M9340=0 M9342=0\n")


def test_m9346_of_either_axis_cuts_the_straight_lines_ramp_down():
    # LIR as above (run 5000, 200 ms, travel (6000, 8000): X 3000 Hz, Y 4000 Hz, rates 15000
    # and 20000 Hz/s): Off at 1000 ms (2700, 3600); 100 ms into the ramp X 300 - 75 = 225, Y 400
    # - 100 = 300 more; the Y axis's M9366 then stops both at once (the ramp would end at
    # 3000, 4000); the condition is Off: released, no M9343/M9363
    run("LD M0\nLIR D1000 K0\n",
        "0ms D1001=5000 D1002=200 D1003=6000 D1004=8000 M0=1\n1000ms M0=0\n"
        "1000ms expect D9354:d=2700 D9374:d=3600\n1100ms M9366=1\n"
        "1100ms expect D9354:d=2925 D9374:d=3900 M9341=0 M9361=0 M9340=0 M9360=0\n"
        "1300ms expect D9354:d=2925 D9374:d=3900 M9343=0 M9363=0 M9342=0 M9362=0\n")
