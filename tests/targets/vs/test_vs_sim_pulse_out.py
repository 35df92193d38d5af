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


def test_plsr_raised_s1_while_cruising_ramps_at_the_new_rate_and_keeps_the_count():
    # 6-7 FNC 59: S1 may change while running. D0 = 1000, S3 = 1 s, 10000 pulses: 500 on the
    # ramp, cruising at 1000 Hz; at 2 s (1500 out) D0 = 2000: the rate is now 2000 Hz/s
    # (S3 is the time from 0 to S1), so 1000 -> 2000 Hz takes 0.5 s and 750 pulses
    # (1500 + 1000 x 0.25 + 2000 x 0.25^2 / 2 = 1812.5 at 2.25 s); the final ramp 2000 -> 0
    # takes 1 s and 1000 pulses, so the cruise is (10000 - 1500 - 750 - 1000) / 2000 =
    # 3.375 s, from 2.5 s (2250 out) to 5.875 s (9000 out); done at 6.875 s
    run("LD X20\nPLSR D0 K10000 K1000 Y0\n",
        "0ms D0=1000 X20=1\n2s expect D9352:d=1500 D9350:d=1000\n2s D0=2000\n"
        "2250ms expect D9352:d=1812 D9350:d=1500\n2500ms expect D9352:d=2250 D9350:d=2000\n"
        "3s expect D9352:d=3250 D9350:d=2000\n5870ms expect D9352:d=8990\n"
        # 6.4 s: 0.525 s into the ramp down: 9000 + 2000 x 0.525 - 2000 x 0.525^2 / 2
        "6400ms expect D9352:d=9774 D9350:d=950 M9342=0\n"
        "6870ms expect D9352:d=9999 M9341=1\n6880ms expect D9352:d=10000 M9342=1 M9341=0\n")


def test_plsr_lowered_s1_ramps_down_to_it_then_cruises():
    # D0 = 2000: ramp 1 s (1000 pulses), cruise; at 2 s (3000 out) D0 = 1000: rate 1000 Hz/s,
    # 2000 -> 1000 Hz in 1 s (1500 pulses; 3875 at 2.5 s), final ramp 1000 -> 0 in 1 s (500),
    # so cruising (10000 - 3000 - 1500 - 500) / 1000 = 5 s from 3 s: 9500 at 8 s, done at 9 s
    run("LD X20\nPLSR D0 K10000 K1000 Y1\n",
        "0ms D0=2000 X20=1\n1s expect D9372:d=1000 D9370:d=2000\n2s D0=1000\n"
        "2500ms expect D9372:d=3875 D9370:d=1500\n3s expect D9372:d=4500 D9370:d=1000\n"
        "8s expect D9372:d=9500\n8500ms expect D9372:d=9875 D9370:d=500\n"
        "8990ms expect M9362=0\n9s expect D9372:d=10000 M9362=1\n")


def test_plsr_raised_s1_on_a_short_rest_peaks_lower_and_off_stops_at_the_new_rate():
    # 1875 pulses, D0 = 1000, S3 = 1 s: cruising from 1 s; at 1.5 s (1000 out, 875 left) D0 =
    # 2000 (2000 Hz/s): up and down meet at sqrt((2 x 2000 x 875 + 1000^2) / 2) = 1500 Hz,
    # reached at 1.75 s (1312.5 out), then down for 0.75 s: done at 2.5 s; at 2.1 s
    # 1312.5 + 1500 x 0.35 - 2000 x 0.35^2 / 2 = 1715 out at 800 Hz
    run("LD X20\nPLSR D0 K1875 K1000 Y0\n",
        "0ms D0=1000 X20=1\n1500ms D0=2000\n1750ms expect D9352:d=1312 D9350:d=1500\n"
        "2100ms expect D9352:d=1715 D9350:d=800\n2500ms expect D9352:d=1875 M9342=1\n")
    # the decelerating stop after a change uses the new rate: raised to 2000 at 2 s as in the
    # first test, 3250 out at 3 s at 2000 Hz; X20 Off: 1 s and 1000 pulses to stop
    run("LD X20\nPLSR D0 K30000 K1000 Y0\n",
        "0ms D0=1000 X20=1\n2s D0=2000\n3s X20=0\n3500ms expect D9352:d=4000 D9350:d=1000 M9341=1\n"
        "4010ms expect D9352:d=4250 M9340=0\n")


def test_plsr_lowered_s1_near_the_end_stops_exactly_and_final_ramp_ignores_changes():
    # 3000 pulses at 1000 Hz, S3 = 1 s: at 2.5 s (2000 out, 1000 left) D0 = 100: the new rate
    # 100 Hz/s would need 5000 pulses to stop, so (DECISION) the speed falls to 0 at
    # 1000^2 / (2 x 1000) = 500 Hz/s, ending at 3000 exactly at 4.5 s (2750 at 3.5 s, 500 Hz)
    run("LD X20\nPLSR D0 K3000 K1000 Y0\n",
        "0ms D0=1000 X20=1\n2500ms D0=100\n3500ms expect D9352:d=2750 D9350:d=500\n"
        "4490ms expect M9342=0 M9341=1\n4500ms expect D9352:d=3000 M9342=1 M9343=0\n")
    # a change read in the final ramp (from 3 s) is ignored: 2875 out at 3.5 s either way
    run("LD X20\nPLSR D0 K3000 K1000 Y0\n",
        "0ms D0=1000 X20=1\n3200ms D0=5000\n3500ms expect D9352:d=2875 D9350:d=500\n"
        "4s expect D9352:d=3000 M9342=1\n")


def test_plsr_without_ramp_changes_speed_at_once():
    # S3 = 0: 100 Hz, at 1 s (100 out) D0 = 200: 300 at 2 s, the rest of 1000 at 5.5 s
    run("LD X20\nPLSR D0 K1000 K0 Y2\n",
        "0ms D0=100 X20=1\n1s D0=200\n1s expect D9392:d=100 D9390:d=200\n2s expect D9392:d=300\n"
        "5490ms expect M9382=0\n5500ms expect D9392:d=1000 M9382=1\n")
