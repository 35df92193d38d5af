"""ZRN's DOG front-edge home mode, the automatic DOG search with limit switches and the travel
limits LSF/LSR (8-1-2, 8-3 FNC 300; mlctool/targets/vs/positioning/homing.py, positioning.py). Limit and DOG
inputs come from the stimulus as plain X inputs; numbers worked out by hand from the
trapezoid (docs/vs.md "Positioning")."""

from __future__ import annotations

from test_vs_sim_positioning import form

from vskit import run

ZRN = "LD M0\nDZRN K5000 K1000 Y0 Y4\n"
NO_RAMPS = "0ms D9343=0 D9344=0 D9346:d=7 M0=1\n"


def test_dog_front_edge_mode_backs_out_of_the_dog_at_the_creep_speed():
    # 8-1-2 "DOG前緣定位原點復歸": toward home at S1, the DOG's front edge ramps down to the
    # creep speed, the motor turns the other way and the zero is where the DOG goes Off.
    # Max 10 kHz, ramps 100 ms (100000 Hz/s): 5000 Hz after 50 ms (125); DOG at 200 ms
    # (-875); down to 1000 Hz in 40 ms (80 in the first 20 ms, 120 in all: -995 at 240 ms), turn: 10 ms up to 1000 Hz
    # (5), then 1000 Hz increasing (Y4 On); DOG Off at 300 ms: the origin value
    with form(home_mode="dog_front"):
        run(ZRN, "0ms D9340:d=10000 D9346:d=7 M0=1\n0ms expect Y4=0\n200ms X10=1\n"
                 "200ms expect D9354:d=-875\n220ms expect D9354:d=-955 D9350:d=3000\n"
                 "240ms expect D9354:d=-995 Y4=1\n260ms expect D9354:d=-980 D9350:d=1000\n"
                 "290ms expect D9354:d=-950 M9344=0 M9342=0\n"
                 "300ms X10=0\n300ms expect D9354:d=7 M9344=1 M9342=1 M9341=0\n")


def test_dog_front_edge_mode_without_ramps_turns_at_the_front_edge():
    # no ramps: the creep speed at once, so the turn is at the front edge itself (-500)
    with form(home_mode="dog_front"):
        run(ZRN, NO_RAMPS + "100ms X10=1\n100ms expect D9354:d=-500 Y4=1\n"
                 "140ms expect D9354:d=-460\n150ms X10=0\n150ms expect D9354:d=7 M9344=1\n")


def test_search_from_between_the_dog_and_the_limit_switch():
    # 8-1-2 automatic search, case (3): home-ward at S1 to the limit switch (LSR X20: home is
    # the decreasing position, motor reverse), stop, back at S1 past the whole DOG (On, then
    # Off), stop, home-ward again; then the DOG rear-edge mode as usual. No ramps: every
    # stop is at once; the turn is at the stop's instant
    with form(lsr=["X20", "", "", ""]):
        run(ZRN, NO_RAMPS + "100ms X20=1\n100ms expect D9354:d=-500 Y4=0\n"
                 "150ms X20=0\n150ms expect D9354:d=-250 Y4=1 M9343=0\n"
                 "200ms X10=1\n200ms expect D9354:d=0\n300ms X10=0\n300ms expect D9354:d=500\n"
                 "350ms expect D9354:d=250 Y4=0\n400ms X10=1\n400ms expect D9354:d=0\n"
                 "490ms expect D9354:d=-90 D9350:d=1000\n"
                 "500ms X10=0\n500ms expect D9354:d=7 M9344=1 M9342=1 M9343=0\n")


def test_search_starting_in_the_dog_or_on_the_limit_switch():
    # case (2): the DOG On at the start: away from home until it goes Off, then as case (1)
    with form(lsr=["X20", "", "", ""]):
        run(ZRN, NO_RAMPS + "0ms X10=1\n0ms expect Y4=1\n100ms X10=0\n100ms expect D9354:d=500\n"
                 "150ms expect D9354:d=250 Y4=0\n200ms X10=1\n300ms X10=0\n"
                 "300ms expect D9354:d=7 M9344=1\n")
    # case (4): on the limit switch: away past the whole DOG (X10 On at 100 ms, Off at 200 ms)
    with form(lsr=["X20", "", "", ""]):
        run(ZRN, NO_RAMPS + "0ms X20=1\n0ms expect Y4=1\n50ms X20=0\n100ms X10=1\n"
                 "100ms expect D9354:d=500\n200ms X10=0\n200ms expect D9354:d=1000\n"
                 "250ms expect D9354:d=750 Y4=0\n300ms X10=1\n300ms expect D9354:d=500\n"
                 "400ms X10=0\n400ms expect D9354:d=7 M9344=1\n")
    # without a limit switch in the form, a DOG On at the start is its front edge (creep)
    run(ZRN, NO_RAMPS + "0ms X10=1\n0ms expect Y4=0\n90ms expect D9354:d=-90\n")


