"""`mlc check` rules: for every instruction of the nc5 target a legal and illegal uses, plus the
manual's notes, structure, lint, directives, suppressions and configured severities.

Expected codes, lines and columns are written out or derived from the table data and the
manual's numbers (device ranges, constant ranges), never taken from the checker's output.
"""

from __future__ import annotations

import pytest

from mlctool.check import check_texts
from mlctool.config import Config
from mlctool.syntax.source import decode
from mlctool.targetapi import load_target

T = load_target("nc5")
LINT = {"W401", "W402", "W403", "W404", "W405", "W406"}


def run(text: str, config: Config | None = None, *more: str):
    srcs = [decode("t.il", text.encode())[0]]
    srcs += [decode(f"m{k}.il", m.encode())[0] for k, m in enumerate(more)]
    return check_texts(srcs, T, config)


def found(text: str, config: Config | None = None, keep_lint: bool = True) -> list[tuple[str, int, int]]:
    return [(d.code, d.span.line, d.span.col) for d in run(text, config).diagnostics
            if keep_lint or d.code not in LINT]


# ------------------------------------------------------------------ generated from the tables

# a legal representative of each kind; counters: 16-bit for 16-bit forms, 32-bit for 32-bit forms
REP = {"X": "X1", "Y": "Y2", "M": "M10", "A": "A3", "T": "T4", "D": "D100", "V": "V1", "Z": "Z1",
       "F": "F1.5", "KnX": "K1X0", "KnY": "K2Y0", "KnM": "K4M100", "KnA": "K1A0", "P": "P10"}


def rep(spec, o, kind: str) -> str | None:
    """A legal operand of `kind` for operand spec `o` of `spec`, or None if the form forbids it."""
    w = spec.width
    if kind == "C":
        rng = o.devices32 if w == 32 else o.devices16
        if rng:
            return f"C{rng[0]}"
        return "C70" if w == 32 else "C5"
    if kind == "K":
        rng = (o.range32 if w == 32 else o.range16)
        if o.word_range:
            rng = o.word_range
        return f"K{rng[1] if rng else 1}"
    if kind == "F" and w != 32:
        return None  # decision: an F constant needs a 32-bit form (tested below)
    if kind == "Z" and w == 32:
        return None  # Z only in 16-bit instructions (tested below)
    return REP[kind]


def default_ops(spec) -> list[str]:
    """One legal operand per role, first allowed kind in a fixed order of preference."""
    pref = ["D", "M", "Y", "K", "T", "C", "X", "A", "F", "P", "KnM"]
    out = []
    for o in spec.operands:
        kinds = [k for k in pref if k in o.kinds] + sorted(o.kinds - set(pref))
        out.append(next(r for k in kinds if (r := rep(spec, o, k)) is not None))
    if "same-kind" in spec.constraints:
        out[1] = out[0]
    return out


def program(spec, ops: list[str]) -> tuple[str, int]:
    """A complete legal program around `MNEMONIC ops`; returns (text, line of the instruction)."""
    line = " ".join([spec.mnemonic, *ops])
    cls = spec.cls
    if cls == "load":
        return f"{line}\nOUT Y0\nEND\n", 1
    if cls in ("and", "or"):
        return f"LD X0\n{line}\nOUT Y0\nEND\n", 2
    if spec.op == "call":
        return f"LD X0\n{line}\nFEND\nP10:\nSRET\nEND\n", 2
    if spec.op == "cj":
        return f"LD X0\n{line}\nP10:\nEND\n", 2
    if cls == "output":
        return f"LD X0\n{line}\nEND\n", 2
    if cls == "label":
        return f"LD X0\nCJ {ops[0]}\n{line}\nEND\n", 3
    fixed = {
        "end": ("END\n", 1), "fend": ("LD X0\nOUT Y0\nFEND\nEND\n", 3),
        "sret": ("LD X0\nCALL P1\nFEND\nP1:\nSRET\nEND\n", 5),
        "for": (f"{line}\nLD X0\nOUT Y0\nNEXT\nEND\n", 1), "next": ("FOR K2\nNEXT\nEND\n", 2),
        "anb": ("LD X0\nOR X1\nLD X2\nOR X3\nANB\nOUT Y0\nEND\n", 5),
        "orb": ("LD X0\nAND X1\nLD X2\nAND X3\nORB\nOUT Y0\nEND\n", 5),
        "mps": ("LD X0\nMPS\nAND X1\nOUT Y0\nMPP\nOUT Y1\nEND\n", 2),
        "mrd": ("LD X0\nMPS\nAND X1\nOUT Y0\nMRD\nAND X2\nOUT Y1\nMPP\nOUT Y2\nEND\n", 5),
        "mpp": ("LD X0\nMPS\nAND X1\nOUT Y0\nMPP\nOUT Y1\nEND\n", 5),
        "inv": ("LD X0\nINV\nOUT Y0\nEND\n", 2), "nop": ("LD X0\nNOP\nOUT Y0\nEND\n", 2),
    }
    if spec.op == "for":
        return fixed["for"]
    return fixed[spec.op]


