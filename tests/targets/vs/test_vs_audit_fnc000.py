"""docs/vs-audit.md, section "FNC 000-049": one case per rule the manual's pages 6-2 ... 6-6
state (program flow, compare/move/convert, arithmetic, rotate/shift, data processing).

Cases are written from the pages' own example programs where the page has one (the ladder
diagrams read back into IL). `test_check_rule` asserts the diagnostics `mlc check` gives
(code at line), `test_sim_rule` runs a program against stimulus expectations (device
values, flags, the operation-error relay M9067 and code D9067)."""

from __future__ import annotations

import pytest

import vskit

# (program, the diagnostics it must give as (code, line); [] = no error at all)
CHECKS = [
    # 6-2 CJ: "一個指標P的號碼或程序指標在程序中僅能出現一次"
    pytest.param("P1\nLD X0\nOUT Y0\nP1\nLD X1\nCJ P1\nEND", [("E303", 4)], id="FNC00-label-once"),
    # 6-2 CALL: "程序中若同時存在有CJ及CALL指令時，不可使用相同的P指標號碼或程序指標"
    pytest.param("LD X0\nCJ P1\nLD X1\nCALL P1\nFEND\nP1\nSRET\nEND", [("E305", 2)], id="FNC00-cj-call-share"),
    # 6-2 CJ: P0-P1023 (and program labels, together at most 1024)
    pytest.param("LD X0\nCJ P1024\nEND", [("E205", 2)], id="FNC00-p-range"),
    # 6-2 CALL: "巢狀式子程序呼叫不可超過 5層": the 6th level (P6, called at line 22) is refused;
    # a subroutine calling itself never ends its chain
    pytest.param("LD X0\nCALL P1\nFEND\nP1\nLD X0\nCALL P2\nSRET\nP2\nLD X0\nCALL P3\nSRET\nP3\nLD X0\nCALL P4\nSRET\nP4\nLD X0\nCALL P5\nSRET\nP5\nLD X0\nCALL P6\nSRET\nP6\nLD X0\nINC D0\nSRET\nEND", [("E307", 22)], id="FNC01-nesting-5"),
    pytest.param("LD X0\nCALL P1\nFEND\nP1\nLD X1\nCALL P1\nSRET\nEND", [("E307", 6)], id="FNC01-recursion"),
    pytest.param("LD X0\nCALL P1\nLD X1\nCALL P2\nFEND\nP1\nLD X0\nCALL P2\nSRET\nP2\nLD X0\nINC D0\nSRET\nEND", [],
                 id="FNC01-nesting-legal"),
    # 6-2 CALL: "子程序必須寫在 FEND指令之後"
    pytest.param("LD X0\nCALL P1\nP1\nSRET\nFEND\nEND", [("E305", 2), ("E305", 4)], id="FNC01-after-fend"),
    # 6-2 FEND: several FENDs: subroutines between the last FEND and END
    pytest.param("LD X0\nCALL P1\nFEND\nLD X1\nOUT Y1\nFEND\nP1\nLD X2\nOUT Y2\nSRET\nEND", [],
                 id="FNC06-several-fends"),
    # 6-2 FOR: NEXT before FOR, FOR/NEXT unpaired, NEXT after FEND are errors
    pytest.param("NEXT\nFOR K3\nEND", [("E306", 1), ("E306", 2)], id="FNC08-next-before-for"),
    pytest.param("FOR K3\nFEND\nNEXT\nEND", [("E306", 1), ("E306", 3)], id="FNC09-next-after-fend"),
    # 6-2 FOR: "巢狀式的 FOR∼NEXT迴圈最多可使用 5層"
    pytest.param("FOR K1\nFOR K1\nFOR K1\nFOR K1\nFOR K1\nFOR K1\nNEXT\nNEXT\nNEXT\nNEXT\nNEXT\nNEXT\nEND",
                 [("E307", 6)], id="FNC08-nesting-5"),
    # 6-3 MOV: "如果傳送對象是 32位元計數器，則指令名稱前一定要加上D"
    pytest.param("LD X21\nMOV C200 D10\nEND", [("E211", 2)], id="FNC12-c32-needs-dmov"),
    pytest.param("LD X21\nDMOV C200 D10\nEND", [], id="FNC12-dmov-c200"),
    # 6-3 SMOV: m1 = 1-4
    pytest.param("LD X0\nSMOV D0 K5 K2 D1 K2\nEND", [("E206", 2)], id="FNC13-m1-range"),
    # 6-3 SMOV: "m1＝1〜4 m2＝1〜m1 n＝m2〜4"
    pytest.param("LD X0\nSMOV D0 K2 K3 D1 K3\nEND", [("E221", 2)], id="FNC13-m2-le-m1"),
    pytest.param("LD X0\nSMOV D0 K3 K2 D1 K1\nEND", [("E221", 2)], id="FNC13-n-ge-m2"),
    pytest.param("LD X20\nSMOV D0 K3 K2 D1 K2\nEND", [], id="FNC13-page-example-legal"),
    # 6-3 BMOV: "位元元件之區塊傳送時，則 S 與 D 之位數必須一致"
    pytest.param("LD X20\nBMOV K1M0 K2Y20 K2\nEND", [("E222", 2)], id="FNC15-same-kn"),
    pytest.param("LD X20\nBMOV K1M0 K1Y20 K2\nBMOV K4M0 D0 K2\nEND", [], id="FNC15-kn-legal"),
    # 6-3 BMOV: n = 1-512
    pytest.param("LD X20\nBMOV D0 D100 K513\nEND", [("E206", 2)], id="FNC15-n-range"),
    # 6-3 FMOV: n = 1-512
    pytest.param("LD X20\nFMOV K0 D100 K0\nEND", [("E206", 2)], id="FNC16-n-range"),
    # 6-5 ROR/ROL/RCR/RCL: n = 0-16 (16-bit), 0-32 (32-bit)
    pytest.param("LD X20\nRORP D0 K17\nEND", [("E206", 2)], id="FNC30-n-range"),
    # DECISION (the page's matrix is lost; FX takes K/H only): n is a constant
    pytest.param("LD X20\nROR D0 D1\nEND", [("E204", 2)], id="FNC30-n-constant"),
    pytest.param("LD X20\nDROL D0 K32\nLD X21\nROL D2 K0\nEND", [], id="FNC31-n-range-32"),
    pytest.param("LD X20\nRCR D0 K17\nEND", [("E206", 2)], id="FNC32-n-range"),
    pytest.param("LD X20\nDRCL D0 K33\nEND", [("E206", 2)], id="FNC33-n-range"),
    # 6-3 BCD: S outside 0-9,999 (32-bit 0-99,999,999) is an operation error: a constant is refused
    pytest.param("LD X20\nBCD K10000 D0\nDBCD K100000000 D2\nBCD K9999 D4\nDBCD K99999999 D6\nEND",
                 [("E206", 2), ("E206", 3)], id="FNC18-s-range"),
    # 6-3 BIN: a source that is not BCD is an operation error: a constant one is refused
    pytest.param("LD X20\nBIN H12A4 D0\nBIN K10 D1\nBIN H1234 D2\nEND", [("E206", 2), ("E206", 3)], id="FNC19-bcd-source"),
    # 6-4 DIV: "當除數等于 0時，PLC認定為運算錯誤": a constant K0 divisor is refused
    pytest.param("LD X20\nDIV D0 K0 D2\nDDIV D0 K0 D4\nDIV D0 K3 D8\nEND", [("E206", 2), ("E206", 3)],
                 id="FNC23-divisor-zero"),
    # 6-5: "D指定為KnY,KnM,KnS時，16位元指令只能指定K4Y,K4M,K4S，32位元指令只能指定K8Y,K8M,K8S"
    pytest.param("LD X20\nROR K2Y0 K1\nDROL K4M0 K1\nRCR K4S0 K1\nDRCL K8Y0 K1\nEND", [("E220", 2), ("E220", 3)],
                 id="FNC30-whole-word-kn"),
    # 6-5 SFTR/SFTL/WSFR/WSFL: "n1＝1〜1024 n2＝1〜n1"
    pytest.param("LD X20\nSFTR X0 M0 K4 K8\nSFTL X0 M0 K4 K5\nWSFR D100 D0 K3 K4\nWSFL D100 D0 K12 K13\nEND",
                 [("E221", 2), ("E221", 3), ("E221", 4), ("E221", 5)], id="FNC34-n2-le-n1"),
    # 6-5 WSFR/WSFL: S and D "元件屬性必須相同" and "Kn的位數必須相同"
    pytest.param("LD X20\nWSFR K1X0 K2Y20 K4 K2\nWSFL D0 K1Y20 K4 K2\nEND", [("E222", 2), ("E222", 3)],
                 id="FNC36-same-kn-and-kind"),
    pytest.param("LD X20\nWSFRP K1X0 K1Y20 K4 K2\nWSFLP K1X20 K1Y20 K4 K1\nWSFRP D100 D0 K12 K3\nEND", [],
                 id="FNC36-page-examples-legal"),
    # 6-5 SFTR/SFTL: n1 = 1-1024
    pytest.param("LD X20\nSFTR X0 M0 K1025 K1\nEND", [("E206", 2)], id="FNC34-n1-range"),
    pytest.param("LD X20\nSFTL X0 M0 K16 K0\nEND", [("E206", 2)], id="FNC35-n2-range"),
    # 6-5 WSFR/WSFL: n1 = 1-512
    pytest.param("LD X20\nWSFR D100 D0 K513 K3\nEND", [("E206", 2)], id="FNC36-n1-range"),
    pytest.param("LD X20\nWSFL D100 D0 K512 K0\nEND", [("E206", 2)], id="FNC37-n2-range"),
    # 6-5 SFWR/SFRD: n = 2-512
    pytest.param("LD X20\nSFWR D100 D0 K1\nEND", [("E206", 2)], id="FNC38-n-range"),
    pytest.param("LD X21\nSFRD D0 D101 K513\nEND", [("E206", 2)], id="FNC39-n-range"),
    # 6-6 ZRST: "D1及D2必須指定相同類型元件"; no 16-bit counter start with a 32-bit end
    pytest.param("LD X0\nZRST M10 D5\nEND", [("E214", 2)], id="FNC40-same-kind"),
    pytest.param("LD X0\nZRST C100 C210\nEND", [("E214", 2)], id="FNC40-counter-widths"),
    pytest.param("LD M9002\nZRST S500 S599\nZRST D7000 D7100\nZRST C100 C110\nZRST C200 C255\n"
                 "ZRST M2000 M2499\nEND", [], id="FNC40-page-example"),
    # 6-6 ZRST: "D1元件號碼必須≦D2元件號碼"; D1 > D2 runs but resets D1 only: a warning
    pytest.param("LD X0\nZRST M10 M5\nEND", [("W220", 2)], id="FNC40-backwards"),
    # 6-6 DECO: bit D: n = 1-8; word D: n = 1-4
    pytest.param("LD X20\nDECOP X0 M0 K9\nEND", [("E206", 2)], id="FNC41-n-bit"),
    pytest.param("LD X20\nDECOP D0 D1 K5\nEND", [("E216", 2)], id="FNC41-n-word"),
    # 6-6 ENCO: bit S: n = 1-8; word S: n = 1-4
    pytest.param("LD X20\nENCOP D0 D1 K5\nEND", [("E216", 2)], id="FNC42-n-word"),
    pytest.param("LD X20\nENCOP M0 D0 K8\nEND", [], id="FNC42-n-bit"),
    # 6-6 BON: n = 0-15 (16-bit), 0-31 (32-bit)
    pytest.param("LD X20\nBON D0 M0 K16\nEND", [("E206", 2)], id="FNC44-n-range"),
    pytest.param("LD X20\nDBON D0 M0 K31\nEND", [], id="FNC44-n-range-32"),
    # 6-6 SQR: "16位元指令，S=0∼32767  32位元指令，S=0∼2147483647"
    pytest.param("LD X20\nSQR K-4 D1\nEND", [("E206", 2)], id="FNC48-s-range"),
    pytest.param("LD X20\nDSQR K2147483647 D2\nSQR K32767 D1\nEND", [], id="FNC48-s-range-legal"),
    # 6-6 MEAN: n = 1-64
    pytest.param("LD X20\nMEAN D0 D10 K65\nEND", [("E206", 2)], id="FNC45-n-range"),
    # 6-6 ANS: S = T0-T199, m = 1-32767, D = S900-S999
    pytest.param("LD X20\nANS T200 K15 S900\nEND", [("E205", 2)], id="FNC46-timer-range"),
    # 6-6 ANS: "請勿在程序中使用已在本指令中使用過的計時器編號"
    pytest.param("LD X20\nANS T0 K15 S900\nLD X21\nOUT T0 K10\nEND", [("W402", 4)], id="FNC46-timer-once"),
    pytest.param("LD X20\nANS T0 K0 S900\nEND", [("E206", 2)], id="FNC46-m-range"),
    pytest.param("LD X20\nANS T0 K15 S899\nEND", [("E205", 2)], id="FNC46-step-range"),
]


