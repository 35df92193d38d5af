"""GX Works2 projects (.gxw, mlctool/gxw.py, `mlc import X.gxw`): the public notes' token bytes
decode as the notes say; IL -> .gxw (the fixture writer tests/gxwkit.py) -> import gives the
IL back with the same step addresses, on the corpus's subset and on generated programs;
damaged and hostile files give a diagnostic with a code, never a traceback or a hang."""

from __future__ import annotations

import io
import re
import struct
from pathlib import Path

import gxwkit
import olefile
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from conftest import run_mlc
from mlctool.gxw import GxwError, decode_pou, read_program
from mlctool.imports import import_file, import_project
from mlctool.targetapi import load_target

VS = load_target("vs")
CORPUS = Path(__file__).resolve().parent / "corpus"


def _pou(hexes: str) -> bytes:
    return gxwkit.pou(bytes.fromhex(hexes))


def _decoded(hexes: str) -> list[str]:
    return [" ".join([i.mnemonic, *i.operands]) for i in decode_pou(_pou(hexes), "P")]


# --- the notes' bytes (written by hand from docs/process/research/gxw_reverse_engineering.md) --

NOTES = {
    # 37_SERIES_X1_M1_Y1
    "03 00 03 04 9C 01 04 03 0C 03 04 90 01 04 03 20 03 04 9D 01 04 03 34 03":
        ["LD X1", "AND M1", "OUT Y1", "END"],
    # 44_BRANCH_ORB
    "03 00 03 04 9C 01 04 03 0C 03 04 90 01 04 03 00 03 04 9C 02 04 03 0C 03 04 90 02 04 03 18 03 "
    "03 20 03 04 9D 01 04 03 34 03": ["LD X1", "AND M1", "LD X2", "AND M2", "ORB", "OUT Y1", "END"],
    # 39 LDI, 40 ANDI, 43 ORI, 45 ANB, 23 SET, 24 RST
    "03 01 03 04 9C 01 04 03 0D 03 04 90 01 04 03 07 03 04 9C 02 04 03 19 03 03 23 03 04 90 01 04 "
    "03 24 03 04 90 01 04 03 34 03": ["LDI X1", "ANI M1", "ORI X2", "ANB", "SET M1", "RST M1", "END"],
    # 41_TIMER_T0_K10, 47 C1: the T/C output form
    "03 00 03 04 9C 01 04 04 21 03 04 04 C2 00 04 04 E8 0A 04 04 21 03 04 04 C5 01 04 04 E8 0A 04 03 34 03":
        ["LD X1", "OUT T0 K10", "OUT C1 K10", "END"],
    # octal X: X10 -> 0x08, X100 -> 0x40; K256, D256 two bytes
    "03 00 03 04 9C 08 04 03 06 03 04 9C 40 04 05 4C 05 00 05 05 E8 00 01 05 05 A8 00 01 05 03 34 03":
        ["LD X10", "OR X100", "MOV K256 D256", "END"],
    # MOV K-1 D1; DMOV K-1 D0; DMOV K32768 D0; BMOV D0 D10 K5; H10
    "05 4C 05 00 05 05 E8 FF FF 05 04 A8 01 04 05 4C 09 01 05 07 E9 FF FF FF FF 07 04 A8 00 04 "
    "05 4C 09 01 05 05 E9 00 80 05 04 A8 00 04 05 4C 07 06 05 04 A8 00 04 04 A8 0A 04 04 E8 05 04 "
    "05 4C 05 00 05 04 EA 10 04 04 A8 01 04 03 34 03":
        ["MOV K-1 D1", "DMOV K-1 D0", "DMOV K32768 D0", "BMOV D0 D10 K5", "MOV H10 D1", "END"],
    # ADD SUB MUL DIV D1 D2 D3, DADD DSUB D0 D2 D4, INC DEC D1
    "05 49 07 28 05 04 A8 01 04 04 A8 02 04 04 A8 03 04 05 49 07 2A 05 04 A8 01 04 04 A8 02 04 04 A8 03 04 "
    "05 49 07 2C 05 04 A8 01 04 04 A8 02 04 04 A8 03 04 05 49 07 2E 05 04 A8 01 04 04 A8 02 04 04 A8 03 04 "
    "05 49 0D 29 05 04 A8 00 04 04 A8 02 04 04 A8 04 04 05 49 0D 2B 05 04 A8 00 04 04 A8 02 04 04 A8 04 04 "
    "05 4A 03 00 05 04 A8 01 04 05 4A 03 02 05 04 A8 01 04 03 34 03":
        ["ADD D1 D2 D3", "SUB D1 D2 D3", "MUL D1 D2 D3", "DIV D1 D2 D3", "DADD D0 D2 D4", "DSUB D0 D2 D4",
         "INC D1", "DEC D1", "END"],
}