def col_of(spec, ops: list[str], k: int) -> int:
    """1-based column of operand k in `MNEMONIC op0 op1 ...` (k = -1: the mnemonic)."""
    return 1 if k < 0 else len(spec.mnemonic) + 2 + sum(len(o) + 1 for o in ops[:k])


NAMES = sorted(T.instructions)


@pytest.mark.parametrize("name", NAMES)
def test_legal_every_allowed_kind(name):
    """Every kind of every operand's `*` row is accepted (one program per variation)."""
    spec = T.instructions[name]
    base = default_ops(spec)
    variants = [base]
    for k, o in enumerate(spec.operands):
        for kind in sorted(o.kinds):
            r = rep(spec, o, kind)
            if r is None:
                continue
            ops = list(base)
            ops[k] = r
            if "same-kind" in spec.constraints:
                ops = [r, r]
            if o.word_range_of and kind == "K":
                continue
            if spec.mnemonic in ("DECO", "ENCO") and k != 2:
                # n must suit a word (1-4) or bit (1-8) operand: K3 suits both
                ops[2] = "K3"
            variants.append(ops)
    for ops in variants:
        text, line = program(spec, ops)
        got = found(text, keep_lint=False)
        assert got == [], f"{text!r}: {[d.message for d in run(text).diagnostics]}"
        instrs = [i for i in run(text).modules[0].instrs if i.line == line]
        assert instrs and instrs[0].mnemonic == spec.mnemonic and instrs[0].valid


@pytest.mark.parametrize("name", NAMES)
def test_illegal_operand_count(name):
    spec = T.instructions[name]
    ops = default_ops(spec) if spec.operands else []
    n = len(spec.operands)
    if spec.cls == "label":
        return  # `P10` alone is the label syntax; a label with operands is E103 (below)
    if spec.table:
        bad = ops[:-1]  # VRT: up to 64 table entries may follow, so drop one instead
        where = -1
    else:
        bad = ops + ["D0"]
        where = n
    text, line = program(spec, bad) if spec.cls not in ("free", "anb", "orb", "mps", "mrd", "mpp", "inv", "nop") \
        else (f"LD X0\n{spec.mnemonic} {' '.join(bad)}\nOUT Y0\nEND\n", 2)
    assert ("E202", line, col_of(spec, bad, where)) in found(text), text


def _bad_kind(o) -> str | None:
    """An operand whose kind the row does not allow and that is not an E210 (write) case."""
    for kind, text in (("D", "D7"), ("M", "M7"), ("T", "T7"), ("Y", "Y7"), ("KnM", "K1M8"), ("A", "A7"),
                       ("C", "C7"), ("V", "V2"), ("F", "F2.5"), ("P", "P3")):
        if kind not in o.kinds:
            return text
    return None


@pytest.mark.parametrize("name", [n for n in NAMES if T.instructions[n].operands and T.instructions[n].cls != "label"])
def test_illegal_device_kind(name):
    spec = T.instructions[name]
    base = default_ops(spec)
    for k, o in enumerate(spec.operands):
        bad = _bad_kind(o)
        assert bad is not None
        ops = list(base)
        ops[k] = bad
        text, line = program(spec, ops)
        got = [g for g in found(text) if g[0].startswith("E2")]
        assert got[:1] == [("E204", line, col_of(spec, ops, k))], (text, got)


@pytest.mark.parametrize("name", [n for n in NAMES if any(o.writes for o in T.instructions[n].operands)])
def test_illegal_write_to_input_or_constant(name):
    spec = T.instructions[name]
    base = default_ops(spec)
    for k, o in enumerate(spec.operands):
        if not o.writes:
            continue
        for bad in ("X1", "K1"):
            ops = list(base)
            ops[k] = bad
            text, line = program(spec, ops)
            assert ("E210", line, col_of(spec, ops, k)) in found(text), text


@pytest.mark.parametrize("name", [n for n in NAMES if T.instructions[n].operands])
def test_illegal_number_out_of_range(name):
    spec = T.instructions[name]
    base = default_ops(spec)
    cases = 0
    for k, o in enumerate(spec.operands):
        for kind in sorted(o.kinds):
            if kind in ("K", "F") or kind.startswith("Kn"):
                continue
            dev = T.devices[kind]
            ops = list(base)
            ops[k] = f"{kind}{dev.hi + 1}"
            if "same-kind" in spec.constraints:
                ops[1 - k] = f"{kind}{dev.lo}"
            text, line = program(spec, ops) if spec.cls != "label" else (f"LD X0\nCJ P0\nP{dev.hi + 1}:\nEND\n", 3)
            exp = ("E205", line, col_of(spec, ops, k) if spec.cls != "label" else 1)
            assert exp in found(text), (text, found(text))
            cases += 1
    assert cases or all(o.kinds <= {"K", "F"} for o in spec.operands)


