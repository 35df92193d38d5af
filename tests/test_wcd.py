"""GX Developer device comments (`COMMENT.wcd`, mlctool/wcd.py) read into `mlc import
--comments`: the layout of tests/wcdkit.py read back, each broken field refused with its code
and offset (exit 2, no traceback), X/Y written in octal, the comments mapped as a CSV's."""

from __future__ import annotations

import struct
from pathlib import Path

import pytest
import wcdkit
from hypothesis import given, settings
from hypothesis import strategies as st

from conftest import run_mlc
from mlctool import wcd as reader
from mlctool.gxdeveloper import CPU_AT
from mlctool.wcd import ALIAS_WIDTH, DEVICES, TABLE_AT, TABLE_HEAD, WcdError

CORPUS = Path(__file__).resolve().parent / "corpus"
X, Y, M, SM, D, SD, T, C = 0x9C, 0x9D, 0x90, 0x91, 0xA8, 0xA9, 0xC2, 0xC5
RECORDS_AT = TABLE_AT + TABLE_HEAD  # + 10 a run


def _error(data: bytes, encoding: str | None = None) -> WcdError:
    with pytest.raises(WcdError) as e:
        reader.read(data, encoding)
    return e.value


_text = st.text(st.characters(min_codepoint=0x21, max_codepoint=0x7E), max_size=8).map(str.encode)


@settings(max_examples=25, deadline=None)
@given(st.dictionaries(st.tuples(st.sampled_from(sorted(DEVICES)), st.integers(0, 600)),
                       st.tuples(_text, _text), max_size=12),
       st.sampled_from([16, 32]))
def test_what_is_written_is_read_back(table, width):
    table = {(k, n + DEVICES[k][2]): v for (k, n), v in table.items()}
    got = reader.read(wcdkit.wcd(table, width))
    assert got.width == width and got.cpu == "FX3U/FX3UC"
    want = []
    for (kind, number), (alias, text) in sorted(table.items()):
        letter, octal, _ = DEVICES[kind]
        if alias or text:
            want.append((f"{letter}{number:o}" if octal else f"{letter}{number}", alias.decode(), text.decode()))
    assert [(c.device, c.alias, c.text) for c in got.comments] == want


def test_devices_as_fx_writes_them():
    """X/Y numbers are stored as numbers and written in octal; 0x91 / 0xA9 are M8000 / D8000 up."""
    data = wcdkit.wcd({(X, 8): (b"", b"x10"), (Y, 63): (b"", b"y77"), (SM, 8002): (b"", b"pulse"),
                       (SD, 8000): (b"", b"wdt"), (T, 5): (b"", b"t"), (C, 235): (b"", b"hsc"),
                       (M, 100): (b"", b"m"), (D, 10): (b"", b"d")})
    assert [c.device for c in reader.read(data).comments] == ["M100", "M8002", "X10", "Y77", "D10", "D8000",
                                                              "T5", "C235"]


def test_an_all_space_record_is_no_comment_and_offsets_are_the_records():
    data = wcdkit.wcd({(X, 0): (b"", b"first"), (X, 1): (b"", b""), (X, 2): (b"go", b"")}, width=16)
    got = reader.read(data).comments
    assert [(c.device, c.alias, c.text) for c in got] == [("X0", "", "first"), ("X2", "go", "")]
    assert got[1].offset == RECORDS_AT + 10 + 2 * (ALIAS_WIDTH + 16)
    assert data[got[1].offset:got[1].offset + 2] == b"go"


def _patched(data: bytes, at: int, fmt: str, *values) -> bytes:
    out = bytearray(data)
    struct.pack_into(fmt, out, at, *values)
    return bytes(out)


GOOD = wcdkit.wcd({(X, 0): (b"", b"start"), (X, 1): (b"", b"stop"), (Y, 0): (b"mtr", b"motor")}, width=16)