@pytest.mark.parametrize("hexes", NOTES)
def test_the_notes_token_streams_decode_as_the_notes_say(hexes):
    assert _decoded(hexes) == NOTES[hexes]
    # and the fixture writer writes exactly those bytes back
    lines = [(w.split()[0], w.split()[1:]) for w in NOTES[hexes]]
    assert gxwkit.program(lines) == _pou(hexes)


def test_application_widths_are_the_vendors_step_counts_and_the_targets():
    """The header's width (1 + 2 x word slots) is GX Works2's step count of the instruction; the
    target's step convention counts the same, so the imported addresses are the vendor's."""
    text = ".dialect fx\nLD X0\nMOV K10 D1\nDMOV K32768 D0\nBMOV D0 D10 K5\nADD D1 D2 D3\nDMUL D0 D2 D4\nINC D1\nEND\n"
    prog = read_program(gxwkit.il_project(text, VS))
    assert [(i.mnemonic, i.width) for i in prog.instructions if i.width] == \
        [("MOV", 5), ("DMOV", 9), ("BMOV", 7), ("ADD", 7), ("DMUL", 13), ("INC", 3)]
    il, _, diags = import_project("p.gxw", gxwkit.il_project(text, VS), VS)
    assert il == text and diags == []
    # a MOV whose header stores another width is refused: width = 1 + 2 x word slots
    with pytest.raises(GxwError) as e:
        decode_pou(_pou("05 4C 07 00 05 04 E8 0A 04 04 A8 01 04 03 34 03"), "MAIN.Program.pou")
    assert e.value.code == "E919" and "offset 0x4F" in e.value.message and "width 7" in e.value.message


# --- round trips ----------------------------------------------------------------------------

SUBSET = {"LD", "LDI", "AND", "ANI", "OR", "ORI", "ORB", "ANB", "OUT", "SET", "RST", "MOV", "DMOV", "BMOV",
          "ADD", "SUB", "MUL", "DIV", "DADD", "DSUB", "DMUL", "DDIV", "INC", "DEC"}


def _subset_rungs(il: str) -> list[list[str]]:
    """The rungs of an IL program made of the subset's instructions alone (comments dropped:
    the subset has no line statements), in order."""
    rungs: list[list[str]] = []
    for line in il.splitlines():
        code = line.split(";")[0].strip()
        if not code or code.startswith("."):
            continue
        words = code.split()
        if words[0] in ("LD", "LDI", "LDF", "LDP", "LD=") or not rungs or code.endswith(":"):
            if not rungs or rungs[-1] and rungs[-1][-1].split()[0] not in ("LD", "LDI", "AND", "ANI", "OR", "ORI"):
                rungs.append([])
        rungs[-1].append(code)
    return [r for r in rungs if r and _in_subset(r)]


def _in_subset(rung: list[str]) -> bool:
    if any(line.split()[0] not in SUBSET for line in rung):
        return False
    try:
        gxwkit.program(gxwkit.il_lines(".dialect fx\n" + "".join(f"{line}\n" for line in rung) + "END\n", VS))
    except ValueError:  # an operand outside the subset (S20, LD T0), or a rung the checker refuses
        return False
    return True


# the FX programs of the corpus (GX exports); mrd_compare_blocks.il has no rung of the subset
# (MPS and compare contacts in each), the Delta exports are no GX Works2 programs
CORPUS_FILES = sorted(p.name for p in CORPUS.glob("*.csv") if not p.name.startswith("COMMENT")
                      and p.name not in ("delta.csv", "wplsoft.csv"))


@pytest.mark.parametrize("name", CORPUS_FILES)
def test_corpus_subset_round_trips_with_the_vendors_steps(name, tmp_path):
    il, _, _ = import_file(str(CORPUS / name), VS)
    rungs = _subset_rungs(il)
    assert rungs, "no rung of the subset"
    text = ".dialect fx\n" + "".join(line + "\n" for rung in rungs for line in rung) + "END\n"
    data = gxwkit.il_project(text, VS)
    back, fmt, diags = import_project("p.gxw", data, VS)
    assert fmt == "gxw" and back == text, [d.message for d in diags]
    assert not [d for d in diags if d.code == "W107"]
    (tmp_path / "p.gxw").write_bytes(data)
    r = run_mlc("import", "p.gxw", "-o", "p.il", cwd=tmp_path)
    assert r.code == 0 and (tmp_path / "p.il").read_text("utf-8") == text, r.err
    r = run_mlc("build", "--target", "vs", "p.il", "-o", "p.mlx", "--listing", "p.lst", cwd=tmp_path)
    assert r.code == 0, r.err