def test_travel_limit_ramps_down_and_refuses_moves_toward_it():
    # 8-1-2 LSF: the forward limit (X21) ramps the axis down and only moves the other way are
    # accepted. DDRVR at 10 kHz, ramps 100 ms: 5500 at 600 ms, 500 more to stand (6000),
    # abnormal end M9343 (DECISION), no M9342
    with form(lsf=["X21", "", "", ""]):
        run("LD M0\nDDRVR K100000 K10000 Y0 Y4\nLD M1\nDDRVR K-1000 K10000 Y0 Y4\n",
            "0ms D9340:d=10000 M0=1\n600ms X21=1\n600ms expect D9354:d=5500\n"
            "650ms expect D9354:d=5875 M9341=1\n700ms expect D9354:d=6000 M9343=1 M9342=0\n"
            "800ms M0=0\n900ms M0=1\n900ms expect M9343=1 D9354:d=6000\n"   # toward it: no pulse
            "1000ms expect D9354:d=6000 M9341=0\n1100ms M0=0\n"
            "1200ms M1=1\n1200ms expect Y4=0\n1400ms expect D9354:d=5000 M9342=1 M9343=0\n")


def test_m9346_cuts_the_ramp_down_of_a_travel_limit_and_of_zrn():
    # the LSF case above: 5875 at 650 ms, 50 ms into the limit's ramp down; M9346 then stops
    # the output at once (it would have run to 6000); abnormal end M9343 as the limit set it
    with form(lsf=["X21", "", "", ""]):
        run("LD M0\nDDRVR K100000 K10000 Y0 Y4\n",
            "0ms D9340:d=10000 M0=1\n600ms X21=1\n600ms expect D9354:d=5500\n650ms M9346=1\n"
            "650ms expect D9354:d=5875 M9341=0 D9350:d=0 M9343=1 M9340=1 M9342=0\n"
            "800ms expect D9354:d=5875 M9343=1\n")
    # ZRN toward home at 5000 Hz (max 10 kHz, ramps 100 ms): -875 at 200 ms, the condition
    # Off ramps down (50 ms, 125 pulses); 20 ms in: 100 - 20 = 80 more (-955); M9346 then:
    # stopped at once (the ramp would end at -1000), released, neither M9343 nor M9344
    run(ZRN, "0ms D9340:d=10000 M0=1\n200ms M0=0\n200ms expect D9354:d=-875\n220ms M9346=1\n"
             "220ms expect D9354:d=-955 M9341=0 M9340=0\n"
             "300ms expect D9354:d=-955 M9343=0 M9344=0 M9342=0\n")


def test_reverse_limit_stops_jog_and_the_dtbl_table():
    # LSR (X22) on a JOGR: a decelerating stop (no ramps: at once), abnormal end
    with form(lsr=["X22", "", "", ""]):
        run("LD M0\nDJOGR K0 K1000 Y0 Y4\n",
            "0ms D9343=0 D9344=0 M0=1\n300ms X22=1\n300ms expect D9354:d=-300 M9343=1\n"
            "400ms expect D9354:d=-300\n")
    # a DTBL step running into LSF stops, and the table stays stopped (no next step)
    with form(lsf=["X21", "", "", ""]):
        run(".table Q0 DTBL K5000 K1000 K-1 K1\n.table Q0 DTBL K100 K1000 K-1 K1\n"
            ".table Q0 DTBL K0 K0 K-1 K0\nLD M0\nDTBL Q0 D100 Y0 Y4\n",
            "0ms D9343=0 D9344=0 M0=1\n10ms M9347=1\n200ms X21=1\n"
            "200ms expect D9354:d=190 M9343=1 M9342=0\n300ms expect D9354:d=190 D100=0\n")


def test_a_limit_of_either_axis_stops_the_straight_line():
    # LIR (8-3 FNC 315) on Y0/Y1, no ramp: X 2400 Hz, Y 1800 Hz (the page's split of 3000 Hz
    # over (4000, 3000)); Y1's LSF (X21) at 500 ms stops both (0.49 s: 1176, 882), abnormal end
    with form(lsf=["", "X21", "", ""]):
        run("LD M0\nLIR D1000 K0\n",
            "0ms D1000=0 D1001=3000 D1002=0 D1003=4000 D1004=3000\n10ms M0=1\n500ms X21=1\n"
            "500ms expect D9354:d=1176 D9374:d=882 M9343=1 M9363=1 M9342=0\n"
            "600ms expect D9354:d=1176 D9374:d=882\n")


MPG = "LD M0\nMPG K1 D100 Y0 Y4\n"
MPG_SETUP = "0ms D100=5 D101=1 D102=1 M0=1\n"


