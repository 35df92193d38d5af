"""Vigor VS interrupts (2-12, 2-15-1, 6-2 FNC 03-05 IRET/EI/DI) and special-module buffer
memory (6-9 FNC 78/79 FROM/TO): checker rules and the simulator, from the manual's examples."""

from __future__ import annotations

from mlctool.check import check_texts
from mlctool.sim.stimulus.stimulus import parse_stimulus_text
from mlctool.syntax.source import SourceText
from vskit import VS, image_of, run, simulate

ROUTINE_X0 = "FEND\nIX0P:\nLD M9000\nINC D0\nIRET\n"


def codes(text: str, model: str | None = None) -> list[tuple[str, int]]:
    target = VS if model is None else VS.for_model(model) if hasattr(VS, "for_model") else VS
    r = check_texts([SourceText("t.il", text)], target)
    return sorted((d.code, d.span.line) for d in r.diagnostics if d.severity == "error")


def test_interrupt_pointers_are_their_own_label_class():
    # a pointer line is the instruction I (class "interrupt"), numbered apart from P
    # ITA01 is I601 and P601 a P label: no collision; IX0P is no named label (no free P used)
    ok = ("LD X20\nCJ P601\nP601:\nLD M9000\nOUT Y1\nFEND\nIX0P:\nLD M9000\nSET Y0\nIRET\n"
          "ITA01:\nLD M9000\nINC D0\nIRET\nIHC3:\nIRET\nIHHC2:\nIRET\nEND\n")
    assert codes(ok) == []


def test_interrupt_layout_errors_are_e908():
    bad = ("IX2P:\nLD M9000\nOUT Y1\nFEND\n"       # 1: before FEND (and no IRET before FEND)
           "IX0P:\nLD M9000\nSET Y0\n"            # 5: no IRET before the next pointer
           "IX0F:\nIRET\n"                        # 8: IX0P and IX0F both
           "IRET\n"                               # 10: IRET closing nothing
           "ITB05:\nIRET\nITB05:\nIRET\n"         # 13: written twice
           "END\n")
    got = codes(bad)
    assert ("E908", 1) in got and ("E908", 5) in got and ("E908", 8) in got
    assert ("E908", 10) in got and ("E908", 13) in got
    assert all(c == "E908" or c == "E313" for c, _ in got), got
    # names outside the families' units are no pointers: ITA00 / IX8P read as named labels
    assert codes("FEND\nITA100:\nIRET\nEND\n") != []


def test_routines_run_on_input_edges_and_disable_relay():
    # 6-2 FNC 03-05 example: IX0P on X0 rising, IX1F on X1 falling; X20 drives M9050, which
    # disables the requests of X0 (dropped, not remembered)
    il = ("LD X20\nOUT M9050\nFEND\nIX0P:\nLD M9000\nINC D0\nIRET\n"
          "IX1F:\nLD M9000\nINC D1\nIRET\n")
    run(il, "0ms X1=1\n5ms X0=1\n10ms expect D0=1 D1=0\n13ms X0=0\n14ms X0=1\n15ms X1=0\n"
            "20ms expect D0=2 D1=1\n30ms X20=1\n35ms X0=0\n36ms X0=1\n"
            "40ms expect D0=2 M9050=1\n50ms X20=0\n60ms expect D0=2\n")


def test_routine_state_is_kept_between_interrupts():
    # 2-12: a device driven in an interrupt routine keeps its state until the next interrupt
    run("LD M9000\nMOV K0 D5\nFEND\nIX0P:\nLD X21\nOUT Y0\nIRET\n",
        "0ms X21=1\n5ms X0=1\n10ms expect Y0=1\n15ms X21=0\n30ms expect Y0=1\n"
        "35ms X0=0\n36ms X0=1\n40ms expect Y0=0\n")


def test_timer_interrupt_every_5ms_and_its_disable_relay():
    # 2-12 ITA05: every 5 ms of virtual time from RUN, two per 10 ms scan; M9058 disables ITA
    run("LD X20\nOUT M9058\nFEND\nITA05:\nLD M9000\nINC D0\nIRET\n",
        "0ms expect D0=0\n10ms expect D0=2\n100ms expect D0=20\n100ms X20=1\n"
        "200ms expect D0=20\n")


def test_pulse_train_edges_request_routines():
    # every rising edge of a 1 kHz train requests IX0P; the falling edges of a 500 Hz train IX1F
    run(ROUTINE_X0 + "IX1F:\nLD M9000\nINC D1\nIRET\n",
        "0ms X0 pulses 1kHz until 10ms\n0ms X1 pulses 500Hz until 10ms\n"
        "10ms expect D0=10 D1=5\n50ms expect D0=10 D1=5\n")


