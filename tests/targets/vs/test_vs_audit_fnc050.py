"""docs/vs-audit.md, section FNC 050-149: one case per rule a page of the Vigor VS manual
states (6-7 ... 6-13), each case id named by its row. Static rules: a legal line checks clean
and an illegal one gives the diagnostic; run-time rules: the page's example (written in IL
from the page) against a stimulus whose expectations must hold."""

from __future__ import annotations

import pytest

from vskit import check_codes as found
from vskit import run


def program(*lines: str) -> str:
    """Each line on its own condition X0 ... (the lines 2, 4, 6 ... of the program)."""
    return "".join(f"LD X{k}\n{line}\n" for k, line in enumerate(lines)) + "END\n"


# ------------------------------------------------------------------ static rules

# (model, legal line, illegal line, code the illegal one gets). The illegal line is the only
# change; the code must be reported at it (line 2 of `program`).
CHECKS = [
    # 6-7 FNC 50 REF: D = X0, X10 or Y0; n = 8 or 16
    pytest.param("VS3", "REF X10 K8", "REF X20 K8", "E205", id="FNC50-D-is-X0-X10-Y0"),
    pytest.param("VS3", "REF X0 K16", "REF X0 K17", "E206", id="FNC50-n-range"),
    # 6-7 FNC 51 REFF: n = 0-60 ms
    pytest.param("VS3", "REFF K60", "REFF K61", "E206", id="FNC51-n-0-60"),
    # 6-7 FNC 52 MTR: n = 2-8, S an X
    pytest.param("VS3", "MTR X20 Y20 M0 K8", "MTR X20 Y20 M0 K9", "E206", id="FNC52-n-2-8"),
    pytest.param("VS3", "MTR X20 Y20 M0 K2", "MTR M20 Y20 M0 K2", "E204", id="FNC52-S-is-X"),
    # 6-7 FNC 53-55: 32-bit only, S2 = C235-C255, D = Y0-Y7 / IHC0-IHC7
    pytest.param("VS3", "DHSCS K200 C235 Y0", "HSCS K200 C235 Y0", "E201", id="FNC53-32-bit-only"),
    pytest.param("VS3", "DHSCS K200 C255 Y7", "DHSCS K200 C234 Y0", "E205", id="FNC53-S2-C235-C255"),
    pytest.param("VS3", "DHSCS K200 C235 Y7", "DHSCS K200 C235 Y10", "E205", id="FNC53-D-Y0-Y7"),
    pytest.param("VS3", "DHSCR K200 C235 Y0", "HSCR K200 C235 Y0", "E201", id="FNC54-32-bit-only"),
    pytest.param("VS3", "DHSCR K200 C235 C235", "DHSCR K200 C235 Y10", "E205", id="FNC54-D-Y0-Y7"),
    pytest.param("VS3", "DHSZ K100 K200 C255 Y0", "HSZ K100 K200 C255 Y0", "E201", id="FNC55-32-bit-only"),
    pytest.param("VS3", "DHSZ K100 K200 C255 M0", "DHSZ K100 K200 C234 M0", "E205", id="FNC55-S-C235-C255"),
    # 6-7 FNC 56 SPD: S1 = X0-X7, D occupies 3 words
    pytest.param("VS3", "SPD X7 K1000 D0", "SPD X10 K1000 D0", "E205", id="FNC56-S1-X0-X7"),
    pytest.param("VS3", "SPD X0 K1000 R23997", "SPD X0 K1000 R23998", "E208", id="FNC56-D-occupies-3"),
    # 6-7 FNC 57-59: D = Y0-Y3
    pytest.param("VS3", "PLSY K500 D100 Y3", "PLSY K500 D100 Y4", "E205", id="FNC57-D-Y0-Y3"),
    pytest.param("VS3", "PWM D0 K100 Y3", "PWM D0 K100 Y4", "E205", id="FNC58-D-Y0-Y3"),
    pytest.param("VS3", "PLSR K1000 D100 K1000 Y3", "PLSR K1000 D100 K1000 Y4", "E205", id="FNC59-D-Y0-Y3"),
    # 6-8 FNC 61 SER: n = 1-256 (16-bit), 1-128 (32-bit)
    pytest.param("VS3", "SER D0 D10 D20 K256", "SER D0 D10 D20 K257", "E206", id="FNC61-n-16-bit"),
    pytest.param("VS3", "DSER D0 D10 D20 K128", "DSER D0 D10 D20 K129", "E206", id="FNC61-n-32-bit"),
    # 6-8 FNC 62 ABSD: S2 = C0-C199 (16-bit), C200-C255 (32-bit); n = 1-64
    pytest.param("VS3", "ABSD D0 C199 M0 K4", "ABSD D0 C200 M0 K4", "E211", id="FNC62-S2-16-bit"),
    pytest.param("VS3", "DABSD D0 C200 M0 K4", "DABSD D0 C199 M0 K4", "E211", id="FNC62-S2-32-bit"),
    pytest.param("VS3", "ABSD D0 C0 M0 K64", "ABSD D0 C0 M0 K65", "E206", id="FNC62-n-1-64"),
    # 6-8 FNC 63 INCD: S2 = C0-C198 (two counters), n = 1-64
    pytest.param("VS3", "INCD D0 C198 M0 K5", "INCD D0 C199 M0 K5", "E205", id="FNC63-S2-C0-C198"),
    pytest.param("VS3", "INCD D0 C0 M0 K64", "INCD D0 C0 M0 K65", "E206", id="FNC63-n-1-64"),
    # 6-8 FNC 64 TTMR: n = 0-2, D occupies 2
    pytest.param("VS3", "TTMR D0 K2", "TTMR D0 K3", "E206", id="FNC64-n-0-2"),
    # 6-8 FNC 65 STMR: S = T0-T199, m = 1-32767
    pytest.param("VS3", "STMR T199 K20 Y20", "STMR T200 K20 Y20", "E205", id="FNC65-S-T0-T199"),
    pytest.param("VS3", "STMR T0 K1 Y20", "STMR T0 K0 Y20", "E206", id="FNC65-m-1-32767"),
    # 6-8 FNC 66 ALT: D is a bit device
    pytest.param("VS3", "ALT M100", "ALT D0", "E204", id="FNC66-D-bit"),
    # 6-8 FNC 67 RAMP: n = 1-32767, D occupies 2
    pytest.param("VS3", "RAMP D0 D1 D2 K32767", "RAMP D0 D1 D2 K0", "E206", id="FNC67-n-1-32767"),
    # 6-8 FNC 69 SORT: m1 = 1-32, m2 = 1-6, n = 1-6
    pytest.param("VS3", "SORT D0 K32 K6 D200 K6", "SORT D0 K33 K6 D200 K6", "E206", id="FNC69-m1-1-32"),
    pytest.param("VS3", "SORT D0 K5 K6 D100 D200", "SORT D0 K5 K7 D100 D200", "E206", id="FNC69-m2-1-6"),
    # 6-9 FNC 70 TKY: S a bit device (10 inputs), D2 11 bits
    pytest.param("VS3", "TKY X20 D0 M0", "TKY D20 D0 M0", "E204", id="FNC70-S-bits"),
    pytest.param("VS3", "TKY X20 D0 M8181", "TKY X20 D0 M8182", "E205", id="FNC70-D2-11-bits"),
    # 6-9 FNC 71 HKY: S an X, D1 a Y
    pytest.param("VS3", "HKY X20 Y20 D0 M0", "HKY X20 M20 D0 M0", "E204", id="FNC71-D1-is-Y"),
    # 6-9 FNC 72 DSW: n = 1-2
    pytest.param("VS3", "DSW X20 Y20 D0 K2", "DSW X20 Y20 D0 K3", "E206", id="FNC72-n-1-2"),
    # 6-9 FNC 73 SEGD: D a word destination, not an input
    pytest.param("VS3", "SEGD D0 K2Y20", "SEGD D0 K2X20", "E210", id="FNC73-D-written"),
    # 6-9 FNC 74 SEGL: n = 0-7, D a Y
    pytest.param("VS3", "SEGL D0 Y20 K7", "SEGL D0 Y20 K8", "E206", id="FNC74-n-0-7"),
    # 6-9 FNC 76 ASC: S the letters typed in the instruction
    pytest.param("VS3", 'ASC "ABCDEFGH" D0', "ASC D10 D0", "E204", id="FNC76-S-letters"),
    # 6-9 FNC 77 PR: D a Y (10 outputs), S a register
    pytest.param("VS3", "PR D0 Y20", "PR D0 M20", "E204", id="FNC77-D-is-Y"),
    # 6-9 FNC 78/79 FROM/TO: not on VS1; m2 = 0-32767, n = 1-32767
    pytest.param("VS2", "FROM K2 K5 D0 K4", "FROM K2 K5 D0 K0", "E206", id="FNC78-n-1-32767"),
    pytest.param("VS1", "MOV K1 D0", "FROM K2 K5 D0 K4", "E901", id="FNC78-not-on-VS1"),
    pytest.param("VS2", "TO K2 K0 D0 K1", "TO K2 K-1 D0 K1", "E206", id="FNC79-m2-0-32767"),
    pytest.param("VS1", "MOV K1 D0", "TO K2 K0 D0 K1", "E901", id="FNC79-not-on-VS1"),
    # 6-10 FNC 80 RS: m, n = 0-4096
    pytest.param("VS3", "RS D0 K4096 D100 K0 K1", "RS D0 K4097 D100 K0 K1", "E206", id="FNC80-m-n-0-4096"),
    # 6-10 FNC 81 PRUN: S = KnX or KnM, D = KnY or KnM
    pytest.param("VS3", "PRUN K4X20 K4M0", "PRUN D0 K4M0", "E204", id="FNC81-S-KnX-KnM"),
    # 6-10 FNC 82-84 ASCI/HEX/CCD: n = 1-256; CCD D occupies 2
    pytest.param("VS3", "ASCI D0 D100 K256", "ASCI D0 D100 K257", "E206", id="FNC82-n-1-256"),
    pytest.param("VS3", "HEX D100 D0 K256", "HEX D100 D0 K0", "E206", id="FNC83-n-1-256"),
    pytest.param("VS3", "CCD D0 D100 K256", "CCD D0 D100 K257", "E206", id="FNC84-n-1-256"),
    # 6-10 FNC 87 CPUL, 89 LINK, 149 MBUS: S1 a table (Q), S2 a 4-register work area
    pytest.param("VS3", "CPUL Q0 D100 K1", "CPUL D0 D100 K1", "E204", id="FNC87-S1-table"),
    pytest.param("VS3", "LINK Q0 D100 K5", "LINK Q0 D100 K6", "E206", id="FNC89-n-CP1-CP5"),
    pytest.param("VS3", "MBUS Q0 D100 K5", "MBUS Q0 D100 K0", "E206", id="FNC149-n-CP1-CP5"),
    # 6-10 FNC 88 PID: all four operands registers
    pytest.param("VS3", "PID D0 D1 D100 D200", "PID K0 D1 D100 D200", "E204", id="FNC88-registers"),
    # 6-11 FNC 90/91 DBRD/DBWR: address 0-655359, n = 1-32767
    pytest.param("VS3", "DBRD K655359 D1000 K1", "DBRD K655360 D1000 K1", "E206", id="FNC90-S-0-655359"),
    pytest.param("VS3", "DBWR D1000 K0 K32767", "DBWR D1000 K0 K32768", "E206", id="FNC91-n-1-32767"),
    # 6-11 FNC 92 TPID: n = 1-16
    pytest.param("VS3", "TPID D7000 D0 D100 D7100 K16", "TPID D7000 D0 D100 D7100 K17", "E206",
                 id="FNC92-n-1-16"),
    # 6-11 FNC 93 DTRD: S1 a table pointer or name
    pytest.param("VS3", "DTRD Q0 K0 D1000 K100", "DTRD D0 K0 D1000 K100", "E204", id="FNC93-S1-table"),
    # 6-11 FNC 102/103 ZPUSH/ZPOP: VS3 only
    pytest.param("VS2", "MOV K0 D0", "ZPUSH D0", "E901", id="FNC102-VS3-only"),
    pytest.param("VS2", "MOV K0 D0", "ZPOP D0", "E901", id="FNC103-VS3-only"),
    # 6-12 FNC 110-137: 32-bit only ("must be written DECMP ..."); D a register pair
    pytest.param("VS3", "DECMP D0 D10 M0", "ECMP D0 D10 M0", "E201", id="FNC110-32-bit-only"),
    pytest.param("VS3", "DEZCP D0 D2 D10 M0", "EZCP D0 D2 D10 M0", "E201", id="FNC111-32-bit-only"),
    pytest.param("VS3", "DEMOV D0 D10", "EMOV D0 D10", "E201", id="FNC112-32-bit-only"),
    pytest.param("VS3", "DESTR D20 D10 D0", "ESTR D20 D10 D0", "E201", id="FNC116-32-bit-only"),
    pytest.param("VS2", "DEMOV D0 D10", "DESTR D20 D10 D0", "E901", id="FNC116-VS3-only"),
    pytest.param("VS3", "DEVAL D0 D100", "EVAL D0 D100", "E201", id="FNC117-32-bit-only"),
    pytest.param("VS2", "DEMOV D0 D10", "DEVAL D0 D100", "E901", id="FNC117-VS3-only"),
    pytest.param("VS3", "DEBCD D0 D10", "EBCD D0 D10", "E201", id="FNC118-32-bit-only"),
    pytest.param("VS3", "DEBIN D2 D12", "EBIN D2 D12", "E201", id="FNC119-32-bit-only"),
    pytest.param("VS3", "DEADD D0 D2 D10", "DEADD D0 D2 K4M0", "E204", id="FNC120-D-register"),
    pytest.param("VS3", "DESUB D0 D2 D10", "ESUB D0 D2 D10", "E201", id="FNC121-32-bit-only"),
    pytest.param("VS3", "DEMUL D0 D2 D10", "EMUL D0 D2 D10", "E201", id="FNC122-32-bit-only"),
    pytest.param("VS3", "DEDIV D0 D2 D10", "EDIV D0 D2 D10", "E201", id="FNC123-32-bit-only"),
    pytest.param("VS3", "DEXP D0 D10", "EXP D0 D10", "E201", id="FNC124-32-bit-only"),
    pytest.param("VS3", "DLOGE D0 D10", "LOGE D0 D10", "E201", id="FNC125-32-bit-only"),
    pytest.param("VS3", "DLOG10 D0 D10", "LOG10 D0 D10", "E201", id="FNC126-32-bit-only"),
    pytest.param("VS3", "DESQR D0 D10", "ESQR D0 D10", "E201", id="FNC127-32-bit-only"),
    pytest.param("VS3", "DENEG D0", "ENEG D0", "E201", id="FNC128-32-bit-only"),
    pytest.param("VS3", "DINT D0 D10", "INT D0 K4M0", "E204", id="FNC129-D-register"),
    pytest.param("VS3", "DSIN D0 D10", "SIN D0 D10", "E201", id="FNC130-32-bit-only"),
    pytest.param("VS3", "DCOS D0 D10", "COS D0 D10", "E201", id="FNC131-32-bit-only"),
    pytest.param("VS3", "DTAN D0 D10", "TAN D0 D10", "E201", id="FNC132-32-bit-only"),
    pytest.param("VS3", "DASIN D0 D10", "ASIN D0 D10", "E201", id="FNC133-32-bit-only"),
    pytest.param("VS3", "DACOS D0 D10", "ACOS D0 D10", "E201", id="FNC134-32-bit-only"),
    pytest.param("VS3", "DATAN D0 D10", "ATAN D0 D10", "E201", id="FNC135-32-bit-only"),
    pytest.param("VS3", "DRAD D0 D10", "RAD D0 D10", "E201", id="FNC136-32-bit-only"),
    pytest.param("VS3", "DDEG D0 D10", "DEG D0 D10", "E201", id="FNC137-32-bit-only"),
    # 6-13 FNC 140-144: VS3 only; UNI/DIS n = 0-4
    pytest.param("VS2", "MOV K0 D0", "WSUM D10 D100 K5", "E901", id="FNC140-VS3-only"),
    pytest.param("VS2", "MOV K0 D0", "WTOB D10 D20 K5", "E901", id="FNC141-VS3-only"),
    pytest.param("VS2", "MOV K0 D0", "BTOW D10 D20 K5", "E901", id="FNC142-VS3-only"),
    pytest.param("VS3", "UNI D10 D20 K4", "UNI D10 D20 K5", "E206", id="FNC143-n-0-4"),
    pytest.param("VS3", "DIS D10 D20 K4", "DIS D10 D20 K5", "E206", id="FNC144-n-0-4"),
    # 6-13 FNC 147 SWAP: S is written back (not a constant)
    pytest.param("VS3", "SWAP D0", "SWAP K5", "E210", id="FNC147-S-written"),
    # ---- the pages' operand notes beyond kinds and ranges (targets/vs/operand_rules.toml)
    pytest.param("VS3", "REF X10 K8", "REF X10 K16", "E232", id="FNC50-n-by-D"),
    pytest.param("VS3", 'ASC "ABCDEFGH" D0', 'ASC "ABCDEFGHI" D0', "E206", id="FNC76-up-to-8-letters"),
    pytest.param("VS3", "TKY X360 D0 M0", "TKY X370 D0 M0", "E208", id="FNC70-S-10-points"),
    pytest.param("VS3", "HKY X374 Y20 D0 M0", "HKY X375 Y20 D0 M0", "E208", id="FNC71-S-4-points"),
    pytest.param("VS3", "DSW X374 Y374 D0 K1", "DSW X20 Y375 D0 K1", "E208", id="FNC72-D1-4-points"),
    pytest.param("VS3", "SEGL D0 Y370 K0", "SEGL D0 Y371 K0", "E208", id="FNC74-D-8-points"),
    pytest.param("VS3", "MTR X20 Y20 M0 K2", "MTR X21 Y20 M0 K2", "E230", id="FNC52-S-ends-in-0"),
    pytest.param("VS3", "MTR X20 Y10 M10 K2", "MTR X20 Y10 M15 K2", "E230", id="FNC52-D2-ends-in-0"),
    pytest.param("VS3", "DHSCR K200 C235 C235", "DHSCR K200 C235 C236", "E232", id="FNC54-D-is-S2"),
    pytest.param("VS3", "DHSZ K100 K200 C255 Y5", "DHSZ K100 K200 C255 Y6", "E205", id="FNC55-D-Y0-Y5"),
    pytest.param("VS3", "PLSY K500 K0 Y0", "PLSY K500 K-1 Y0", "E206", id="FNC57-S2-not-negative"),
    pytest.param("VS3", "PWM K0 K1 Y0", "PWM K0 K0 Y0", "E206", id="FNC58-T-1-32767"),
    pytest.param("VS3", "PWM K100 K100 Y0", "PWM K101 K100 Y0", "E232", id="FNC58-t-not-above-T"),
    pytest.param("VS3", "PLSR K1000 K1 K100 Y0", "PLSR K1000 K0 K100 Y0", "E206", id="FNC59-S2-positive"),
    pytest.param("VS3", "ABSD K4M8 C0 M100 K4", "ABSD K4M4 C0 M100 K4", "E231", id="FNC62-S1-K4-at-8"),
    pytest.param("VS3", "DABSD K8M0 C200 M100 K4", "DABSD K4M0 C200 M100 K4", "E231", id="FNC62-S1-K8"),
    pytest.param("VS3", "INCD K4X0 C0 M0 K5", "INCD K2X0 C0 M0 K5", "E231", id="FNC63-S1-K4"),
    pytest.param("VS2", "FROM K8 K5 D0 K4", "FROM K9 K5 D0 K4", "E206", id="FNC78-m1-per-model"),
    pytest.param("VS2", "TO K8 K0 D0 K1", "TO K9 K0 D0 K1", "E206", id="FNC79-m1-per-model"),
    pytest.param("VS1", "RS D0 K0 D100 K0 K2", "RS D0 K0 D100 K0 K3", "E206", id="FNC80-n1-per-model"),
    pytest.param("VS2", "RS D0 K0 D100 K0 K3", "RS D0 K0 D100 K0 K4", "E206", id="FNC80-n1-VS2"),
    pytest.param("VS3", "PRUN K4X20 K4M0", "PRUN K4X21 K4M0", "E230", id="FNC81-ends-in-0"),
    pytest.param("VS3", "PRUN K4X20 K4M0", "PRUN K4X20 K4Y20", "E232", id="FNC81-KnX-to-KnM"),
    pytest.param("VS3", "PRUN K4M0 K4Y20", "PRUN K4M0 K4M20", "E232", id="FNC81-KnM-to-KnY"),
    pytest.param("VS3", "ASCI K4M0 D100 K4", "ASCI K2M0 D100 K4", "E231", id="FNC82-K4"),
    pytest.param("VS3", "HEX D100 K4M0 K4", "HEX D100 K2M0 K4", "E231", id="FNC83-K4"),
    pytest.param("VS3", "CCD K4M0 D100 K2", "CCD K3M0 D100 K2", "E231", id="FNC84-K4"),
    pytest.param("VS1", "CPUL Q0 D100 K2", "CPUL Q0 D100 K3", "E206", id="FNC87-n-per-model"),
    pytest.param("VS1", "LINK Q0 D100 K2", "LINK Q0 D100 K3", "E206", id="FNC89-n-per-model"),
    pytest.param("VS3", "WSUM D10 D100 K1", "WSUM D10 D100 K0", "E206", id="FNC140-n-positive"),
    pytest.param("VS3", "SORT2 D0 K32 K6 D200 K6", "SORT2 D0 K33 K6 D200 K6", "E206", id="FNC148-m1-1-32"),
    pytest.param("VS3", "SORT2 D0 K5 K6 D100 D200", "SORT2 D0 K5 K7 D100 D200", "E206", id="FNC148-m2-1-6"),
    pytest.param("VS3", "SORT2 D0 K5 K4 D0 D200", "SORT2 D0 K5 K4 D10 D200", "E234", id="FNC148-blocks-apart"),
    pytest.param("VS2", "MBUS Q0 D100 K3", "MBUS Q0 D100 K4", "E206", id="FNC149-n-per-model"),
]


