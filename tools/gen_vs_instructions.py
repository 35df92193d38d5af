"""Generate mlctool/targets/vs/instructions.toml from the structured reading of the Vigor VS
manual (../shared/notes/vs_instructions.json) plus the rules below, each marked with its source.

Run once by hand when the rules change; the generated TOML is the reviewed artefact.
    python3 tools/gen_vs_instructions.py > mlctool/targets/vs/instructions.toml
    (from a worktree: VS_NOTES=/work/shared/notes/vs_instructions.json python3 tools/...)
"""

from __future__ import annotations

import json
import os
import sys
from pathlib import Path

# ../shared/notes beside the checkout (/work/main -> /work/shared); a worktree elsewhere names
# it with VS_NOTES=/path/to/vs_instructions.json.
NOTES = Path(os.environ.get("VS_NOTES") or Path(__file__).resolve().parents[2] / "shared" / "notes" / "vs_instructions.json")

# Operand device kinds by role. SOURCE: general operand rules of 5-1/5-2 (the per-page
# device matrices were lost in the text extraction): K/H are sources only; T/C mean present
# values; D.b R.b V Z are not indexable; float instructions convert K/H to float.
WS = "K H KnX KnY KnM KnS T C D R V Z"  # word source
WD = "KnY KnM KnS T C D R V Z"  # word destination
CNT = "K H D R"  # counts and modes ("m, n: constants that may also be registers")
BS = "X Y M S"  # bit source
BD = "Y M S"  # bit destination
FS = "K H E D R"  # float source
FD = "D R"  # float destination
STRS = "$ D R"  # string source
STRD = "D R"

GENERAL = "rule 5-1/5-2 (matrix lost)"


def op(role, kinds, access="r", **extra):
    d = {"role": role, "kinds": kinds}
    if access != "r":
        d["access"] = access
    d.update(extra)
    return d


# Per-instruction operands where the role default (S* source, D* destination, m*/n* count)
# does not say enough; ranges are the notes printed under each page's matrix.
def n(role="n", lo=None, hi=None, lo32=None, hi32=None, kinds=CNT):
    e = {}
    if lo is not None:
        e["range"] = [lo, hi]
    if lo32 is not None:
        e["range32"] = [lo32, hi32]
    return op(role, kinds, **e)


Y03 = {"Y": [[0, 3]]}
HSC = {"C": [[235, 255]]}
POS = [op("S1", WS), op("S2", WS), op("D1", "Y", "w", ranges=Y03), op("D2", BD, "w", ranges={"Y": [[0, 7]]})]
ROT = [op("D", WD, "rw"), n(lo=0, hi=16, lo32=0, hi32=32, kinds="K H")]
CMP3 = [op("S1", WS), op("S2", WS), op("D", BD, "w", bits=3)]