def test_the_corpus_steps_are_the_vendors():
    """The GX export's step column (GX Works2's own count) against the widths the project stores."""
    rows = [line.split("\t") for line in (CORPUS / "gxworks2_en.csv").read_bytes().decode("utf-16").splitlines()]
    steps = [(int(r[0].strip('"')), r[2].strip('"')) for r in rows[3:] if r[0].strip('"').isdigit()]
    mov = next(k for k, (_, m) in enumerate(steps) if m == "MOV")
    data = gxwkit.il_project(".dialect fx\nLD M9002\nMOV K5 D10\nEND\n", VS)
    width = read_program(data).instructions[1].width
    assert steps[mov + 1][0] - steps[mov][0] == width == 5


_BIT = st.one_of(st.integers(0, 0o177).map(lambda n: f"X{n:o}"), st.integers(0, 0o177).map(lambda n: f"Y{n:o}"),
                 st.integers(0, 1535).map(lambda n: f"M{n}"))
_COIL = st.one_of(st.integers(0, 0o177).map(lambda n: f"Y{n:o}"), st.integers(0, 1535).map(lambda n: f"M{n}"))
_D = st.integers(0, 7999).map(lambda n: f"D{2 * (n // 2)}")
_WORD = st.one_of(_D, st.integers(-32768, 32767).map(lambda n: f"K{n}"), st.integers(0, 0xFFFF).map(lambda n: f"H{n:X}"))
_DWORD = st.one_of(_D, st.integers(-(2**31), 2**31 - 1).map(lambda n: f"K{n}"))


def _no_zero_divisor(mnemonic: str, ops: list[str]) -> list[str]:
    """A constant divisor of 0 is E206 at check (the CPU does not divide): the programs the
    round trip builds divide by K1 there instead."""
    if mnemonic in ("DIV", "DDIV") and ops[1] in ("K0", "H0"):
        return [ops[0], "K1", *ops[2:]]
    return ops


@st.composite
def _rung(draw) -> list[str]:
    out = [f"{draw(st.sampled_from(['LD', 'LDI']))} {draw(_BIT)}"]
    for _ in range(draw(st.integers(0, 3))):
        kind = draw(st.sampled_from(["AND", "ANI", "OR", "ORI", "block"]))
        if kind == "block":
            out += [f"LD {draw(_BIT)}", f"AND {draw(_BIT)}", draw(st.sampled_from(["ORB", "ANB"]))]
        else:
            out.append(f"{kind} {draw(_BIT)}")
    for _ in range(draw(st.integers(1, 2))):
        kind = draw(st.sampled_from(["coil", "tc", "word", "dword", "one"]))
        if kind == "coil":
            out.append(f"{draw(st.sampled_from(['OUT', 'SET', 'RST']))} {draw(_COIL)}")
        elif kind == "tc":
            out.append(f"OUT {draw(st.sampled_from(['T', 'C']))}{draw(st.integers(0, 199))} K{draw(st.integers(1, 32767))}")
        elif kind == "word":
            m = draw(st.sampled_from(["MOV", "ADD", "SUB", "MUL", "DIV"]))
            ops = [draw(_WORD)] + [draw(_WORD) for _ in range(1 if m == "MOV" else 2)][:-1] + [draw(_D)]
            out.append(" ".join([m, *_no_zero_divisor(m, ops)]))
        elif kind == "dword":
            m = draw(st.sampled_from(["DMOV", "DADD", "DSUB", "DMUL", "DDIV"]))
            ops = [draw(_DWORD)] + ([draw(_DWORD)] if m != "DMOV" else []) + [draw(_D)]
            out.append(" ".join([m, *_no_zero_divisor(m, ops)]))
        else:
            out.append(f"{draw(st.sampled_from(['INC', 'DEC']))} {draw(_D)}")
    return out


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(_rung(), min_size=1, max_size=4), st.lists(st.integers(1, 9999), min_size=1, max_size=1),
       st.booleans(), st.sampled_from(["utf-8", "utf-16"]))
def test_generated_programs_round_trip(rungs, number, diffgram, encoding):
    text = ".dialect fx\n" + "".join(f"{line}\n" for rung in rungs for line in rung) + "END\n"
    data = gxwkit.il_project(text, VS, numbers={"MAIN": number[0]}, diffgram=diffgram, encoding=encoding)
    back, _, diags = import_project("p.gxw", data, VS)
    assert back == text, [d.message for d in diags]
    assert not [d for d in diags if d.severity != "note"], [d.message for d in diags]


# --- the container writer -------------------------------------------------------------------

@settings(max_examples=15, deadline=None)
@given(st.dictionaries(st.text("abcXYZ_0123456789", min_size=1, max_size=31),
                       st.sampled_from([0, 1, 63, 64, 65, 511, 512, 4095, 4096, 4097, 9000]).map(lambda n: bytes(
                           (k * 7 + n) % 251 for k in range(n))), max_size=12))
def test_the_compound_file_writer_is_read_back_by_olefile(streams):
    ole = olefile.OleFileIO(io.BytesIO(gxwkit.compound_file(streams)), raise_defects=olefile.DEFECT_INCORRECT)
    assert sorted(e[0] for e in ole.listdir()) == sorted(streams)
    assert {n: ole.openstream(n).read() for n in streams} == streams


