"""GX Developer program bodies (.wpg, mlctool/wpg.py, `mlc import X.wpg`): IL -> .wpg (the
fixture writer tests/wpgkit.py) -> import gives the IL back; the target's steps and the NOP
fill after END make the program memory's size, as on every public FX body (docs/formats.md);
each defect is a diagnostic with a code and the offset, exit 2, never a traceback."""

from __future__ import annotations

import struct
from pathlib import Path

import pytest
import wpgkit
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from conftest import run_mlc
from mlctool.check import check_texts
from mlctool.gxdeveloper import CPU_AT as CPU_FIELD
from mlctool.gxw import GxwError
from mlctool.imports import import_wpg
from mlctool.syntax.source import SourceText
from mlctool.targetapi import load_target
from mlctool.wpg import TOKENS, read_program

VS = load_target("vs")

PROGRAM = (".dialect fx\nLD X0\nOR M0\nANI X1\nOUT M0\nLD M0\nOUT T0 K50\nLD M1\nOUT Y0\n"
           "LD X2\nMOV K10 D0\nDADD D0 D2 D4\nEND\n")


def _built(il: str) -> list[tuple[int, int, str]]:
    result = check_texts([SourceText("p.il", il)], VS)
    assert not [d for d in result.diagnostics if d.severity == "error"]
    return [(ins.addr, ins.steps, ins.spec.mnemonic) for ins in result.modules[0].instrs]


def test_a_body_imports_with_the_vendors_step_count():
    """The decoded program is the IL written; the application headers' widths are the built
    instructions' steps (each the vendor's), and the built program plus the NOP fill is the
    memory the body was written for: the whole program's steps are GX Developer's."""
    data = wpgkit.il_body(PROGRAM, VS, memory=2000)
    prog = read_program(data)
    assert prog.cpu == "FX3U/FX3UC" and prog.instructions[0].offset == TOKENS
    built = _built(PROGRAM)
    assert [(i.mnemonic, i.width) for i in prog.instructions if i.width] == [("OUT", 3), ("MOV", 5), ("DADD", 13)]
    assert [s for _, s, m in built if m in ("MOV", "DADD") or s == 3] == [3, 5, 13]
    last_address, last_steps, _ = built[-1]
    assert last_address + last_steps + prog.fill == 2000
    il, fmt, diags = import_wpg("p.wpg", data, VS)
    assert (il, fmt, diags) == (PROGRAM, "wpg", [])


def test_a_nop_within_the_program_takes_its_step():
    """An empty frame before END is a NOP: one step, so the instructions after it sit one step on."""
    text = ".dialect fx\nLD X0\nNOP\nOUT Y0\nEND\n"
    data = wpgkit.il_body(text, VS)
    il, _, diags = import_wpg("p.wpg", data, VS)
    assert il == text and diags == []
    assert _built(il) == [(0, 1, "LD"), (1, 1, "NOP"), (2, 1, "OUT"), (3, 1, "END")]
    assert read_program(data).fill == 8000 - 4


def test_a_fill_that_makes_no_memory_size_is_w916_with_both_figures(tmp_path):
    lines = wpgkit.il_lines(PROGRAM, VS)
    steps = wpgkit.steps(PROGRAM, VS)
    data = wpgkit.body(lines, 8000 - steps - 1)
    il, _, diags = import_wpg("p.wpg", data, VS)
    assert il == PROGRAM and [d.code for d in diags] == ["W916"]
    said = diags[0].message
    assert f"{8000 - steps - 1} NOP steps" in said and f"counts the program as {steps} steps" in said
    assert f"{steps + 1} steps if its memory is 8000" in said  # one NOP fewer: one step more by GX
    (tmp_path / "p.wpg").write_bytes(data)
    r = run_mlc("import", "p.wpg", "-o", "p.il", cwd=tmp_path)
    assert r.code == 0 and "W916" in r.err and (tmp_path / "p.il").read_text("utf-8") == PROGRAM