OPERANDS = {
    "CJ": [op("S", "P")], "CALL": [op("S", "P")],
    "FOR": [op("S", WS)],
    # 16x16 -> 32-bit product / quotient + remainder in (D, D+1); 32-bit: four words (6-4 notes)
    "MUL": [op("S1", WS), op("S2", WS), op("D", WD, "w", words=[2, 4])],
    "DIV": [op("S1", WS), op("S2", WS), op("D", WD, "w", words=[2, 4])],
    # BCD: S = 0-9,999 (32-bit 0-99,999,999), "超出...的範圍，則PLC認定為運算錯誤" (6-3)
    "BCD": [op("S", WS, range=[0, 9999], range32=[0, 99999999]), op("D", WD, "w")],
    "CMP": CMP3, "ZCP": [op("S1", WS), op("S2", WS), op("S", WS), op("D", BD, "w", bits=3)],
    "SMOV": [op("S", WS), n("m1", 1, 4, kinds="K H"), n("m2", 1, 4, kinds="K H"), op("D", WD, "w"),
             n("n", 1, 4, kinds="K H")],
    "BMOV": [op("S", WS), op("D", WD, "w"), n(lo=1, hi=512)],
    "FMOV": [op("S", WS), op("D", WD, "w"), n(lo=1, hi=512)],
    "XCH": [op("D1", WD, "rw"), op("D2", WD, "rw")],
    "INC": [op("D", WD, "rw")], "DEC": [op("D", WD, "rw")], "NEG": [op("D", WD, "rw")],
    "ROR": ROT, "ROL": ROT, "RCR": ROT, "RCL": ROT,
    "SFTR": [op("S", BS), op("D", BD, "w"), n("n1", 1, 1024), n("n2", 1, 1024)],
    "SFTL": [op("S", BS), op("D", BD, "w"), n("n1", 1, 1024), n("n2", 1, 1024)],
    "WSFR": [op("S", WS), op("D", WD, "w"), n("n1", 1, 512), n("n2", 1, 512)],
    "WSFL": [op("S", WS), op("D", WD, "w"), n("n1", 1, 512), n("n2", 1, 512)],
    # the file of n points: the pointer, then n-1 data (6-5 FNC 38/39)
    "SFWR": [op("S", WS), op("D", WD, "rw", span="n"), n(lo=2, hi=512)],
    "SFRD": [op("S", WD, "rw", span="n"), op("D", WD, "w"), n(lo=2, hi=512)],
    "ZRST": [op("D1", "Y M S T C D R", "w"), op("D2", "Y M S T C D R", "w")],
    # the low n bits of S decoded into 2^n bits of D; ENCO the reverse (6-6 FNC 41/42): a bit
    # device S covers n bits (DECO) or 2^n (ENCO), a bit device D 2^n; a word one word
    "DECO": [op("S", "X Y M S K H T C D R V Z", span="n", span_kinds="bit"),
             op("D", "Y M S T C D R", "w", span="2^n", span_kinds="bit"),
             op("n", "K H", range=[1, 8], word_range=[1, 4], word_range_of="D")],
    "ENCO": [op("S", "X Y M S T C D R V Z", span="2^n", span_kinds="bit"), op("D", "T C D R V Z", "w"),
             op("n", "K H", range=[1, 8], word_range=[1, 4], word_range_of="S")],
    "BON": [op("S", WS), op("D", BD, "w"), n(lo=0, hi=15, lo32=0, hi32=31)],
    "MEAN": [op("S", "KnX KnY KnM KnS T C D R"), op("D", WD, "w"), n(lo=1, hi=64)],
    # SQR: S = 0-32767 (32-bit 0-2147483647) (6-6)
    "SQR": [op("S", WS, range=[0, 32767], range32=[0, 2147483647]), op("D", WD, "w")],
    "ANS": [op("S", "T", ranges={"T": [[0, 199]]}), n("m", 1, 32767, kinds="K H"),
            op("D", "S", "w", ranges={"S": [[900, 999]]})],
    "REF": [op("D", "X Y", ranges={"X": [[0, 0], [8, 8]], "Y": [[0, 0]]}), n(lo=8, hi=16, kinds="K H")],
    "REFF": [n(lo=0, hi=60)],
    # S occupies 8 inputs (6-7 FNC 52 note)
    "MTR": [op("S", "X", bits=8), op("D1", "Y", "w"), op("D2", BD, "w"), n(lo=2, hi=8, kinds="K H")],
    # D: Y0-Y7 or an interrupt pointer IHC0-IHC7 (I10-I80, target.toml [interrupts]) (6-7 note)
    "DHSCS": [op("S1", WS), op("S2", "C", ranges=HSC),
              op("D", "Y I", "w", ranges={"Y": [[0, 7]], "I": [[10, 80]]})],
    "DHSCR": [op("S1", WS), op("S2", "C", ranges=HSC), op("D", "Y C", "w", ranges={"Y": [[0, 7]], **HSC})],
    "DHSZ": [op("S1", WS), op("S2", WS), op("S", "C", ranges=HSC), op("D", BD, "w", bits=3, ranges={"Y": [[0, 5]]})],
    "SPD": [op("S1", "X", ranges={"X": [[0, 7]]}), op("S2", WS), op("D", "T C D R V Z", "w", words=[3, 6])],
    # S2 = 0-32767 (16-bit), 0-2147483647 (32-bit); below 0 an operation error (6-7 note)
    "PLSY": [op("S1", WS), op("S2", WS, range=[0, 32767], range32=[0, 2147483647]), op("D", "Y", "w", ranges=Y03)],
    "PWM": [op("S1", WS), op("S2", WS, range=[1, 32767]), op("D", "Y", "w", ranges=Y03)],
    "PLSR": [op("S1", WS), op("S2", WS, range=[1, 32767], range32=[1, 2147483647]), op("S3", WS),
             op("D", "Y", "w", ranges=Y03)],
    "SER": [op("S1", "KnX KnY KnM KnS T C D R"), op("S2", WS), op("D", WD, "w", words=[5, 10]),
            n(lo=1, hi=256, lo32=1, hi32=128)],
    # n points: S1 a table of n (on, off) pairs (ABSD) or n values (INCD), D n outputs (6-7)
    "ABSD": [op("S1", "KnX KnY KnM KnS T C D R", words=[2, 4], span="n"),
             op("S2", "C", devices16=[0, 199], devices32=[200, 255]), op("D", BD, "w", span="n"), n(lo=1, hi=64)],
    "INCD": [op("S1", "KnX KnY KnM KnS T C D R", span="n"), op("S2", "C", ranges={"C": [[0, 198]]}),
             op("D", BD, "w", span="n"), n(lo=1, hi=64)],
    "TTMR": [op("D", "D R", "rw", words=[2, 4]), n(lo=0, hi=2, kinds="K H")],
    "STMR": [op("S", "T", ranges={"T": [[0, 199]]}), n("m", 1, 32767, kinds="K H"), op("D", BD, "w", bits=4)],
    "ALT": [op("D", BD, "rw")],
    "RAMP": [op("S1", "D R"), op("S2", "D R"), op("D", "D R", "rw", words=[2, 4]), n(lo=1, hi=32767)],
    "SORT": [op("S", "D R"), n("m1", 1, 32, kinds="K H"), n("m2", 1, 6, kinds="K H"), op("D", "D R", "w"),
             n("n", 1, 6)],
    # points occupied (6-9 notes): TKY S 10; HKY S 4, D1 4, D3 8; DSW S 4 (8 for n = 2), D1 4;
    # SEGL D 8 (12 for n = 4-7): the smaller extent where it depends on n
    "TKY": [op("S", BS, bits=10), op("D1", WD, "w"), op("D2", BD, "w", bits=11)],
    "HKY": [op("S", "X", bits=4), op("D1", "Y", "w", bits=4), op("D2", WD, "w"), op("D3", BD, "w", bits=8)],
    "DSW": [op("S", "X", bits=4), op("D1", "Y", "w", bits=4), op("D2", WD, "w"), n(lo=1, hi=2, kinds="K H")],
    "SEGL": [op("S", WS), op("D", "Y", "w", bits=8), n(lo=0, hi=7, kinds="K H")],
    "ASC": [op("S", "$"), op("D", "T C D R", "w", words=[4, 4])],  # 8 characters, 4 words (6-9)
    "PR": [op("S", "T C D R"), op("D", "Y", "w", bits=10)],
    # n words (32-bit: n pairs) from the module's buffer memory into D / from S (6-9)
    "FROM": [n("m1", 1, 16), n("m2", 0, 32767), op("D", WD, "w", span="n"), n(lo=1, hi=32767)],
    "TO": [n("m1", 1, 16), n("m2", 0, 32767), op("S", WS, span="n"), n(lo=1, hi=32767)],
    "RS": [op("S", "D R"), n("m", 0, 4096), op("D", "D R", "w"), n(lo=0, hi=4096), n("n1", 1, 5, kinds="K H")],
    "PRUN": [op("S", "KnX KnM"), op("D", "KnY KnM", "w")],
    "ASCI": [op("S", WS), op("D", WD, "w"), n(lo=1, hi=256)],
    "HEX": [op("S", WS), op("D", WD, "w"), n(lo=1, hi=256)],
    "CCD": [op("S", "KnX KnY KnM KnS T C D R"), op("D", "T C D R", "w", words=[2, 4]), n(lo=1, hi=256)],
    "CPUL": [op("S1", "Q"), op("S2", "D R", "rw"), n(lo=1, hi=5, kinds="K H")],
    # S3 the parameter block: 20 registers (25 with the output limits, known at run time) (6-10)
    "PID": [op("S1", "D R"), op("S2", "D R"), op("S3", "D R", "rw", words=[20, 20]), op("D", "D R", "w")],
    "LINK": [op("S1", "Q"), op("S2", "D R", "rw"), n(lo=1, hi=5, kinds="K H")],
    "MBUS": [op("S1", "Q"), op("S2", "D R", "rw"), n(lo=1, hi=5, kinds="K H")],
    "DBRD": [op("S", WS, range=[0, 655359], words=[2, 2]), op("D", "D R", "w"), n(lo=1, hi=32767)],
    "DBWR": [op("S", "D R"), op("D", WS, range=[0, 655359], words=[2, 2]), n(lo=1, hi=32767)],
    # n loops: S1/S2 n set and present values, S3 10 common + 10 a loop, S4 6 a loop (6-11)
    "TPID": [op("S1", "D R", span="n"), op("S2", "D R", span="n"), op("S3", "D R", words=[10, 10], span="n+1"),
             op("S4", "D R", "rw", words=[6, 6], span="n"), n(lo=1, hi=16, kinds="K H")],
    "DTRD": [op("S1", "Q"), op("S2", WS), op("D", WD, "w"), n()],
    # D: the nesting count, then 16 registers a level (Z0-Z7, V0-V7) (6-12 FNC 102/103)
    "ZPUSH": [op("D", "D R", "rw", words=[17, 17])], "ZPOP": [op("D", "D R", "rw", words=[17, 17])],
    "UNI": [op("S", "KnX KnY KnM KnS T C D R"), op("D", WD, "w"), n(lo=0, hi=4)],
    "DIS": [op("S", WS), op("D", "KnY KnM KnS T C D R", "w"), n(lo=0, hi=4)],
    "SWAP": [op("S", WD, "rw")],
    # m1 = 1-32, m2 = 1-6, n = 1-m2 (6-13 FNC 148 note, as SORT)
    "SORT2": [op("S", WS), n("m1", 1, 32), n("m2", 1, 6), op("D", WD, "w"), n("n", 1, 6)],
    # n > 0 (6-13 FNC 140 note); the sum of n values (32-bit: pairs) is 32 bits (64) in D
    "WSUM": [op("S", WS, span="n"), op("D", WD, "w", words=[2, 4]), n(lo=1, hi=32767)],
    # S1 hour 0-23, S2 minute and S3 second 0-59 (6-14 FNC 160 note)
    "TCMP": [n("S1", 0, 23, kinds=WS), n("S2", 0, 59, kinds=WS), n("S3", 0, 59, kinds=WS),
             op("S", "T C D R", words=[3, 6]), op("D", BD, "w", bits=3)],
    "TZCP": [op("S1", "T C D R", words=[3, 6]), op("S2", "T C D R", words=[3, 6]), op("S", "T C D R", words=[3, 6]),
             op("D", BD, "w", bits=3)],
    "TADD": [op("S1", "T C D R", words=[3, 6]), op("S2", "T C D R", words=[3, 6]), op("D", "T C D R", "w", words=[3, 6])],
    "TSUB": [op("S1", "T C D R", words=[3, 6]), op("S2", "T C D R", words=[3, 6]), op("D", "T C D R", "w", words=[3, 6])],
    "TRD": [op("D", "T C D R", "w", words=[7, 14])], "TWR": [op("S", "T C D R", words=[7, 14])],
    "HOUR": [op("S", WS), op("D1", "D R", "rw", words=[2, 3]), op("D2", BD, "w")],
    "TFT": [op("D1", "D R", "rw"), op("S", WS), op("D2", BD, "w")],
    "TFH": [op("D1", "D R", "rw"), op("S", WS), op("D2", BD, "w")],
    "TFK": [op("D1", "D R", "rw"), op("S", WS), op("D2", BD, "w")],
    "RND": [op("D", WD, "w")],
    # n1, n2 >= 0 ("n1或n2<0 ... 運算錯誤", 6-16)
    "DUTY": [n("n1", 0, 32767, kinds=WS), n("n2", 0, 32767, kinds=WS), op("D", "M", "w", ranges={"M": [[9330, 9334]]})],
    "CRC": [op("S", "KnX KnY KnM KnS T C D R"), op("D", WD, "w"), n(lo=1, hi=256)],
    "DHSCT": [op("S1", "D R"), n("m", 1, 16, kinds="K H"), op("S2", "C", ranges=HSC), op("D", BD, "w"),
              n(lo=1, hi=16, kinds="K H")],
    "TBL": [op("S1", "Q"), op("S2", "D R", "rw", words=[4, 4]), op("D1", "Y", "w", ranges=Y03),
            op("D2", BD, "w", ranges={"Y": [[0, 7]]})],
    # S and D1 occupy 3 bits, D2 2 words (8-3 FNC 313 note)
    "DABS": [op("S", BS, bits=3), op("D1", BD, "w", bits=3), op("D2", "D R", "w")],
    "MPG": [n("S1", 0, 3), op("S2", "D R", "rw", words=[3, 6]), op("D1", "Y", "w", ranges=Y03), op("D2", BD, "w")],
    "LIR": [op("S", "D R", words=[9, 18]), op("D", "K H", range=[0, 1])],
    "LIA": [op("S", "D R", words=[9, 18]), op("D", "K H", range=[0, 1])],
    # S 3 words (32-bit: 6), D 4 words (32-bit: 6) (6-21 FNC 260/261 notes)
    "DABIN": [op("S", WS, words=[3, 6]), op("D", WD, "w")],
    # S: hours, minutes, seconds (3 registers); STOH D likewise (6-15 FNC 165/166)
    "HTOS": [op("S", WS, words=[3, 6]), op("D", WD, "w")], "STOH": [op("S", WS), op("D", WD, "w", words=[3, 6])],
    # FLT: the float result is a pair of D or R whatever the width; INT: the float source (6-6
    # FNC 49, 6-12 FNC 129; 5-1 "all floats occupy two words")
    "FLT": [op("S", WS), op("D", FD, "w", words=[2, 2])],
    "INT": [op("S", FS, words=[2, 2]), op("D", FD, "w")],
    # STR: S1 the format (characters, decimals: two registers), S2 the binary value (6-18 FNC 200
    # "S1：指定轉換格式的元件, S2：欲轉換之 2進制值"); MIDR/MIDW S2: position and count (two)
    "STR": [op("S1", "D R", words=[2, 2]), op("S2", WS), op("D", STRD, "w")],
    "MIDR": [op("S1", STRS), op("D", STRD, "w"), op("S2", "D R", words=[2, 2])],
    "MIDW": [op("S1", STRS), op("D", STRD, "rw"), op("S2", "D R", words=[2, 2])],
    # DESTR S2: form, total characters, decimals (three registers); DEVAL S: the string to
    # read (6-12 FNC 116/117: "float->string", "string->float": a K/H/E is no string)
    "ESTR": [op("S1", FS), op("S2", "D R", words=[3, 3]), op("D", STRD, "w")],
    "EVAL": [op("S", STRS), op("D", FD, "w")],
    "BINDA": [op("S", WS), op("D", WD, "w", words=[4, 6])],
    "SCL": [op("S1", WS), op("S2", "D R"), op("D", WD, "w")],
    "SCL2": [op("S1", WS), op("S2", "D R"), op("D", WD, "w")],
    "SFR": [op("D", WD, "rw"), n(lo=0, hi=15, kinds="K H")],
    "SFL": [op("D", WD, "rw"), n(lo=0, hi=15, kinds="K H")],
    # n bytes: two a word in the packed operand (WTOB S, BTOW D), one a word in the other (6-19)
    "WTOB": [op("S", WS, span="n/2"), op("D", WD, "w", span="n"), n()],
    "BTOW": [op("S", WS, span="n"), op("D", WD, "w", span="n/2"), n()],
    # S: the pointer, then the n-1 data (as SFWR's file); it counts down, so it is written (6-19)
    "POP": [op("S", WD, "rw", span="n"), op("D", WD, "w"), n(lo=2, hi=512)],
    # n > 0 (6-19: "n的值必須>0"; its upper bound, the table's count, is known at run time only)
    "FDEL": [op("S", WD, "rw"), op("D", WD, "w"), n(lo=1, hi=32767)],
    "FINS": [op("S", WS), op("D", WD, "rw", span="n"), n(lo=1, hi=32767)],
    # n >= 0 (6-18: a negative n is an operation error; n = 0 gives the empty string)
    "RIGHT": [op("S", STRS), op("D", STRD, "w"), n(lo=0, hi=32767)],
    "LEFT": [op("S", STRS), op("D", STRD, "w"), n(lo=0, hi=32767)],
}
OPERANDS["DECMP"] = [op("S1", FS), op("S2", FS), op("D", BD, "w", bits=3)]
OPERANDS["DEZCP"] = [op("S1", FS), op("S2", FS), op("S", FS), op("D", BD, "w", bits=3)]
for m in ("BKCMP=", "BKCMP>", "BKCMP<", "BKCMP<>", "BKCMP<=", "BKCMP>="):
    OPERANDS[m] = [op("S1", WS), op("S2", WS), op("D", BD, "w"), n()]