@pytest.mark.parametrize("il, expected", CHECKS)
def test_check_rule(il, expected):
    found = vskit.check_codes(il)
    if expected:
        missing = [e for e in expected if e not in found]
        assert not missing, (missing, found)
    else:
        assert vskit.check_codes(il, None, ("error",)) == []


# (program, stimulus with expectations); the program's END is added
SIMS = [
    # 6-2 CJ: "CJ P63及CJ P255相當于跳到程序END處"
    pytest.param("LD X0\nCJ P63\nLD M9000\nINC D0\nLD X1\nCJ P255\nLD M9000\nINC D1",
                 "0ms X0=1\n0ms expect D0=0 D1=0\n10ms X0=0 X1=1\n10ms expect D0=1 D1=0", id="FNC00-p63-p255"),
    # 6-2 CJ: while jumped, Y/M/S keep their state and application instructions do not run;
    # counters stop counting
    pytest.param("LD X20\nCJ P0\nLD X0\nOUT Y0\nLD X1\nOUT C0 K10\nLD M9000\nINC D0\nP0",
                 "0ms X0=1 X1=1\n0ms expect Y0=1 C0:w=1 D0=1\n10ms X20=1 X0=0 X1=0\n20ms X1=1\n"
                 "30ms expect Y0=1 C0:w=1 D0=1\n40ms X20=0\n40ms expect Y0=0 D0=2", id="FNC00-skipped-region"),
    # 6-2 CJ: running 1 ms timers keep timing while jumped, their contact waits for the OUT;
    # T192-T199 keep timing and their contacts work
    pytest.param("LD X20\nCJ P0\nLD M9000\nOUT T256 K50\nLD M9000\nOUT T192 K2\nP0\nLD T256\nOUT Y1\nLD T192\nOUT Y2",
                 "0ms X20=0\n10ms X20=1\n100ms expect T256:w=50 Y1=0 Y2=0\n300ms expect Y1=0 Y2=1\n310ms X20=0\n"
                 "320ms expect Y1=1",
                 id="FNC00-skipped-timers"),
    # 6-2 CALL: the page's program with a named label (緊急停止); SRET returns after the CALL
    pytest.param("LD X20\nCALL 緊急停止\nLD M9000\nINC D1\nFEND\n緊急停止:\nLD M9000\nINC D0\nSRET",
                 "0ms X20=1\n0ms expect D0=1 D1=1\n10ms X20=0\n10ms expect D0=1 D1=2", id="FNC01-named-label"),
    pytest.param("LD M9000\nCALL P1\nMOV D0 D1\nFEND\nP1\nLD M9000\nINC D0\nSRET",
                 "0ms expect D0=1 D1=1\n10ms expect D0=2 D1=2", id="FNC02-sret-returns"),
    # 6-2 WDT: the page's program: D9000 = 300 from the first scan, WDT reloads the watchdog.
    # DECISION: the simulator's scans are virtual and never overrun it; WDT changes no device
    pytest.param("LD M9002\nMOV K300 D9000\nWDT",
                 "0ms X0=1\n0ms expect D9000=300 M9067=0\n20ms expect D9000=300", id="FNC07-page-example"),
    # 6-2 CALL: "巢狀式子程序呼叫不可超過 5層": the 6th level is not executed; operation error 6702
    # (M9067, D9067). The chain goes through an indexed CALL, which no check can follow
    pytest.param("LD M9000\nCALL P1\nFEND\nP1\nLD M9000\nCALL P2Z0\nSRET\nP2\nLD M9000\nCALL P3\nSRET\n"
                 "P3\nLD M9000\nCALL P4\nSRET\nP4\nLD M9000\nCALL P5\nSRET\nP5\nLD M9000\nINC D1\nCALL P6\nSRET\n"
                 "P6\nLD M9000\nINC D0\nSRET",
                 "0ms expect D1=1 D0=0 M9067=1 D9067=6702 M9004=1", id="FNC01-nesting-6702"),
    # 6-2 FOR: 5 levels at most, error 6704. DECISION: a 6th level (here 3 in the main program
    # around a CALL of a subroutine with 3 more) is not executed and its body runs once
    pytest.param("FOR K2\nFOR K1\nFOR K1\nLD M9000\nCALL P1\nNEXT\nNEXT\nNEXT\nFEND\nP1\nFOR K1\nFOR K1\n"
                 "FOR K3\nLD M9000\nINC D0\nNEXT\nNEXT\nNEXT\nSRET",
                 "0ms expect D0=2 M9067=1 D9067=6704", id="FNC08-nesting-6704"),
    # 6-2 FOR: the page's example: D0-D9 summed into D10 with Z0 (3 levels shown: 5 x A)
    pytest.param("LD M9000\nMOV K0 D10\nMOV K0 Z0\nFOR K10\nLD M9000\nADD D10 D0Z0 D10\nINC Z0\nNEXT",
                 "0ms D0=1 D1=2 D2=3 D3=4 D4=5 D5=6 D6=7 D7=8 D8=9 D9=10\n10ms expect D10=55",
                 id="FNC08-page-example"),
    # 6-2 FOR: "S=1∼32767(此範圍之外一律視為 1)"
    pytest.param("FOR D0\nLD M9000\nINC D1\nNEXT\nFOR D2\nLD M9000\nINC D3\nNEXT",
                 "0ms D0=0 D2=-5\n0ms expect D1=1 D3=1", id="FNC08-outside-is-1"),
    # 6-3 CMP: the page's example; results held when the condition is Off
    pytest.param("LD X20\nCMP K100 D100 M100",
                 "0ms X20=1 D100=50\n0ms expect M100=1 M101=0 M102=0\n10ms D100=100\n10ms expect M101=1 M100=0\n"
                 "20ms D100=200\n20ms expect M102=1 M101=0\n30ms X20=0 D100=0\n30ms expect M102=1 M100=0",
                 id="FNC10-page-example"),
    # 6-3 ZCP: the page's example; "當 S1 > S2 時，則指令以 S1 做為上、下限值進行比較"
    pytest.param("LD X20\nZCP K100 K200 D100 M100\nLD X20\nZCP K200 K100 D100 M110",
                 "0ms X20=1 D100=50\n0ms expect M100=1 M101=0\n10ms D100=150\n10ms expect M101=1 M110=1 M112=0\n"
                 "20ms D100=200\n20ms expect M101=1 M112=0 M111=1\n30ms D100=201\n30ms expect M102=1 M112=1\n"
                 "40ms X20=0 D100=0\n40ms expect M102=1", id="FNC11-page-example"),
    # 6-3 MOV: word -> K2M0 writes M0-M7 only; K2M0 -> word zero-fills the high bits
    pytest.param("LD X20\nMOV D0 K2M0\nMOV K2M0 D1\nLD X21\nDMOV C200 D10\nLD X22\nMOV K1X0 K1Y20",
                 "0ms X20=1 D0=H55AA M8=1 M15=1\n0ms expect M1=1 M0=0 M8=1 M15=1 D1=H00AA\n"
                 "10ms X21=1 C200:d=70000 X22=1 X1=1 X3=1\n10ms expect D10:d=70000 Y21=1 Y23=1 Y20=0",
                 id="FNC12-page-example"),
    # 6-3 SMOV: the page's example (BCD mode): D0 digits 3-2 into D1 from digit 2
    pytest.param("LD X20\nSMOV D0 K3 K2 D1 K2",
                 "0ms X20=1 D0=1234 D1=5678\n0ms expect D1=5623", id="FNC13-page-example"),
    # 6-3 SMOV: M9168 Off: a value above 9999 or below 0 is an operation error
    pytest.param("LD X20\nSMOV D0 K3 K2 D1 K2",
                 "0ms X20=1 D0=12345 D1=5678\n0ms expect D1=5678 M9067=1 D9067=6706 M9004=1", id="FNC13-bcd-error"),
    # 6-3 SMOV: M9168 On: hex digits
    pytest.param("LD M9000\nSET M9168\nSMOV D0 K4 K2 D1 K2",
                 "0ms D0=H1234 D1=H5678\n0ms expect D1=H5612 M9067=0", id="FNC13-hex-mode"),
    # 6-3 CML: the page's example
    pytest.param("LD X20\nCML D0 D1", "0ms X20=1 D0=H55AA\n0ms expect D1=HAA55\n10ms X20=0 D0=0\n10ms expect D1=HAA55",
                 id="FNC14-page-example"),
    # 6-3 BMOV: the page's examples; overlapping blocks copied in the order that keeps S
    pytest.param("LD X20\nBMOVP D100 D200 K4\nLD X21\nBMOV D1 D0 K3\nLD X22\nBMOV D11 D12 K3",
                 "0ms X20=1 D100=1 D101=2 D102=3 D103=4\n0ms expect D200=1 D203=4\n"
                 "10ms X21=1 X22=1 D1=1 D2=2 D3=3 D11=1 D12=2 D13=3\n10ms expect D0=1 D1=2 D2=3 D12=1 D13=2 D14=3",
                 id="FNC15-page-example"),
    # 6-3 BMOV with Kn groups of one size: K1M0, K1M4 -> K1Y20, K1Y24
    pytest.param("LD X20\nBMOV K1M0 K1Y20 K2", "0ms X20=1 M0=1 M7=1\n0ms expect Y20=1 Y27=1 Y21=0",
                 id="FNC15-kn-example"),
    # 6-3 BMOV: "特殊繼電器M9024為BMOV指令專用傳送方向控制標誌位": On, D0-D99 <- D100-D199
    pytest.param("LD X20\nBMOVP D0 D100 K100\nLD X21\nSET M9024",
                 "0ms D0=1 D99=2 D100=3 D199=4\n10ms X20=1\n10ms expect D100=1 D199=2\n20ms X20=0 X21=1 D100=7 D199=8\n"
                 "30ms X20=1\n30ms expect D0=7 D99=8 D100=7", id="FNC15-m9024-direction"),
    # 6-3 FMOV: the page's example: K0 into D100-D104
    pytest.param("LD X20\nFMOV K0 D100 K5", "0ms D100=1 D104=5 D105=6\n10ms X20=1\n10ms expect D100=0 D104=0 D105=6",
                 id="FNC16-page-example"),
    # 6-3 FMOV: "如果 D 所指定的範圍超過該元件的使用範圍時，只有有效範圍會被傳送" (R23999 is the last R)
    pytest.param("LD M9000\nFMOV K7 R23998 K5", "0ms expect R23998=7 R23999=7", id="FNC16-in-range-only"),
    # 6-3 BMOV past the device's end: DECISION as FMOV: only the part inside both ranges moves
    pytest.param("LD M9000\nBMOV R23998 D0 K5", "0ms R23998=4 R23999=8 D2=9\n0ms expect D0=4 D1=8 D2=9",
                 id="FNC15-in-range-only"),
    # 6-3 XCH: the page's examples, 16 and 32 bits
    pytest.param("LD X20\nXCHP D100 D200\nLD X21\nDXCHP D0 D300",
                 "0ms X20=1 X21=1 D100=1 D200=2 D0:d=70000 D300:d=2\n0ms expect D100=2 D200=1 D300:d=70000 D0:d=2",
                 id="FNC17-page-example"),
    # 2-14-1 M9160 "指定XCH指令執行SWAP功能": XCH D1 D1 exchanges D1's bytes. DECISION (FX
    # M8160): two different devices are an operation error (6705)
    pytest.param("LD M9000\nSET M9160\nLD X20\nXCHP D0 D0\nDXCHP D2 D2\nLD X21\nXCH D4 D5",
                 "0ms D0=H1234 D2:d=H11223344 D4=1 D5=2\n10ms X20=1\n10ms expect D0=H3412 D2:d=H22114433 M9067=0\n"
                 "20ms X21=1\n20ms expect D4=1 D5=2 M9067=1 D9067=6705", id="FNC17-m9160-swap"),
    # 6-3 BCD/BIN: the page's example: K4X20 BCD -> D100, D100 -> K4Y20 as BCD
    pytest.param("LD M9000\nBIN K4X20 D100\nBCD D100 K4Y20",
                 "0ms X20=1 X25=1 X34=1\n0ms expect D100=1021 Y20=1 Y25=1 Y34=1",
                 id="FNC18-page-example"),
    # 6-3 BCD: 16-bit outside 0-9999, 32-bit outside 0-99,999,999: operation error (M9067)
    pytest.param("LD X20\nBCD D0 D1", "0ms X20=1 D0=10000\n0ms expect D1=0 M9067=1 D9067=6706", id="FNC18-range-error"),
    pytest.param("LD X20\nDBCD D0 D2", "0ms X20=1 D0:d=99999999\n0ms expect D2:d=H99999999 M9067=0",
                 id="FNC18-range-32"),
    # 6-3 BIN: "若來源元件的內容不是BCD值時，則PLC認定為運算錯誤"
    pytest.param("LD X20\nBIN D0 D1", "0ms X20=1 D0=H12A4\n0ms expect D1=0 M9067=1 D9067=6706", id="FNC19-not-bcd"),
    # 6-4 ADD: the page's examples; M9020 zero, M9022 carry (> 32,767), M9021 borrow (< -32,768)
    pytest.param("LD X20\nADDP D0 D1 D2",
                 "0ms X20=1 D0=5 D1=-5\n0ms expect D2=0 M9020=1\n"
                 "10ms X20=0\n20ms X20=1 D0=32767 D1=1\n20ms expect D2=-32768 M9022=1 M9020=0 M9021=0\n"
                 "30ms X20=0\n40ms X20=1 D0=-32768 D1=-1\n40ms expect M9021=1 M9022=0",
                 id="FNC20-flags"),
    pytest.param("LD X20\nDADD D0 D2 D4", "0ms X20=1 D0:d=70000 D2:d=1\n0ms expect D4:d=70001 M9022=0\n"
                 "10ms D0:d=2147483647\n10ms expect D4:d=-2147483648 M9022=1",
                 id="FNC20-carry-32"),
    # 6-4 SUB: flags as ADD
    pytest.param("LD X20\nSUBP D0 D1 D2\nLD X21\nDSUBP D10 D12 D14",
                 "0ms X20=1 D0=-32768 D1=1 X21=1 D10:d=5 D12:d=5\n0ms expect D2=32767 D14:d=0 M9020=1 M9021=0\n"
                 "10ms X20=0 X21=0\n20ms X20=1 D0=3 D1=3\n20ms expect D2=0 M9020=1\n30ms X20=0\n"
                 "40ms X20=1 D0=-32768 D1=1\n40ms expect M9021=1 M9020=0", id="FNC21-flags"),
    # 6-4 MUL: 16 x 16 -> 32 bits in (D+1, D), 32 x 32 -> 64 bits; M9023 when the product is 0
    pytest.param("LD X20\nMUL D0 D1 D2\nLD X21\nDMULP D10 D12 D14",
                 "0ms X20=1 D0=-300 D1=300 X21=1 D10:d=100000 D12:d=100000\n"
                 "0ms expect D2:d=-90000 D14:d=1410065408 D16:d=2 M9023=0\n10ms D0=0\n10ms expect D2:d=0 M9023=1",
                 id="FNC22-product"),
    # 6-4 DIV: quotient D, remainder D+1 with the dividend's sign; /0 an operation error
    pytest.param("LD X20\nDIVP D0 D1 D2\nLD X21\nDDIVP D10 D12 D14",
                 "0ms X20=1 D0=-7 D1=2 X21=1 D10:d=-100001 D12:d=10\n0ms expect D2=-3 D3=-1 D14:d=-10000 D16:d=-1\n"
                 "10ms X20=0\n20ms X20=1 D1=0\n20ms expect D2=-3 M9067=1 D9067=6706", id="FNC23-quotient-remainder"),
    pytest.param("LD X20\nDIV D0 D1 D2", "0ms X20=1 D0=-32768 D1=-1\n0ms expect M9025=1 M9023=0\n"
                 "10ms D0=1 D1=2\n10ms expect M9023=1 M9025=0", id="FNC23-flags"),
    # 6-4 INC/DEC: wrap at +-32,767 / +-2,147,483,647; "本指令運算結果不會影響任何標誌位"
    pytest.param("LD X20\nINCP D100\nLD X21\nDECP D101\nLD X22\nDINC D102\nLD X23\nDDEC D104",
                 "0ms M9020=1 M9021=1 M9022=1 D100=32767 D101=-32768 D102:d=2147483647 D104:d=-2147483648\n"
                 "10ms X20=1 X21=1 X22=1 X23=1\n10ms expect D100=-32768 D101=32767 D102:d=-2147483648 "
                 "D104:d=2147483647 M9020=1 M9021=1 M9022=1", id="FNC24-wrap-no-flags"),
    pytest.param("LD X20\nINC D100", "0ms X20=1\n30ms expect D100=4", id="FNC24-every-scan"),
    pytest.param("LD X20\nDECP D101", "0ms X20=1\n30ms expect D101=-1", id="FNC25-pulse-once"),
    # 6-4 WAND/WOR/WXOR: the page's example
    pytest.param("LD X20\nWAND D0 D1 D2\nLD X21\nWOR D3 D4 D5\nLD X22\nWXOR D6 D7 D8",
                 "0ms X20=1 X21=1 X22=1 D0=H0F0F D1=H00FF D3=H0F0F D4=H00FF D6=H0F0F D7=H00FF\n"
                 "0ms expect D2=H000F D5=H0FFF D8=H0FF0", id="FNC26-page-example"),
    pytest.param("LD X21\nDWOR D0 D2 D4", "0ms X21=1 D0:d=H10000 D2:d=1\n0ms expect D4:d=H10001",
                 id="FNC27-32-bit"),
    pytest.param("LD X22\nDWXOR D0 D2 D4", "0ms X22=1 D0:d=-1 D2:d=H0000FFFF\n0ms expect D4:d=-65536",
                 id="FNC28-32-bit"),
    # 6-4 NEG: the page's absolute-value programs (BON D100 M0 K15 / NEGP; D0.F / NEGP D0)
    pytest.param("LD M9000\nBON D100 M0 K15\nLD M0\nNEGP D100\nLD D0.F\nNEGP D0",
                 "0ms D100=-25 D0=-7\n10ms expect D100=25 D0=7\n20ms D100=30\n30ms expect D100=30",
                 id="FNC29-page-example"),
    # 6-5 ROR/ROL: the page's examples: 4 bits a turn, "並將被旋出的資料傳送到進制標誌位M9022中"
    pytest.param("LD X20\nRORP D0 K4\nLD X21\nROLP D1 K4",
                 "0ms D0=H0018 D1=H8000\n10ms X20=1\n10ms expect D0=H8001 M9022=1\n20ms X21=1\n"
                 "20ms expect D1=H0008 M9022=0", id="FNC30-page-example"),
    pytest.param("LD X21\nROL D1 K1\nLD X22\nDROR D2 K1",
                 "0ms X21=1 D1=H8000\n0ms expect D1=1 M9022=1\n10ms X21=0 X22=1 D2:d=2\n10ms expect D2:d=1 M9022=0",
                 id="FNC31-carry"),
    # 6-5 n = 0 moves nothing and leaves M9022 alone (DECISION)
    pytest.param("LD X20\nROR D0 K0", "0ms X20=1 D0=5 M9022=1\n0ms expect D0=5 M9022=1", id="FNC30-n-zero"),
    # 6-5 RCR/RCL: the page's examples: D0 and M9022 rotate together 4 bits
    pytest.param("LD X20\nRCRP D0 K4\nLD X21\nRCLP D1 K4",
                 "0ms M9022=0 D0=H0018\n10ms X20=1\n10ms expect D0=H0001 M9022=1\n20ms X21=1 D1=H8000\n"
                 "20ms expect D1=H000C M9022=0", id="FNC32-page-example"),
    pytest.param("LD X21\nRCLP D1 K1", "0ms X21=1 D1=H8000 M9022=0\n0ms expect D1=0 M9022=1", id="FNC33-carry-out"),
    # 6-5 SFTR/SFTL: the page's example: M0-M15 shift 4, X0-X3 enter at M12-M15 (right) /
    # M0-M3 (left)
    pytest.param("LD X20\nSFTRP X0 M0 K16 K4\nLD X21\nSFTLP X10 M100 K16 K4",
                 "0ms M4=1 X0=1 X3=1 M100=1 X10=1\n10ms X20=1 X21=1\n10ms expect M0=1 M4=0 M12=1 M15=1 M104=1 M100=1 M103=0",
                 id="FNC34-page-example"),
    pytest.param("LD X21\nSFTLP X0 M0 K16 K4", "0ms M12=1 X1=1\n10ms X21=1\n10ms expect M1=1 M12=0 M0=0",
                 id="FNC35-page-example"),
    # 6-5 n2 > n1 with register counts: an operation error at run time
    pytest.param("LD X20\nSFTR X0 M0 D0 D1", "0ms X20=1 D0=4 D1=8 X0=1\n0ms expect M0=0 M9067=1",
                 id="FNC34-n2-le-n1-run"),
    # 6-5 WSFR/WSFL: the page's examples (D0-D11 shift 3 words; K1X0 -> K1Y20 4 groups by 2)
    pytest.param("LD X20\nWSFRP D100 D0 K12 K3\nLD X21\nWSFRP K1X0 K1Y20 K4 K2",
                 "0ms D100=7 D101=8 D102=9 D3=33\n10ms X20=1 X21=1 X0=1 X4=1 Y30=1\n"
                 "10ms expect D9=7 D10=8 D11=9 D0=33 Y20=1 Y30=1 Y24=0", id="FNC36-page-example"),
    pytest.param("LD X21\nWSFLP D100 D0 K12 K3",
                 "0ms D100=7 D101=8 D102=9 D0=5\n10ms X21=1\n10ms expect D0=7 D1=8 D2=9 D3=5", id="FNC37-page-example"),
    # 6-5 SFWR: the page's example: pointer D0, D100 into D1, D2 ...; full (pointer >= n-1):
    # no write, M9022 On
    pytest.param("LD X20\nSFWRP D100 D0 K3",
                 "0ms D100=11\n10ms X20=1\n10ms expect D0=1 D1=11\n20ms X20=0 D100=12\n30ms X20=1\n30ms expect D0=2 D2=12 M9022=0\n"
                 "40ms X20=0 D100=13\n50ms X20=1\n50ms expect D0=2 D2=12 M9022=1", id="FNC38-page-example"),
    # 6-5 SFRD: the page's example: D1 -> D101, D1-D9 move down, pointer - 1; empty: M9020
    pytest.param("LD X21\nSFRDP D0 D101 K10",
                 "0ms D0=2 D1=5 D2=6\n10ms X21=1\n10ms expect D101=5 D1=6 D0=1\n20ms X21=0\n30ms X21=1\n"
                 "30ms expect D101=6 D0=0 M9020=1\n40ms X21=0 D101=99\n50ms X21=1\n50ms expect D101=99 D0=0 M9020=1",
                 id="FNC39-page-example"),
    # 6-6 ZRST: the page's example: M2000-M2499 reset in the first scan
    pytest.param("LD M9002\nZRST M2000 M2499\nZRST D7000 D7100",
                 "0ms expect M2000=0 M2499=0 D7000=0\n", id="FNC40-page-example-run"),
    # 6-6 ZRST: "當 D1 > D2 的號碼時，只有 D1 所指定的元件被復歸"
    pytest.param("LD M9000\nSET M5\nSET M10\nLD X0\nZRST M10 M5\nLD X0\nZRST D7 D3",
                 "0ms D3=3 D7=7\n10ms X0=1\n10ms expect M10=0 M5=1 D7=0 D3=3", id="FNC40-d1-above-d2"),
    # 6-6 DECO: the page's examples: X0-X2 = 2 -> M2; D0 (b0-b2) = 5 -> D1 = bit 5, b8-b15 0
    pytest.param("LD X20\nDECOP X0 M0 K3\nLD X21\nDECOP D0 D1 K3",
                 "0ms X1=1 M5=1 D0=5 D1=HFF00\n10ms X20=1 X21=1\n10ms expect M2=1 M5=0 D1=H0020", id="FNC41-page-example"),
    # 6-6 ENCO: the page's examples; several bits On: the highest wins; result held when Off
    pytest.param("LD X20\nENCOP M0 D0 K3\nLD X21\nENCOP D10 D1 K4",
                 "0ms M3=1 M1=1 D10=H0101\n10ms X20=1 X21=1\n10ms expect D0=3 D1=8", id="FNC42-page-example"),
    # 6-6 ENCO: "如果 S 的內容為 0時，PLC認定為運算錯誤"
    pytest.param("LD X20\nENCO M0 D0 K3", "0ms X20=1 D0=7\n0ms expect D0=7 M9067=1 D9067=6706", id="FNC42-zero-error"),
    # 6-6 SUM: the page's example; all 0 -> M9020; DSUM still writes two registers
    pytest.param("LD X20\nSUM D0 D10\nLD X21\nDSUM D20 D30",
                 "0ms X20=1 D0=H0F0F X21=1 D20:d=-1 D31=5\n0ms expect D10=8 D30=32 D31=0 M9020=0\n"
                 "10ms X21=0 D0=0\n10ms expect D10=0 M9020=1", id="FNC43-page-example"),
    # 6-6 BON: the page's example: D0 b5 -> M0; held when Off
    pytest.param("LD X20\nBON D0 M0 K5", "0ms X20=1 D0=H0020\n0ms expect M0=1\n10ms X20=0 D0=0\n10ms expect M0=1",
                 id="FNC44-page-example"),
    # 6-6 MEAN: the page's example: D0-D4 averaged into D10, remainder dropped
    pytest.param("LD X20\nMEAN D0 D10 K5", "0ms X20=1 D0=1 D1=2 D2=3 D3=4 D4=8\n0ms expect D10=3",
                 id="FNC45-page-example"),
    # 6-6 MEAN: "如果被指定的元件號碼超出範圍，則只有在合法範圍內的元件會被處理"
    pytest.param("LD M9000\nMEAN R23998 D0 K5", "0ms R23998=4 R23999=8\n0ms expect D0=6", id="FNC45-in-range-only"),
    # 6-6 ANS: the page's example: X20 and X21 On over 1.5 s -> S900 On and kept
    pytest.param("LD X20\nAND X21\nANS T0 K15 S900\nLD X0\nANR",
                 "0ms X20=1 X21=1\n1.4s expect S900=0\n1.6s expect S900=1\n1.7s X21=0\n1.8s expect S900=1 T0:w=0\n"
                 "1.9s X0=1\n1.9s expect S900=0", id="FNC46-page-example"),
    # 6-6 ANS/ANR: M9049 On: M9048 = some alarm step On, D9049 = the lowest one; ANR resets
    # the lowest first
    pytest.param("LD M9000\nOUT M9049\nLD X20\nANS T0 K60 S900\nLD X21\nANS T1 K60 S901\nLD X27\nANR",
                 "0ms X20=1 X21=1\n6.1s expect S900=1 S901=1 M9048=1 D9049=900\n6.2s X20=0 X21=0 X27=1\n"
                 "6.2s expect S900=0 S901=1 D9049=901\n6.3s X27=0\n6.4s X27=1\n6.4s expect S901=0", id="FNC47-lowest-first"),
    # 6-6 SQR: fraction dropped -> M9021, 0 -> M9020, negative -> operation error (M9067)
    pytest.param("LD X20\nSQR D0 D1", "0ms X20=1 D0=10\n0ms expect D1=3 M9021=1 M9020=0\n10ms D0=0\n"
                 "10ms expect D1=0 M9020=1 M9021=0\n20ms D0=-4\n20ms expect D1=0 M9067=1 D9067=6706", id="FNC48-flags"),
    # 6-6 FLT: the page's examples (D0 -> D11:D10, D3:D2 -> D13:D12; D always two words) and
    # the float program 2 x 3.14 x D0
    pytest.param("LD X0\nFLT D0 D10\nLD X1\nDFLT D2 D12\nLD X2\nDEDIV K314 K100 D20\nDEMUL K2 D20 D22\n"
                 "FLT D0 D24\nDEMUL D22 D24 D30",
                 "0ms X0=1 X1=1 X2=1 D0=-3 D2:d=100000\n0ms expect D10:f=-3 D12:f=100000 D30:f=-18.84", id="FNC49-page-example"),
]


@pytest.mark.parametrize("il, stim", SIMS)
def test_sim_rule(il, stim):
    vskit.run(il, stim, alarms=True)