@pytest.mark.parametrize("name", [n for n in NAMES if any("K" in o.kinds for o in T.instructions[n].operands)])
def test_illegal_constant_out_of_range(name):
    spec = T.instructions[name]
    base = default_ops(spec)
    for k, o in enumerate(spec.operands):
        if "K" not in o.kinds:
            continue
        rng = (o.range32 if spec.width == 32 else o.range16) or T.krange(spec.width)
        for value in (rng[0] - 1, rng[1] + 1):
            ops = list(base)
            ops[k] = f"K{value}"
            text, line = program(spec, ops)
            assert ("E206", line, col_of(spec, ops, k)) in found(text), (text, found(text))


@pytest.mark.parametrize("name", [n for n in NAMES if any("Z" in o.kinds for o in T.instructions[n].operands)])
def test_z_only_in_16_bit(name):
    spec = T.instructions[name]
    base = default_ops(spec)
    for k, o in enumerate(spec.operands):
        if "Z" not in o.kinds:
            continue
        ops = list(base)
        ops[k] = "Z2"
        text, line = program(spec, ops)
        got = found(text)
        if spec.width == 32:
            assert ("E211", line, col_of(spec, ops, k)) in got, text
        else:
            assert [g for g in got if g[0].startswith("E")] == [], text


@pytest.mark.parametrize("name", [n for n in NAMES if T.instructions[n].api is not None
                                  and T.instructions[n].op not in ("cnt", "zrst")
                                  and any("C" in o.kinds for o in T.instructions[n].operands)])
def test_32_bit_counter_only_in_32_bit_forms(name):
    """3.2.5 item 5: C64-C79 as data only in 32-bit instructions; LD※ on them needs DLD※."""
    spec = T.instructions[name]
    base = default_ops(spec)
    for k, o in enumerate(spec.operands):
        if "C" not in o.kinds:
            continue
        ops = list(base)
        ops[k] = "C64"
        text, line = program(spec, ops)
        got = [g for g in found(text) if g[0].startswith("E")]
        if spec.width == 16:
            assert got == [("E211", line, col_of(spec, ops, k))], text
            d = [d for d in run(text).diagnostics if d.code == "E211"][0]
            assert "C64" in d.message and "32-bit" in d.message
        else:
            assert got == [], text


@pytest.mark.parametrize("name", [n for n in NAMES if T.instructions[n].operands])
def test_index_modification(name):
    """V/Z index: application instructions on indexable kinds (3.4); never basic instructions;
    V only in 32-bit forms (1.8.2)."""
    spec = T.instructions[name]
    if spec.cls == "label":
        return
    base = default_ops(spec)
    for k, o in enumerate(spec.operands):
        kind = next(iter(sorted(o.kinds - {"F"})), None)
        if kind is None or kind == "P" and spec.cls == "label":
            continue
        r = rep(spec, o, kind)
        if r is None:
            continue
        for ix in ("V0", "Z0"):
            ops = list(base)
            ops[k] = r + ix
            text, line = program(spec, ops)
            got = [g for g in found(text) if g[0].startswith("E")]
            legal = spec.index and kind in T.indexable and not (spec.width == 32 and ix == "Z0")
            if kind in ("V", "Z"):
                legal = False
            if legal:
                assert got == [], (text, got)
            else:
                assert got[:1] == [("E209", line, col_of(spec, ops, k))], (text, got)


def test_every_instruction_has_generated_cases():
    # the parametrizations above cover the whole instruction set
    assert len(NAMES) == len(T.instructions) > 100


# ------------------------------------------------------------------ notes of the manual (hand-written)