@pytest.mark.parametrize("model, legal, illegal, code", CHECKS)
def test_operand_rule_is_checked(model, legal, illegal, code):
    assert [c for c, _ in found(program(legal), model) if c[0] == "E"] == []
    assert (code, 2) in found(program(illegal), model), found(program(illegal), model)


# once per program (E904): the page says "只能使用一次"
ONCE = [
    pytest.param("MTR X20 Y20 M0 K2", id="FNC52-once"),
    pytest.param("SORT D0 K5 K4 D100 D200", id="FNC69-once"),
    pytest.param("HKY X20 Y20 D0 M0", id="FNC71-once"),
    pytest.param("DSW X20 Y20 D0 K1", id="FNC72-once"),
    pytest.param("SEGL D0 Y20 K0", id="FNC74-once"),
    pytest.param("PR D0 Y20", id="FNC77-once"),
]


@pytest.mark.parametrize("line", ONCE)
def test_once_per_program(line):
    assert ("E904", 4) not in found(program(line))
    assert ("E904", 4) in found(program(line, line))


# devices only one instruction may use: (first line, a second line that is legal, one that is
# not, the code the illegal one gets at line 4)
SHARED = [
    pytest.param("PWM D0 K100 Y0", "PWM D1 K100 Y1", "PWM D1 K100 Y0", "E233", id="FNC58-one-PWM-a-Y"),
    pytest.param("PWM D0 K100 Y1", "PLSY K500 D100 Y0", "PLSY K500 D100 Y1", "E233", id="FNC58-not-with-PLSY"),
    pytest.param("PWM D0 K100 Y2", "DPLSR K1000 D100 K100 Y3", "DPLSR K1000 D100 K100 Y2", "E233",
                 id="FNC58-not-with-PLSR"),
    pytest.param("PWM D0 K100 Y3", "DDRVA K1000 K500 Y0 Y3", "DDRVA K1000 K500 Y3 Y7", "E233",
                 id="FNC58-not-with-positioning"),
    pytest.param("SPD X2 K100 D0", "SPD X3 K100 D10", "SPD X2 K100 D10", "E235", id="FNC56-one-SPD-an-input"),
    pytest.param("OUT C235 K100", "SPD X1 K100 D0", "SPD X0 K100 D0", "E235", id="FNC56-not-a-counter-input"),
    pytest.param("DHSZ K1 K2 C251 M0", "SPD X2 K100 D0", "SPD X1 K100 D0", "E235", id="FNC56-not-an-AB-input"),
    pytest.param("STMR T0 K20 Y20", "OUT T1 K10", "OUT T0 K10", "W230", id="FNC65-own-timer"),
    pytest.param("STMR T5 K20 Y20", "MOV T6 D0", "MOV T5 D0", "W230", id="FNC65-own-timer-read"),
]