for m in ("ZRN", "JOGF", "JOGR", "DRVR", "DRVA", "DV2R", "DV2A", "DVIT", "DV2I", "DVSR", "DVSA"):
    OPERANDS[m] = POS
# "S1及S2各佔用 2個元件" (DV2R/DV2A), "S2 會佔用2個元件" (DV2I): two speeds / two amounts (8-3)
OPERANDS["DV2R"] = OPERANDS["DV2A"] = [op("S1", WS, words=[2, 4]), op("S2", WS, words=[2, 4])] + POS[2:]
OPERANDS["DV2I"] = [op("S1", WS), op("S2", WS, words=[2, 4])] + POS[2:]
OPERANDS["PLSV"] = [op("S", WS), op("D1", "Y", "w", ranges=Y03), op("D2", BD, "w", ranges={"Y": [[0, 7]]})]

# Ops of the simulator (mlctool/sim/semantics.py), where they share a routine with another
# target or with each other; everything else is its own op (lower-case mnemonic).
OPS = {
    "CJ": "cj", "CALL": "call", "SRET": "sret", "IRET": "iret", "FEND": "fend", "FOR": "for", "NEXT": "next",
    "MOV": "mov", "CML": "cml", "BCD": "bcd", "BIN": "bin", "ADD": "add", "SUB": "sub", "MUL": "mul",
    "DIV": "div", "INC": "inc", "DEC": "dec", "WAND": "wand", "WOR": "wor", "WXOR": "wxor", "NEG": "neg",
    "ROR": "ror", "ROL": "rol", "ZRST": "zrst", "DECO": "deco", "ENCO": "enco", "BON": "bon", "ALT": "alt",
    "FMOV": "fill", "DEMOV": "fmov", "DEADD": "fadd", "DESUB": "fsub", "DEMUL": "fmul", "DEDIV": "fdiv",
    "DECMP": "fcmp3", "FLT": "flt", "INT": "int", "DRAD": "frad", "DDEG": "fdeg",
    "BK+": "bk_add", "BK-": "bk_sub", "$+": "str_concat", "$MOV": "str_mov",
    "BKCMP=": "bkcmp_eq", "BKCMP>": "bkcmp_gt", "BKCMP<": "bkcmp_lt", "BKCMP<>": "bkcmp_ne",
    "BKCMP<=": "bkcmp_le", "BKCMP>=": "bkcmp_ge",
}
CMP_OPS = {"=": "cmp_eq", ">": "cmp_gt", "<": "cmp_lt", "<>": "cmp_ne", "<=": "cmp_le", ">=": "cmp_ge"}
# operand sources other than the default (kinds of MUL/DIV from 5-1/5-2, only D's words from the note)
SOURCES = {"TBL": "page note (S1 table Q0-Q31 or name, S2 4 words, D1 Y0-Y3, D2 Y0-Y7)", "MUL": GENERAL, "DIV": GENERAL,
           "BCD": GENERAL}