@pytest.mark.parametrize("line,expect", [
    # ZRST 4.5: same kind; 16/32-bit counters not mixed; the manual's own examples are legal
    ("ZRST M300 M399", []), ("ZRST C0 C63", []), ("ZRST T0 T127", []), ("ZRST A0 A127", []),
    ("ZRST D0 D100", []), ("ZRST C64 C77", []), ("ZRST D10 D5", []),
    ("ZRST M0 D10", [("E214", 2, 9)]), ("ZRST C0 C64", [("E214", 2, 9)]), ("ZRST C70 C10", [("E214", 2, 10)]),
    ("ZRST Y0 M5", [("E214", 2, 9)]),
    # CNT preset register not D20000-D38999 (1.7.1); DCNT has no such note
    ("CNT C0 D9999", []), ("CNT C0 D20000", [("E216", 2, 8)]), ("CNT C63 D38999", [("E216", 2, 9)]),
    ("CNT C0 D39000", []), ("DCNT C64 D20000", [("W253", 2, 10)]),  # (a 32-bit read of 16-bit D20000)
    ("CNT C0 K65535", []), ("CNT C0 K65536", [("E206", 2, 8)]), ("CNT C0 K-1", [("E206", 2, 8)]),
    ("CNT C64 K5", [("E211", 2, 5)]), ("DCNT C63 K5", [("E211", 2, 6)]), ("DCNT C79 K-2147483648", []),
    ("TMR T255 K65535", []), ("TMR T256 K1", [("E205", 2, 5)]), ("TMR T0 K65536", [("E206", 2, 8)]),
    # DECO/ENCO n: 1-8 with bit D/S, 1-4 with a word (4.5)
    ("DECO X0 M100 K8", []), ("DECO X0 M100 K9", [("E206", 2, 14)]), ("DECO X0 M100 K0", [("E206", 2, 14)]),
    ("DECO D10 D20 K4", []), ("DECO D10 D20 K5", [("E216", 2, 14)]), ("DECO K3 D20 K3", []),
    ("ENCO M0 D0 K8", []), ("ENCO M0 D0 K9", [("E206", 2, 12)]), ("ENCO D10 D20 K4", []),
    ("ENCO D10 D20 K5", [("E216", 2, 14)]),
    # Kn groups: K1-K4 in 16-bit, K1-K8 in 32-bit (3.2.6); the 4n bits must exist
    ("MOV K4X0 D0", []), ("MOV K5X0 D0", [("E207", 2, 5)]), ("MOV K0X0 D0", [("E207", 2, 5)]),
    ("DMOV K8M0 D0", []), ("DMOV K9M0 D0", [("E207", 2, 6)]),
    ("MOV K4M65520 D0", [("W213", 2, 5)]), ("MOV K4M65521 D0", [("E207", 2, 5)]),
    ("MOV K1 K4Y496", []), ("MOV K1 K4Y497", [("E207", 2, 8)]),
    # pairs and multi-word operands past the end (E208)
    ("DMOV K1 D65534", [("W213", 2, 9)]), ("DMOV K1 D65535", [("E208", 2, 9)]),
    ("MUL D0 D1 D65535", [("E208", 2, 11)]), ("DMUL D0 D2 D65532", [("W213", 2, 12)]),
    ("DMUL D0 D2 D65533", [("E208", 2, 12)]), ("FCMP F1 D0 M65533", [("W213", 2, 12)]),
    ("FCMP F1 D0 M65534", [("E208", 2, 12)]), ("DADD D0 D2 T255", [("E208", 2, 12)]),
    # reserved areas (W213); the special M/D of ch. 5: the signal table speaks (W250 a write to an
    # R row, W251 a number no row defines; tests/check/test_check_signals.py), not the area (W212)
    ("MOV D15000 D0", [("W213", 2, 5)]), ("OUT M15000", [("W213", 2, 5)]), ("OUT Y40", [("W213", 2, 5)]),
    ("MOV K1 D40000", [("W213", 2, 8)]), ("MOV K1 D62000", [("W213", 2, 8)]),
    ("OUT M30000", [("W250", 2, 5)]), ("MOV K1 D30005", [("W251", 2, 8)]), ("OUT M59000", [("W251", 2, 5)]),
    ("MOV D30005 D0", [("W251", 2, 5)]), ("OUT M20000", [("W251", 2, 5)]), ("MOV K1 D21000", []),
    ("OUT M60000", []), ("DMOV K1 D38999", [("W251", 2, 9)]), ("DMOV K1 D29999", [("W251", 2, 9)]),
    # F constants: 32-bit forms only; at most 3 decimals within +-99999.999
    ("DMOV F1.5 D0", []), ("MOV F1.5 D0", [("E204", 2, 5)]), ("FADD F99999.999 D0 D2", []),
    ("FADD F100000 D0 D2", [("E206", 2, 6)]), ("FADD F1.2345 D0 D2", [("E206", 2, 6)]),
    ("FADD K1 D0 D2", [("E204", 2, 6)]), ("FMOV K1 D0", []),
    # K ranges of the forms (1.1.2): 16-bit / 32-bit
    ("MOV K32767 D0", []), ("MOV K32768 D0", [("E206", 2, 5)]), ("MOV K-32769 D0", [("E206", 2, 5)]),
    ("DMOV K2147483647 D0", []), ("DMOV K2147483648 D0", [("E206", 2, 6)]),
    # ROR/ROL/BON n
    ("ROR D0 K16", []), ("ROR D0 K17", [("E206", 2, 8)]), ("DROR D0 K32", []), ("DROL D0 K33", [("E206", 2, 9)]),
    ("BON D0 M0 K15", []), ("BON D0 M0 K16", [("E206", 2, 11)]), ("DBON D0 M0 K31", []),
    # VRT: n = 1-6, up to 64 table entries of K constants
    ("VRT M30 K4 D1062 K0 K20 K32 K50 K79", []), ("VRT M30 K7 D1062", [("E206", 2, 9)]),
    ("VRT M30 K4 D1062 D5", [("E204", 2, 18)]), ("VRT M30 K4 D1062 K40000", [("E206", 2, 18)]),
    ("VRT M30 K4 D1062 " + " ".join(["K1"] * 64), []),
    ("VRT M30 K4 D1062 " + " ".join(["K1"] * 65), [("E202", 2, 18 + 64 * 3)]),
    ("DVRT M30 K4 D1062 K70000", []),
    # index: K20V0 (3.4 example) is a modified constant; P may be modified (CJ/CALL)
    ("MOV K20V0 D24", []), ("DMOV K20V0 D24", []), ("DMOV K20Z0 D24", [("E209", 2, 6)]),
    ("MOV D5V0 D0", []), ("MOV D5Z8 D0", [("E205", 2, 5)]), ("MOV K1 D0V7", []),
    # malformed operands
    ("MOV H10 D0", [("E203", 2, 5)]), ("MOV 10 D0", [("E203", 2, 5)]), ("MOV K1 Q5", [("E203", 2, 8)]),
    ("MOV K1 D0.5", [("E215", 2, 8)]), ("MOV K1 D-1", [("E203", 2, 8)]),
])
def test_manual_notes(line, expect):
    assert found(f"LD X0\n{line}\nEND\n") == expect


