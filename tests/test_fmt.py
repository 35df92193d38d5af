"""`mlc fmt`: canonical layout, idempotent, code unchanged."""

from __future__ import annotations

from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from mlctool.check.resolve import resolve
from mlctool.fmt import FormatOptions, format_source
from mlctool.syntax.parser import parse
from mlctool.syntax.source import decode
from mlctool.targetapi import load_target
from tests.conftest import SAMPLES

NC5 = load_target("nc5")


def _fmt(text: str, steps: str = "drop") -> str:
    out, diags = format_source(decode("f.il", text.encode())[0], NC5, FormatOptions(steps))
    assert not diags
    return out


def _code(text: str):
    """What the assembler sees: instructions with operands, steps and addresses."""
    module, _ = resolve(parse(decode("f.il", text.encode())[0]), NC5)
    return [(i.mnemonic, i.operands, i.steps, i.addr, i.table) for i in module.instrs]


MESSY = """; conveyor
.define START X0
0000 ld start   ; start button
ani m1
out y0
// second rung
ld x1
tmr t0,k50
P10:
ld t0
out y1 // motor


mov k10 d0
END
"""


def test_canonical_layout():
    assert _fmt(MESSY) == """; conveyor
.define START X0
LD      start                           ; start button
ANI     M1
OUT     Y0

// second rung
LD      X1
TMR     T0 K50

P10:
LD      T0
OUT     Y1                              // motor

MOV     K10 D0
END
"""


def test_steps_renumbered_and_kept():
    out = _fmt(MESSY, "renumber")
    assert "00000 LD      start" in out and "00008 LD      T0" in out and "00014 END" in out
    assert _fmt(out, "keep") == out
    assert "0000 LD" not in _fmt("0000 ld x0\nout y0\nend\n")


def _samples():
    return sorted(p for p in SAMPLES.rglob("*.il"))


@pytest.mark.parametrize("path", _samples(), ids=lambda p: str(p.relative_to(SAMPLES)))
def test_samples_idempotent_and_code_unchanged(path: Path):
    text = path.read_text("utf-8")
    once = _fmt(text)
    assert _fmt(once) == once
    assert _code(once) == _code(text)


RUNG_LINES = st.sampled_from(["ld x0", "LDI M1 ; c", "and x2", "or m3", "ANB", "ORB", "mps", "mrd", "mpp",
                              "out y0", "SET M5 // s", "mov k1,d0", "dmov k70000 d2", "P3", "P4:",
                              "; comment", "", "   ", "cj p3", "fend", "ld= d0 k5", "0007 inc d1"])


@settings(max_examples=200, deadline=None)
@given(st.lists(RUNG_LINES, max_size=30))
def test_generated_idempotent_and_code_unchanged(lines):
    text = "\n".join(lines) + "\nEND\n"
    once = _fmt(text)
    assert _fmt(once) == once
    assert _code(once) == _code(text)


def test_cli_check_and_syntax_errors(mlc, tmp_path):
    p = tmp_path / "a.il"
    p.write_text(MESSY)
    r = mlc("fmt", "--check", str(p))
    assert r.code == 1 and "+LD      start" in r.out and p.read_text() == MESSY
    assert mlc("fmt", str(p)).code == 0
    assert mlc("fmt", "--check", str(p)).code == 0
    bad = tmp_path / "bad.il"
    bad.write_text("LD X0 @\nEND\n")
    r = mlc("fmt", str(bad))
    assert r.code == 1 and "E103" in r.err and bad.read_text() == "LD X0 @\nEND\n"


# ------------------------------------------------------------------ the file stays the same file

UGLY = "ld x0 ; 啟動\nout   y0\nend\n"
PRETTY = _fmt(UGLY)


@pytest.mark.parametrize("encoding, bom, newline, named", [
    ("utf-8", b"", "\r\n", None),
    ("utf-8", b"\xef\xbb\xbf", "\r\n", None),
    ("utf-16-le", b"\xff\xfe", "\r\n", None),
    ("utf-16-be", b"\xfe\xff", "\n", None),
    ("utf-16-le", b"", "\r\n", "utf-16"),  # no BOM: named, and written back without one
    ("cp950", b"", "\r\n", "cp950"),  # Big5 as Delta's and Vigor's editors write it
    ("cp950", b"", "\r\n", None),  # ... guessed (N108)
    ("utf-8", b"", "\r", None),
])
def test_fmt_keeps_encoding_bom_and_line_endings(mlc, tmp_path, encoding, bom, newline, named):
    p = tmp_path / "p.il"
    p.write_bytes(bom + UGLY.replace("\n", newline).encode(encoding))
    args = ["--encoding", named] if named else []
    r = mlc("fmt", *args, str(p))
    assert r.code == 0, r.err
    assert p.read_bytes() == bom + PRETTY.replace("\n", newline).encode(encoding)
    assert mlc("fmt", "--check", *args, str(p)).code == 0