def test_di_remembers_requests_until_ei():
    # 6-2: requests between DI and EI are remembered and served at EI (once per pointer);
    # while X20 skips the EI the request waits; at EI the routine runs inside the scan
    il = ("LD X20\nCJ P1\nEI\nLD M9000\nMOV D0 D1\nP1:\nDI\n" + ROUTINE_X0)
    run(il, "0ms X20=1\n5ms X0=1\n7ms X0=0\n8ms X0=1\n20ms expect D0=0\n"
            "30ms X20=0\n30ms expect D0=1 D1=1\n50ms expect D0=1\n")


def test_external_interrupt_delay_fixed_form():
    # 2-15-1: `LD M9163 / MOV K25 D9163` right after the pointer delays the routine 25 ms
    run("FEND\nIX0P:\nLD M9163\nMOV K25 D9163\nLD M9000\nMOV T0 D1\nINC D0\nIRET\n",
        "3ms X0=1\n20ms expect D0=0\n30ms expect D0=1\n")


def test_iret_outside_a_routine_is_a_fault():
    image = image_of("LD X0\nCALL P1\nFEND\nP1:\nIRET\nEND\n")
    if image is None:  # the checker already refuses it (E908)
        return
    r = simulate(image, "0ms X0=1\n")
    assert r.fault is not None and "IRET" in r.fault.message


def test_from_to_on_the_simulated_buffer_memory():
    # 6-9 FNC 78 examples: FROM K2 K5 D0 K4 reads BFM#5-#8 of module 2 into D0-D3;
    # DFROM K1 K4 D100 K2 reads #4-#7 as two pairs; TO writes; module K17: operation error
    il = ("LD X20\nFROM K2 K5 D0 K4\nLD X21\nDFROM K1 K4 D100 K2\nLD X22\nTO K3 K0 D10 K2\n"
          "LD X23\nMOV K17 D60\nFROM D60 K0 D50 K1\n")
    run(il, "0ms BFM2#5=11 BFM2#6=-2 BFM2#8=H7FFF BFM1#4:d=70000 BFM1#6:d=-5 D10=7 D11=8\n"
            "10ms X20=1 X21=1 X22=1\n"
            "20ms expect D0=11 D1=-2 D2=0 D3=32767 D100:d=70000 D102:d=-5 BFM3#0=7 BFM3#1=8\n"
            "30ms X23=1\n40ms expect alarm OPERATION_ERROR\n", alarms=True)


def test_bfm_names_in_the_stimulus_are_checked():
    cases = {"0ms BFM0#1=1": 5, "0ms X0=1 BFM17#0=1": 10, "0ms BFM1#32768=2": 5,
             "0ms BFM1=3": 5, "10ms expect BFM1#3:w=1 BFM1#2:x=1": 24}
    for text, col in cases.items():
        _, diags = parse_stimulus_text("t.stim", text, VS)
        assert [(d.code, d.span.col) for d in diags] == [("E602", col)], (text, diags)
    _, diags = parse_stimulus_text("t.stim", "0ms BFM1#0=70000", VS)
    assert [(d.code, d.span.col) for d in diags] == [("E601", 5)]


# -- high-speed counter interrupts: IHC0-IHC7 from DHSCS (6-7 FNC 53), IHHC1/IHHC2 (2-15-4)

IHC_PROGRAM = ("LD M9000\nOUT C254 K2147483647\nDHSCS K100 C254 IHC0\nFEND\n"
               "IHC0:\nLD M9000\nINC D0\nMOV D9 D1\nIRET\n"
               "ITA10:\nLD M9000\nINC D9\nIRET\n")  # D9 counts 10 ms ticks: D1 dates the request


def test_dhscs_takes_an_ihc_pointer_as_d():
    assert codes(IHC_PROGRAM + "END\n") == []
    bad = "LD M9000\nDHSCS K5 C235 IX1P\nDHSCS K5 C235 ITA10\nDHSCS K5 C235 Y0\nFEND\nIX1P:\nIRET\nEND\n"
    assert codes(bad) == [("E205", 2), ("E205", 3)]
    r = check_texts([SourceText("t.il", bad)], VS)
    assert "takes IHC0-IHC7, not IX1P" in next(d.message for d in r.diagnostics if d.code == "E205")


def test_ihc_routine_runs_at_the_pulse_that_meets_the_compare():
    # the manual's 6-7 example (C254 = 100 jumps to IHC0) on the 1-phase C235 (X0) at 1 kHz,
    # compare value 95: the 95th count is the edge at 95 ms, between two scans
    il = IHC_PROGRAM.replace("C254", "C235").replace("K100", "K95")
    run(il, "0ms X0 pulses 1kHz for 300ms\n"
            "85ms expect D0=0\n"
            "105ms expect D0=1 D1=9\n"  # at 95 ms: after ITA10's 9th tick, before its 10th
            "400ms expect D0=1 D9=40 C235:d=299\n")  # once: the count passes 95 only once