def test_index_p_and_32_bit_v():
    assert found("LD X0\nCJ P10V1\nP10:\nEND\n", keep_lint=False) == []
    assert found("LD X0\nCJ P10Z1\nP10:\nEND\n", keep_lint=False) == []


def test_comparison_contacts_on_c64_need_d_form():
    # 4.7: "32 位元計數器 (C64 ~ C79) 代入本指令做比較時，必須使用 32 位元指令"
    assert found("LD= C64 K5\nOUT Y0\nEND\n") == [("E211", 1, 5)]
    assert found("DLD> K678493 C64\nOR M3\nOUT M50\nEND\n") == []


def test_symbols_resolve_and_undefined_symbol():
    text = ".define START X0\n.define LAMP Y0\nLD START\nOUT LAMP\nLD STOP\nOUT Y1\nEND\n"
    assert found(text) == [("E215", 5, 4)]
    d = [d for d in run(text).diagnostics if d.code == "E215"][0]
    assert "STOP" in d.message


@pytest.mark.parametrize("text,expect", [
    (".define START X0\n.define START X1\nEND\n", [("E106", 2, 9)]),
    (".define X1 X2\nEND\n", [("E106", 1, 9)]),
    (".define K10 X2\nEND\n", [("E106", 1, 9)]),
    (".define SPEED Q9\nEND\n", [("E106", 1, 15)]), (".define S1 X0\nEND\n", [("E106", 1, 9)]),
    (".defne S X0\nEND\n", [("E105", 1, 1)]),
    (".define S\nEND\n", [("E105", 1, 1)]),
    (".export X0\nEND\n", [("E105", 1, 9)]),
    (".library 3\n", [("E105", 1, 1), ("E301", 1, 1)]),
    (".export P7\nLD X0\nCJ P7\nP7:\nEND\n", []),
    (".export P8\nEND\n", [("E304", 1, 1)]),
    (".library\nP9:\nLD X0\nOUT Y0\nSRET\n", []),
    (".library\nP9:\nLD X0\nOUT Y0\nSRET\nEND\n", [("E305", 6, 1)]),
])
def test_directives(text, expect):
    assert found(text, keep_lint=False) == expect


# ------------------------------------------------------------------ syntax (E103) with columns