# --- the project: metadata, choices, warnings -------------------------------------------------

SIMPLE = [("LD", ["X0"]), ("OUT", ["Y0"]), ("END", [])]


def _codes(data: bytes, **kw) -> list[str]:
    il, _, diags = import_project("p.gxw", data, VS, **kw)
    return [d.code for d in diags]


def test_programs_are_found_by_name_never_by_stream_number(tmp_path):
    two = {"MAIN": gxwkit.program(SIMPLE), "SUB": gxwkit.program([("LD", ["X1"]), ("OUT", ["Y1"]), ("END", [])])}
    data = gxwkit.project(two, numbers={"MAIN": 40, "SUB": 16})
    assert _codes(data) == ["E922"]
    il, _, _ = import_project("p.gxw", data, VS, program="SUB")
    assert il == ".dialect fx\nLD X1\nOUT Y1\nEND\n"
    (tmp_path / "p.gxw").write_bytes(data)
    r = run_mlc("import", "p.gxw", cwd=tmp_path)
    assert r.code == 2 and "E922" in r.err and "MAIN, SUB" in r.err and "--program" in r.err
    r = run_mlc("import", "--program", "MAIN", "p.gxw", cwd=tmp_path)
    assert r.code == 0 and r.out == ".dialect fx\nLD X0\nOUT Y0\nEND\n"
    r = run_mlc("import", "--program", "NONE", "p.gxw", cwd=tmp_path)
    assert r.code == 2 and "E916" in r.err and "'NONE'" in r.err
    (tmp_path / "p.csv").write_text("LD X0\nEND\n", "utf-8")
    r = run_mlc("import", "--program", "MAIN", "p.csv", cwd=tmp_path)
    assert r.code == 2 and "--program" in r.err
    # the stream listed but absent from _hdb; metadata missing or hostile
    assert _codes(gxwkit.project({"MAIN": gxwkit.program(SIMPLE)}, extra={})) == []
    outer = olefile.OleFileIO(io.BytesIO(data))
    parts = {n[0]: outer.openstream(n[0]).read() for n in outer.listdir()}
    for change in ({"_hdb": gxwkit.compound_file({"16": two["SUB"]})},
                   {"projectdatalist.xml": b"<DSPROJECTDATA><D_Projectdata><szName>MAIN.Program.pou</szName>"},
                   {"projectdatalist.xml": b'<!DOCTYPE x [<!ENTITY a "aaaa">]><DSPROJECTDATA/>'},
                   {"projectdatalist.xml": b"<DSPROJECTDATA><D_Projectdata><szName>MAIN.Program.pou</szName>"
                                           b"<iID>x</iID></D_Projectdata></DSPROJECTDATA>"}):
        broken = gxwkit.compound_file({k: v for k, v in (parts | change).items()})
        with pytest.raises(GxwError) as e:
            read_program(broken, "MAIN")
        assert e.value.code == "E916", e.value.message
    with pytest.raises(GxwError) as e:
        read_program(gxwkit.compound_file({k: v for k, v in parts.items() if k != "_hdb"}))
    assert e.value.code == "E916" and "'_hdb'" in e.value.message


def test_history_and_comments_are_said(tmp_path):
    main = gxwkit.program(SIMPLE)
    assert _codes(gxwkit.project({"MAIN": main}, history={"MAIN.Program.pou": {"iFileSize": "411"}})) == ["W913"]
    data = gxwkit.project({"MAIN": main}, comments=b"\x00" * 82)
    assert _codes(data) == ["W912"]
    assert _codes(data, comments={"X0": "start"}) == []
    (tmp_path / "p.gxw").write_bytes(data)
    (tmp_path / "c.csv").write_text('"COMMENT"\n"Device Name"\t"Comment"\n"X000"\t"start"\n', "utf-16")
    r = run_mlc("import", "--comments", "c.csv", "p.gxw", cwd=tmp_path)
    assert r.code == 0 and "LD X0 ; X0 start" in r.out and "W912" not in r.err


def test_the_fx_dialect_path_of_the_csv_imports(tmp_path):
    """M8000 -> M9000 (N910), FX3U's M8411 is E911 (exit 1) naming the POU and offset."""
    data = gxwkit.project({"MAIN": gxwkit.program([("LD", ["M8411"]), ("MOV", ["H1097", "D100"]), ("END", [])])})
    (tmp_path / "p.gxw").write_bytes(data)
    r = run_mlc("import", "p.gxw", "-o", "p.il", cwd=tmp_path)
    assert r.code == 1 and "E911" in r.err and "MAIN.Program.pou offset 0x4F: M8411" in r.err
    assert not (tmp_path / "p.il").exists()


