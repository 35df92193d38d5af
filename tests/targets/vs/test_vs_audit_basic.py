"""docs/vs-audit.md, section "Basic instructions (chapter 3) and device chapters (2, 4)": one
case per rule of the basic-instruction pages (3-2 ... 3-10), the device chapters (2-5
timers, 2-6 counters, 2-9 index registers, 2-14 special relays) and the step ladder (4-4 ...
4-6) and MC/MCR.

Cases use the pages' own programs where a page has one. `test_check_rule` asserts the
diagnostics of `mlc check` (code at line); `test_sim_rule` runs a program against
stimulus expectations."""

from __future__ import annotations

import pytest

import vskit

NINE_ANB = "".join(f"LD X{k}\n" for k in ("0", "1", "2", "3", "4", "5", "6", "7", "10", "11")) + "ANB\n" * 9
TWELVE_MPS = "LD X0\n" + "MPS\n" * 12 + "OUT Y0\n" + "MPP\n" * 12

# (program, the diagnostics it must give as (code, line); [] = no error and no warning)
CHECKS = [
    # 3-2 END: "END之後的程序不會被執行" (code after END is refused)
    pytest.param("LD X0\nOUT Y0\nEND\nLD X1\nOUT Y1", [("E302", 4)], id="3-2-code-after-end"),
    # 3-4: "連續輸入ANB及ORB指令的次數不可超過 8次"
    pytest.param(NINE_ANB + "OUT Y0\nEND", [("E906", 19)], id="3-4-eight-anb-orb"),
    # 3-5: MPS - MPP <= 11; equal counts when the branches end
    pytest.param(TWELVE_MPS + "END", [("E309", 13)], id="3-5-mps-11"),
    pytest.param("LD X0\nMPS\nOUT Y0\nEND", [("E308", 2)], id="3-5-mps-balanced"),  # at the MPS left open
    # 3-6: N0 outermost, then N1 ... N7 in order without gaps
    pytest.param("LD X0\nMC N1\nMCR N1\nEND", [("E903", 2)], id="3-6-mc-starts-n0"),
    pytest.param("LD X0\nMC N0\nLD X1\nMC N2\nMCR N2\nMCR N0\nEND", [("E903", 4)], id="3-6-mc-no-gap"),
    # 3-7: "SET/RST指令可使用同一輸出線圈，且使用次數無限制" (no double-coil warning)
    pytest.param("LD X0\nSET Y0\nLD X1\nSET Y0\nLD X2\nRST Y0\nLD X3\nRST Y0\nEND", [], id="3-7-set-rst-any-times"),
    # 3-10-2 / 1-1-7: a double coil is legal but suspicious: the last OUT wins (warning)
    pytest.param("LD X0\nOUT Y0\nLD X1\nOUT Y0\nEND", [("W401", 4)], id="3-10-double-coil"),
    # 3-8: PLS/PLF take Y and M, "特M除外"
    pytest.param("LD X0\nPLS M9000\nEND", [("E205", 2)], id="3-8-pls-no-special-m"),
    # 3-9: a timer preset outside K0-K32767 is taken as 0, a 16-bit counter's outside K1-K32767
    # as 1: the program runs, but not with the preset written
    pytest.param("LD X0\nOUT T0 K-1\nLD X1\nOUT C0 K0\nLD X2\nOUT C1 K-3\nEND", [("W221", 2), ("W221", 4), ("W221", 6)],
                 id="3-9-preset-taken-as"),
    pytest.param("LD X0\nOUT T0 K0\nLD X1\nOUT C0 K1\nLD X2\nOUT C200 K-5\nEND", [], id="3-9-preset-legal"),
    # 2-6-2: "32位元計數器，OUT C指令的元件號碼不可用VZ寄存器索引。但是，其設定值可用VZ寄存器索引"
    pytest.param("LD X0\nOUT C200Z0 K5\nEND", [("E209", 2)], id="2-6-2-no-index"),
    pytest.param("LD X0\nOUT C200 D0Z0\nLD X1\nOUT C0Z0 K5\nEND", [], id="2-6-2-preset-index-legal"),
    # 2-5-3 (4): "中斷子程序...中的計時器，一定要使用 T192∼T199計時器"
    pytest.param("LD X0\nOUT Y0\nFEND\nIX0P:\nLD M9000\nOUT T0 K10\nLD M9000\nOUT T192 K10\nIRET\nEND", [("W222", 6)],
                 id="2-5-3-interrupt-timers"),
    # 4-4 item 9: a program with step ladder may not drive step relays in an interrupt routine
    pytest.param("LD M9002\nSET S20\nSTL S20\nLD X0\nSET S21\nSTL S21\nLD X1\nSET S20\nRET\nFEND\nIX0P:\n"
                 "LD M9000\nSET S21\nLD M9000\nSET M5\nIRET\nEND", [("W223", 13)], id="4-4-no-steps-in-interrupts"),
    # 4-4 item 10: adjacent steps may not share a timer; steps that are not adjacent may, with
    # different presets
    pytest.param("LD M9002\nSET S20\nSTL S20\nOUT T0 K10\nLD T0\nSET S21\nSTL S21\nOUT T0 K20\nLD T0\nSET S20\nRET\nEND",
                 [("W402", 8)], id="4-4-adjacent-steps-timer"),
    pytest.param("LD M9002\nSET S20\nSTL S20\nOUT T0 K10\nLD T0\nSET S21\nSTL S21\nOUT Y1\nLD X1\nSET S22\nSTL S22\n"
                 "OUT T0 K20\nLD T0\nSET S23\nSTL S23\nOUT Y3\nLD X3\nSET S20\nRET\nEND", [], id="4-4-non-adjacent-steps-timer"),
    # 4-4: "每一個選擇性分歧或並進式分歧，最多只能有 8個分歧點"
    pytest.param("LD M9002\nSET S20\nSTL S20\n" + "".join(f"LD X{k}\nSET S{30 + k}\n" for k in range(8))
                 + "LD X10\nSET S40\n" + "".join(f"STL S{30 + k}\nOUT Y{k}\n" for k in range(8))
                 + "STL S40\nOUT Y10\nRET\nEND", [("W224", 21)], id="4-4-eight-branches"),
    # 4-4: no MC/MCR in SFC; a step relay heads one step only
    pytest.param("LD M9002\nSET S20\nSTL S20\nLD X0\nMC N0\nOUT Y0\nMCR N0\nRET\nEND", [("E902", 5)], id="4-4-no-mc-in-steps"),
    pytest.param("LD M9002\nSET S20\nSTL S20\nOUT Y0\nSTL S20\nOUT Y1\nRET\nEND", [("E902", 5)], id="4-4-step-once"),
    # 2-3: M8192-M8999 do not exist; special M9000-M9511
    pytest.param("LD X0\nOUT M8500\nEND", [("E205", 2)], id="2-3-m-ranges"),
    # 2-14-1 ■ read-only specials: the system drives them
    pytest.param("LD X0\nOUT M9000\nEND", [("W212", 2)], id="2-14-read-only"),
    # 2-9 / 5-1: D.b R.b V Z cannot be indexed; 32-bit instructions index with Zn only
    pytest.param("LD X0\nDMOV K1 D0V1\nEND", [("E209", 2)], id="2-9-index32-with-z"),
    pytest.param("LD X0\nMOV K1 D0Z1\nOUT Y0Z0\nEND", [], id="2-9-index-legal"),
    # 4-6-1: MPS/MRD/MPP may not be used directly on the STL bus; no STL in a subroutine
    pytest.param("STL S20\nMPS\nOUT Y0\nMPP\nOUT Y1\nRET\nEND", [("E902", 2)], id="4-6-no-mps-on-stl-bus"),
    pytest.param("LD X0\nCALL P1\nFEND\nP1\nSTL S20\nOUT Y0\nRET\nSRET\nEND", [("E902", 5)], id="4-4-no-stl-in-subroutine"),
    # 4-4: one coil in two steps of one flow is no double coil
    pytest.param("LD M9002\nSET S20\nSTL S20\nOUT Y0\nLD X0\nSET S21\nSTL S21\nOUT Y0\nLD X1\nSET S20\nRET\nEND", [],
                 id="4-4-same-coil-in-two-steps"),
]


