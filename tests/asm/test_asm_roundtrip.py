"""Round trip (objdump --il then build gives the same bytes) and determinism of builds."""

from __future__ import annotations

import os
import random
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from conftest import SAMPLES, run_mlc
from mlctool.asm.encode import directives_of, object_from_module
from mlctool.asm.listing import unit_il
from mlctool.asm.objfile import decode, encode
from mlctool.check import check_texts
from mlctool.syntax.source import SourceText
from mlctool.targetapi import load_target

PROJECT = SAMPLES / "project"
T = load_target("nc5")


def build_bytes(path: str, text: str) -> bytes:
    """In-process `mlc build SRC -o X.mlo` of one source text."""
    result = check_texts([SourceText(path, text)], T)
    assert result.errors == 0, [d.message for d in result.diagnostics if d.severity == "error"]
    (module,) = result.modules
    return encode(object_from_module(module, directives_of(path, result.lines[path])))


def il_of(data: bytes) -> str:
    return unit_il(decode(data, T), 0)


# ------------------------------------------------------------------ samples, through the CLI

SAMPLE_SOURCES = sorted((SAMPLES / "nc5").glob("*.il")) + sorted((PROJECT / "src").glob("*.il"))


@pytest.mark.parametrize("path", SAMPLE_SOURCES, ids=lambda p: p.name)
def test_sample_round_trip(tmp_path, path):
    name = path.name
    shutil.copy(path, tmp_path / name)
    first = run_mlc("build", name, "-o", "a.mlo", cwd=tmp_path)
    if first.code == 1 and "E304" in first.err:
        pytest.skip("needs the other modules of its project (tested below)")
    assert first.code == 0, first.err
    il = run_mlc("objdump", "--il", "a.mlo", cwd=tmp_path)
    assert il.code == 0, il.err
    again = tmp_path / "again"
    again.mkdir()
    (again / name).write_text(il.out, "utf-8")
    second = run_mlc("build", name, "-o", "b.mlo", cwd=again)
    assert second.code == 0, second.err
    assert (again / "b.mlo").read_bytes() == (tmp_path / "a.mlo").read_bytes()


def test_project_round_trip_through_il_dir(tmp_path):
    """A linked program: objdump --il-dir writes every module; building them again gives
    the same .mlx (and the separately compiled objects link to the same bytes too)."""
    r = run_mlc("build", "-o", str(tmp_path / "a.mlx"), cwd=PROJECT)
    assert r.code == 0, r.err
    r = run_mlc("objdump", "--il-dir", str(tmp_path / "src2"), str(tmp_path / "a.mlx"))
    assert r.code == 0, r.err
    srcs = ["src/conveyor.il", "src/pickplace.il"]
    r = run_mlc("build", *srcs, "-o", str(tmp_path / "b.mlx"), cwd=tmp_path / "src2")
    assert r.code == 0, r.err
    assert (tmp_path / "b.mlx").read_bytes() == (tmp_path / "a.mlx").read_bytes()
    objs = tmp_path / "objs"
    objs.mkdir()
    r = run_mlc("build", "-c", *srcs, "-o", str(objs), cwd=PROJECT)
    assert r.code == 0, r.err
    r = run_mlc("link", str(objs / "conveyor.mlo"), str(objs / "pickplace.mlo"), "-o", str(tmp_path / "c.mlx"))
    assert r.code == 0, r.err
    assert (tmp_path / "c.mlx").read_bytes() == (tmp_path / "a.mlx").read_bytes()


# ------------------------------------------------------------------ generated programs

SAMPLE_OPERANDS = {
    "X": ["X0", "X7", "X511", "X600"], "Y": ["Y0", "Y17", "Y600"], "M": ["M0", "M100", "M15000"],
    "A": ["A0", "A3"], "T": ["T0", "T200"], "C": ["C0", "C70"], "D": ["D0", "D100", "D5V0", "D12000"],
    "V": ["V1"], "Z": ["Z2"], "K": ["K0", "K3", "K-7", "K100000", "K20V0"], "F": ["F1.5", "F-0.25", "F3"],
    "KnX": ["K1X0", "K4X10"], "KnY": ["K2Y0", "K8Y0"], "KnM": ["K4M0", "K1M5"], "KnA": ["K1A0"],
}