# --- damaged and hostile files ----------------------------------------------------------------

def _refused(data: bytes) -> GxwError:
    with pytest.raises(GxwError) as e:
        read_program(data)
    return e.value


@pytest.mark.parametrize(("hexes", "code", "where"), [
    ("03 00 03 04 9C 01 05 03 34 03", "E918", "offset 0x55: closing sentinel"),  # wrong sentinel
    ("03 00 03 02 9C 03 34 03", "E918", "offset 0x52: token length 2"),
    ("03 00 03 09 9C 01", "E918", "offset 0x52: a token of 9 bytes runs past"),
    ("03 02 03 04 9C 01 04 03 34 03", "E919", "offset 0x4F: token [02]: basic instruction opcode 02"),
    ("05 49 07 30 05 04 A8 01 04 04 A8 02 04 04 A8 03 04 03 34 03", "E919", "family 49 subtype 30"),
    ("04 9C 01 04 03 34 03", "E919", "an operand where an instruction was expected"),
    ("03 00 03 04 C1 00 04 03 34 03", "E920", "offset 0x52: LD's contact operand is type C1"),  # LD T0: unsampled
    ("03 00 03 04 93 00 04 03 34 03", "E920", "type 93"),  # F0, an annunciator (MC F 0x93): not in the registry
    ("03 20 03 04 C2 00 04 03 34 03", "E920", "type C2 (T)"),  # OUT T0 without its preset: not a coil
    ("05 4C 09 01 05 04 EA 10 04 04 A8 00 04 03 34 03", "E920", "type EA (H)"),  # H in a 32-bit slot
    ("05 4C 05 00 05 07 E8 01 02 03 04 07 04 A8 00 04 03 34 03", "E920", "K operand of 4 value bytes"),
    ("03 00 03 04 9C 01 04 03 20 03", "E920", "OUT lacks its operand 1 of 1"),
    ("03 00 03 04 9C 01 04 04 21 03 04 04 C5 EB 04 04 E8 64 04 03 34 03", "E920", "OUT C235: the registry takes C0-C199"),
    ("03 00 03 04 9C 01 04", "E921", "does not end with END"),
    ("03 34 03 03 34 03", "E921", "offset 0x52: tokens after END"),
])
def test_bad_tokens_are_refused_at_their_offset(hexes, code, where, tmp_path):
    e = _refused(gxwkit.project({"MAIN": _pou(hexes)}, numbers={"MAIN": 23}))
    assert e.code == code and where in e.message and e.message.startswith("MAIN.Program.pou (_hdb stream 23)"), \
        e.message
    (tmp_path / "p.gxw").write_bytes(gxwkit.project({"MAIN": _pou(hexes)}))
    r = run_mlc("import", "p.gxw", "-o", "p.il", cwd=tmp_path)
    assert r.code == 2 and code in r.err and not (tmp_path / "p.il").exists()


def test_a_pou_of_another_layout_is_refused():
    good = gxwkit.program(SIMPLE)
    bad_length = good[:0x37] + struct.pack("<I", 99) + good[0x3B:]
    assert "offset 0x37: length field 99" in _refused(gxwkit.project({"MAIN": bad_length})).message
    bad_trailer = good[:-3] + b"\x01" + good[-2:]
    assert "trailer is not zero" in _refused(gxwkit.project({"MAIN": bad_trailer})).message
    assert _refused(gxwkit.project({"MAIN": good[:40]})).code == "E917"


def test_a_pou_ending_in_20_zero_bytes_is_read_as_public_projects_are(tmp_path):
    # GX Works2 projects in public repositories (docs/formats.md) end the program POU in 20 zero
    # bytes, the length fields still the token length + 20; they were refused (E917) for the 24
    # of the notes' samples.
    (tmp_path / "p.gxw").write_bytes(gxwkit.project({"MAIN": gxwkit.pou(b"".join(gxwkit.instruction(m, o) for m, o in SIMPLE), trailer=20)}))
    r = run_mlc("import", "p.gxw", "-o", "p.il", cwd=tmp_path)
    assert r.code == 0, r.err
    twin = tmp_path / "twin"
    twin.mkdir()
    (twin / "p.gxw").write_bytes(gxwkit.project({"MAIN": gxwkit.program(SIMPLE)}))
    assert run_mlc("import", "p.gxw", "-o", "p.il", cwd=twin).code == 0
    assert (tmp_path / "p.il").read_text() == (twin / "p.il").read_text()
    # Neither 20 nor 24 after the tokens the fields say, or the two fields differing: still E917.
    for cut in (4, 8):
        short = gxwkit.pou(b"".join(gxwkit.instruction(m, o) for m, o in SIMPLE), trailer=20)[:-cut]
        e = _refused(gxwkit.project({"MAIN": short}))
        assert e.code == "E917" and f"leaves {20 - cut} bytes after the tokens" in e.message, e.message
    good = gxwkit.program(SIMPLE)
    e = _refused(gxwkit.project({"MAIN": good[:0x3B] + struct.pack("<I", 7) + good[0x3F:]}))
    assert "length field" in e.message and "the one at 0x3B says 7" in e.message, e.message