def test_the_fx_dialect_path_through_the_cli(tmp_path):
    """`mlc import X.wpg`: target vs by default, FX specials mapped (M8000 -> M9000, a contact of
    one step as the vendor counts it: no W916), the comments of --comments."""
    (tmp_path / "p.wpg").write_bytes(wpgkit.body([("LD", ["M8000"]), ("OUT", ["Y0"]), ("LD", ["X0"]),
                                                  ("OUT", ["Y1"]), ("END", [])], 8000 - 5))
    (tmp_path / "c.csv").write_text("Device Name,Comment\nX000,start\n", encoding="utf-8")
    r = run_mlc("import", "p.wpg", "--comments", "c.csv", "-o", "p.il", cwd=tmp_path)
    il = (tmp_path / "p.il").read_text("utf-8")
    assert r.code == 0 and "wpg -> p.il" in r.err and "target vs" in r.err, r.err
    assert il.startswith(".dialect fx\n") and "LD M9000" in il and "LD X0 ; X0 start" in il
    assert "N910" in r.err and "W916" not in r.err, r.err
    assert run_mlc("build", "--target", "vs", "p.il", "-o", "p.mlx", cwd=tmp_path).code == 0
    r = run_mlc("import", "p.wpg", "--program", "MAIN", cwd=tmp_path)
    assert r.code == 2 and "one program" in r.err


BUNDLED = ".dialect fx\nLD X0\nOR Y0\nANI X1\nOUT Y0\nLD Y0\nOUT T0 K50\nEND\n"


def test_the_bundled_body_is_the_kits():
    """tests/data/wpg/MAIN.wpg (the docs' examples run on it) is written by tests/wpgkit.py."""
    data = (Path(__file__).parent / "data" / "wpg" / "MAIN.wpg").read_bytes()
    assert data == wpgkit.il_body(BUNDLED, VS)
    assert import_wpg("MAIN.wpg", data, VS) == (BUNDLED, "wpg", [])


# --- defects: each a code and the offset, exit 2 --------------------------------------------

_GOOD = wpgkit.body([("LD", ["X0"]), ("OUT", ["Y0"]), ("END", [])], 8000 - 3)
_END = len(wpgkit.header()) + len(wpgkit.tokens([("LD", ["X0"]), ("OUT", ["Y0"])]))  # END's offset


def _with(at: int, new: bytes) -> bytes:
    return _GOOD[:at] + new + _GOOD[at + len(new):]


DEFECTS = {
    "empty": (b"", "E932", "offset 0: an empty file"),
    "binary junk": (bytes(range(256)) * 4, "E932", "offset 0: 00 01 02 03"),
    "inside the header": (_GOOD[:0x30], "E932", "offset 0x30"),
    "header length": (_with(0, b"\x44\x00"), "E932", "offset 0: 44 00 22 01"),
    "mark at 0x40": (_with(0x40, b"\x05\x00\xff\xff"), "E932", "offset 0x40"),
    "A-series CPU": (_with(CPU_FIELD, struct.pack("<H", 0x010A)), "E933", "0x010A: a program for the A3N"),
    "Q-series CPU": (_with(CPU_FIELD, struct.pack("<H", 0x0092)), "E933", "0x0092: a program for the Q06UDEH"),
    "unknown CPU": (_with(CPU_FIELD, struct.pack("<H", 0x0299)), "E933", "offset 0x26: CPU type 0x0299"),
    "broken frame": (_with(0x46, b"\x04"), "E918", "offset 0x46: closing sentinel 0x04"),
    "frame of 1": (_with(TOKENS, b"\x01"), "E918", "offset 0x44: token length 1, the least is 2"),
    "truncated in a frame": (_GOOD[:TOKENS + 5], "E918", "runs past"),
    "truncated before END": (_GOOD[:_END], "E921", "does not end with END"),
    "junk after END": (_with(_END + 3, b"\x04\x9c\x00\x04"), "E921", f"offset 0x{_END + 3:X}: token [9C 00] after END"),
    "unknown token": (_with(TOKENS, b"\x03\x7e\x03"), "E919", "offset 0x44: token [7E]"),
    "unknown operand": (_with(TOKENS + 3, b"\x04\x91\x00\x04"), "E920", "offset 0x47"),
}


@pytest.mark.parametrize("name", DEFECTS)
def test_defects_are_a_code_with_the_offset(name):
    data, code, said = DEFECTS[name]
    il, _, diags = import_wpg("p.wpg", data, VS)
    assert il is None and [d.code for d in diags] == [code] and said in diags[0].message, diags[0].message


def test_defects_exit_2_through_the_cli(tmp_path):
    for name in ("empty", "A-series CPU", "broken frame", "junk after END", "unknown token"):
        data, code, said = DEFECTS[name]
        (tmp_path / "p.wpg").write_bytes(data)
        r = run_mlc("import", "p.wpg", "-o", "p.il", cwd=tmp_path)
        assert r.code == 2 and code in r.err and said in r.err and "Traceback" not in r.err, (name, r.err)
        assert not (tmp_path / "p.il").exists()