@pytest.mark.parametrize("text,expect", [
    ("LD #\nOUT Y0\nEND\n", [("E103", 1, 4)]),
    ("LD X0\nOUT Y0 @\nEND\n", [("E103", 2, 8)]),
    ("  LD X0\n  OUT Y0\n  END $\n", [("E103", 3, 7)]),
    ("LD X0\nOUT Y0\nP5: LD X1\nEND\n", [("E103", 3, 5)]),
    ("LD X0\nOUT Y0\n:\nEND\n", [("E103", 3, 1)]),
    ("LD X0\nOUT Y0\nQ1:\nEND\n", [("E103", 3, 1)]),
    ("LD X0\nOUT Y0\n.define A X0 X1 X2\nEND\n", [("E105", 3, 1)]),
    ("LD X0\nOUT Y0\nEND\n", []),
    ("LD X0 ; comment\nOUT Y0 // comment\nEND\n", []),
    # the first number against the address, each later one by its distance (issue 29)
    ("000013,LD,X0\n000014,OUT,Y0\n000015,END\n", [("W107", 1, 1)]),
    ("0 LD X0\n1 OUT Y0\n3 LD X1\n4 OUT Y1\n5 END\n", [("W107", 3, 1)]),
    ("0 LD X0\n1 OUT Y0\n2 END\n", []),
    ("0 LD X0\n1 OUT Y0\n3 END\n", [("W107", 3, 1)]),
    ("LD X0\nOUT Y0\nFROB X1\nEND\n", [("E201", 3, 1)]),
    ("LDP X0\nMOVP K1 D0\nEND\n", [("E201", 2, 1)]),
    ("LD X0\nADD K1 D0\nEND\n", [("E202", 2, 1)]),
])
def test_syntax_and_step_numbers(text, expect):
    assert found(text, keep_lint=False) == expect


def test_label_out_of_range():
    assert ("E205", 3, 1) in found("LD X0\nCJ P0\nP256:\nEND\n")
    assert ("E205", 2, 4) in found("LD X0\nCJ P256\nEND\n")


# ------------------------------------------------------------------ structure (E3xx)

@pytest.mark.parametrize("text,expect", [
    # E301 no END, E302 code after END
    ("LD X0\nOUT Y0\n", [("E301", 2, 1)]),
    ("LD X0\nOUT Y0\nEND\nLD X1\nOUT Y1\n", [("E302", 4, 1)]),
    # E303 duplicate label
    ("LD X0\nCJ P1\nP1:\nP1:\nEND\n", [("E303", 4, 1)]),
    # E304 undefined label
    ("LD X0\nCJ P2\nEND\n", [("E304", 2, 1)]),
    ("LD X0\nCALL P3\nFEND\nEND\n", [("E304", 2, 1)]),
    # E305 subroutine layout: CALL target before FEND; CJ and CALL share a P; SRET before FEND
    ("LD X0\nCALL P1\nP1:\nLD X1\nOUT Y1\nFEND\nEND\n", [("E305", 2, 1)]),
    ("LD X0\nCALL P1\nLD X1\nCJ P1\nFEND\nP1:\nSRET\nEND\n", [("E305", 4, 1)]),
    ("LD X0\nOUT Y0\nSRET\nFEND\nEND\n", [("E305", 3, 1)]),
    ("LD X0\nCJ P4\nFEND\nP4:\nSRET\nEND\n", [("E305", 2, 1)]),
    # E306 FOR/NEXT pairing; E307 nesting > 5 (4.1 API-07/08)
    ("NEXT\nEND\n", [("E306", 1, 1)]),
    ("FOR K2\nLD X0\nOUT Y0\nEND\n", [("E306", 1, 1)]),
    ("FOR K2\nFEND\nNEXT\nEND\n", [("E306", 1, 1), ("E306", 3, 1)]),
    ("FOR K1\nFOR K1\nFOR K1\nFOR K1\nFOR K1\nNEXT\nNEXT\nNEXT\nNEXT\nNEXT\nEND\n", []),
    ("FOR K1\nFOR K1\nFOR K1\nFOR K1\nFOR K1\nFOR K1\nNEXT\nNEXT\nNEXT\nNEXT\nNEXT\nNEXT\nEND\n", [("E307", 6, 1)]),
    # E308 MPS/MRD/MPP balance; E309 depth (target.toml mps_depth)
    ("LD X0\nMRD\nOUT Y0\nEND\n", [("E308", 2, 1)]),
    ("LD X0\nMPS\nOUT Y0\nLD X1\nOUT Y1\nEND\n", [("E308", 2, 1)]),  # at the MPS left open
    ("LD X0\n" + "MPS\nAND X1\n" * 9 + "OUT Y0\n" + "MPP\n" * 9 + "OUT Y1\nEND\n", [("E309", 18, 1)]),
    ("LD X0\n" + "MPS\nAND X1\n" * 8 + "OUT Y0\n" + "MPP\nOUT Y1\n" * 8 + "END\n", []),
    # E310 ANB/ORB without two blocks
    ("LD X0\nANB\nOUT Y0\nEND\n", [("E310", 2, 1)]),
    ("ORB\nEND\n", [("E310", 1, 1)]),
    # E311 contact without a load; E312 output without condition; E313 unfinished rung
    ("AND X0\nOUT Y0\nEND\n", [("E311", 1, 1)]),
    ("OR X0\nOUT Y0\nEND\n", [("E311", 1, 1)]),
    ("MPS\nEND\n", [("E308", 1, 1), ("E311", 1, 1)]),
    ("OUT Y0\nEND\n", [("E312", 1, 1)]),
    ("MOV K1 D0\nEND\n", [("E312", 1, 1)]),
    ("LD X0\nLD X1\nOUT Y0\nEND\n", [("E313", 3, 1)]),
    ("LD X0\nAND X1\nEND\n", [("E313", 3, 1)]),
    # the comparison contacts start a rung (LD※ 4.7)
    ("LD= D0 K5\nAND> D1 K2\nOR<> D2 K3\nOUT Y0\nEND\n", []),
])
def test_structure(text, expect):
    assert found(text, keep_lint=False) == expect