def _entry(data: bytes, name: str):
    return olefile.OleFileIO(io.BytesIO(data)).root.kids_dict[name.lower()]


def test_damaged_containers_are_e915_never_a_traceback():
    data = gxwkit.project({"MAIN": gxwkit.program(SIMPLE)}, extra={"99": b"\x01" * 6000})  # _hdb in sectors
    fat_at = (struct.unpack_from("<I", data, 0x4C)[0] + 1) * 512  # the first FAT sector
    hdb = _entry(data, "_hdb")
    assert hdb.size >= 4096
    loop = bytearray(data)
    struct.pack_into("<I", loop, fat_at + 4 * (hdb.isectStart + 1), hdb.isectStart)  # _hdb's chain loops
    dir_start = struct.unpack_from("<I", data, 0x30)[0]
    huge = bytearray(data)
    struct.pack_into("<I", huge, (dir_start + 1) * 512 + 128 * hdb.sid + 0x78, 0xFFFFFF00)  # _hdb's size
    out_of_file = bytearray(data)
    struct.pack_into("<I", out_of_file, 0x30, 0x00FFFFFF)  # the directory far outside the file
    cases = {"loop": (bytes(loop), "the sector chain of stream '_hdb' loops back to sector"),
             "huge": (bytes(huge), "declares 4,294,967,040 bytes"),
             "outside": (bytes(out_of_file), "sector index out of range"),
             "truncated": (data[:600], "not a readable compound file"),
             "header only": (data[:512], "not a readable compound file"),
             "short": (b"\xd0\xcf\x11\xe0", "offset 0: d0 cf 11 e0 is not the compound-file signature"),
             "zip": (b"PK\x03\x04" + bytes(600), "offset 0: 50 4b 03 04")}
    for name, (damaged, said) in cases.items():
        e = _refused(damaged)
        assert e.code == "E915" and said in e.message, (name, e.message)
    # a loop in the nested file's MiniFAT (the program's own chain)
    inner = gxwkit.compound_file({"12": gxwkit.program(SIMPLE) + bytes(200)})
    pou = _entry(inner, "12")
    minifat_at = (struct.unpack_from("<I", inner, 0x3C)[0] + 1) * 512
    looped = bytearray(inner)
    struct.pack_into("<I", looped, minifat_at + 4 * (pou.isectStart + 1), pou.isectStart)
    outer = olefile.OleFileIO(io.BytesIO(data))
    parts = {n[0]: outer.openstream(n[0]).read() for n in outer.listdir()}
    e = _refused(gxwkit.compound_file(parts | {"_hdb": bytes(looped)}))
    assert e.code == "E915" and "the mini sector chain of stream '12' loops" in e.message, e.message
    # the tail of the last sector missing (GX Works2 writes files so): read as it is
    trimmed = data.rstrip(b"\x00")
    assert len(trimmed) % 512 and read_program(trimmed).instructions[-1].mnemonic == "END"


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.data())
def test_mutated_projects_give_a_code_or_a_program(data):
    base = gxwkit.project({"MAIN": gxwkit.program([("LD", ["X0"]), ("MOV", ["K10", "D1"]), ("END", [])])})
    raw = bytearray(base)
    for _ in range(data.draw(st.integers(1, 8))):
        raw[data.draw(st.integers(0, len(raw) - 1))] = data.draw(st.integers(0, 255))
    cut = data.draw(st.one_of(st.none(), st.integers(0, len(raw))))
    try:
        read_program(bytes(raw[:cut]))
    except GxwError as e:
        assert re.fullmatch(r"[EW]9[12][0-9]", e.code)


@settings(max_examples=60, deadline=None)
@given(st.binary(max_size=200))
def test_any_token_stream_decodes_or_is_refused(body):
    try:
        decode_pou(gxwkit.pou(body), "P")
    except GxwError as e:
        assert e.code in ("E917", "E918", "E919", "E920", "E921")


# --- the registry against the target (the DECISION of mlctool/gxw_tokens.toml) -----------------

_KIND = {"M": "M", "S": "S", "X": "X", "Y": "Y", "D": "D", "T": "T", "C": "C", "K": "K", "H": "H", "P": "P"}
# the program structure every entry's rung sits in: CJ jumps to P1 in the main routine, CALL
# calls the subroutine P2 after FEND
_TAIL = "P1:\nLD X0\nMPS\nOUT Y0\nMRD\nOUT Y1\nMPP\nOUT Y2 ; a note\nFEND\nP2:\nLD X1\nOUT Y3\nSRET\nEND\n"