@pytest.mark.parametrize("first, legal, illegal, code", SHARED)
def test_device_of_one_instruction(first, legal, illegal, code):
    assert [c for c, _ in found(program(first, legal)) if c in ("E233", "W230")] == []
    assert (code, 4) in found(program(first, illegal)), found(program(first, illegal))


def test_spd_input_is_no_interrupt_input():
    # 6-7 FNC 56: SPD X1 with an interrupt routine IX1P on the same input; IX2P is fine
    il = "LD X20\nSPD X1 K100 D0\nFEND\n{}:\nIRET\nEND\n"
    assert ("E235", 2) in found(il.format("IX1P"))
    assert [c for c, _ in found(il.format("IX2P")) if c[0] == "E"] == []


def test_zpush_zpop_in_pairs():
    # 6-11 FNC 102/103: "兩個指令必須配對使用"
    assert [c for c, _ in found(program("ZPUSH D0", "ZPOP D0")) if c == "W231"] == []
    assert ("W231", 2) in found(program("ZPUSH D0", "MOV K0 D0"))
    assert ("W231", 4) in found(program("MOV K0 D0", "ZPOP D0"))


def test_rs_send_request_is_not_reset_by_the_program():
    # 6-10 FNC 80: "M9100在資料傳送結束後會自動變為OFF，請不要用程序RST M9100"
    rs = "RS D0 D200 D100 D201 K1"
    assert ("W232", 4) in found(program(rs, "RST M9100"))
    assert ("W232", 4) in found(program(rs, "RST M9120"))
    assert [c for c, _ in found(program(rs, "RST M9101")) if c == "W232"] == []  # the receive flag: reset it
    assert [c for c, _ in found(program("MOV K0 D0", "RST M9100")) if c == "W232"] == []  # no RS