# Cross-operand and program-wide rules, checked generically (mlctool/check/resolve.py
# check_constraints, mlctool/check/blocks.py): "kn4" every Kn operand is K4 (CRC 6-16);
# "disjoint-blocks" S1, S2 and D blocks of n may not overlap (BK+/BK- 6-17, W240);
# "unique-destination" each D device by one instruction of the program (DUTY 6-16, E240);
# ZRST D1/D2 one kind, no 16/32-bit counter mix, D1 <= D2 (6-6, W220); "full-width-kn"
# rotate KnY/KnM/KnS only K4 (K8) (6-5, E220); "n2-within-n1" SFTR..WSFL n2 <= n1 (6-5),
# "smov-digits" SMOV m2 <= m1, m2 <= n (6-3) (E221); "same-kn" WSFR/WSFL S and D one
# attribute and one Kn size, "same-kn-bits" BMOV bit groups one Kn size (6-3, 6-5; E222).
# "no-index-hhsc" the HHSC registers are not indexed (DHHCMV 6-16, E209); "latched:D1" D1 in
# a latched area, else cleared at power-off and STOP->RUN (HOUR 6-15, W241).
CONSTRAINTS = {
    "ZRST": ["same-kind", "no-counter-width-mix", "ascending"], "CRC": ["kn4"], "BK+": ["disjoint-blocks"],
    "BK-": ["disjoint-blocks"], "DUTY": ["unique-destination"], "DHHCMV": ["no-index-hhsc"],
    **{r: ["full-width-kn"] for r in ("ROR", "ROL", "RCR", "RCL")},
    **{r: ["n2-within-n1"] for r in ("SFTR", "SFTL")},
    "WSFR": ["n2-within-n1", "same-kn"], "WSFL": ["n2-within-n1", "same-kn"],
    "SMOV": ["smov-digits"], "BMOV": ["same-kn-bits"],
    **{r: ["timer-preset"] for r in ("TFT", "TFH", "TFK")},  # S outside 0-32767 is 0 (6-15, W221)
    # operation errors a constant shows already (E206): DIV by K0 (6-4), BIN of a non-BCD H (6-3)
    "DIV": ["nonzero-divisor"], "BIN": ["bcd-source"],
    "HOUR": ["latched:D1"], "DHSCT": ["rows:S1:m:3"],  # m rows of 3 registers from S1 (6-21, E208)
    # S1, S2 and D occupy n points (2n registers in the 32-bit form; BKCMP's D n bits) (6-17)
    **{r: ["disjoint-blocks", "rows:S1:n:1:width", "rows:S2:n:1:width", "rows:D:n:1:width"] for r in ("BK+", "BK-")},
    **{r: ["rows:S1:n:1:width", "rows:S2:n:1:width", "rows:D:n:1:width"]
       for r in ("BKCMP=", "BKCMP>", "BKCMP<", "BKCMP<>", "BKCMP<=", "BKCMP>=")},
}
ONCE = {"MTR", "HKY", "DSW", "SEGL", "PR", "SORT", "DHSCT", "DABS"}  # "只能使用一次" (vs_reading.md 3)
FREE = {"SRET", "IRET", "EI", "DI", "FEND", "FOR", "NEXT", "WDT"}