def _entries():
    """Every header of the registry: (its payload as stored, mnemonic, slots, stored width or None)."""
    from mlctool.gxw import registry

    reg = registry()
    out = [(bytes([op]), f.mnemonic, f.slots, None) for op, f in reg.basic.items()]
    out += [(p, f.mnemonic, f.slots, p[1]) for p, f in reg.short.items()]
    for (family, subtype, *form), f in reg.application.items():
        width = 1 + 2 * sum(reg.slot[s].words for s in f.slots)
        out.append((bytes([family, width, subtype, *form]), f.mnemonic, f.slots, width))
    return reg, out


def _sample(reg, slot: str, kinds: set[str], position: int) -> str:
    """An operand of the slot's first type the target's operand takes there."""
    for t in reg.slot[slot].types:
        device = reg.operand[t]["device"]
        if device in kinds:
            lo = reg.slot[slot].numbers.get(t, (0, 0))[0]
            return {"D": f"D{10 * position}", "K": "K2", "H": "H2", "P": "P1"}.get(device, f"{device}{lo}")
    raise AssertionError(f"slot {slot}: no type the target takes")


def _line(reg, mnemonic: str, slots, taken) -> str:
    """The entry as an IL line with sample operands (a CALL calls the subroutine P2)."""
    line = " ".join([mnemonic, *(_sample(reg, s, taken[k], k) for k, s in enumerate(slots))])
    return line.replace("P1", "P2") if mnemonic.startswith("CALL") else line


def _rung(line: str) -> str:
    """A rung the checker takes around one instruction (its class decides the contacts it needs)."""
    cls = VS.variants_of(line.split()[0])[0].cls
    if cls in ("mps", "mrd", "mpp"):
        return ""
    return {"load": f"{line}\nOUT Y0\n", "and": f"LD X0\n{line}\nOUT Y0\n", "or": f"LD X0\n{line}\nOUT Y0\n",
            "anb": f"LD X0\nLD X1\n{line}\nOUT Y0\n", "orb": f"LD X0\nLD X1\n{line}\nOUT Y0\n"
            }.get(cls, f"LD X0\n{line}\n")


def test_every_registry_entry_is_the_targets_instruction_with_its_steps():
    """(2) each entry's operand slots are those of target vs's instruction of that name: the count,
    and every type's device kind one the vs operand takes; (3) its stored width (a 2-byte header's
    second byte, an application header's 1 + 2 x word slots) is the vs step count of it."""
    reg, entries = _entries()
    lines, widths = [], []
    for payload, mnemonic, slots, width in entries:
        variants = [v for v in VS.variants_of(mnemonic) if len(v.operands) == len(slots)]
        assert variants, f"{mnemonic}: no vs instruction of {len(slots)} operands"
        taken = [set().union(*(v.operands[k].kinds for v in variants)) for k in range(len(slots))]
        for k, slot in enumerate(slots):
            kinds = {_KIND[reg.operand[t]["device"]] for t in reg.slot[slot].types}
            kinds |= {"Kn" + reg.operand[t]["device"] for t in reg.slot[slot].digits}  # digit groups
            assert kinds <= taken[k], f"{payload.hex(' ')} {mnemonic} operand {k + 1}: {kinds - taken[k]} not vs's"
        if mnemonic in ("END", "FEND", "SRET"):
            continue  # program structure: their steps are the convention's 1 (tests below place them)
        lines.append(_line(reg, mnemonic, slots, taken))
        widths.append((payload.hex(" "), width))
    from mlctool.check import check_texts
    from mlctool.syntax.source import SourceText

    text = "".join(_rung(line) for line in lines) + _TAIL
    result = check_texts([SourceText("p.il", text)], VS)
    assert not [d.message for d in result.diagnostics if d.severity == "error"]
    steps = {" ".join([i.spec.mnemonic, *map(str, i.operands)]).upper(): i.steps for i in result.modules[0].instrs}
    for line, (payload, width) in zip(lines, widths):
        if width is not None:
            assert steps[line.upper()] == width, f"[{payload}] {line}: stored {width}, vs {steps[line.upper()]}"


def _every_entry_program() -> str:
    """IL with one rung for every registry entry (sample operands as above), a line statement
    with a byte outside ASCII, a note, labels, MPS/MRD/MPP, FEND, a subroutine, END."""
    reg, entries = _entries()
    lines = []
    for _, mnemonic, slots, _ in entries:
        if mnemonic in ("END", "FEND", "SRET"):
            continue
        variants = [v for v in VS.variants_of(mnemonic) if len(v.operands) == len(slots)]
        taken = [set().union(*(v.operands[k].kinds for v in variants)) for k in range(len(slots))]
        lines.append(_line(reg, mnemonic, slots, taken))
    return ".dialect fx\n; every registry entry, caf\\xE9\n" + "".join(_rung(line) for line in lines) + _TAIL


