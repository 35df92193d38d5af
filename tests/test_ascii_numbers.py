"""One rule for every number of every input: ASCII digits only (mlctool/limits.py; issue
30.8, 30.16). Python's readers are wider: int() takes "٣" (Arabic-Indic three) as 3,
str.isdigit() takes "²", which int() then refuses. Each input kind below gets non-ASCII digits
where a number goes: a diagnostic with its place (or a usage error naming the option), exit 2
(1 for an import row), never exit 3, never the number read as if it were ASCII."""

from __future__ import annotations

import pytest

from conftest import ROOT, run_mlc
from mlctool.limits import integer, real

NOT_ASCII = ("²", "¹⁰", "٣", "３", "0²")  # superscripts (isdigit), Arabic-Indic and fullwidth (int() reads them)


@pytest.mark.parametrize("text", NOT_ASCII + ("1_000", " 5", "+", "", "0x"))
def test_the_readers_take_ascii_digits_only(text):
    for base in (10, 16, 0):
        with pytest.raises(ValueError):
            integer(text, base)
    if text.strip():
        with pytest.raises(ValueError):
            real(text)


def test_the_readers_read_what_int_and_float_read():
    assert [integer(t) for t in ("0", "-12", "+7", "9" * 20)] == [0, -12, 7, int("9" * 20)]
    assert integer("ff", 16) == 255 and integer("0x1F", 0) == 31 and integer("-0b101", 0) == -5
    assert [real(t) for t in ("1.5", "-.25", "2e3", "7")] == [1.5, -0.25, 2000.0, 7.0]
    assert real("inf", finite=False) == float("inf")
    with pytest.raises(ValueError):
        real("inf")
    with pytest.raises(ValueError):
        integer("9" * 21)


NC5_IL = "LD X0\nOUT Y0\nEND\n"
FBS_IL = "LD X0\nOUT Y0\nEND\n"
# (target, stimulus lines after `scan 10ms`, what the message names); {n} is the non-ASCII number
STIMULI = [
    ("nc5", "0ms X0={n}", "X0"),
    ("nc5", "0ms D0=K{n}", "D0"),
    ("nc5", "0ms D0=H{n}", "D0"),
    ("nc5", "0ms D0:f={n}.5", "D0"),
    ("nc5", "{n}ms X0=1", "time"),
    ("fbs", "model stepper axis={n}", "axis"),
    ("fbs", "model stepper axis=0 pulses_per_rev={n}", "pulses_per_rev"),
    ("fbs", "model stepper axis=0 um_per_rev={n}", "um_per_rev"),
    ("nc5", "model xc100 in1=Y0 out1=X0 p1=ABS:{n}:50", "POS"),
    ("nc5", "model xc100 in1=Y0 out1=X0 p1=ABS:100:{n}", "speed"),
    ("nc5", "model xc100 in1=Y0 out1=X0 r0706={n}", "r0706"),
    ("nc5", "model xc100 in1=Y0 out1=X0 lead={n}", "lead"),
]


@pytest.mark.parametrize(("target", "line", "named"), STIMULI)
@pytest.mark.parametrize("n", ["²", "٣"])
def test_a_stimulus_number_in_other_digits_is_e601_where_it_stands(tmp_path, target, line, named, n):
    (tmp_path / "p.il").write_text(NC5_IL if target == "nc5" else FBS_IL)
    (tmp_path / "p.stim").write_text(f"scan 10ms\n{line.format(n=n)}\n")
    r = run_mlc("sim", "--target", target, "p.il", "--stimulus", "p.stim", cwd=tmp_path)
    assert r.code == 2 and "p.stim:2:" in r.err and "error[E6" in r.err, r.err
    assert named in r.err and "internal error" not in r.err


@pytest.mark.parametrize("n", NOT_ASCII)
def test_a_gx_works2_step_field_in_other_digits_is_e907_at_its_row(tmp_path, n):
    text = (ROOT / "tests/corpus/gxworks2_en.csv").read_bytes().decode("utf-16")
    first = text.index('"0"\t""\t"LD"')
    row = text[:first].count("\n") + 1
    (tmp_path / "g.csv").write_bytes((text[:first] + f'"{n}"' + text[first + 3:]).encode("utf-16"))
    r = run_mlc("import", "g.csv", "-o", "g.il", cwd=tmp_path)
    assert r.code == 1 and f"g.csv:{row}:1: error[E907]" in r.err and repr(n) in r.err, r.err
    assert not (tmp_path / "g.il").exists()


@pytest.mark.parametrize("n", ["²", "٣"])
def test_other_inputs_refuse_other_digits(tmp_path, n):
    """IL operands and step numbers, FBs positioning sources and register images, mlc.toml."""
    (tmp_path / "p.il").write_text(f"LD X0\nMOV K{n} D0\n{n} OUT Y0\nEND\n")
    r = run_mlc("check", "p.il", cwd=tmp_path)
    assert r.code == 1 and "p.il:2:" in r.err and "p.il:3:" in r.err, r.err
    (tmp_path / "h.pos").write_text(f"001 SPD {n}000\n DRV ADR,+,1000,Ut\n MEND\n")
    r = run_mlc("check", "--target", "fbs", "h.pos", cwd=tmp_path)
    assert r.code == 1 and "h.pos:1:" in r.err, r.err
    (tmp_path / "t.csv").write_text(f"register,value\nR5000,{n}\n")
    r = run_mlc("objdump", "t.csv", cwd=tmp_path)
    assert r.code == 2 and "t.csv" in r.err and "internal error" not in r.err, r.err
    (tmp_path / "mlc.toml").write_text(f'target = "nc5"\ncapacity = {n}\n')
    r = run_mlc("check", "p.il", cwd=tmp_path)
    assert r.code == 2 and "mlc.toml:2:" in r.err and "E110" in r.err, r.err


OPTIONS = [
    ["sim", "p.il", "--stimulus", "p.stim", "--jobs", "{n}"],
    ["sim", "p.il", "--stimulus", "p.stim", "--scans", "{n}"],
    ["sim", "p.il", "--stimulus", "p.stim", "--watchdog", "{n}"],
    ["sim", "p.il", "--stimulus", "p.stim", "--until", "{n}ms"],
    ["sim", "p.il", "--stimulus", "p.stim", "--scan-time", "{n}ms"],
    ["test", "--jobs", "{n}"],
    ["debug", "p.il", "--checkpoint-every", "{n}"],
    ["device", "serve", "xc100", "--tcp", "127.0.0.1:502{n}"],
    ["device", "serve", "xc100", "--tcp", "127.0.0.1:5020", "--station", "{n}"],
    ["device", "serve", "xc100", "--tcp", "127.0.0.1:5020", "--lead", "{n}"],
    ["device", "serve", "xc100", "--tcp", "127.0.0.1:5020", "--duration", "{n}s"],
]


@pytest.mark.parametrize("args", OPTIONS, ids=lambda a: " ".join(a[:1] + a[-2:-1]))
@pytest.mark.parametrize("n", ["٣", "３"])
def test_a_number_option_in_other_digits_is_a_usage_error(tmp_path, args, n):
    (tmp_path / "p.il").write_text(NC5_IL)
    (tmp_path / "p.stim").write_text("scan 10ms\n0ms X0=1\n")
    r = run_mlc(*[a.format(n=n) for a in args], cwd=tmp_path)
    assert r.code == 2 and "internal error" not in r.err, r.err
    assert any(a in r.err for a in ("Invalid value", "E801", "E601", "not a time", "ASCII")), r.err
