"""`mlc check --target vs`: the manual's program rules (issue 8) and, for every range note the
tables carry, one legal and one illegal use."""

from __future__ import annotations

import pytest

from mlctool.check import check_texts
from mlctool.syntax.operands import device_number
from mlctool.syntax.source import decode
from mlctool.targetapi import load_target

VS = load_target("vs")


def diags(il: str, model: str = "VS3"):
    src, _ = decode("t.il", il.encode())
    return check_texts([src], load_target("vs", model)).diagnostics


def codes(il: str, severity: str | None = None) -> list[str]:
    return [d.code for d in diags(il) if severity is None or d.severity == severity]


# ------------------------------------------------------------------ every printed range note

# A legal operand of each kind, the number being the lowest the operand allows.
_DEFAULT = {"D": "D100", "R": "R100", "K": "K1", "H": "H1", "X": "X0", "Y": "Y10", "M": "M100",
            "S": "S100", "T": "T0", "C": "C0", "Q": "Q0", "$": '"A"', "E": "E1.5", "KnY": "K4Y10",
            "KnM": "K4M100", "KnX": "K4X0", "KnS": "K4S100", "V": "V0", "Z": "Z0", "P": "P0"}
_ORDER = ["D", "K", "M", "Y", "X", "S", "T", "C", "R", "KnM", "KnY", "KnX", "H", "Q", "E", "$"]


def _operand(spec, o) -> str:
    for kind in _ORDER:
        if kind not in o.kinds:
            continue
        allowed = o.allowed(kind)
        narrow = o.devices32 if spec.width == 32 else o.devices16
        if kind in ("K", "H"):
            rng = (o.range32 if spec.width == 32 else o.range16)
            return f"{kind}{rng[0] if rng else 1}" if kind == "K" else f"H{rng[0] if rng else 1:X}"
        if allowed:
            return f"{kind}{device_number(allowed[0][0], VS.devices[kind].radix)}"
        if narrow:
            return f"{kind}{narrow[0]}"
        if kind == "C" and spec.width == 32:
            return "C200"
        if kind == "T" and spec.width == 32:
            return "D100"
        return _DEFAULT[kind]
    raise AssertionError(f"no default operand for {spec.mnemonic} {o.role} {sorted(o.kinds)}")


def _notes():
    """(mnemonic, operand index, legal texts, illegal texts) for every range the tables print."""
    out = []
    for name, spec in sorted(VS.instructions.items()):
        if spec.pulse or spec.cls == "label" or len(VS.variants_of(name)) > 1:
            continue
        for k, o in enumerate(spec.operands):
            rng = o.range32 if spec.width == 32 else o.range16
            if rng and ("K" in o.kinds):
                lo, hi = rng
                legal, illegal = [f"K{lo}", f"K{hi}"], [f"K{lo - 1}", f"K{hi + 1}"]
                out.append((name, k, legal, illegal))
            for kind, spans in o.ranges:
                dev = VS.devices[kind]
                lo, hi = spans[0][0], spans[-1][1]
                legal = [f"{kind}{device_number(lo, dev.radix)}", f"{kind}{device_number(hi, dev.radix)}"]
                illegal = [f"{kind}{device_number(n, dev.radix)}" for n in (lo - 1, hi + 1)
                           if dev.lo <= n <= dev.hi and not any(a <= n <= b for a, b in spans)]
                out.append((name, k, legal, illegal))
    return out


NOTES = _notes()


def test_the_notes_are_many():
    assert len(NOTES) > 60  # every n range, Y0-Y3, C235-C255, T0-T199, S900-S999 ...


@pytest.mark.parametrize("name, k, legal, illegal", NOTES, ids=[f"{n[0]}-{n[1]}" for n in NOTES])
def test_every_range_note_has_a_legal_and_an_illegal_use(name, k, legal, illegal):
    spec = VS.instructions[name]
    # an n whose range depends on another operand being a bit device (DECO/ENCO): make it one
    bits = {o.word_range_of for o in spec.operands if o.word_range_of}
    base = [_operand(spec, o) if o.role not in bits else "M100" for o in spec.operands]
    head = "LD X0\n" if spec.cls not in ("load",) else ""
    tail = "OUT Y0\n" if spec.cls in ("load", "and", "or") else ""
    for text in legal:
        ops = base[:k] + [text] + base[k + 1:]
        # relations between operands have their own cases with the pages: E232 (REF Y0 takes
        # n = 8 only, a DHSCR counter D is S2; test_vs_audit_fnc050.py), E221 (n2 <= n1, SMOV
        # m2 <= m1 ...: the other counts stay at their lowest here; test_vs_audit_fnc000.py)
        # E208: a count at its legal top makes the block it sizes (FROM D: n words) run past
        # the device's end (the spans: tests/test_checked_means_runs.py)
        spanned = any(o.span and o.span[0] == spec.operands[k].role for o in spec.operands)
        skip = ("E221", "E232") + (("E208",) if spanned else ())
        found = [(d.code, d.message) for d in diags(f"{head}{name} {' '.join(ops)}\n{tail}END\n")
                 if d.severity == "error" and d.code not in skip]
        assert found == [], (name, ops)
    assert illegal or spec.operands[k].ranges, name
    for text in illegal:
        ops = base[:k] + [text] + base[k + 1:]
        found = {d.code for d in diags(f"{head}{name} {' '.join(ops)}\n{tail}END\n")}
        assert found & {"E205", "E206", "E211", "E216"}, (name, ops, found)


