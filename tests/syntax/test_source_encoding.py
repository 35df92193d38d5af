"""Source encodings (mlctool/syntax/source.py): Big5/cp950, GB18030 and Shift-JIS files as
Taiwanese, Chinese and Japanese vendor tools write them; --encoding, mlc.toml `encoding`, and
a guess with a note (N108) when a file is not UTF-8."""

from __future__ import annotations

import json
import subprocess

import pytest

from conftest import MLC_COMMAND, ROOT, run_mlc

# The bytes as the vendor tools write them (not produced by Python's codecs in the test):
# a conveyor rung with comments. Big5: 啟動 = B1D2 B0CA; GB18030: 启动 = C6F4 B6AF;
# Shift-JIS: 起動 = 8B4E 93AE.
BIG5 = (b"; \xbf\xe9\xb0e\xb1a \xb1\xd2\xb0\xca\xab\xf6\xb6s\xab\xf6\xa4U\xab\xe1\xb0\xa8\xb9F\xb9B\xc2\xe0\r\n"
        b"LD X0   ; \xb1\xd2\xb0\xca\xab\xf6\xb6s\r\nOUT Y0  ; \xb0\xa8\xb9F\r\nEND\r\n")
GB18030 = (b"; \xca\xe4\xcb\xcd\xb4\xf8 \xc6\xf4\xb6\xaf\xb0\xb4\xc5\xa5\xb0\xb4\xcf\xc2\xba\xf3\xb5\xe7\xbb\xfa"
           b"\xd4\xcb\xd7\xaa\nLD X0   ; \xc6\xf4\xb6\xaf\xb0\xb4\xc5\xa5\nOUT Y0  ; \xb5\xe7\xbb\xfa\nEND\n")
SHIFT_JIS = (b"; \x83R\x83\x93\x83x\x83A \x8bN\x93\xae\x83{\x83^\x83\x93\x82\xf0\x89\x9f\x82\xb7\x82\xc6\x83\x82"
             b"\x81[\x83^\x81[\x82\xaa\x89\xf1\x82\xe9\nLD X0   ; \x8bN\x93\xae\x83{\x83^\x83\x93\n"
             b"OUT Y0  ; \x83\x82\x81[\x83^\x81[\nEND\n")
FILES = {  # bytes, the encoding to name, a comment word as text, the guess
    "big5": (BIG5, "cp950", "啟動按鈕", "cp950"),
    "gb18030": (GB18030, "gb18030", "启动按钮", "gb18030"),
    "shift_jis": (SHIFT_JIS, "shift_jis", "起動ボタン", "cp932"),
}


@pytest.fixture(params=list(FILES))
def vendor_file(request, tmp_path):
    data, named, word, guess = FILES[request.param]
    (tmp_path / "p.il").write_bytes(data)
    return tmp_path, named, word, guess


def _json(r):
    return json.loads(r.out)["diagnostics"]


def test_a_file_that_is_not_utf8_is_guessed_with_a_note(vendor_file):
    folder, _named, _word, guess = vendor_file
    r = run_mlc("check", "--format", "json", "p.il", cwd=folder)
    assert r.code == 0, r.out
    [note] = _json(r)
    assert (note["code"], note["severity"], note["line"]) == ("N108", "note", 1)
    assert f"read as {guess}" in note["message"] and f"--encoding {guess}" in note["message"]


def test_a_named_encoding_reads_the_file_without_a_note(vendor_file):
    folder, named, word, _guess = vendor_file
    assert _json(run_mlc("check", "--format", "json", "--encoding", named, "p.il", cwd=folder)) == []
    (folder / "mlc.toml").write_text(f'encoding = "{named}"\n')
    assert _json(run_mlc("check", "--format", "json", "p.il", cwd=folder)) == []
    # the comment arrives as text: the listing of a build shows it
    r = run_mlc("build", "--encoding", named, "p.il", "-o", "out/p.mlx", "--listing", "out/p.lst", cwd=folder)
    assert r.code == 0, r.err
    assert word in (folder / "out" / "p.lst").read_text("utf-8")


def test_every_command_that_reads_sources_takes_encoding(vendor_file):
    folder, named, word, _guess = vendor_file
    (folder / "p.stim").write_text("0ms X0=1\n10ms expect Y0=1\n")
    for args in (["sim", "p.il", "--stimulus", "p.stim"], ["ladder", "p.il", "-o", "p.svg"],
                 ["fmt", "--check", "p.il"], ["build", "-c", "p.il", "-o", "objs"]):
        r = run_mlc(args[0], "--encoding", named, *args[1:], cwd=folder)
        assert r.code in (0, 1) and "N108" not in r.err and "E102" not in r.err, (args, r.err)
    assert word in (folder / "p.svg").read_text("utf-8")
    r = run_mlc("import", "--encoding", named, "--target", "nc5", "p.il", cwd=folder)
    assert r.code == 0 and word in r.out