# ------------------------------------------------------------------ run-time rules

# (program without END, stimulus with expectations, whether an operation error is expected)
RUNS = [
    # 6-8 FNC 66 ALT: the page's example ALTP M100: odd presses On, even presses Off
    pytest.param("LDP X20\nALT M100\nLD M100\nOUT Y20\nLDI M100\nOUT Y21\n",
                 "0ms X20=1\n0ms expect M100=1 Y20=1 Y21=0\n10ms expect M100=1\n20ms X20=0\n"
                 "30ms X20=1\n30ms expect M100=0 Y20=0 Y21=1\n", False, id="FNC66-alternates"),
    # 6-7 FNC 51 REFF: n goes to D9020 (10 at power-on); a register n above 60 is an operation error
    pytest.param("LD X20\nREFF K1\nLD X21\nREFF D0\n",
                 "0ms expect D9020=10\n10ms X20=1\n10ms expect D9020=1\n20ms X20=0 X21=1 D0=61\n"
                 "20ms expect D9020=1 M9067=1\n", True, id="FNC51-D9020"),
    # 6-7 FNC 57 PLSY: S1 below 1 is 1 Hz, above the model's maximum (VS3: 200 kHz) the maximum
    pytest.param("LD X20\nDPLSY D0 K0 Y0\nLD X20\nPLSY D2 K0 Y1\n",
                 "0ms D0:d=300000 D2=0 X20=1\n0ms expect D9350:d=200000 D9370:d=1\n", False,
                 id="FNC57-S1-clamped"),
    # 6-8 FNC 64 TTMR n = 2: D0 = D1 x 100
    pytest.param("LD X20\nTTMR D0 K2\n", "0ms X20=1\n3s expect D1=3 D0=300\n", False, id="FNC64-n-times"),
    # 6-12 FNC 110 DECMP: the page's example; X0 Off keeps M0-M2
    pytest.param("LD X0\nDECMP D0 D10 M0\n",
                 "0ms D0:f=2.5 D10:f=1.5 X0=1\n0ms expect M0=1 M1=0 M2=0\n10ms D0:f=1.5\n"
                 "10ms expect M0=0 M1=1 M2=0\n20ms X0=0 D0:f=-1\n20ms expect M0=0 M1=1 M2=0\n",
                 False, id="FNC110-compare-and-hold"),
    # 6-12 FNC 110-123: a K/H source is converted to float first
    pytest.param("LD X0\nDEADD K1 K2 D0\nDECMP K3 D0 M0\nDEMOV K7 D4\n",
                 "0ms X0=1\n0ms expect D0:f=3 M1=1 D4:f=7\n", False, id="FNC120-K-to-float"),
    # 6-12 FNC 123 DEDIV: divisor 0 is an operation error, D unchanged
    pytest.param("LD X0\nDEDIV D0 D2 D10\n", "0ms D0:f=1 D2:f=0 D10:f=5 X0=1\n"
                 "0ms expect D10:f=5 M9067=1 D9067=6706\n", True, id="FNC123-divide-by-0"),
    # 6-12 FNC 127 DESQR: zero result turns M9020 On
    pytest.param("LD X0\nDESQR D0 D10\n", "0ms D0:f=0 D10:f=5 X0=1\n0ms expect D10:f=0 M9020=1\n"
                 "10ms D0:f=16\n10ms expect D10:f=4 M9020=0\n", False, id="FNC127-zero-flag"),
    # 6-12 FNC 129 INT: fraction dropped -> M9021, 0 -> M9020, out of range -> M9022
    pytest.param("LD X0\nINT D0 D10\nLD X1\nDINT D2 D12\n",
                 "0ms D0:f=123.45 X0=1\n0ms expect D10=123 M9021=1 M9020=0 M9022=0\n"
                 "10ms D0:f=0.5\n10ms expect D10=0 M9020=1 M9021=1\n"
                 "20ms D0:f=40000 D10=7\n20ms expect D10=7 M9022=1\n"
                 "30ms X0=0 X1=1 D2:f=123456.7\n30ms expect D12:d=123456 M9021=1\n",
                 False, id="FNC129-flags"),
    # 6-12 FNC 136/137 DRAD/DDEG: degrees x pi / 180 and back
    pytest.param("LD X0\nDRAD D0 D10\nDDEG D10 D12\n",
                 "0ms D0:f=180 X0=1\n0ms expect D10:f=3.141592..3.141593 D12:f=179.9999..180.0001\n",
                 False, id="FNC136-degrees-radians"),
    # 6-12 FNC 117 DEVAL: a zero result turns M9020 On
    pytest.param("LD X0\nDEVAL D0 D100\n", "0ms D0:h=H3020 D1:h=H0030 D100:f=9 X0=1\n"
                 "0ms expect D100:f=0 M9020=1\n", False, id="FNC117-zero-flag"),
    # 6-13 FNC 142-144: n = 0: not executed
    pytest.param("LD X0\nBTOW D10 D20 K0\nUNI D10 D30 K0\nDIS D10 D40 K0\n",
                 "0ms D10:h=H1234 D20=5 D30=6 D40=7 X0=1\n0ms expect D20=5 D30=6 D40=7\n",
                 False, id="FNC142-n-0-not-executed"),
    # 6-13 FNC 147 SWAP: the page's examples SWAPP D0 and DSWAP D10
    pytest.param("LDP X20\nSWAP D0\nLD X21\nDSWAP D10\n",
                 "0ms D0:h=H00FF D10:h=H1234 D11:h=H5678 X20=1 X21=1\n"
                 "0ms expect D0:h=HFF00 D10:h=H3412 D11:h=H7856\n", False, id="FNC147-bytes-swapped"),
    # 6-10 FNC 83 HEX: a character that is no 0-9/A-F is an operation error, D unchanged
    pytest.param("LD X21\nHEX D100 D0 K4\n", "0ms D100:h=H3031 D101:h=H3247 D0=5 X21=1\n"
                 "0ms expect D0=5 M9067=1 D9067=6706\n", True, id="FNC83-not-hex"),
    # 6-10 FNC 82 ASCI: M9161 On puts one character a register
    pytest.param("LD X20\nASCI D0 D100 K4\n", "0ms D0:h=H4567 M9161=1 X20=1\n"
                 "0ms expect D100:h=H34 D101:h=H35 D102:h=H36 D103:h=H37\n", False, id="FNC82-eight-bit"),
    # 6-9 FNC 76 ASC: M9161 On puts one letter a register
    pytest.param('LD X20\nASC "AB" D0\n', "0ms M9161=1 X20=1\n0ms expect D0:h=H41 D1:h=H42 D2:h=H20 "
                 "D7:h=H20\n", False, id="FNC76-eight-bit"),
    # 6-9 FNC 76 ASC: fewer than 8 letters are filled up with spaces (20H)
    pytest.param('LD X20\nASC "ABC" D0\n', "0ms D1=0 D3=0 D4=9 X20=1\n"
                 "0ms expect D0:h=H4241 D1:h=H2043 D2:h=H2020 D3:h=H2020 D4=9\n", False, id="FNC76-space-filled"),
    # 6-13 FNC 148 SORT2: only two execute together; a third starts when one is done
    pytest.param("LD X0\nSORT2 D0 K2 K1 D10 K1\nSORT2 D0 K2 K1 D20 K1\nSORT2 D0 K2 K1 D30 K1\n",
                 "0ms D0=5 D1=3 X0=1\n10ms expect D10=3 D11=5 D20=3 D21=5 D30=0\n20ms expect D30=3 D31=5\n",
                 False, id="FNC148-two-at-once"),
    # 6-13 FNC 148 SORT2: S and D blocks overlapping (not the same): DECISION operation error
    pytest.param("LD X0\nSORT2 D0 D100 K1 D1 K1\n", "0ms D0=5 D1=3 D100=2 X0=1\n"
                 "10ms expect D1=3 D2=0 M9067=1\n", True, id="FNC148-overlap-at-run-time"),
    # 6-12 FNC 117 DEVAL: a result below 2^-126 turns M9021 On
    pytest.param("LD X0\nDEVAL D0 D100\n", "0ms D0:h=H4531 D1:h=H342D D2:h=H0035 X0=1\n"
                 "0ms expect M9021=1 M9020=0\n", False, id="FNC117-borrow-flag"),
    # 6-7 FNC 57 PLSY: S2 changed while running is ignored ("S2之變更則視為無效")
    pytest.param("LD X20\nPLSY K1000 D0 Y0\n", "0ms D0=100 X20=1\n50ms D0=1000\n"
                 "200ms expect D9352:d=100 M9342=1\n", False, id="FNC57-S2-read-at-start"),
    # 6-7 FNC 59 PLSR: S3 above 32000 ms is 32000 (1000 Hz / 32 s: 31 Hz after 1 s), below 0 is 0
    pytest.param("LD X20\nDPLSR K1000 K30000 D0 Y0\nLD X21\nPLSR K1000 K30000 D2 Y1\n",
                 "0ms D0:d=40000 D2=-5 X20=1 X21=1\n0ms expect D9370:d=1000\n1s expect D9350:d=31\n",
                 False, id="FNC59-S3-clamped"),
    # 6-7 FNC 58 PWM: t > T is an operation error (6-7 page)
    pytest.param("LD X20\nPWM D0 K100 Y0\n", "0ms D0=101 X20=1\n10ms expect Y0=0 M9067=1\n",
                 True, id="FNC58-t-above-T"),
    # 6-7 FNC 59 PLSR: S2 <= 0 is an operation error
    pytest.param("LD X20\nPLSR K1000 D100 K100 Y0\n", "0ms D100=0 X20=1\n10ms expect Y0=0 M9067=1\n",
                 True, id="FNC59-S2-not-positive"),
    # 6-7 FNC 53: more than 8 compares active together is an operation error
    pytest.param("LD M9000\n" + "".join(f"DHSZ K{100 + k} K500 C235 M{3 * k}\n" for k in range(9)),
                 "0ms expect M9067=1\n", True, id="FNC53-eight-active"),
    # 6-7 FNC 53: a value written by MOV is not compared (no count input, no output)
    pytest.param("LD M9000\nOUT C235 K5000\nLD X20\nDHSCS K200 C235 Y0\nLDP X21\nDMOV K200 C235\n",
                 "0ms X20=1\n10ms X21=1\n20ms expect C235:d=200 Y0=0\n", False, id="FNC53-no-count-no-compare"),
]


@pytest.mark.parametrize("il, stim, alarms", RUNS)
def test_page_rule_runs(il, stim, alarms):
    r = run(il, stim, alarms=alarms)
    assert bool(r.alarms) is alarms
