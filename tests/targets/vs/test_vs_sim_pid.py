"""Vigor VS PID (6-10 FNC 88) and TPID (6-11 FNC 92): the page's example programs, checked
against the page's formulas worked by hand (docs/vs.md "PID")."""

from __future__ import annotations

from vskit import run

PID_PROGRAM = "LD X0\nPID D0 D1 D100 D200\n"


def params(ts=100, mode=1, alpha=0, kp=100, ti=10, kd=0, td=0) -> str:
    return (f"D100={ts} D101:h=H{mode:X} D102={alpha} D103={kp} D104={ti} D105={kd} "
            f"D106={td}")


def test_pid_proportional_integral_reverse_action():
    # 6-10 example PID D0 D1 D100 D200 on X0; reverse action (b0 On), KP 100 %, TI 1 s,
    # Ts 100 ms: every sample adds KP {(EVn - EVn-1) + Ts/TI EVn}
    run(PID_PROGRAM,
        f"0ms D0=1000 D1=0 {params()} X0=1\n"
        "0ms expect D200=100\n90ms expect D200=100\n100ms expect D200=200\n"
        "500ms expect D200=600\n"
        "510ms D1=500\n"       # EV 1000 -> 500: -500 + 0.1 x 500 at the 600 ms sample
        "590ms expect D200=600\n600ms expect D200=150\n700ms expect D200=200\n"
        "710ms X0=0\n1s expect D200=200\n")


def test_pid_derivative_with_input_filter_forward_action():
    # forward action (b0 Off): EVn = PVnf - SV; a = 50 %, KP 200 %, TD 100 ms, KD 50 %:
    # Dn = TD/(Ts + KD TD) (PVnf - 2 PVnf-1 + PVnf-2) + KD TD/(Ts + KD TD) Dn-1
    # 200 ms: PVnf 50, Dn 33.3, dMV 2 (50 + 33.3) = 166.7 -> 167
    # 300 ms: PVnf 75, Dn -16.7 + 11.1 = -5.6, dMV 2 (25 - 5.6) = 38.9 -> 205.6 -> 206
    run(PID_PROGRAM,
        f"0ms D0=0 D1=0 {params(mode=0, alpha=50, kp=200, ti=0, kd=50, td=10)} X0=1\n"
        "100ms expect D200=0\n110ms D1=100\n200ms expect D200=167\n300ms expect D200=206\n")


def test_pid_output_limits_and_input_change_alarm():
    # b5: MV kept within S3+23 .. S3+22; b1: S3+24 b0 when PV rises more than S3+20 in a sample
    run(PID_PROGRAM,
        f"0ms D0=1000 D1=0 {params(mode=0x23)} D120=100 D121=100 D122=250 D123=0 X0=1\n"
        "100ms expect D200=200\n200ms expect D200=250\n500ms expect D200=250 D124=0\n"
        "510ms D1=700\n600ms expect D124=1\n700ms expect D124=0\n"
        "710ms D1=0\n800ms expect D124=2\n")


def test_pid_parameter_errors_stop_it_and_short_sampling_continues():
    # 6730-6736 stop the instruction (D unchanged); 6740: Ts <= scan time, sampled every scan
    r = run(PID_PROGRAM + "LD X1\nPID D10 D11 D120 D210\n",
            f"0ms D0=1000 D200=7 {params(kp=0)} X0=1\n0ms expect D200=7 D9067=6733 M9067=1\n"
            "0ms D10=100 D11=0 D120=5 D121:h=H1 D123=100 D124=1\n"
            "10ms M9067=0 D9067=0 X0=0 X1=1\n"
            # first sample at 10 ms with Ts 5 ms: KP Ts/TI EV = 5/100 x 100 = 5; later
            # samples every scan with Ts = the 10 ms scan: +10 each, 6740 reported
            "10ms expect D210=5 D9067=0\n20ms expect D210=15 D9067=6740 M9067=1\n"
            "30ms expect D210=25\n", alarms=True)
    assert {a.name for a in r.alarms} == {"OPERATION_ERROR"}
    assert any("6740" in a.message or "sampling time" in a.message for a in r.alarms)


def test_tpid_example_time_proportional_output_and_alarms():
    # 6-11 example 1: TPID D0 D10 D100 D7000 K1, SV 245.0 C, cycle 1000 x 10 ms, reverse
    # (heating); KP 1.00, TI 10 s: first cycle 450 (45.0 %) -> D105 b0 On for 4.5 s of 10 s
    run("LD X0\nTPID D0 D10 D100 D7000 K1\n",
        "0ms D0=2450 D10=2000 D100=1000 D101=0 D102=0 D103=0 D104=0\n"
        "0ms D7000=100 D7001=100 D7002=0 D7004=2800 D7005=100 X0=1\n"
        "0ms expect D110=450 D105=1 D106=0 D107=1\n4.49s expect D105=1\n4.5s expect D105=0\n"
        "10s expect D110=900 D105=1\n18.99s expect D105=1\n19s expect D105=0\n"
        "19.5s D10=2900\n19.5s expect D106=1\n"
        "19.9s X0=0\n19.9s expect D105=0 D110=0\n")