def test_every_registry_entry_round_trips_through_a_project_and_a_body():
    """Each entry written by the fixture writers (the registry read backwards: 1-byte, 2-byte and
    application headers, with and without a form byte, text records) reads back as the IL written;
    in a .wpg the target's steps plus the fill make the memory exactly (no W916), and no stored
    width differs from the target's count (no W107)."""
    import wpgkit

    from mlctool.imports import import_wpg

    text = _every_entry_program()
    il, _, diags = import_project("p.gxw", gxwkit.il_project(text, VS), VS)
    assert il == text and [d.code for d in diags] == []
    body = wpgkit.il_body(text, VS, memory=4000)
    il, _, diags = import_wpg("p.wpg", body, VS)
    assert il == text and [d.code for d in diags] == []
    assert b"\x80\x00every registry entry, caf\xe9" in body  # the statement, its byte restored
    assert b"\x9d\x02\x04\x0a\x82\x00a note\x0a" in body  # OUT Y2's operand, then its note


@pytest.mark.parametrize(("hexes", "said"), [
    # a text record of each public kind: a comment line, no instruction, no step
    ("05 82 00 41 05 03 00 03 04 9C 01 04 07 80 00 61 5C F1 07 03 20 03 04 9D 01 04 03 34 03",
     ["; A", "LD X1", "; a\\x5C\\xF1", "OUT Y1", "END"]),
])
def test_text_records_are_comment_lines_with_other_bytes_kept_as_escapes(hexes, said):
    prog = decode_pou(_pou(hexes), "P")
    assert [f"; {i.text}" if i.text is not None else " ".join([i.mnemonic, *i.operands]) for i in prog] == said


@pytest.mark.parametrize(("hexes", "where"), [
    ("05 80 02 41 05 03 34 03", "token [80 02 41]"),  # a Q CPU's text record (its second byte not 00)
    ("04 00 03 04 04 F2 01 04 04 A8 00 04 03 34 03", "instruction 00 of 3 steps"),  # LD D0.1: no source decodes it
    ("04 2C 03 04 04 D2 00 04 04 90 64 04 03 34 03", "instruction 2C of 3 steps"),  # MC N0 M100: no source names it
])
def test_headers_no_source_names_stay_refused(hexes, where):
    with pytest.raises(GxwError) as e:
        decode_pou(_pou(hexes), "P")
    assert e.value.code == "E919" and where in e.value.message, e.value.message


def test_special_relays_of_either_code_are_mapped_by_the_fx_specials():
    """M8002 as GX stores it in programs (90, its number) and as its comment files store it (91,
    the MC protocol's SM): both LD M8002, mapped to the VS's M9002; 91 below 8000 (a Q CPU's SM0)
    is no FX device."""
    hexes = "03 00 03 05 90 42 1F 05 03 06 03 05 91 42 1F 05 03 20 03 04 9D 00 04 03 34 03"
    assert _decoded(hexes) == ["LD M8002", "OR M8002", "OUT Y0", "END"]
    il, _, diags = import_project("p.gxw", gxwkit.project({"MAIN": _pou(hexes)}), VS)
    assert il == ".dialect fx\nLD M9002\nOR M9002\nOUT Y0\nEND\n" and [d.code for d in diags] == ["N910"]
    with pytest.raises(GxwError) as e:
        decode_pou(_pou("03 00 03 04 91 00 04 03 34 03"), "P")
    assert e.value.code == "E920" and "M0: the registry takes M8000-M8511" in e.value.message


def test_digit_groups_decode_and_round_trip_with_the_vendors_steps():
    """A digit group is the modifier [F1 n] and its bit device (MOV K4X0 D0 as a public body stores
    it), one word slot: MOV K4X0 D0 5 steps, DMOV K8M0 D2 9; K5 in a 16-bit slot, or a digit group
    of a destination's X, is refused."""
    assert _decoded("05 4C 05 00 05 04 F1 04 04 04 9C 00 04 04 A8 00 04 03 34 03") == ["MOV K4X0 D0", "END"]
    import wpgkit

    from mlctool.imports import import_wpg

    text = ".dialect fx\nLD X0\nMOV K4X0 D0\nBCD D14 K1M0\nDMOV K8M0 D2\nMOV D1 K4Y0\nEND\n"
    il, _, diags = import_wpg("p.wpg", wpgkit.il_body(text, VS), VS)
    assert il == text and diags == []
    for hexes, said in (("05 4C 05 00 05 04 F1 05 04 04 9C 00 04 04 A8 00 04 03 34 03", "K1-K4"),
                        ("05 4C 05 00 05 04 A8 00 04 04 F1 04 04 04 9C 00 04 03 34 03", "type 9C (X)")):
        with pytest.raises(GxwError) as e:
            decode_pou(_pou(hexes), "P")
        assert e.value.code == "E920" and said in e.value.message, e.value.message
