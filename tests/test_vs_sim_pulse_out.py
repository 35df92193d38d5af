"""Pulse outputs PLSY, PWM, PLSR (6-7 FNC 57-59) on virtual time: the pages' examples, the
axis registers (D9352 pulse count, D9350 speed) and flags (M9340 busy, M9341 outputting,
M9342 done, M9343 abnormal end), a level per scan on the Y pin."""

from __future__ import annotations

from vskit import run


def test_plsy_page_example_counts_d100_pulses_at_500hz():
    # 6-7 FNC 57: X20 On: Y0 puts out D100 pulses at 500 Hz (D100 = 100: 200 ms), counted in
    # D9353:D9352; M9342 when all are out; X20 Off clears the flags and Y0
    run("LD X20\nPLSY K500 D100 Y0\n",
        "0ms D100=100 X20=1\n0ms expect M9340=1 M9341=1 Y0=1 D9350:d=500\n"
        "10ms expect Y0=1 D9352:d=5\n100ms expect D9352:d=50 M9342=0\n"
        "200ms expect D9352:d=100 M9342=1 M9341=0 Y0=0 D9350:d=0 M9340=1\n"
        "300ms expect D9352:d=100\n310ms X20=0\n310ms expect M9342=0 M9340=0\n")


def test_plsy_off_stops_at_once_and_restarts_from_the_first_pulse():
    # the count register is cumulative from power-on; the stop relay ends early with M9343
    run("LD X20\nPLSY K1000 K0 Y1\n",
        "0ms X20=1\n50ms X20=0\n50ms expect D9372:d=50 Y1=0 M9361=0\n"
        "100ms X20=1\n150ms expect D9372:d=100\n150ms M9366=1\n"
        "160ms expect D9372:d=100 M9363=1 M9361=0\n")


def test_plsy_frequency_change_applies_from_the_execution_that_reads_it():
    run("LD X20\nPLSY D0 K1000 Y2\n",
        "0ms D0=1000 X20=1\n100ms D0=2000\n100ms expect D9392:d=100\n"
        "200ms expect D9392:d=300 D9390:d=2000\n")


def test_plsy_negative_count_is_an_operation_error_and_a_busy_axis_refuses():
    r = run("LD X20\nPLSY K100 D0 Y0\n", "0ms D0=-1 X20=1\n10ms expect M9067=1 M9340=0 Y0=0\n",
            alarms=True)
    assert r.alarms
    # a second instruction on Y0 is not executed while the first holds the axis
    run("LD X20\nPLSY K100 K0 Y0\nLD X21\nPLSY K1000 K0 Y0\n",
        "0ms X20=1 X21=1\n100ms expect D9352:d=10 D9350:d=100\n")


def test_pwm_page_example_one_ms_and_tenth_ms_bases():
    # 6-7 FNC 58: D0 = 50, K100, M9035 Off: 50 ms On in every 100 ms; M9035 On with D0 = 20:
    # 2 ms in 10 ms; X20 Off: Y0 Off
    run("LD X20\nPWM D0 K100 Y0\n",
        "0ms D0=50 X20=1\n0ms expect Y0=1\n40ms expect Y0=1\n50ms expect Y0=0\n90ms expect Y0=0\n"
        "100ms expect Y0=1\n120ms X20=0\n120ms expect Y0=0\n")
    # 0.1 ms base, t = 2 ms of T = 15 ms: the 10 ms scans see phases 0, 10, 5, 0 ms
    run("LD M9000\nOUT M9035\nLD X20\nPWM D0 K150 Y1\n",
        "0ms D0=20 X20=1\n0ms expect Y1=1\n10ms expect Y1=0\n20ms expect Y1=0\n30ms expect Y1=1\n")


def test_pwm_t_above_period_is_an_operation_error():
    run("LD X20\nPWM D0 K100 Y0\n", "0ms D0=101 X20=1\n10ms expect Y0=0 M9067=1\n", alarms=True)


def test_plsr_page_example_ramps_up_cruises_and_ramps_down():
    # 6-7 FNC 59: PLSR K1000 D100 K1000 Y0: ramps 0 -> 1000 Hz in 1 s, D100 = 3000 pulses:
    # 500 on the ramp up, 2000 cruising (2 s), 500 down; done at 4 s
    run("LD X20\nPLSR K1000 D100 K1000 Y0\n",
        "0ms D100=3000 X20=1\n500ms expect D9352:d=125 D9350:d=500 M9341=1\n"
        "1s expect D9352:d=500 D9350:d=1000\n2s expect D9352:d=1500\n"
        "3500ms expect D9352:d=2875\n4s expect D9352:d=3000 M9342=1 M9341=0 Y0=0\n"
        "4100ms X20=0\n4100ms expect M9342=0 M9340=0\n")


def test_plsr_short_move_peaks_lower_and_off_decelerates():
    # 100 pulses with a 1 s ramp to 1000 Hz: a triangle peaking at sqrt(100 x 1000) Hz at
    # 316 ms (1000 x 0.32^2 / 2 = 51.2 pulses at 320 ms), done at 632 ms
    run("LD X20\nPLSR K1000 K100 K1000 Y0\n",
        "0ms X20=1\n320ms expect D9352:d=51\n640ms expect D9352:d=100 M9342=1\n")
    # Off at 1 s (1000 Hz, 500 pulses): decelerating stop takes 1 s and 500 more pulses
    run("LD X20\nPLSR K1000 K30000 K1000 Y0\n",
        "0ms X20=1\n1s X20=0\n1500ms expect D9352:d=875 M9341=1 M9340=1\n"
        "2010ms expect D9352:d=1000 M9341=0 M9340=0 M9343=0\n")