@pytest.mark.parametrize(("data", "code", "offset", "says"), [
    (b"", "E936", 0, "empty file"),
    (b"MZ" + GOOD[2:], "E936", 0, "not 40 00 22 01"),
    (_patched(GOOD, 0x24, "<H", 0x0304), "E936", 0x24, "04 02"),
    (_patched(GOOD, CPU_AT, "<H", 0x010A), "E936", CPU_AT, "A-series"),
    (_patched(GOOD, 0x30, "<B", 3), "E936", 0x30, "0xFF fill"),  # a program body's bytes are here
    (_patched(GOOD, TABLE_AT + 4, "<H", 1), "E936", TABLE_AT + 4, "holds 0"),
    (_patched(GOOD, TABLE_AT + 6, "<B", 24), "E936", TABLE_AT + 6, "comment width 24"),
    (_patched(GOOD, TABLE_AT + 7, "<B", 16), "E936", TABLE_AT + 7, "alias width 16"),
    (GOOD[:0x45], "E937", 0x45, "inside the header"),
    (GOOD[:-1], "E937", len(GOOD) - 1, "truncated"),
    (GOOD + b" ", "E937", len(GOOD), "1 bytes after the last record"),
    (_patched(GOOD, TABLE_AT, "<I", 40), "E937", TABLE_AT, "says 40 bytes"),
    (_patched(GOOD, RECORDS_AT + 6, "<I", 3), "E937", len(GOOD), "truncated"),  # counts vs the length
    (_patched(GOOD, RECORDS_AT + 6, "<I", 0), "E937", RECORDS_AT + 6, "no devices"),
    (_patched(GOOD, RECORDS_AT, "<H", Y), "E937", RECORDS_AT + 10, "out of order"),
    (_patched(GOOD, RECORDS_AT, "<H", 0x98), "E938", RECORDS_AT, "device type 0x0098"),
    (_patched(GOOD, RECORDS_AT + 10, "<HI", SM, 7999), "E937", RECORDS_AT + 12, "outside its numbers"),
    (_patched(GOOD, RECORDS_AT + 10 * 2 + 3, "<B", 0x07), "E939", RECORDS_AT + 23, "control code"),
    (_patched(GOOD, RECORDS_AT + 10 * 2 + 8, "<B", 0xB1), "E939", RECORDS_AT + 28, "not ASCII"),
], ids=lambda v: v if isinstance(v, str) and v[:1] == "E" else None)
def test_each_broken_field_is_refused_at_its_offset(data, code, offset, says):
    e = _error(data)
    assert (e.code, e.offset) == (code, offset) and says in e.message, str(e)


def test_runs_that_meet_are_refused():
    """GX Developer writes consecutive devices as one run (every public file); two that meet
    or overlap are a damaged table."""
    two = wcdkit.wcd({(X, 0): (b"", b"a"), (X, 2): (b"", b"b")})
    for first in (1, 0):  # meets X0's run, overlaps it
        e = _error(_patched(two, RECORDS_AT + 10 + 2, "<I", first))
        assert e.code == "E937" and e.offset == RECORDS_AT + 10 and ("meets" in e.message or "order" in e.message)


def test_text_beyond_ascii_needs_its_encoding():
    """The file does not name its code page (the public files hold CP932 and CP950 text)."""
    kana = "ｽﾀｰﾄ".encode("cp932")
    data = wcdkit.wcd({(X, 0): (b"", kana)})
    assert _error(data).code == "E939"
    assert reader.read(data, "cp932").comments[0].text == "ｽﾀｰﾄ"
    assert _error(data, "utf-8").code == "E939"  # B9 is no UTF-8 text
    assert _error(wcdkit.wcd({(X, 0): (b"", b"ab\x80")}), "cp932").offset == RECORDS_AT + 10 + ALIAS_WIDTH + 2