def test_the_header_bytes_not_read_do_not_matter():
    """The title and the bytes not identified are seeded random in the fixtures: any give the program."""
    lines = [("LD", ["X0"]), ("OUT", ["Y0"]), ("END", [])]
    got = {tuple(read_program(wpgkit.body(lines, 1997, seed=seed)).instructions) for seed in range(5)}
    assert len(got) == 1


# --- generated programs ---------------------------------------------------------------------

_BIT = st.one_of(st.integers(0, 0o177).map(lambda n: f"X{n:o}"), st.integers(0, 1535).map(lambda n: f"M{n}"),
                 st.integers(0, 511).map(lambda n: f"T{n}"), st.integers(0, 255).map(lambda n: f"C{n}"),
                 st.integers(0, 999).map(lambda n: f"S{n}"))
_COIL = st.one_of(st.integers(0, 0o177).map(lambda n: f"Y{n:o}"), st.integers(0, 1535).map(lambda n: f"M{n}"))
_D = st.integers(0, 3999).map(lambda n: f"D{2 * n}")
_OUTPUT = st.one_of(
    st.tuples(st.sampled_from(["OUT", "SET", "RST", "PLS", "PLF"]), _COIL).map(" ".join),
    st.tuples(st.sampled_from(["SET S", "RST S", "RST T", "RST C"]), st.integers(0, 199)).map(lambda t: f"{t[0]}{t[1]}"),
    st.tuples(st.sampled_from("TC"), st.integers(0, 199), st.integers(1, 32767)).map(lambda t: f"OUT {t[0]}{t[1]} K{t[2]}"),
    st.tuples(st.sampled_from("TC"), st.integers(0, 199), _D).map(lambda t: f"OUT {t[0]}{t[1]} {t[2]}"),
    st.tuples(st.integers(-32768, 32767), _D).map(lambda t: f"MOV K{t[0]} {t[1]}"),
    st.tuples(st.sampled_from("TC"), st.integers(0, 199), _D).map(lambda t: f"MOV {t[0]}{t[1]} {t[2]}"),
    st.tuples(st.sampled_from(["DADD", "DSUB"]), _D).map(lambda t: f"{t[0]} D0 D2 {t[1]}"))
_LOAD = st.one_of(st.tuples(st.sampled_from(["LD", "LDI", "LDP", "LDF"]), _BIT).map(" ".join),
                  st.tuples(st.sampled_from(["LD=", "LD<>", "LD>=", "LDD<"]), _D, st.integers(0, 999)).map(
                      lambda t: f"{t[0]} {t[1]} K{t[2]}"))
_SERIES = st.tuples(st.sampled_from(["AND", "ANI", "OR", "ORI", "ANDP", "ANDF", "ORP", "ORF"]), _BIT).map(" ".join)
_STATEMENT = st.text("abcdefghij XYZ:-=0123456789", min_size=1, max_size=30).map(lambda t: f"; {t.strip() or 'x'}")
_RUNG = st.tuples(st.lists(_STATEMENT, max_size=1), _LOAD, st.lists(_SERIES, max_size=2),
                  st.sampled_from([[], ["NOP"]]), st.lists(_OUTPUT, min_size=1, max_size=2)).map(
    lambda r: [*r[0], r[1], *r[2], *r[3], *r[4]])


@settings(max_examples=15, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(_RUNG, min_size=1, max_size=4), st.sampled_from([2000, 8000]),
       st.sampled_from([wpgkit.FX3U, wpgkit.FX2N, wpgkit.FX1N]), st.integers(0, 9))
def test_generated_programs_round_trip_with_the_vendors_steps(rungs, memory, cpu, seed):
    text = ".dialect fx\n" + "".join(f"{line}\n" for rung in rungs for line in rung) + "END\n"
    data = wpgkit.il_body(text, VS, memory, cpu=cpu, seed=seed)
    il, _, diags = import_wpg("p.wpg", data, VS)
    assert il == text and diags == [], [d.message for d in diags]
    prog = read_program(data)
    built = _built(il)
    decoded = [i for i in prog.instructions if i.text is None]  # a statement is a comment line, no step
    assert [i.mnemonic for i in decoded] == [m for _, _, m in built]
    assert all(i.width == steps for i, (_, steps, _) in zip(decoded, built, strict=True) if i.width)
    assert built[-1][0] + built[-1][1] + prog.fill == memory