def default_operands(names: list[str], floaty: bool, stringy: bool) -> list[dict]:
    out = []
    for r in names:
        role = r.split("(")[0]
        if role.startswith("S"):
            out.append(op(role, STRS if stringy else FS if floaty else WS))
        elif role.startswith("D"):
            out.append(op(role, STRD if stringy else FD if floaty else WD, "w"))
        else:
            out.append(n(role))
    return out


def q(s: str) -> str:
    return json.dumps(s, ensure_ascii=False)


def toml_value(v) -> str:
    if isinstance(v, str):
        return q(v)
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, list):
        return "[" + ", ".join(toml_value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{ " + ", ".join(f"{k if k.isidentifier() else q(k)} = {toml_value(x)}" for k, x in v.items()) + " }"
    return str(v)


def entry(x: dict) -> list[str]:
    name = x["written_as"]
    bits = x["bits"]
    models = x["series"]
    floaty = 110 <= x["fnc"] <= 137
    stringy = 200 <= x["fnc"] <= 209
    cls = "free" if name in FREE else "output"
    opname = OPS.get(name, name.lower())
    if name[:2] in ("LD", "AN", "OR") and x["fnc"] >= 224 and x["fnc"] <= 246:
        stem = "LD" if name.startswith("LD") else "AND" if name.startswith("AND") else "OR"
        rel = name[len(stem):]
        cls = {"LD": "load", "AND": "and", "OR": "or"}[stem]
        opname = CMP_OPS[rel]
        names = [name, f"{stem}D{rel}"]  # 32-bit spelling LDD>= (FX); DLD>= gets a hint
    elif bits == "32 only" or name == "TBL":  # TBL is written DTBL only (8-3 FNC 312)
        names = ["", "DTBL" if name == "TBL" else name]
    elif bits in ("16/32", "16/32?"):
        names = [name, "D" + name]
    else:
        names = [name, ""]
    ops = OPERANDS.get(name) or OPERANDS.get(name.lstrip("D") if bits == "32 only" else name)
    source = SOURCES.get(name, "page note" if ops else GENERAL)
    if ops is None:
        ops = default_operands(x["operands"], floaty, stringy)
    lines = ["[[instr]]", f"names = {toml_value(names)}", f"api = {x['fnc']}", f"class = {q(cls)}",
             f"op = {q(opname)}"]
    if x["pulse"]:
        lines.append("pulse = true")
    if floaty:
        lines.append("float = true")
    if len(models) < 4:
        lines.append(f"models = {toml_value(models)}")
    if name in ONCE:
        lines.append("once = true")
    if name in CONSTRAINTS:
        lines.append(f"constraints = {toml_value(CONSTRAINTS[name])}")
    if cls == "free" and not ops:
        lines.append("index = false")
    if ops:
        lines.append("operands = [")
        lines += [f"  {toml_value(o)}," for o in ops]
        lines.append("]")
    lines.append(f"section = {q(x['section'] + ' FNC ' + str(x['fnc']) + ' ' + x['mnem'])}")
    lines.append(f"source = {q('operands: ' + source + '; steps: FX convention (target.toml)')}")
    if x["note"]:
        lines.append(f"note = {q(x['note'])}")
    return lines


def main() -> None:
    data = json.loads(NOTES.read_text("utf-8"))["instructions"]
    head = Path(__file__).with_name("vs_basic.toml").read_text("utf-8")
    out = [head.rstrip(), "", "# " + "-" * 60 + " application instructions (ch. 6, 8-3), generated",
           "# by tools/gen_vs_instructions.py from ../shared/notes/vs_instructions.json", ""]
    for x in data:
        out += entry(x) + [""]
    sys.stdout.write("\n".join(out))


if __name__ == "__main__":
    main()