# ------------------------------------------------------------------ once per program (E904)

@pytest.mark.parametrize("line", ["MTR X0 Y0 M0 K8", "SEGL D0 Y0 K4", "DHSCT D0 K1 C235 M0 K1", "DABS X0 M0 D0"])
def test_once_per_program(line):
    assert "E904" not in codes(f"LD X0\n{line}\nEND\n")
    assert codes(f"LD X0\n{line}\nLD X1\n{line}\nEND\n", "error") == ["E904"]


def test_once_counts_both_widths():
    assert codes("LD X0\nHKY X0 Y0 D0 M0\nLD X1\nDHKY X0 Y0 D0 M0\nEND\n", "error") == ["E904"]


# ------------------------------------------------------------------ MC/MCR nesting (E903)

def test_mc_levels_in_order():
    assert codes("LD X0\nMC N0\nLD X1\nMC N1\nLD X2\nOUT Y0\nMCR N1\nMCR N0\nEND\n") == []
    assert codes("LD X0\nMC N0\nLD X1\nMC N1\nLD X2\nOUT Y0\nMCR N0\nEND\n") == []  # N0 closes N1 too


@pytest.mark.parametrize("il", [
    "LD X0\nMC N1\nLD X1\nOUT Y0\nMCR N1\nEND\n",              # outermost must be N0
    "LD X0\nMC N0\nLD X1\nMC N2\nOUT Y0\nMCR N0\nEND\n",        # no gaps
    "LD X0\nMC N0\nLD X1\nOUT Y0\nEND\n",                      # not closed
    "LD X1\nOUT Y0\nMCR N0\nEND\n",                            # nothing to close
])
def test_mc_nesting_errors(il):
    assert codes(il, "error") == ["E903"]


# ------------------------------------------------------------------ step ladder (E902)

STEPS = "LD M9002\nSET S0\nSTL S0\nLD X0\nSET S20\nSTL S20\nOUT Y0\nLD X1\nOUT S0\nRET\n"


def test_step_ladder_legal():
    assert codes(STEPS + "END\n") == []


@pytest.mark.parametrize("il", [
    STEPS.replace("RET\n", "") + "END\n",                                     # no RET
    STEPS + "STL S20\nOUT Y1\nRET\nEND\n",                                    # S20 used twice
    STEPS.replace("OUT Y0\n", "MPS\nOUT Y0\nMPP\nOUT Y1\n") + "END\n",         # MPS on the bus
    STEPS.replace("OUT Y0\n", "MC N0\nLD X2\nOUT Y0\nMCR N0\n") + "END\n",     # MC in a step
    "LD X0\nCALL P1\nFEND\nP1\n" + STEPS + "SRET\nEND\n",                     # STL in a subroutine
    "LD X0\nOUT Y0\nRET\nEND\n",                                              # RET without STL
])
def test_step_ladder_errors(il):
    assert "E902" in codes(il, "error")


def test_same_coil_in_two_steps_is_no_double_coil():
    two_steps = ("LD M9002\nSET S0\nSTL S0\nOUT Y5\nLD X0\nSET S20\nSTL S20\nOUT Y5\nLD X1\nSET S0\n"
                 "RET\n")
    assert "W401" not in codes(two_steps + "END\n")
    assert "W401" in codes(two_steps + "LD X3\nOUT Y5\nEND\n")  # and outside the steps
    assert "W401" in codes(two_steps.replace("OUT Y5\nLD X1", "OUT Y5\nOUT Y5\nLD X1") + "END\n")


def test_double_coil_outside_steps_still_warns():
    assert "W401" in codes("LD X0\nOUT Y0\nLD X1\nOUT Y0\nEND\n")


# ------------------------------------------------------------------ ANB/ORB runs (E906)

def test_eight_anb_orb_in_a_row():
    assert codes("LD X0\n" + "LD X1\n" * 8 + "ORB\n" * 8 + "OUT Y0\nEND\n", "error") == []
    assert codes("LD X0\n" + "LD X1\n" * 9 + "ORB\n" * 9 + "OUT Y0\nEND\n", "error") == ["E906"]


# ------------------------------------------------------------------ read-only specials (W212)