def test_fmt_writes_through_a_symlink_and_keeps_the_mode(mlc, tmp_path):
    real = tmp_path / "real.il"
    real.write_text(UGLY, "utf-8")
    real.chmod(0o600)
    link = tmp_path / "link.il"
    link.symlink_to("real.il")
    assert mlc("fmt", str(link)).code == 0
    assert link.is_symlink() and link.readlink() == Path("real.il")
    assert real.read_text("utf-8") == PRETTY
    assert real.stat().st_mode & 0o777 == 0o600


def test_fmt_keeps_hard_links(mlc, tmp_path):
    a = tmp_path / "a.il"
    a.write_text(UGLY, "utf-8")
    a.chmod(0o640)
    b = tmp_path / "b.il"
    b.hardlink_to(a)
    inode = a.stat().st_ino
    assert mlc("fmt", str(a)).code == 0
    assert a.stat().st_ino == b.stat().st_ino == inode and a.stat().st_nlink == 2
    assert b.read_text("utf-8") == PRETTY and a.stat().st_mode & 0o777 == 0o640
    assert [x.name for x in tmp_path.iterdir() if x.name.startswith(".mlc-")] == []


def test_fmt_of_a_single_file_is_atomic_and_keeps_the_mode(mlc, tmp_path):
    p = tmp_path / "p.il"
    p.write_text(UGLY, "utf-8")
    p.chmod(0o600)
    assert mlc("fmt", str(p)).code == 0
    assert p.read_text("utf-8") == PRETTY and p.stat().st_mode & 0o777 == 0o600
    assert [x.name for x in tmp_path.iterdir()] == ["p.il"]


def test_failed_in_place_write_restores_the_old_text(tmp_path, monkeypatch):
    """A hard-linked file is overwritten in place: when that write fails, the old bytes return."""
    import builtins

    from mlctool.diagnostics import MlcError
    from mlctool.fileio import rewrite

    a = tmp_path / "a.il"
    a.write_bytes(b"OLD TEXT\n")
    (tmp_path / "b.il").hardlink_to(a)
    real_open = builtins.open

    class Failing:
        def __init__(self, f):
            self.f, self.writes = f, 0

        def write(self, data):
            self.writes += 1
            if self.writes == 1:
                self.f.write(data[:3])
                raise OSError(28, "No space left on device")
            return self.f.write(data)

        def __getattr__(self, name):
            return getattr(self.f, name)

        def __enter__(self):
            return self

        def __exit__(self, *exc):
            return self.f.__exit__(*exc)

    def fake_open(path, mode="r", *args, **kw):
        f = real_open(path, mode, *args, **kw)
        return Failing(f) if mode == "r+b" else f

    monkeypatch.setattr(builtins, "open", fake_open)
    with pytest.raises(MlcError, match="unchanged"):
        rewrite(str(a), b"NEW, LONGER TEXT\n")
    monkeypatch.undo()
    assert (tmp_path / "b.il").read_bytes() == b"OLD TEXT\n"
    assert sorted(x.name for x in tmp_path.iterdir()) == ["a.il", "b.il"]


def test_a_full_disk_leaves_no_temporary_file_beside_a_hard_linked_file(tmp_path, monkeypatch):
    """The in-place rewrite first saves the old bytes beside the file: when even that copy
    cannot be written (a full disk), the empty copy is removed and the file is unchanged
    (issue 30.18: an empty .mlc-*.tmp was left)."""
    import os

    from mlctool import fileio
    from mlctool.diagnostics import MlcError

    a = tmp_path / "a.il"
    a.write_bytes(b"OLD TEXT\n")
    (tmp_path / "b.il").hardlink_to(a)
    real_fdopen = os.fdopen

    class Full:
        def __init__(self, f):
            self.f = f

        def write(self, data):
            raise OSError(28, "No space left on device")

        def __enter__(self):
            return self

        def __exit__(self, *exc):
            return self.f.__exit__(*exc)

    monkeypatch.setattr(fileio.os, "fdopen", lambda fd, mode="r", *a, **k: Full(real_fdopen(fd, mode, *a, **k)))
    with pytest.raises(MlcError, match="No space left"):
        fileio.rewrite(str(a), b"NEW TEXT\n")
    monkeypatch.undo()
    assert a.read_bytes() == b"OLD TEXT\n"
    assert sorted(x.name for x in tmp_path.iterdir()) == ["a.il", "b.il"]