@pytest.mark.parametrize("il, expected", CHECKS)
def test_check_rule(il, expected):
    if expected:
        found = vskit.check_codes(il)
        missing = [e for e in expected if e not in found]
        assert not missing, (missing, found)
    else:
        assert vskit.check_codes(il, None, ("error", "warning")) == []


# (program, stimulus with expectations); END is added
SIMS = [
    # 3-2: the page's program (LD/OR/AND/OUT, LDI/ORI/ANI/OUT; INV)
    pytest.param("LD X20\nOR Y20\nAND X21\nOUT Y20\nLDI X22\nORI Y21\nANI X23\nOUT Y21\nLD X24\nINV\nOUT Y22",
                 "0ms X21=1\n0ms expect Y20=0 Y21=1 Y22=1\n10ms X20=1 X22=1 X23=1 X24=1\n10ms expect Y20=1 Y21=0 Y22=0\n"
                 "20ms X20=0\n20ms expect Y20=1", id="3-2-page-example"),
    # 3-3: edge contacts and MEP/MEF are On for one scan
    pytest.param("LDP X0\nOUT M0\nLDF X0\nOUT M1\nLD X7\nMEP\nOUT M2\nLD X7\nMEF\nOUT M3",
                 "0ms X0=1 X7=1\n0ms expect M0=1 M2=1\n10ms expect M0=0 M2=0\n20ms X0=0 X7=0\n20ms expect M1=1 M3=1\n"
                 "30ms expect M1=0 M3=0", id="3-3-one-scan"),
    # 3-4: block series and parallel (a block starts with LD/LDI)
    pytest.param("LD X0\nOR X1\nLD X2\nOR X3\nANB\nOUT Y0\nLD X0\nAND X1\nLDI X2\nAND X3\nORB\nOUT Y1",
                 "0ms X1=1 X3=1\n0ms expect Y0=1 Y1=1\n10ms X3=0\n10ms expect Y0=0 Y1=0", id="3-4-anb-orb"),
    # 3-5: three branches from one point
    pytest.param("LD X0\nMPS\nAND X1\nOUT Y0\nMRD\nAND X2\nOUT Y1\nMPP\nAND X3\nOUT Y2",
                 "0ms X0=1 X1=1 X3=1\n0ms expect Y0=1 Y1=0 Y2=1\n10ms X0=0\n10ms expect Y0=0 Y2=0", id="3-5-branches"),
    # 3-6: MC Off: OUT coils and general timers Off; retentive timers, counters and SET/RST
    # devices keep their state
    pytest.param("LD X0\nMC N0\nLD X1\nOUT Y20\nLD X1\nOUT T0 K100\nLD X1\nOUT T250 K100\nLD X2\nOUT C0 K5\n"
                 "LD X1\nSET M10\nMCR N0",
                 "0ms X0=1 X1=1\n10ms X2=1\n500ms expect Y20=1 T0:w=5 T250:w=5 C0:w=1 M10=1\n510ms X0=0\n"
                 "520ms expect Y20=0 T0:w=0 T250:w=5 C0:w=1 M10=1", id="3-6-mc-off"),
    # 3-6: an Off block has no power whatever its contacts: an OR (ORB, MPS branch) of an On
    # contact does not bring it back; OUT coils and the general timer Off, the retentive timer,
    # the counter and the SET coil keep; an inner level inside the Off block is Off too
    pytest.param("LD M100\nMC N0\nLD X0\nOR X1\nOUT Y0\nLD X0\nOR X1\nOUT T0 K100\nLD X0\nOR X1\n"
                 "OUT T250 K100\nLD X0\nOR X2\nOUT C0 K5\nLD X0\nOR X1\nSET M10\nLD X1\nMPS\nOUT Y1\nMPP\n"
                 "LD X0\nOR X1\nANB\nOUT Y2\nLD X0\nOR X1\nMC N1\nLD X0\nOR X1\nOUT Y3\nMCR N1\nMCR N0\n"
                 "LD X1\nOUT Y4",
                 "0ms M100=1 X1=1\n10ms X2=1\n500ms expect Y0=1 Y1=1 Y2=1 Y3=1 T0:w=5 T250:w=5 C0:w=1 M10=1\n"
                 "510ms M100=0\n520ms expect Y0=0 Y1=0 Y2=0 Y3=0 Y4=1 T0:w=0 T250:w=5 C0:w=1 M10=1",
                 id="3-6-mc-off-or"),
    # 3-6: nested levels: the page's 2-level form, N1 inside N0
    pytest.param("LD X0\nMC N0\nLD X1\nOUT Y20\nLD X2\nMC N1\nLD M10\nOUT Y21\nMCR N1\nMCR N0",
                 "0ms X0=1 X1=1 X2=1 M10=1\n0ms expect Y20=1 Y21=1\n10ms X2=0\n10ms expect Y20=1 Y21=0\n"
                 "20ms X2=1 X0=0\n20ms expect Y20=0 Y21=0", id="3-6-nesting"),
    # 3-7: SET holds; RST clears a coil, a timer, a counter, a register
    pytest.param("LD X0\nSET Y0\nLD X1\nOUT T0 K1\nLD X1\nOUT C0 K1\nLD X2\nRST Y0\nRST T0\nRST C0\nRST D0",
                 "0ms X0=1 X1=1 D0=5\n10ms X0=0 X1=0\n10ms expect Y0=1 C0=1\n20ms X2=1\n20ms expect Y0=0 T0=0 C0=0 "
                 "C0:w=0 D0=0", id="3-7-set-rst"),
    # 3-8: the page's program: PLS/PLF one scan
    pytest.param("LD X0\nPLS M0\nLD X0\nPLF M1",
                 "0ms X0=1\n0ms expect M0=1 M1=0\n10ms expect M0=0\n20ms X0=0\n20ms expect M1=1\n30ms expect M1=0",
                 id="3-8-page-example"),
    # 3-9: "設定值超出此範圍一律視為 0" (timers, 0-32767): a register preset of -1 acts as 0
    pytest.param("LD X0\nOUT T0 D0", "0ms D0=-1 X0=1\n10ms expect T0=1", id="3-9-timer-preset-outside"),
    # 3-9: "當設定值超出此範圍一律視為1" (16-bit counters, 1-32767)
    pytest.param("LD X1\nOUT C0 D0", "0ms D0=0\n10ms X1=1\n20ms expect C0=1 C0:w=1", id="3-9-counter-preset-outside"),
    # 3-9 / 2-5-2: retentive timers T246-T255 are cleared by RST only (the page's program)
    pytest.param("LD X1\nOUT T246 K2000\nLD X2\nRST T246",
                 "0ms X1=1\n1s X1=0\n1.5s expect T246:w=990 T246=0\n2s X1=1\n3.01s expect T246=1\n3.1s X2=1\n"
                 "3.1s expect T246:w=0 T246=0", id="2-5-2-retentive"),
    # 2-5-1: a general timer: Off (or power off) clears the value and the contact
    pytest.param("LD X0\nOUT T0 K100", "0ms X0=1\n10.0s expect T0=1\n10.1s X0=0\n10.1s expect T0=0 T0:w=0",
                 id="2-5-1-general"),
    # 2-5-4: the preset from a register: T200 (10 ms) with D0 = 200 is a 2 s timer
    pytest.param("LD X0\nMOV K200 D0\nLD X0\nOUT T200 D0", "0ms X0=1\n1.9s expect T200=0\n2.01s expect T200=1",
                 id="2-5-4-register-preset"),
    # 2-5-5: "計時器的設定值為 0時，在下一次掃描時其輸出接點動作"
    pytest.param("LD X0\nOUT T0 K0", "0ms X0=1\n10ms expect T0=1", id="2-5-5-preset-0"),
    # 2-5: time bases: T200-T245 10 ms, T256-T511 1 ms
    pytest.param("LD X0\nOUT T200 K50\nLD X0\nOUT T256 K500", "0ms X0=1\n490ms expect T200=0 T256=0\n"
                 "510ms expect T200=1 T256=1", id="2-5-time-bases"),
    # 2-6-1: the page's program: C0 counts X1 to 10, then holds; RST C0 clears it
    pytest.param("LD X0\nRST C0\nLD X1\nOUT C0 K3",
                 "0ms X1=1\n10ms X1=0\n20ms X1=1\n30ms X1=0\n40ms X1=1\n40ms expect C0=1 C0:w=3\n50ms X1=0\n"
                 "60ms X1=1\n60ms expect C0:w=3 C0=1\n70ms X0=1\n70ms expect C0=0 C0:w=0", id="2-6-1-page-example"),
    # 2-6-2: the page's program: M9200 from X0 sets C200's direction; preset K-5: the contact
    # turns On counting -6 -> -5 and Off counting -5 -> -6
    pytest.param("LD X0\nOUT M9200\nLD X1\nRST C200\nLD X2\nOUT C200 K-5",
                 "0ms C200:d=-7\n10ms X2=1\n10ms expect C200:d=-6 C200=0\n20ms X2=0\n30ms X2=1\n"
                 "30ms expect C200:d=-5 C200=1\n40ms X2=0\n50ms X2=1\n50ms expect C200:d=-4 C200=1\n60ms X2=0 X0=1\n"
                 "70ms X2=1\n70ms expect C200:d=-5 C200=1\n80ms X2=0\n90ms X2=1\n90ms expect C200:d=-6 C200=0\n"
                 "100ms X1=1\n100ms expect C200:d=0", id="2-6-2-page-example"),
    # 2-6-1: "使用MOV指令將一個大于設定值的數值傳送到現在值寄存器時，在下次計數輸入信號ON時，則接點
    # 立即變成ON，同時現在值內容變成與設定值相同"
    pytest.param("LD X0\nMOV K20 C0\nLD X1\nOUT C0 K10",
                 "0ms X0=1\n10ms X0=0\n30ms expect C0=0 C0:w=20\n40ms X1=1\n40ms expect C0=1 C0:w=10",
                 id="2-6-1-mov-above-preset"),
    # 2-6-1 "立即": DECISION: the contact changes when OUT C executes; a contact after the coil
    # sees it in the same scan, one before it the next scan
    pytest.param("LD C0\nOUT Y0\nLD X1\nOUT C0 K1\nLD C0\nOUT Y1", "10ms X1=1\n10ms expect C0=1 Y1=1 Y0=0\n20ms expect Y0=1",
                 id="2-6-1-contact-at-once"),
    # 2-6-2: "當使用DMOV指令將一個大于設定值的數值傳送到現在值寄存器時，在下回計數輸入信號ON時會計數
    # 但接點不會變化"
    pytest.param("LD X0\nDMOV K20 C200\nLD X1\nOUT C200 K10",
                 "0ms X0=1\n10ms X0=0\n30ms X1=1\n30ms expect C200=0 C200:d=21\n40ms X1=0 M9200=1\n50ms X1=1\n"
                 "50ms expect C200:d=20 C200=0", id="2-6-2-dmov-above-preset"),
    # 2-6-2: 32-bit counters wrap 2,147,483,647 -> -2,147,483,648 and back
    pytest.param("LD X0\nOUT M9201\nLD X2\nOUT C201 K5",
                 "0ms C201:d=2147483647\n10ms X2=1\n10ms expect C201:d=-2147483648\n20ms X2=0 X0=1\n30ms X2=1\n"
                 "30ms expect C201:d=2147483647", id="2-6-2-wrap"),
    # 2-6-3: presets from registers: C0 with D0 = 2, C200 with the pair D3:D2 = 70000
    pytest.param("LD M9000\nMOV K2 D0\nDMOV K70000 D2\nLD X1\nOUT C0 D0\nLD X2\nOUT C200 D2",
                 "0ms X1=1 C200:d=69998\n10ms X1=0\n20ms X1=1 X2=1\n20ms expect C0=1 C0:w=2 C200:d=69999 C200=0\n"
                 "30ms X2=0\n40ms X2=1\n40ms expect C200:d=70000 C200=1",
                 id="2-6-3-register-presets"),
    # 2-9: the index is added to the device ordinal, octal X/Y re-expressed (Z0 = 10: X0Z0 is
    # X12, Y5Z0 is Y17); 32-bit instructions take the pair (V1, Z1) written Z1
    pytest.param("LD M9000\nMOV K10 Z0\nDMOV K8 Z1\nLD X0Z0\nOUT Y5Z0\nLD M9000\nDMOV K70000 D0Z1",
                 "0ms X12=1\n10ms expect Y17=1 D8:d=70000 V1=0 Z1=8", id="2-9-index"),
    # 2-14-1: M9000 On / M9001 Off in RUN, M9002 On / M9003 Off in the first scan, M9013 1 s
    pytest.param("LD M9000\nOUT Y0\nLD M9001\nOUT Y1\nLD M9002\nOUT Y2\nLDI M9003\nOUT Y3\nLD M9013\nOUT Y4",
                 "0ms expect Y0=1 Y1=0 Y2=1 Y3=1\n10ms expect Y2=0 Y3=0\n400ms expect Y4=1\n600ms expect Y4=0\n1.4s expect Y4=1",
                 id="2-14-system-relays"),
    # 2-14-1: M9031 clears the non-latched devices, M9032 the latched ones (special devices kept)
    pytest.param("LD X0\nSET M0\nSET M2000\nSET Y1\nMOV K5 D0\nMOV K6 D7000\nMOV K7 R0\nLD X1\nOUT M9031\nLD X2\nOUT M9032",
                 "0ms X0=1 D9039=3\n10ms X0=0 X1=1\n10ms expect M9031=1 M0=1 D0=5\n20ms X1=0\n"
                 "20ms expect M0=0 Y1=0 D0=0 R0=0 M2000=1 D7000=6 D9039=3\n30ms X2=1\n40ms X2=0\n"
                 "40ms expect M2000=0 D7000=0 D9039=3",
                 id="2-14-1-device-clear"),
    # 2-3, 2-4, 2-5, 2-6, 2-8: latched ranges keep their state over a power cycle (M2000-M3999,
    # S500-S899 and S1000-S1499, T246-T255, C100-C199 and C220-C255, D7000-D8999); R does not
    pytest.param("LD X0\nSET M0\nSET M2000\nSET S0\nSET S500\nSET S1000\nSET S1500\nMOV K5 D0\nMOV K6 D7000\n"
                 "MOV K7 R0\nLD X0\nOUT C0 K10\nLD X0\nOUT C100 K10\nLD X0\nOUT C200 K10\nLD X0\nOUT C220 K10\n"
                 "LD X1\nOUT T0 K100\nLD X1\nOUT T250 K100",
                 "0ms X0=1 X1=1\n200ms X0=0 X1=0\n250ms power-cycle\n260ms expect M0=0 M2000=1 S0=0 S500=1 S1000=1 "
                 "S1500=0 D0=0 D7000=6 R0=0 C0:w=0 C100:w=1 C200:d=0 C220:d=1 T250:w=1 T0:w=0", id="2-latched-ranges"),
    # 2-5-5: a contact written before its coil sees the timer one scan later (the +Ts of the
    # accuracy formula)
    pytest.param("LD T0\nOUT Y0\nLD X0\nOUT T0 K1", "0ms X0=1\n100ms expect T0=1 Y0=0\n110ms expect Y0=1",
                 id="2-5-5-contact-before-coil"),
    # 2-5-3: T192-T199 are timed at END, so a subroutine not run every scan may use them
    pytest.param("LD X0\nCALL P1\nFEND\nP1\nLD M9000\nOUT T192 K5\nSRET", "0ms X0=1\n10ms X0=0\n600ms expect T192=1",
                 id="2-5-3-t192-in-subroutine"),
    # 2-14-1 / 2-14-3: an operation error turns M9067 and M9004 On, code in D9067; the PLC runs on
    pytest.param("LD M9000\nDIV D0 D1 D2\nLD M9000\nINC D10", "0ms D0=1 D1=0\n10ms expect M9067=1 M9004=1 D9067=6706 D10=2",
                 id="2-14-operation-error"),
    # 4-6-1 / 4-1-3: SET Sx transfers: the target On at once, the source still On for the rest
    # of that scan, Off the next scan (its OUT coils go Off with it)
    pytest.param("LD M9002\nSET S0\nSTL S0\nOUT Y0\nLD X0\nSET S20\nLD S20\nOUT M0\nSTL S20\nOUT Y1\nLD X1\nSET S0\nRET",
                 "0ms expect S0=1 Y0=1 S20=0\n10ms X0=1\n10ms expect S20=1 S0=0 M0=1 Y1=1\n20ms expect Y0=0 S0=0",
                 id="4-6-1-transfer"),
    # 4-6-1: OUT Sx transfers to a step of another flow; the source resets itself
    pytest.param("LD M9002\nSET S0\nSTL S0\nOUT Y0\nLD X0\nOUT S30\nSTL S30\nOUT Y1\nRET",
                 "0ms expect S0=1\n10ms X0=1\n20ms expect S0=0 S30=1 Y1=1 Y0=0", id="4-6-1-out-other-flow"),
    # 4-5: M9047 On: the On steps' numbers in D9040-D9047, lowest first, and M9046. DECISION:
    # refreshed before each scan (the END of the previous one)
    pytest.param("LD M9000\nOUT M9047\nLD M9002\nSET S20\nSET S5\nLD X0\nRST S5\nRST S20",
                 "0ms D9042=7\n10ms expect M9046=1 D9040=5 D9041=20 D9042=0\n20ms X0=1\n30ms expect M9046=0 D9040=0",
                 id="4-5-step-monitor"),
    # 4-5: M9040 On inhibits every transfer (single-step operation)
    pytest.param("LD M9002\nSET S0\nLD X5\nOUT M9040\nSTL S0\nLD X0\nSET S20\nSTL S20\nOUT Y1\nRET",
                 "0ms X5=1 X0=1\n30ms expect S0=1 S20=0\n40ms X5=0\n50ms expect S20=1 S0=0", id="4-5-m9040-inhibit"),
    # 4-6-1: SET-driven outputs of a step stay On after it is left
    pytest.param("LD M9002\nSET S0\nSTL S0\nSET Y5\nOUT Y0\nLD X0\nSET S20\nSTL S20\nOUT Y1\nRET",
                 "10ms X0=1\n30ms expect S0=0 Y0=0 Y5=1 Y1=1", id="4-6-1-set-outputs-stay"),
]


@pytest.mark.parametrize("il, stim", SIMS)
def test_sim_rule(il, stim):
    vskit.run(il, stim, alarms=True)