def test_ihc_requests_are_dropped_while_m9061_is_on():
    il = IHC_PROGRAM.replace("C254", "C235")
    run(il, "0ms X0 pulses 1kHz for 300ms\n0ms M9061=1\n400ms expect D0=0\n")


def test_ihhc1_at_the_hardware_counters_set_value():
    # 2-15-4 example, 1-phase mode: set value 1005 (DHHCMV writes the circuit at once)
    il = ("LD M9002\nMOVP K1 D9224\nDHHCMVP K0 D9226\nDHHCMV K1005 D9230\nFEND\n"
          "IHHC1:\nLD M9000\nINC D0\nMOV D9 D1\nIRET\n"
          "IHHC2:\nLD M9000\nINC D2\nIRET\n"
          "ITA10:\nLD M9000\nINC D9\nIRET\n")
    # 10 kHz from 0 ms: count 1005 at 100.5 ms (the edge at 0 ms is before the mode is set)
    run(il, "0ms X0 pulses 10kHz for 300ms\n400ms expect D0=1 D1=10 D2=0 D9226:d=2999\n")
    run(il, "0ms X0 pulses 10kHz for 300ms\n0ms M9062=1\n400ms expect D0=0 D9226:d=2999\n")


REF_ROUTINE = ("FEND\nIX0P:\nLD X10\nOUT Y1\nLD M9000\nREF X10 K8\nLD X10\nOUT Y0\n"
               "LDI X11\nOUT Y2\nIRET\n")


def test_ref_in_a_routine_reads_the_inputs_at_the_request_time():
    # 2-12 / 6-7 FNC 50: the image holds what the scan at 10 ms read (X10 Off); X10 goes On
    # at 13 ms and X0 rises at 15 ms: before its REF the routine still sees X10 Off (Y1 Off),
    # after `REF X10 K8` On (Y0 On); X11 (in the REF's 8 points) too
    run(REF_ROUTINE,
        "0ms X11=1\n13ms X10=1\n14ms X11=0\n15ms X0=1\n20ms expect Y0=1 Y1=0 Y2=1\n"
        # X10 Off again at 33 ms, X0 rises at 40 ms, exactly at the scan's time: the lines
        # come first, the routine before the scan's read: Y1 still On, Y0 Off
        "25ms X0=0\n33ms X10=0\n40ms X0=1\n40ms expect Y0=0 Y1=1\n")


def test_ref_in_a_routine_reads_a_pulse_train_at_the_request_time():
    # X10 pulses 100 Hz: On in the first 5 ms of each 10 ms, so every scan reads it On; the
    # routine at 17 ms sees the image On (Y1) but REF reads the train's level then: Off
    run(REF_ROUTINE,
        "0ms X10 pulses 100Hz\n0ms X11=1\n17ms X0=1\n20ms expect Y0=0 Y1=1 X10=1\n"
        "21ms X0=0\n22ms X0=1\n30ms expect Y0=1\n")


def test_ref_y_in_a_routine_puts_the_output_out_at_the_request_time():
    # the routine sets Y0 and puts it out by REF Y0 K8 (Y0-Y7) at 15 ms; Y10 it sets without
    # REF goes out after the next scan (20 ms); the main program clears Y0 at every scan, so
    # the trace (and the VCD) show Y0 On from 15 ms to the scan at 20 ms and Y10 from 20 ms
    from mlctool.sim.run.run import Simulation
    from mlctool.sim.run.vcd import to_vcd

    image = image_of("LD M9000\nRST Y0\nFEND\nIX0P:\nLD M9000\nSET Y0\nSET Y10\nLD M9000\nREF Y0 K8\n"
                     "IRET\nEND\n")
    st, sd = parse_stimulus_text("t.stim", "15ms X0=1\n30ms expect Y0=0 Y10=1\n", VS)
    assert not sd
    r = Simulation(image, VS, st, [], 10_000, [], True).run(4)
    assert r.ok
    names = [v.name for v in r.views]
    y0, y10 = names.index("Y0"), names.index("Y10")
    seen = [(t, names[i], v) for t, changes in r.trace for i, v in changes if i in (y0, y10)]
    assert (15_000, "Y0", 1) in seen and (20_000, "Y0", 0) in seen
    assert (20_000, "Y10", 1) in seen and not any(n == "Y10" and t == 15_000 for t, n, _ in seen)
    vcd = to_vcd(r, image, VS)
    assert "#15000" in vcd.splitlines()


def test_ref_in_the_main_program_changes_nothing():
    # the scan is instantaneous at its start: its inputs are current, REF is accepted
    run("LD M9000\nREF X0 K16\nREF Y0 K8\nLD X10\nOUT Y0\n", "5ms X10=1\n10ms expect Y0=1\n")