def _pool() -> list[str]:
    """Instruction lines valid after `LD X0` (checked once), from the target's tables."""
    rnd = random.Random(1)
    candidates = []
    for spec in T.instructions.values():
        if spec.cls not in ("output", "and", "or") or not spec.operands or spec.op in ("cj", "call"):
            continue
        for _ in range(8):
            ops = [rnd.choice([o for k in sorted(s.kinds) for o in SAMPLE_OPERANDS.get(k, [])] or ["K1"])
                   for s in spec.operands]
            if "same-kind" in spec.constraints:  # ZRST: both ends one kind
                ops[1] = rnd.choice([o for o in SAMPLE_OPERANDS[ops[0][0]] if o[1:].isdigit()])
            ops += [f"K{rnd.randint(-5, 5)}" for _ in range(rnd.randint(0, 3))] if spec.table else []
            # a contact needs a coil after it to close the rung
            candidates.append(" ".join([spec.mnemonic, *ops]) + ("\nOUT M1" if spec.cls != "output" else ""))
    pool = []
    for line in sorted(set(candidates)):
        r = check_texts([SourceText("p.il", f"LD X0\n{line}\nEND\n")], T)
        if r.errors == 0:
            pool.append(line)
    return pool


POOL = _pool()
CONTACTS = ["LD X1", "LDI M3", "LDP X2", "LD= D0 K5", "DLD> D10 K-3", "LDF T0"]
SEPARATORS = [" ", "  ", "\t", ", ", " ,"]


@st.composite
def programs(draw) -> str:
    lines = [".define IN X5", ".define OUTV Y3"]
    labels = iter(range(0, 256, 7))
    for _ in range(draw(st.integers(1, 12))):
        kind = draw(st.sampled_from(["pool", "pool", "symbol", "jump", "blank"]))
        if kind == "pool":
            lines += [draw(st.sampled_from(CONTACTS)), *draw(st.sampled_from(POOL)).split("\n")]
        elif kind == "symbol":
            lines += ["LD IN", "OUT OUTV" if draw(st.booleans()) else "SET outv"]
        elif kind == "jump":
            p = next(labels)
            lines += ["LD X1", f"CJ P{p}", "LD X2", "OUT M7", f"P{p}:"]
        else:
            lines.append(draw(st.sampled_from(["", "; a comment", "   // another"])))
    call = next(labels)
    if draw(st.booleans()):  # a main program with its own subroutine
        lines += ["LD X3", f"CALL P{call}", "FEND", f"P{call}:", "LD X4", "INC D1", "SRET", "END"]
    else:  # a library: the same rungs as an exported subroutine
        lines = [".library", f".export P{call}", f"P{call}:"] + lines + ["SRET"]
    out = []
    for n, line in enumerate(lines):
        indent = draw(st.sampled_from(["", " ", "    ", "\t"]))
        step = f"{n:04d} " if line and not line.startswith((";", "/")) and draw(st.booleans()) else ""
        words = line.split(" ")
        sep = draw(st.sampled_from(SEPARATORS)) if not line.startswith(".") else " "
        text = sep.join(words) if words[0] and not words[0].startswith((";", "/")) else line
        if draw(st.booleans()) and text and not text.startswith((";", "/", ".")):
            text = text.lower()
        out.append(indent + step + text)
    return "\n".join(out) + "\n"


@settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(programs())
def test_generated_round_trip(text):
    first = build_bytes("gen/prog.il", text)
    il = il_of(first)
    assert build_bytes("gen/prog.il", il) == first
    assert il_of(first) == il  # and the IL is stable


def test_pool_covers_the_instruction_set():
    mnemonics = {line.split()[0] for line in POOL}
    wanted = {s.mnemonic for s in T.instructions.values()
              if s.cls in ("output", "and", "or") and s.operands and s.op not in ("cj", "call")}
    assert mnemonics == wanted, sorted(wanted - mnemonics)


# ------------------------------------------------------------------ determinism

def _build_project(copy: Path, cwd: Path, env_extra: dict) -> dict[str, bytes]:
    env = dict(os.environ, **env_extra)
    r = subprocess.run([sys.executable, "-c", "from mlctool.cli import main; main()", "build"], cwd=cwd, env=env,
                       capture_output=True, text=True, timeout=60)
    assert r.returncode == 0, r.stderr
    return {p.name: p.read_bytes() for p in sorted((copy / "build").iterdir())}


def test_build_is_deterministic(tmp_path):
    """Two copies at different paths, built from different folders at different times and
    time zones, give the same bytes for .mlx, .map and listing."""
    a, b = tmp_path / "one" / "proj", tmp_path / "two" / "deeper" / "proj"
    for d in (a, b):
        shutil.copytree(PROJECT / "src", d / "src")
        shutil.copy(PROJECT / "mlc.toml", d / "mlc.toml")
    first = _build_project(a, a, {"TZ": "UTC", "SOURCE_DATE_EPOCH": "1"})
    os.utime(b / "src" / "conveyor.il", (2_000_000_000, 2_000_000_000))
    second = _build_project(b, b / "src", {"TZ": "Asia/Taipei", "SOURCE_DATE_EPOCH": "1999999999"})
    assert set(first) == {"program.mlx", "program.map", "program.lst"}
    assert first == second
    assert str(tmp_path).encode() not in first["program.mlx"]
    assert b"/" + b"tmp" not in first["program.mlx"]
