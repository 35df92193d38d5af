"""Objects with a valid seal but bad contents (issue 21 #7): each is built from a real
object, changed, and sealed again with the format's SHA-256 (objfile.encode), then read by
objdump (text, --il, --il-dir) and sim: exit 2 with E502, never a crash or a hang, and no
file (temporary or not) left in the --il-dir folder."""

from __future__ import annotations

import dataclasses
import hashlib

import pytest

from conftest import run_mlc
from mlctool.asm.objfile import TRAILER, ObjectError, decode, encode
from mlctool.targetapi import load_target

NC5 = load_target("nc5")
SOURCE = """LD X0
OUT Y0
LD X1
MOV K5 D0V1
DMOV K70000 D10
CJ P10
P10
END
"""


@pytest.fixture(scope="module")
def good(tmp_path_factory):
    d = tmp_path_factory.mktemp("obj")
    (d / "p.il").write_text(SOURCE, "utf-8")
    r = run_mlc("build", str(d / "p.il"), "-o", str(d / "p.mlx"), cwd=d)
    assert r.code == 0, r.err
    data = (d / "p.mlx").read_bytes()
    return decode(data, NC5)


def _operand(obj, k: int, j: int, **change):
    ins = obj.instrs[k]
    ops = list(ins.operands)
    ops[j] = dataclasses.replace(ops[j], **change)
    instrs = list(obj.instrs)
    instrs[k] = dataclasses.replace(ins, operands=tuple(ops))
    return dataclasses.replace(obj, instrs=instrs)


def _instr(obj, k: int, **change):
    instrs = list(obj.instrs)
    instrs[k] = dataclasses.replace(instrs[k], **change)
    return dataclasses.replace(obj, instrs=instrs)


def _unit_name(obj, name: str):
    return dataclasses.replace(obj, units=[dataclasses.replace(obj.units[0], path=name)],
                               instrs=[dataclasses.replace(i, file=name) for i in obj.instrs])


CASES = {
    "device number past the range": lambda o: _operand(o, 1, 0, number=10**6),
    "device number 2^40": lambda o: _operand(o, 0, 0, number=2**40),
    "unknown device kind": lambda o: _operand(o, 1, 0, kind="Q"),
    "index register at 2^33": lambda o: _operand(o, 3, 1, index=("V", 2**33)),
    "unknown index register": lambda o: _operand(o, 3, 1, index=("Q", 0)),
    # issue 30.7: devices of the target, but no index registers (D0 ran as the index)
    "D0 as the index register": lambda o: _operand(o, 3, 1, index=("D", 0)),
    "X0 as the index register": lambda o: _operand(o, 3, 1, index=("X", 0)),
    "T0 as the index register": lambda o: _operand(o, 3, 1, index=("T", 0)),
    "an empty index register": lambda o: _operand(o, 3, 1, index=("", 0)),
    "32-bit operand past the end": lambda o: _operand(o, 4, 1, number=NC5.devices["D"].hi),
    "constant outside the K range": lambda o: _operand(o, 3, 0, value=10**9),
    "float decimals 2^40": lambda o: _operand(o, 3, 0, kind="F", value=1.5, decimals=2**40),
    "a label past the pointer range": lambda o: _operand(o, 6, 0, number=10**6),
    "line number 2^40": lambda o: _instr(o, 0, line=2**40),
    "column 2^40": lambda o: _instr(o, 0, col=2**40),
    "NUL in a module name": lambda o: _unit_name(o, "a\x00b.il"),
    "line break in an operand as written": lambda o: _instr(o, 1, texts=("Y0\nEND",)),
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_resealed_bad_object_is_refused(good, case, tmp_path):
    data = encode(CASES[case](good))
    assert hashlib.sha256(data[:-TRAILER]).digest() == data[-TRAILER:]  # the seal is valid
    with pytest.raises(ObjectError) as e:
        decode(data, NC5)
    assert e.value.code == "E502"
    obj = tmp_path / "bad.mlx"
    obj.write_bytes(data)
    out = tmp_path / "il"
    for args in (["objdump", str(obj)], ["objdump", "--il", str(obj)], ["objdump", "--json", str(obj)],
                 ["objdump", "--il-dir", str(out), str(obj)], ["sim", str(obj), "--scans", "2"]):
        r = run_mlc(*args, cwd=tmp_path)
        assert r.code == 2, (args, r.out[-500:], r.err[-2000:])
        assert "E502" in r.err
    assert not out.exists() or not any(out.rglob("*"))


def test_the_unchanged_object_still_reads(good):
    assert decode(encode(good), NC5).instrs == good.instrs


def test_a_failed_write_leaves_no_temporary_file(tmp_path):
    """A write that fails after its temporary file exists (here: a name the OS refuses, as
    --il-dir could be given) removes the temporary file and says E605."""
    from mlctool import fileio

    with pytest.raises(fileio.MlcError) as e:
        fileio.Outputs().write({str(tmp_path / "a\x00b.il"): "LD X0\n"})
    assert e.value.diagnostic.code == "E605"
    assert list(tmp_path.iterdir()) == []