def test_capacity_e314():
    body = "LD X0\n" + "MOV K1 D0\n" * 10 + "END\n"  # 1 + 40 + 1 = 42 steps
    assert found(body, Config(capacity=42), keep_lint=False) == []
    assert found(body, Config(capacity=41), keep_lint=False) == [("E314", 12, 1)]


# ------------------------------------------------------------------ lint (W4xx)

@pytest.mark.parametrize("text,expect", [
    ("LD X0\nOUT Y0\nLD X1\nOUT Y0\nEND\n", [("W401", 4, 1)]),
    ("LD X0\nTMR T0 K10\nLD X1\nTMR T0 K20\nEND\n", [("W402", 4, 1)]),
    ("LD X0\nCNT C0 K10\nLD X1\nCNT C0 K20\nEND\n", [("W402", 4, 1)]),
    ("LD X0\nDMOV K70000 D0\nLD X1\nMOV K1 D1\nEND\n", [("W403", 4, 1)]),
    ("LD X0\nMOV K1 D1\nLD X1\nDMOV K70000 D0\nEND\n", [("W403", 4, 1)]),
    ("LD X0\nDMOV K1 D0\nLD X1\nDMOV K1 D1\nEND\n", [("W403", 4, 1)]),
    ("LD X0\nDMOV K1 D0\nLD X1\nDMOV K1 D2\nEND\n", []),
    ("LD X0\nOUT Y0\nP7:\nEND\n", [("W404", 3, 1)]),
    ("LD X0\nSET M5\nEND\n", [("W405", 2, 1)]),
    ("LD X0\nSET M5\nLD X1\nRST M5\nEND\n", []),
    ("LD X0\nSET M5\nLD X1\nZRST M0 M9\nEND\n", []),
    ("LD X0\nSET M5\nLD X1\nMOV K0 K2M0\nEND\n", []),
    ("LD X0\nOUT Y0\nFEND\nLD X1\nOUT Y1\nEND\n", [("W406", 4, 1)]),
    ("LD X0\nCALL P1\nFEND\nP1:\nLD X1\nOUT Y1\nSRET\nLD X2\nOUT Y2\nEND\n", [("W406", 8, 1)]),
])
def test_lint(text, expect):
    assert found(text) == expect


def test_double_coil_across_modules():
    res = run("LD X0\nOUT Y0\nEND\n", None, ".library\nP1:\nLD X1\nOUT Y0\nSRET\n")
    got = [(d.file, d.code, d.span.line) for d in res.diagnostics if d.code == "W401"]
    assert got == [("m0.il", "W401", 4)]


# ------------------------------------------------------------------ suppression and severities

def test_noqa_suppresses_only_the_named_code():
    base = "LD X0\nOUT Y0\nLD X1\nOUT Y0{c}\nEND\n"
    assert found(base.format(c="")) == [("W401", 4, 1)]
    assert found(base.format(c=" ; mlc: noqa W401")) == []
    assert found(base.format(c=" // mlc: noqa: W401, W405")) == []
    assert found(base.format(c=" ; mlc: noqa")) == []
    assert found(base.format(c=" ; mlc: noqa W402")) == [("W401", 4, 1)]
    # a noqa on another line does not apply
    assert found("LD X0 ; mlc: noqa W401\nOUT Y0\nLD X1\nOUT Y0\nEND\n") == [("W401", 4, 1)]
    # an error is never suppressed: it means the program cannot be built (issue 21 #6)
    assert found("LD X0\nMOV K1 D65536 ; mlc: noqa E205\nEND\n") == [("E205", 2, 8)]


def test_config_severity():
    text = "LD X0\nOUT Y0\nLD X1\nOUT Y0\nSET M1\nEND\n"
    assert found(text) == [("W401", 4, 1), ("W405", 5, 1)]
    assert found(text, Config(severity={"W401": "off"})) == [("W405", 5, 1)]
    res = run(text, Config(severity={"W405": "error"}))
    sev = {d.code: d.severity for d in res.diagnostics}
    assert sev == {"W401": "warning", "W405": "error"} and res.errors == 1
    res = run("LD X0\nOUT M15000\nEND\n", Config(severity={"W213": "error"}))
    assert [(d.code, d.severity) for d in res.diagnostics] == [("W213", "error")]


