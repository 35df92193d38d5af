"""The one-key macro call (5.3.8, 6.12), the handwheel run M2x006 (5.3.2) and the system
time D49000-D49002 (5.3.15)."""

from __future__ import annotations

import os

from nc5kit import outcome, run

MACRO = "O9001 (a probe cycle)\nG91 G01 Z-2. F1200\nZ2.\nM99\n"
IL = "LD X1\nMOV K9001 D21064\nOUT M21032\nLD X2\nOUT M21025\nLD X3\nMOV K4 D21000\nLDI X3\nMOV K0 D21000\n"


def _run(il: str, stim: str, part: str = "M30\n", macro: str = MACRO):
    """As nc5kit.run, with the macro file O9001.nc beside the stimulus."""
    import nc5kit

    real = nc5kit.parse_stimulus_text

    def with_macro(path, text, target):
        with open(os.path.join(os.path.dirname(path), "O9001.nc"), "w", encoding="utf-8") as f:
            f.write(macro)
        return real(path, text, target)
    nc5kit.parse_stimulus_text = with_macro
    try:
        r = outcome(il, stim, part)
    finally:
        nc5kit.parse_stimulus_text = real
    assert r.fault is None and not r.failed, [(f.line, f.device, f.expected, f.actual) for f in r.failed]
    return r


def test_prepare_complete_start_run_and_done():
    """6.12's flow: prepare (M3x027 at once), complete (M3x048, M3x028) the step after, start
    in AUTO (M3x028 drops), the macro runs, M3x027 and M3x048 drop at its M99."""
    _run(IL, "model nc5 macro_9001=O9001.nc\n0ms X3=1\n50ms X1=1\n"
             "60ms expect M31027=1 M31048=0\n70ms expect M31048=1 M31028=1 M31029=0\n"
             "100ms X2=1\n110ms expect M31000=0 M31016=0\n"  # JOG: the start waits for AUTO
             "110ms X3=0 X2=0\n150ms X2=1\n"
             "200ms expect M31028=0 M31016=1 NC1.Z.pos=-1000 M31027=1\n"
             "500ms expect M31027=0 M31048=0 M31016=0 NC1.Z.pos=0 M31023=0 D49100:d=0\n")


def test_a_wrong_name_is_an_error_and_reset_clears_the_flags():
    """DECISION (notes #26): 0, 10000 and above, or no macro_N file: M3x029."""
    il = "LD X1\nOUT M21032\nLD X4\nOUT M21004\nLD X5\nMOV K12345 D21065\nOUT M21033\n"
    _run(il, "model nc5 macro_9001=O9001.nc\n0ms X1=1\n20ms expect M31029=1 M31027=0\n"
             "20ms X4=1\n40ms expect M31029=0\n40ms X4=0 X5=1\n60ms expect M31029=1\n")
    _run("LD X1\nMOV K9001 D21064\nOUT M21032\nLD X4\nOUT M21004\n",
         "model nc5 macro_9001=O9001.nc\n0ms X1=1\n30ms expect M31048=1 M31028=1\n"
         "30ms X4=1\n50ms expect M31048=0 M31028=0 M31027=0\n")


def test_a_macro_ends_with_m99_only_as_a_macro():
    from nc5kit import model_diags

    assert model_diags("model nc5 program=part.nc\n", "G01 X1. F100\nM99\n") == [("part.nc", 2, 1, "E262")]


def test_handwheel_run_moves_the_program_by_pulses():
    """5.3.2 M2x006: the moves stop at once and take the pulses (x D2x009); the rest runs."""
    run("LD X2\nOUT M21000\nLD X6\nOUT M21006\nLDI M0\nMOV K10 D21009\n",
        "model nc5 program=part.nc mpg=D100\n0ms X2=1\n300ms X6=1\n"
        "500ms expect NC1.X.pos=3000 M31016=1 M31464=0\n"
        "500ms D100=50\n520ms expect NC1.X.pos=3500\n520ms D100=30\n540ms expect NC1.X.pos=3500\n"
        "540ms X6=0\n1300ms expect NC1.X.pos=10000 M31023=1\n", "G01 X10. F600\nM30\n")


def test_system_time_counts_from_the_clock_parameter():
    """DECISION (5.3.15): two decimal digits a value: year-month, day-hour, minute-second."""
    r = run("", "model nc5 clock=2023-12-31T23:59:58\n1000ms expect D49000=2312 D49001=3123 D49002=5959\n"
                "2000ms expect D49000=2401 D49001=100 D49002=0\n")
    assert r.devices["D49002"] == 0
