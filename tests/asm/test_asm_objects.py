"""Object files, linker, maps, listings and the build/link/objdump commands."""

from __future__ import annotations

import json
import random
import shutil
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from conftest import SAMPLES, run_mlc
from mlctool.asm import program_from_paths
from mlctool.asm.objfile import MAGIC, ObjectError, decode
from mlctool.targetapi import load_target

PROJECT = SAMPLES / "project"
T = load_target("nc5")

MAIN = """\
.define START X0
LD START
CALL P10
LD X1
OUT Y0
END
"""
LIB = """\
.library
.export P10
P10:
LD X2
OUT Y1
SRET
"""


@pytest.fixture(scope="module")
def good_object(tmp_path_factory) -> bytes:
    d = tmp_path_factory.mktemp("obj")
    r = run_mlc("build", "-o", str(d / "p.mlx"), cwd=PROJECT)
    assert r.code == 0, r.err
    return (d / "p.mlx").read_bytes()


def _files(tmp_path: Path, **texts: str) -> None:
    for name, text in texts.items():
        (tmp_path / f"{name}.il").write_text(text, "utf-8")


# ------------------------------------------------------------------ bad object files

def test_bad_objects_one_message_exit_2(tmp_path, good_object):
    cases = {
        "text.mlo": b"LD X0\nEND\n",
        "empty.mlo": b"",
        "truncated.mlx": good_object[: len(good_object) // 2],
        "magic_only.mlx": MAGIC,
        "flipped.mlx": good_object[:100] + bytes([good_object[100] ^ 4]) + good_object[101:],
        "version.mlx": good_object[:8] + b"\x09\x00" + good_object[10:],
    }
    expect = {"text.mlo": "E501", "empty.mlo": "E501", "truncated.mlx": "E502", "magic_only.mlx": "E502",
              "flipped.mlx": "E502", "version.mlx": "E503"}
    for name, data in cases.items():
        (tmp_path / name).write_bytes(data)
        for args in (["objdump", name], ["link", name, "-o", "out.mlx"], ["build", name, "-o", "out.mlx"]):
            r = run_mlc(*args, cwd=tmp_path)
            assert r.code == 2, (name, args, r.err)
            assert expect[name] in r.err and "Traceback" not in r.err + r.out
            assert not (tmp_path / "out.mlx").exists()


def test_wrong_target_is_e503(good_object):
    with pytest.raises(ObjectError) as e:
        decode(good_object.replace(b"\x03nc5", b"\x03xx9"), T)  # checksum fails first
    assert e.value.code == "E502"
    from mlctool.asm.objfile import ObjectFile, encode
    obj = decode(good_object, T)
    other = ObjectFile(obj.kind, "dvp", obj.units, obj.instrs, obj.unit_of, obj.inserted)
    with pytest.raises(ObjectError) as e:
        decode(encode(other), T)
    assert e.value.code == "E503" and "dvp" in str(e.value)


@settings(max_examples=300, deadline=None)
@given(st.binary(max_size=400))
def test_random_bytes_never_crash(data):
    for blob in (data, MAGIC + data):
        with pytest.raises(ObjectError) as e:
            decode(blob, T)
        assert e.value.code in ("E501", "E502", "E503")


def test_every_bit_flip_and_truncation_is_detected(good_object):
    rnd = random.Random(7)
    positions = rnd.sample(range(len(good_object) * 8), 400) + list(range(0, 16 * 8))
    for bit in positions:
        data = bytearray(good_object)
        data[bit // 8] ^= 1 << (bit % 8)
        with pytest.raises(ObjectError):
            decode(bytes(data), T)
    for n in rnd.sample(range(len(good_object)), 100):
        with pytest.raises(ObjectError):
            decode(good_object[:n], T)


# ------------------------------------------------------------------ linking

def test_link_layout_main_fend_libraries_end(tmp_path):
    _files(tmp_path, main=MAIN, lib=LIB)
    r = run_mlc("build", "main.il", "lib.il", "-o", "p.mlx", "--map", "p.map", "--listing", "p.lst", cwd=tmp_path)
    assert r.code == 0, r.err
    doc = json.loads(run_mlc("objdump", "--json", "p.mlx", cwd=tmp_path).out)
    seq = [(i["mnemonic"], i["file"]) for i in doc["instructions"]]
    assert seq == [("LD", "main.il"), ("CALL", "main.il"), ("LD", "main.il"), ("OUT", "main.il"),
                   ("FEND", "main.il"), ("P", "lib.il"), ("LD", "lib.il"), ("OUT", "lib.il"),
                   ("SRET", "lib.il"), ("END", "main.il")]
    assert [i["addr"] for i in doc["instructions"]] == [0, 1, 3, 4, 5, 6, 7, 8, 9, 10]
    assert doc["total_steps"] == 11
    assert {"kind": "label", "name": "P10", "addr": 6, "module": "lib.il", "exported": True} in doc["symbols"]
    text = (tmp_path / "p.map").read_text()
    assert "00000-00005       6 steps  main.il (main)" in text  # with the inserted FEND
    assert "00006-00009       4 steps  lib.il (library)" in text
    assert "P10   00006  exported lib.il:3  used at 00001" in text
    assert "Y1       r: - | w: 00008" in text and "X0       r: 00000 | w: -" in text
    lst = (tmp_path / "p.lst").read_text().splitlines()
    assert "00001     2  main.il:3: CALL P10" in lst
    assert any("FEND" in x and "inserted by the linker" in x for x in lst)


def test_duplicate_label_names_both_modules(tmp_path):
    _files(tmp_path, main=MAIN, lib=LIB, lib2=LIB.replace(".export P10\n", "").replace("Y1", "Y2"))
    objs = tmp_path / "o"
    objs.mkdir()
    for name in ("main", "lib", "lib2"):
        srcs = ["main.il", "lib.il"] if name == "main" else [f"{name}.il"]
        r = run_mlc("build", "-c", *srcs, "-o", str(objs), cwd=tmp_path)
        assert r.code == 0, r.err
    r = run_mlc("link", "o/main.mlo", "o/lib.mlo", "o/lib2.mlo", "-o", "p.mlx", cwd=tmp_path)
    assert r.code == 1 and "E504" in r.err
    assert "lib.il" in r.err and "lib2.il" in r.err
    assert not (tmp_path / "p.mlx").exists()


def test_undefined_and_local_labels(tmp_path):
    _files(tmp_path, main=MAIN, lib=LIB)
    objs = tmp_path / "o"
    objs.mkdir()
    assert run_mlc("build", "-c", "main.il", "lib.il", "-o", "o", cwd=tmp_path).code == 0
    r = run_mlc("link", "o/main.mlo", "-o", "p.mlx", cwd=tmp_path)
    assert r.code == 1 and "E505" in r.err and "no module defines P10" in r.err
    _files(tmp_path, lib=LIB.replace(".export P10\n", ""))
    assert run_mlc("build", "lib.il", "-o", "o/local.mlo", cwd=tmp_path).code == 0
    r = run_mlc("link", "o/main.mlo", "o/local.mlo", "-o", "p.mlx", cwd=tmp_path)
    assert r.code == 1 and "E505" in r.err and "local to lib.il" in r.err
    r = run_mlc("link", "o/lib.mlo", "-o", "p.mlx", cwd=tmp_path)
    assert r.code == 1 and "E507" in r.err


def test_capacity_setting(tmp_path):
    _files(tmp_path, main=MAIN, lib=LIB)
    (tmp_path / "mlc.toml").write_text("capacity = 8\n")
    r = run_mlc("build", "main.il", "lib.il", "-o", "p.mlx", cwd=tmp_path)
    assert r.code == 1 and "E314" in r.err and "holds 8" in r.err
    (tmp_path / "mlc.toml").write_text("capacity = 11\n")
    assert run_mlc("build", "main.il", "lib.il", "-o", "p.mlx", cwd=tmp_path).code == 0


def test_double_coil_across_objects_w506(tmp_path):
    _files(tmp_path, main=MAIN, lib=LIB.replace("Y1", "Y0"))
    assert run_mlc("build", "-c", "main.il", "lib.il", "-o", ".", cwd=tmp_path).code == 0
    r = run_mlc("link", "main.mlo", "lib.mlo", "-o", "p.mlx", cwd=tmp_path)
    assert r.code == 0 and "W506" in r.err and "main.il:5" in r.err
    r = run_mlc("build", "main.il", "lib.il", "-o", "p.mlx", cwd=tmp_path)
    assert "W401" in r.err and "W506" not in r.err  # the checker saw them together: one warning


# ------------------------------------------------------------------ outputs

def test_source_error_writes_nothing_and_keeps_good_output(tmp_path):
    _files(tmp_path, main=MAIN)
    assert run_mlc("build", "main.il", "-o", "m.mlo", "--listing", "m.lst", cwd=tmp_path).code == 0
    good = (tmp_path / "m.mlo").read_bytes()
    _files(tmp_path, main=MAIN.replace("OUT Y0", "OUT X0"))
    r = run_mlc("build", "main.il", "-o", "m.mlo", "--listing", "m.lst", cwd=tmp_path)
    assert r.code == 1 and "E210" in r.err
    assert (tmp_path / "m.mlo").read_bytes() == good
    assert [p.name for p in tmp_path.iterdir() if p.name.startswith(".mlc-")] == []


def test_project_build_without_arguments(tmp_path):
    shutil.copytree(PROJECT, tmp_path / "p", ignore=shutil.ignore_patterns("build"))
    r = run_mlc("build", cwd=tmp_path / "p")
    assert r.code == 0, r.err
    assert sorted(x.name for x in (tmp_path / "p" / "build").iterdir()) == ["program.lst", "program.map", "program.mlx"]
    assert "[xref]" in (tmp_path / "p" / "build" / "program.map").read_text()
    r = run_mlc("build", cwd=tmp_path)
    assert r.code == 2 and "E510" in r.err


def test_usage_errors(tmp_path):
    _files(tmp_path, main=MAIN, lib=LIB)
    r = run_mlc("build", "main.il", "lib.il", "-o", "x.mlo", cwd=tmp_path)
    assert r.code == 2 and "E510" in r.err
    r = run_mlc("build", "main.il", "-o", "x.bin", cwd=tmp_path)
    assert r.code == 2 and "E510" in r.err
    r = run_mlc("build", "main.il", "-o", "x.mlo", "--map", "x.map", cwd=tmp_path)
    assert r.code == 2 and not (tmp_path / "x.mlo").exists()


def test_objdump_text_shows_symbols_and_sources(tmp_path):
    _files(tmp_path, main=MAIN)
    assert run_mlc("build", "main.il", "-o", "m.mlo", cwd=tmp_path).code == 0
    out = run_mlc("objdump", "m.mlo", cwd=tmp_path).out
    assert "00000     1  LD       START=X0" in out and "main.il:2" in out


# ------------------------------------------------------------------ the simulator's entry point

def test_program_from_paths_mixes_sources_objects_and_programs(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    _files(tmp_path, main=MAIN, lib=LIB)
    from_sources, diags, _ = program_from_paths(["main.il", "lib.il"], T)
    assert from_sources is not None and not [d for d in diags if d.severity == "error"]
    assert run_mlc("build", "-c", "main.il", "lib.il", "-o", ".").code == 0
    assert run_mlc("build", "main.il", "lib.il", "-o", "p.mlx").code == 0
    mixed, _, _ = program_from_paths(["main.il", "lib.mlo"], T)
    linked, _, _ = program_from_paths(["p.mlx"], T)
    objects, _, _ = program_from_paths(["main.mlo", "lib.mlo"], T)
    for image in (mixed, linked, objects):
        assert image is not None
        assert [(i.mnemonic, i.operands, i.texts, i.addr, i.line, i.col, i.table) for i in image.instrs] == \
               [(i.mnemonic, i.operands, i.texts, i.addr, i.line, i.col, i.table) for i in from_sources.instrs]
        assert image.modules == from_sources.modules and image.symbols == {"START": "X0"}
    bad, diags, _ = program_from_paths(["p.mlx", "lib.mlo"], T)
    assert bad is None and any(d.code == "E509" for d in diags)


def test_project_symbols_from_mlc_toml(tmp_path):
    (tmp_path / "mlc.toml").write_text('sources = ["a.il"]\noutput = "out/a.mlx"\n[symbols]\nSTART = "X0"\n')
    _files(tmp_path, a="LD START\nOUT Y0\nEND\n")
    r = run_mlc("build", cwd=tmp_path)
    assert r.code == 0, r.err
    doc = json.loads(run_mlc("objdump", "--json", "out/a.mlx", cwd=tmp_path).out)
    assert doc["instructions"][0]["operands"] == ["X0"] and doc["instructions"][0]["texts"] == ["START"]
    (tmp_path / "mlc.toml").write_text('sources = ["a.il"]\n[symbols]\nK1 = "X0"\n')
    r = run_mlc("build", cwd=tmp_path)
    assert r.code == 1 and "E106" in r.err


def test_well_formed_but_wrong_objects_are_rejected(good_object):
    """A valid checksum is not enough: shapes and addresses must match the target's tables."""
    from mlctool.asm.objfile import encode
    obj = decode(good_object, T)
    k = next(k for k, i in enumerate(obj.instrs) if not i.spec.short_steps)
    obj.instrs[k].steps += 1
    with pytest.raises(ObjectError, match="form"):
        decode(encode(obj), T)
    obj = decode(good_object, T)
    obj.instrs[3].addr += 1
    with pytest.raises(ObjectError):
        decode(encode(obj), T)
    obj = decode(good_object, T)
    obj.instrs[0].texts = ()
    with pytest.raises(ObjectError):
        decode(encode(obj), T)


@pytest.mark.parametrize("output", ["x.mlo", "x.mlx"])
def test_objects_never_store_an_absolute_source_path(tmp_path, output):
    """Given absolutely (or as ../c.il), a source was stored with its absolute path: the same
    source gave other bytes from another folder, and objdump --il-dir refused the object
    (issue 21 item 15). Names are relative to the project, else the current folder."""
    src = tmp_path / "c.il"
    src.write_text((SAMPLES / "nc5" / "conveyor.il").read_text())
    (tmp_path / "a").mkdir()
    (tmp_path / "b").mkdir()
    assert run_mlc("build", "c.il", "-o", output, cwd=tmp_path).code == 0
    assert run_mlc("build", str(src), "-o", output, cwd=tmp_path / "a").code == 0
    assert run_mlc("build", "../c.il", "-o", output, cwd=tmp_path / "b").code == 0
    built = [(d / output).read_bytes() for d in (tmp_path, tmp_path / "a", tmp_path / "b")]
    assert built[0] == built[1] == built[2]
    assert str(tmp_path).encode() not in built[1]
    r = run_mlc("objdump", output, "--il-dir", "il", cwd=tmp_path / "a")
    assert r.code == 0, r.err
    assert (tmp_path / "a" / "il" / "c.il").is_file()