def test_config_file_severity(tmp_path, monkeypatch):
    from mlctool.config import load_config

    (tmp_path / "mlc.toml").write_text('target = "nc5"\n[severity]\nW401 = "off"\nw405 = "error"\n')
    cfg = load_config(tmp_path)
    assert cfg.severity == {"W401": "off", "W405": "error"}
    text = "LD X0\nOUT Y0\nLD X1\nOUT Y0\nSET M1\nEND\n"
    res = run(text, cfg)
    assert [(d.code, d.severity) for d in res.diagnostics] == [("W405", "error")]


def test_e210_names_the_destination_not_a_register():
    """Issue 14 §3: "MOV writes its D operand" read as register D."""
    res = run("LD X0\nOUT X1\nMOV K1 K2\nDMOV D0 K5\nEND\n")
    got = [(d.code, d.span.line, d.message) for d in res.diagnostics]
    assert got == [("E210", 2, "X1 is an input (written by the hardware only): the first operand of OUT is its destination"),
                   ("E210", 3, "K2 is a constant: the second operand of MOV is its destination"),
                   ("E210", 4, "K5 is a constant: the second operand of DMOV is its destination")]


def test_unknown_instruction_says_what_was_meant():
    """Issue 14 §3: OTU -> OUT; MOVP on NC5 names the edge instructions the manual offers
    (3.2.4: no P forms); nothing is suggested when nothing is near."""
    res = run("LD X0\nOTU Y0\nMOVP K1 D0\nldpp X1\nQWERTY D0\nEND\n")
    got = {d.span.line: (d.code, d.message, d.notes) for d in res.diagnostics if d.code == "E201"}
    assert got[2][1] == "unknown instruction 'OTU' for target nc5; did you mean OUT?"
    assert got[3][1] == "unknown instruction 'MOVP' for target nc5"
    assert got[3][2] == ("Delta NC5 MLC has no P (pulse) forms: MOV runs on every scan while its condition is on "
                         "(manual 3.2.4); to run it once per rising edge, drive it with LDP/ANDP/ORP or a PLS relay",)
    assert got[4][1] == "unknown instruction 'LDPP' for target nc5; did you mean LDP?"
    assert got[5][1] == "unknown instruction 'QWERTY' for target nc5" and got[5][2] == ()


def test_unknown_instruction_hint_on_vs():
    from mlctool.check.resolve import unknown_instruction_hint
    from mlctool.targetapi import load_target

    vs = load_target("vs")
    assert unknown_instruction_hint(vs, "OTU") == ("; did you mean OUT?", ())
    assert unknown_instruction_hint(vs, "ZRTS") == ("; did you mean ZRST?", ())
    # VS has P forms: MOVPP is a typo, not a missing dialect feature
    assert unknown_instruction_hint(vs, "MOVPP")[0] == "; did you mean MOVP?"


# ------------------------------------------------------------------ nesting, per target (issue 30.17)

def _nested_calls(levels: int) -> str:
    body = "".join(f"P{p}\nLD X0\nCALL P{p + 1}\nSRET\n" for p in range(1, levels))
    return f"LD X0\nCALL P1\nFEND\n{body}P{levels}\nLD X0\nINC D0\nSRET\nEND\n"


def test_a_sixth_call_level_is_the_targets_rule():
    """NC5 4.1 API-01: "包括本身最多可五層 (若進入第六層則該副程式不執行)": the 6th call is not run
    and the scan goes on, W613; VS 6-2 CALL: a rule of the program, E307 citing error 6702.
    Before, nc5 got VS's E307 and its citation."""
    text = _nested_calls(6)
    line = text.split("\n").index("CALL P6") + 1
    for name, code, cited in (("nc5", "W613", "4.1 API-01"), ("vs", "E307", "6-2 CALL, error 6702")):
        diags = check_texts([decode("t.il", text.encode())[0]], load_target(name)).diagnostics
        (d,) = [d for d in diags if d.code in ("E307", "W613")]
        assert (d.code, d.span.line) == (code, line) and cited in d.message, (name, d)
    five = check_texts([decode("t.il", _nested_calls(5).encode())[0]], T).diagnostics
    assert not [d for d in five if d.code in ("E307", "W613")]


def test_a_sixth_for_level_cites_the_targets_own_section():
    text = "LD X0\n" + "FOR K1\n" * 6 + "NEXT\n" * 6 + "END\n"
    for name, cited in (("nc5", "(4.1 API-07)"), ("vs", "(6-2 FOR, error 6704)")):
        diags = check_texts([decode("t.il", text.encode())[0]], load_target(name)).diagnostics
        (d,) = [d for d in diags if d.code == "E307"]
        assert d.message.endswith(cited), (name, d.message)
