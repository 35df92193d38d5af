"""Corpus (issue 16): one FX3U program written in every export format the importer reads —
GX Works2 UTF-16 tab CSV with English, Simplified Chinese, Traditional Chinese and Japanese
headers, GX Developer comma CSV, the headerless GX CSV, and the same program as a Delta DVP
program in WPLSoft's and Delta's CSV — with the stack forms GX Works2 and WPLSoft emit (MPS /
MRD / MPP with new blocks joined by ANB/ORB after MRD and MPP, nested MPS), RST of every
kind, an interrupt pointer, CJ/P, MC/MCR, the families' special relays, and a device-comment
CSV. Each passes import -> check -> build -> ladder -> sim; the GX exports' step column (the
FX3U count the exporter wrote) is the truth for the built addresses."""

from __future__ import annotations

import csv
import io
from pathlib import Path

import pytest

from conftest import run_mlc
from mlctool.imports import import_file
from vskit import VS, image_of

CORPUS = Path(__file__).resolve().parent / "corpus"
GX = ["gxworks2_en.csv", "gxworks2_zh_cn.csv", "gxworks2_zh_tw.csv", "gxworks2_ja.csv", "gxdeveloper.csv",
      "gxworks2_headerless.csv"]
DELTA = ["wplsoft.csv", "delta.csv"]
FORMAT = {"gxdeveloper.csv": "gxdeveloper", "wplsoft.csv": "wplsoft", "delta.csv": "delta"}


def _import(name: str) -> tuple[str, list]:
    text, fmt, diags = import_file(str(CORPUS / name), VS)
    assert text is not None, [d.message for d in diags]
    assert fmt == FORMAT.get(name, "gxworks2")
    return text, diags


def _export_steps(name: str) -> list[int]:
    """The step number of each instruction row of a GX export, in order."""
    raw = (CORPUS / name).read_bytes()
    text = raw.decode("utf-16") if raw.startswith(b"\xff\xfe") else raw.decode("utf-8")
    rows = list(csv.reader(io.StringIO(text), delimiter="\t" if "\t" in text else ","))
    return [int(r[0]) for r in rows if len(r) > 3 and r[0].isdigit() and r[2]]


@pytest.mark.parametrize("name", GX + DELTA)
def test_import_check_build(name):
    il, diags = _import(name)
    codes = sorted({d.code for d in diags})
    # the specials mapped (and Delta's TMR/CNT written OUT), nothing else
    assert codes == (["N910", "N911"] if name in DELTA else ["N910"]), [(d.code, d.message) for d in diags]
    assert "M8000" not in il and "M1000" not in il and "LD M9000" in il and "LD M9002" in il
    assert "IX1P:" in il and "I101" not in il  # the FX pointer, VS-spelled
    image = image_of(il)
    assert image is not None, il
    if name in GX:
        # every instruction at the address the export's step column gives it
        assert [i.addr for i in image.instrs] == _export_steps(name)


def test_the_gx_exports_read_to_one_program_and_the_delta_ones_to_another():
    gx = {_import(n)[0] for n in GX}
    delta = {_import(n)[0].replace("; ", ";") for n in DELTA}
    assert len(gx) == 1
    # WPLSoft keeps the `;` comment rows, Delta's CSV has none: the instructions agree
    assert len({"\n".join(x for x in il.splitlines() if not x.startswith(";")) for il in delta}) == 1


@pytest.mark.parametrize("name", ["gxworks2_en.csv", "wplsoft.csv"])
def test_ladder_and_sim(tmp_path, name):
    r = run_mlc("import", str(CORPUS / name), "-o", "prog.il", cwd=tmp_path)
    assert r.code == 0, r.err
    r = run_mlc("check", "--target", "vs", "prog.il", cwd=tmp_path)
    assert r.code == 0 and "warning" not in r.err, r.err
    r = run_mlc("build", "--target", "vs", "prog.il", "-o", "prog.mlx", cwd=tmp_path)
    assert r.code == 0, r.err
    r = run_mlc("ladder", "--target", "vs", "prog.il", "-o", "prog.svg", cwd=tmp_path)
    assert r.code == 0 and (tmp_path / "prog.svg").stat().st_size > 1000, r.err
    r = run_mlc("sim", "--target", "vs", "prog.il", "--stimulus", str(CORPUS / "program.stim"), cwd=tmp_path)
    assert r.code == 0 and "0 failed" in r.out + r.err, r.out + r.err


def test_without_the_special_mapping_the_program_does_nothing_and_check_says_why(tmp_path):
    """The FX relays kept as written: an ordinary M8000 never turns on, the timer never runs
    (the stimulus fails), and mlc check warns W217 naming the VS relay."""
    il, _ = _import("gxworks2_en.csv")
    fx = il.replace("M9000", "M8000").replace("M9002", "M8002").replace("M9013", "M8013")
    (tmp_path / "fx.il").write_text(fx, "utf-8")
    r = run_mlc("check", "--target", "vs", "fx.il", cwd=tmp_path)
    assert "W217" in r.err and "M8000 is read but never written" in r.err and "M9000" in r.err
    r = run_mlc("sim", "--target", "vs", "fx.il", "--stimulus", str(CORPUS / "program.stim"), cwd=tmp_path)
    assert r.code != 0 and "Y3 expected 1" in r.out + r.err


@pytest.mark.parametrize(("comments", "export", "line"), [
    ("COMMENT.csv", "gxworks2_zh_cn.csv", "LD X0 ; X0 启动按钮"),
    ("COMMENT_en.csv", "gxdeveloper.csv", "LD X0 ; X0 Start button"),
])
def test_device_comments(tmp_path, comments, export, line):
    r = run_mlc("import", "--comments", str(CORPUS / comments), str(CORPUS / export), "-o", "p.il", cwd=tmp_path)
    assert r.code == 0, r.err
    il = (tmp_path / "p.il").read_text("utf-8")
    assert line in il.splitlines()
    if comments == "COMMENT.csv":  # a comment on M8000 follows it to M9000
        assert "; M9000  RUN" in il.splitlines()
    assert run_mlc("check", "--target", "vs", "p.il", cwd=tmp_path).code == 0


def test_mrd_then_compare_blocks_joined_by_orb_and_anb(tmp_path):
    """A stack form seen in a public IL listing: MPS / AND= / MRD / LD= / LD= / ANI / ORB / ANB /
    MPP / AND=. It checks clean on vs and nc5, draws as one rung of three branches, and runs:
    the MRD branch fires for D10 = 545 (first compare) and for 551 only while M5 is Off."""
    il, stim = CORPUS / "mrd_compare_blocks.il", CORPUS / "mrd_compare_blocks.stim"
    for target in ("vs", "nc5"):
        r = run_mlc("check", "--target", target, str(il))
        assert r.code == 0, r.out + r.err
    r = run_mlc("ladder", "--target", "vs", "--term", str(il))
    assert r.code == 0 and r.out.count("MOV K") == 4 and "[K551=D10]" in r.out, r.out
    r = run_mlc("sim", "--target", "vs", str(il), "--stimulus", str(stim))
    assert r.code == 0 and "3 passed, 0 failed" in r.out + r.err, r.out + r.err
    broken = tmp_path / "s.stim"
    broken.write_text(stim.read_text("utf-8").replace("D12=1500", "D12=0"), "utf-8")
    assert run_mlc("sim", "--target", "vs", str(il), "--stimulus", str(broken)).code == 1