@pytest.mark.parametrize("line, warns", [
    ("OUT M9000", True), ("OUT M9013", True), ("SET M9029", True), ("MOV K1 D9010", True),
    ("MOV K1 D9067", True), ("OUT M9040", False), ("MOV K300 D9000", False), ("OUT M9200", False),
])
def test_read_only_special_devices(line, warns):
    assert ("W212" in codes(f"LD X0\n{line}\nEND\n")) is warns
    assert "W212" not in codes(f"LD {line.split()[-1]}\nOUT Y0\nEND\n" if line.startswith(("OUT", "SET"))
                               else "LD X0\nMOV D9010 D0\nEND\n")  # reading is fine


# ------------------------------------------------------------------ labels: names, END

def test_named_labels():
    il = "LD X0\nCJ SKIP_FILL\nLD X1\nOUT Y0\nSKIP_FILL:\nLD X2\nCALL EMERGENCY\nFEND\nEMERGENCY:\nLD X3\nOUT Y1\nSRET\nEND\n"
    assert codes(il) == []
    assert codes(il.replace("CJ SKIP_FILL", "CJ NOWHERE"), "error") == ["E304"]
    assert codes(il.replace("EMERGENCY", "EMERGENCY_STOP_1"), "error") == []  # 16 characters
    assert "E203" in codes(il.replace("EMERGENCY", "EMERGENCY_STOP_12"))  # 17; 16 at most (2-10)
    assert codes(il.replace("LD X2", "SKIP_FILL:\nLD X2"), "error") == ["E303"]


def test_named_labels_take_free_p_numbers():
    src, _ = decode("t.il", b"LD X0\nCJ P1023\nCJ LOOP\nP1023:\nLOOP:\nEND\n")
    m = check_texts([src], VS).modules[0]
    assert [i.operands[0].number for i in m.instrs if i.spec.op == "cj"] == [1023, 1022]


def test_names_are_not_operands_or_mnemonics():
    assert "E103" in codes("LD X0\nCJ P1\nX1:\nP1:\nEND\n")  # X1 reads as a device


def test_p63_and_p255_are_end():
    assert codes("LD X0\nCJ P63\nLD X1\nOUT Y0\nLD X2\nCJ P255\nEND\n") == []
    assert "E303" in codes("LD X0\nCJ P63\nP63\nEND\n")      # it cannot label a line
    assert "E305" in codes("LD X0\nCALL P63\nFEND\nEND\n")   # CJ only
    assert "E304" in codes("LD X0\nCJ P64\nEND\n")          # an ordinary P needs its label


def test_nc5_has_neither_names_nor_end_labels():
    nc5 = load_target("nc5")
    src, _ = decode("t.il", b"LD X0\nCJ P63\nEND\n")
    assert "E304" in [d.code for d in check_texts([src], nc5).diagnostics]
    src, _ = decode("t.il", b"LD X0\nCJ LOOP\nLOOP:\nEND\n")
    assert {"E215", "E103"} <= {d.code for d in check_texts([src], nc5).diagnostics}


def test_w217_foreign_specials_read_but_never_written(tmp_path):
    """FX M8000 / Delta M1002 / FX D8010 read and never written: W217 naming the VS device;
    written by the program (an ordinary use), or a Delta number without a VS counterpart: none."""
    from conftest import run_mlc

    (tmp_path / "p.il").write_text("LD M8000\nOUT Y0\nLD M1002\nOUT Y1\nLD M8100\nOUT Y2\nLD X0\nOUT M8100\n"
                                   "MOV D8010 D0\nLD M1500\nOUT Y3\nEND\n", "utf-8")
    r = run_mlc("check", "--target", "vs", "p.il", cwd=tmp_path)
    found = [line for line in r.err.splitlines() if "W217" in line]
    assert len(found) == 3, r.err
    assert "M8000 is read but never written" in found[0] and "M9000" in found[0]
    assert "M1002" in found[1] and "M9002" in found[1] and "D8010" in found[2] and "D9010" in found[2]
    assert "M8100" not in r.err.split("W217")[-1].split("\n")[0] and "M1500" not in r.err


def test_w217_foreign_special_settings_written_but_never_read(tmp_path):
    """The FX Modbus-slave set-up of public GX Works2 listings, `LD M8002 / MOV H0C87 D8120 /
    MOV K1 D8121`: port format and station written for the CPU, never read by the program.
    On the VS D8120 is an ordinary register, so the port is never set: W217 at each write.
    A register of the range the program also reads is ordinary use: no warning."""
    from conftest import run_mlc

    (tmp_path / "p.il").write_text("LD M9002\nMOV H0C87 D8120\nMOV K1 D8121\nMOV K5 D8200\n"
                                   "LD X0\nMOV D8200 D0\nEND\n", "utf-8")
    r = run_mlc("check", "--target", "vs", "p.il", cwd=tmp_path)
    found = [line for line in r.err.splitlines() if "W217" in line]
    assert [f.split(":")[1] for f in found] == ["2", "3"], r.err
    assert "D8120 is written but never read" in found[0] and "no known counterpart" in found[0]
    assert "D8121" in found[1] and "D8200" not in r.err