def test_import_takes_a_wcd_as_a_comment_csv(tmp_path):
    """`mlc import --comments COMMENT.wcd` gives the IL a CSV of the same comments gives (M8000's
    comment follows it to M9000), told apart by content, whatever the name; alias and comment
    both are `alias: comment`."""
    (tmp_path / "COMMENT.wcd").write_bytes(wcdkit.wcd({
        (X, 0): (b"", b"Start button"), (X, 8): (b"", b"Door"), (Y, 0): (b"", b"Motor"),
        (SM, 8000): (b"", b"RUN"), (T, 0): (b"DELAY", b"Door timer")}))
    (tmp_path / "named.csv").write_bytes((tmp_path / "COMMENT.wcd").read_bytes())
    (tmp_path / "c.csv").write_text('"Device Name","Comment"\n"X000","Start button"\n"X010","Door"\n'
                                    '"Y000","Motor"\n"M8000","RUN"\n"T0","DELAY: Door timer"\n', "utf-8")
    outs = []
    for comments in ("COMMENT.wcd", "named.csv", "c.csv"):
        r = run_mlc("import", "--comments", comments, str(CORPUS / "gxdeveloper.csv"), "-o", f"{comments}.il",
                    cwd=tmp_path)
        assert r.code == 0, r.err
        outs.append((tmp_path / f"{comments}.il").read_text("utf-8"))
    assert outs[0] == outs[1] == outs[2]
    lines = outs[0].splitlines()
    assert "LD X0 ; X0 Start button" in lines and "; M9000  RUN" in lines and "; X10  Door" in lines
    assert "; T0  DELAY: Door timer" in lines
    assert run_mlc("check", "--target", "vs", "COMMENT.wcd.il", cwd=tmp_path).code == 0


@pytest.mark.parametrize(("data", "code", "offset"), [
    (b"", "E936", "0x0"),
    (GOOD[:-3], "E937", f"0x{len(GOOD) - 3:X}"),
    (_patched(GOOD, 0x24, "<H", 0x0304), "E936", "0x24"),
    (_patched(GOOD, TABLE_AT, "<I", 40), "E937", "0x40"),
    (_patched(GOOD, RECORDS_AT, "<H", 0x98), "E938", "0x4A"),
    (wcdkit.MAGIC + bytes(range(256)) * 2, "E936", "0x24"),  # binary junk after the magic
    (_patched(GOOD, RECORDS_AT + 10 * 2 + 3, "<B", 0x00), "E939", f"0x{RECORDS_AT + 23:X}"),
], ids=["empty", "truncated", "header", "counts", "device-type", "junk", "control-byte"])
def test_import_refuses_a_broken_wcd_with_exit_2(tmp_path, data, code, offset):
    (tmp_path / "COMMENT.wcd").write_bytes(data)
    r = run_mlc("import", "--comments", "COMMENT.wcd", str(CORPUS / "gxdeveloper.csv"), "-o", "p.il", cwd=tmp_path)
    assert r.code == 2 and f"error[{code}]: offset {offset}:" in r.err, r.err
    assert "Traceback" not in r.err and "internal error" not in r.err
    assert not (tmp_path / "p.il").exists()



@settings(max_examples=60, deadline=None)
@given(st.binary(max_size=200), st.integers(0, len(GOOD) - 1), st.integers(0, 255))
def test_any_bytes_are_read_or_refused_never_a_crash(tail, at, byte):
    """Bytes after the magic, and GOOD with one byte changed: comments or a WcdError."""
    changed = bytearray(GOOD)
    changed[at] = byte
    for data in (wcdkit.MAGIC + tail, bytes(changed)):
        try:
            reader.read(data)
        except WcdError as e:
            assert e.code in ("E936", "E937", "E938", "E939") and 0 <= e.offset <= len(data)


def test_a_file_larger_than_any_comment_file_is_refused_unread(tmp_path):
    from mlctool.imports import read_comments
    from mlctool.targetapi import load_target

    big = tmp_path / "c.wcd"
    big.write_bytes(GOOD + b" " * reader.MAX_FILE)
    comments, diags = read_comments(str(big), load_target("vs"))
    assert comments is None and diags[0].code == "E937" and "larger than" in diags[0].message