def test_a_wrong_named_encoding_is_e102_and_an_unknown_name_exit_2(tmp_path):
    (tmp_path / "p.il").write_bytes(BIG5)
    r = run_mlc("check", "--format", "json", "--encoding", "utf-8", "p.il", cwd=tmp_path)
    assert r.code == 2 and [d["code"] for d in _json(r)] == ["E102"]
    r = run_mlc("check", "--encoding", "klingon", "p.il", cwd=tmp_path)
    assert r.code == 2 and "unknown encoding" in r.err
    (tmp_path / "mlc.toml").write_text('target = "nc5"\nencoding = "klingon"\n')
    r = run_mlc("check", "p.il", cwd=tmp_path)
    assert r.code == 2 and "E110" in r.err and "mlc.toml:2:" in r.err


NOT_TEXT = ("rot13", "hex", "base64", "bz2", "zip", "uu_codec", "undefined")
# every command that reads sources, with what it needs (mlc debug: a console, ended by EOF)
SOURCE_COMMANDS = (["check", "p.il"], ["fmt", "p.il"], ["build", "p.il", "-o", "p.mlx"], ["ladder", "p.il"],
                   ["sim", "p.il", "--stimulus", "p.stim"], ["import", "--target", "nc5", "p.il"], ["test"],
                   ["debug", "p.il", "--stimulus", "p.stim"])


@pytest.mark.parametrize("codec", NOT_TEXT)
def test_a_codec_that_is_not_a_text_encoding_is_refused_by_every_command(tmp_path, codec):
    """Issue 30.6: Python's bytes-to-bytes codecs (and `undefined`) are codecs, not encodings
    of text: --encoding is a usage error, mlc.toml `encoding` E110 at its line; never exit 3."""
    (tmp_path / "p.il").write_text("LD X0\nOUT Y0\nEND\n")
    (tmp_path / "p.stim").write_text("0ms X0=1\n")
    for args in SOURCE_COMMANDS[:-2]:
        r = run_mlc(args[0], "--encoding", codec, *args[1:], cwd=tmp_path)
        assert r.code == 2 and "--encoding" in r.err and "not an encoding of text files" in r.err, (args, r.err)
    (tmp_path / "mlc.toml").write_text(f'target = "nc5"\nsources = ["p.il"]\ntests = ["p.stim"]\nencoding = "{codec}"\n')
    for args in SOURCE_COMMANDS:
        r = run_mlc(*args, cwd=tmp_path)
        assert r.code == 2 and "mlc.toml:4:1: error[E110]" in r.err and "not an encoding of text files" in r.err, \
            (args, r.err)


def test_a_codec_that_cannot_say_where_it_failed_is_e102(tmp_path):
    """punycode reads text but gives no position for bytes it cannot take: E102, not exit 3."""
    (tmp_path / "p.il").write_text("LD X0\nEND\n")
    r = run_mlc("check", "--encoding", "punycode", "p.il", cwd=tmp_path)
    assert r.code == 2 and "E102" in r.err and "not valid punycode" in r.err, r.err


def test_utf8_files_never_import_the_detector(tmp_path):
    """The fast path: a UTF-8 file is read without charset_normalizer (~0.1 s of import)."""
    (tmp_path / "u.il").write_text("LD X0 ; 啟動\nOUT Y0\nEND\n", "utf-8")
    (tmp_path / "b.il").write_bytes(BIG5)
    probe = ("import sys, runpy; sys.argv = ['mlc', 'check', sys.argv[1]]\n"
             "try: runpy.run_module('mlctool', run_name='__main__')\n"
             "except SystemExit: pass\n"
             "print('DETECTOR' if 'charset_normalizer' in sys.modules else 'FAST')")
    for name, expect in (("u.il", "FAST"), ("b.il", "DETECTOR")):
        out = subprocess.run([MLC_COMMAND[0], "-c", probe, name], cwd=tmp_path, capture_output=True,
                             text=True, env={"PATH": "/usr/bin:/bin", "PYTHONPATH": str(ROOT)}).stdout
        assert out.strip().endswith(expect), out


def test_read_input_reads_what_the_file_holds_up_to_the_limit(tmp_path, monkeypatch):
    """read_input asks for the size fstat gives (plus one byte), and reads on when the file
    turns out longer (it grew meanwhile), never past the limit; an empty file is b''."""
    import os
    from types import SimpleNamespace

    from mlctool import fileio

    path = tmp_path / "f.stim"
    path.write_bytes(bytes(range(100)))
    for limit in (1, 50, 100, 101, 1000):
        assert fileio.read_input(str(path), limit) == bytes(range(100))[:limit]
    real = os.fstat
    monkeypatch.setattr(fileio.os, "fstat", lambda fd: SimpleNamespace(
        st_size=10, st_mode=real(fd).st_mode, st_dev=real(fd).st_dev, st_ino=real(fd).st_ino))
    for limit in (5, 11, 12, 60, 101, 1000):
        assert fileio.read_input(str(path), limit) == bytes(range(100))[:limit]
    monkeypatch.undo()
    (tmp_path / "empty.stim").write_bytes(b"")
    assert fileio.read_input(str(tmp_path / "empty.stim"), 10) == b""