@settings(max_examples=40, deadline=None)
@given(st.integers(0, len(_GOOD) + 8), st.binary(min_size=1, max_size=6))
def test_any_damage_gives_a_code_or_a_program(at, junk):
    data = _GOOD[:at] + junk + _GOOD[at + len(junk):]
    try:
        read_program(data)
    except GxwError as e:
        assert e.code in ("E918", "E919", "E920", "E921", "E932", "E933")
        assert "offset 0x" in e.message or "offset 0:" in e.message


def test_a_gx_developer_project_folder_is_its_body_with_its_comment_file(tmp_path):
    """`mlc import PROJECT`: the folder GX Developer saves (Gppw.gpj, Resource/Pou/Body/*.wpg,
    Resource/Others/COMMENT.wcd; names matched without case) gives its one body with the
    project's comments (W917 and none where they cannot be read: they were not asked for);
    several bodies need --program (E934, the bodies listed), as none does."""
    import wcdkit

    project = tmp_path / "Traffic"
    (project / "Resource" / "Pou" / "Body").mkdir(parents=True)
    (project / "Resource" / "Others").mkdir()
    (project / "Gppw.gpj").write_bytes(b"\0" * 16)
    main = wpgkit.body([("LD", ["X0"]), ("OUT", ["Y0"]), ("END", [])], 8000 - 3)
    (project / "Resource" / "Pou" / "Body" / "MAIN.wpg").write_bytes(main)
    (project / "Resource" / "Others" / "COMMENT.wcd").write_bytes(
        wcdkit.wcd({(0x9C, 0): (b"", b"start"), (0x9D, 0): (b"", b"lamp")}, width=16))
    r = run_mlc("import", "Traffic", "-o", "p.il", cwd=tmp_path)
    assert r.code == 0, r.err
    assert (tmp_path / "p.il").read_text("utf-8").endswith("\nLD X0 ; X0 start\nOUT Y0 ; Y0 lamp\nEND\n")
    (tmp_path / "c.csv").write_text("Device Name,Comment\nX000,go\n", encoding="utf-8")
    r = run_mlc("import", "Traffic", "--comments", "c.csv", cwd=tmp_path)  # --comments names another file
    assert r.code == 0 and "LD X0 ; X0 go\nOUT Y0\n" in r.out, r.err
    r = run_mlc("import", "Traffic", "-o", "Traffic/Resource/Pou/Body/MAIN.wpg", cwd=tmp_path)
    assert r.code == 2 and "E606" in r.err  # the body read is never an output
    assert (project / "Resource" / "Pou" / "Body" / "MAIN.wpg").read_bytes() == main
    (project / "Resource" / "Others" / "COMMENT.wcd").write_bytes(  # Big5 text, no --encoding: not read
        wcdkit.wcd({(0x9C, 0): (b"", "啟動".encode("cp950"))}, width=16))
    r = run_mlc("import", "Traffic", cwd=tmp_path)
    assert r.code == 0 and "warning[W917]: the project's comments are not read: E939" in r.err, r.err
    assert r.out.endswith("\nLD X0\nOUT Y0\nEND\n"), r.out
    (project / "Resource" / "Pou" / "Body" / "SUB1.wpg").write_bytes(main)
    r = run_mlc("import", "Traffic", cwd=tmp_path)
    assert r.code == 2 and "error[E934]" in r.err and "2 program bodies (MAIN, SUB1)" in r.err, r.err
    assert run_mlc("import", "Traffic", "--program", "sub1", cwd=tmp_path).code == 0
    r = run_mlc("import", "Traffic", "--program", "SUB2", cwd=tmp_path)
    assert r.code == 2 and "no program body 'SUB2' (the project's: MAIN, SUB1)" in r.err, r.err
    for body in (project / "Resource" / "Pou" / "Body").iterdir():
        body.unlink()
    r = run_mlc("import", "Traffic", cwd=tmp_path)
    assert r.code == 2 and "error[E934]" in r.err and "no program body" in r.err and "Traceback" not in r.err


def test_a_body_and_its_comments_take_the_same_fx_cpus():
    """The body reader knew three FX CPUs (those public bodies pair with a name) where the
    comment reader took the FX family (MX Component's codes): an FX3G project's comments were
    read and its body refused (E933). One table now (mlctool/gxdeveloper.py)."""
    import wcdkit

    from mlctool import wcd

    for cpu in (0x0201, 0x0209, 0x020A):
        body = wpgkit.body([("LD", ["X0"]), ("OUT", ["Y0"]), ("END", [])], 8000 - 3, cpu=cpu)
        comments = wcdkit.wcd({(0x9C, 0): (b"", b"start")}, width=16, cpu=cpu)
        assert read_program(body).cpu == wcd.read(comments).cpu