def test_mpg_stops_at_once_on_the_limit_ahead_and_follows_the_wheel_away():
    # 8-3 FNC 314: "脈衝輸出中，若碰到正/反轉極限開關，則會立即停止 ... 此時僅能接受相反方向的脈衝
    # 輸出要求". A/B on X3/X4 (S1 = K1), gear 1:1, response 5 ms: x1 events at 102.5,
    # 112.5 ... ms, each seen 5 ms late. LSF X21 On at 300 ms: the 20 events up to 295 ms
    # went out before; the 10 of 302.5-392.5 ms toward the limit are dropped (DECISION: not
    # owed). B leads from 500 ms (10 events): away from the limit with LSF still On; LSF Off,
    # A leads again from 800 ms: +10
    with form(lsf=["X21", "", "", ""]):
        run(MPG, MPG_SETUP + "100ms X3/X4 pulses 100Hz until 400ms\n"
            "290ms expect D9354:d=19 Y4=1\n300ms X21=1\n300ms expect D9354:d=20\n"
            "350ms expect D9354:d=20 D9350:d=0 M9341=0 Y0=0\n"
            "450ms expect D9354:d=20 M9343=0 M9342=0 M9340=1\n"
            "500ms X3/X4 pulses -100Hz until 600ms\n700ms expect D9354:d=10 Y4=0\n"
            "700ms X21=0\n800ms X3/X4 pulses 100Hz until 900ms\n1000ms expect D9354:d=20 Y4=1\n")


def test_mpg_limits_follow_the_motor_rotation():
    # "position increasing: motor reverse" (8-1-1): A leads = the motor forward (the page: D2
    # On), so the position counts down; LSR (X22) limits the reverse rotation (B leads) only
    with form(lsf=["X21", "", "", ""], lsr=["X22", "", "", ""], reverse_rotation=True):
        run(MPG, MPG_SETUP + "100ms X3/X4 pulses 100Hz until 200ms\n"
            "250ms expect D9354:d=-10 Y4=1\n250ms X22=1\n"
            "300ms X3/X4 pulses 100Hz until 400ms\n450ms expect D9354:d=-20 Y4=1\n"
            "500ms X3/X4 pulses -100Hz until 600ms\n700ms expect D9354:d=-20 Y4=1\n"
            "700ms X22=0 X21=1\n800ms X3/X4 pulses -100Hz until 900ms\n"
            "1000ms expect D9354:d=-10 Y4=0\n")


def test_dog_on_a_normally_closed_contact_homes_as_the_normally_open_one():
    # input polarity (the positioning parameter word 2-17-9 BFM#115, b10 DOG: 1 = N/C): the
    # page example of 8-3 FNC 300 (test_zrn_page_example_dog_rear_edge_homing) with X10's
    # levels inverted homes the same: X10 On at the start is "not at the DOG" (an N/O DOG On
    # at the start would creep at once)
    zrn = "LD M0\nDZRN K50000 K1000 Y0 Y4\n"
    with form(input_polarity=[0x400, 0, 0, 0]):
        run(zrn, "0ms X10=1 D9346:d=100 M9344=0 M0=1\n0ms expect Y4=0 M9340=1\n200ms X10=0\n"
            "200ms expect D9354:d=-9375\n490ms expect D9354:d=-10265 D9350:d=1000 M9344=0\n"
            "500ms X10=1\n500ms expect D9354:d=100 M9344=1 M9342=1 M9341=0 Y0=0\n")
    # b9 (STR) has no input on the built-in axes: the N/O stimulus homes as ever
    with form(input_polarity=[0x200, 0, 0, 0]):
        run(zrn, "0ms D9346:d=100 M0=1\n200ms X10=1\n200ms expect D9354:d=-9375\n"
            "500ms X10=0\n500ms expect D9354:d=100 M9344=1\n")


def test_pg0_on_a_normally_closed_contact_counts_its_opening():
    # b11 PG0 N/C, "DOG rear edge, count PG0", 2 zero signals, no ramps: 5000 Hz to the DOG
    # (100 ms, 500), 1000 Hz creep, DOG rear at 200 ms (600). Plain levels: X0 falling at
    # 210 and 230 ms are the zero signals (an N/O PG0 would see one rise, at 220 ms)
    ramps = "0ms D9340:d=5000 D9343=0 D9344=0 D9346:d=-5 M0=1\n100ms X10=1\n200ms X10=0\n"
    with form(home_mode="dog_rear_pg0", input_polarity=[0x800, 0, 0, 0]):
        run(ZRN, "0ms X0=1\n" + ramps + "210ms X0=0\n220ms X0=1\n"
            "220ms expect D9354:d=-620 M9344=0\n230ms X0=0\n230ms expect D9354:d=-5 M9344=1\n")
        # a train (50 Hz from 201 ms: rising at 201, 221 ms, falling at 211, 231 ms): the
        # falling edges count, the zero at 231 ms (an N/O PG0: 221 ms)
        run(ZRN, ramps + "201ms X0 pulses 50Hz\n230ms expect D9354:d=-630 M9344=0\n"
            "240ms expect D9354:d=-5 M9344=1 M9342=1\n")
