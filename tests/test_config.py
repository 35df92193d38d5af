"""mlc.toml / [tool.mlc] validation (issue 14 §3, issue 21 #6 and #10): E110 at the key's line."""

from __future__ import annotations

import json

import pytest

from mlctool.check import check_texts
from mlctool.config import Config, key_positions, load_config
from mlctool.diagnostics import MlcError
from mlctool.syntax.source import SourceText
from mlctool.targetapi import load_target

PROGRAM = "LD X0\nOUT Y0\nEND\n"


def _project(tmp_path, toml: str, name: str = "mlc.toml"):
    (tmp_path / name).write_text(toml)
    (tmp_path / "a.il").write_text(PROGRAM)
    return tmp_path


def _errors(err: str) -> list[str]:
    return [line for line in err.splitlines() if "error[" in line]


@pytest.mark.parametrize("toml, line, expect", [
    ('target = "nc5"\ntaget = "vs"\n', 2, "unknown key `taget` in mlc.toml; did you mean `target`?"),
    ('# a project\n\nsorces = ["a.il"]\n', 3, "unknown key `sorces` in mlc.toml; did you mean `sources`?"),
    ('[symbol]\nA = "X0"\n', 1, "did you mean `symbols`?"),
    ('target = 5\n', 1, "`target` must be a target name string"),
    ('capacity = "big"\n', 1, "`capacity` must be a positive whole number of steps"),
    ('capacity = true\n', 1, "`capacity` must be a positive whole number"),
    ('capacity = 0\n', 1, "`capacity` must be a positive whole number"),
    ('target = "nc5"\nsources = [1, 2]\n', 2, "`sources` must be a list of path strings"),
    ('tests = [1]\n', 1, "`tests` must be a list of glob strings"),
    ('output = 3\n', 1, "`output` must be a path string"),
    ('severity = 1\n', 1, "`severity` must be a table"),
    ('target = "vz"\n', 1, "unknown target 'vz'; did you mean 'vs'?"),
    ('[severity]\nW401 = "off"\nW499 = "off"\n', 3, "unknown code `W499` in [severity]"),
    ('[severity]\nW401 = "of"\n', 2, 'severity of W401 must be "error", "warning" or "off"'),
    ('[severity]\nW401 = 0\n', 2, 'severity of W401 must be'),
    ('[severity]\nE201 = "off"\n', 2, "E201 is an error and cannot be turned off"),
    ('[severity]\n"e205" = "warning"\n', 2, "E205 is an error and cannot be made a warning"),
    ('severity.E201 = "off"\n', 1, "E201 is an error and cannot be turned off"),
    ('target = "nc5"\nsources = [\n', 3, "not valid TOML"),
])
def test_config_errors_at_their_line(mlc, tmp_path, toml, line, expect):
    """Before: unknown keys and codes were ignored, wrong types crashed (exit 3), errors could
    be turned off. Now each is E110 at its own line, exit 2, for every command reading it."""
    _project(tmp_path, toml)
    for args in (("check", "a.il"), ("build",), ("sim", "a.il", "--scans", "1")):
        r = mlc(*args, cwd=tmp_path)
        assert r.code == 2, (args, r.err)
        errors = _errors(r.err)
        assert len(errors) == 1 and "error[E110]" in errors[0] and expect in errors[0], (args, r.err)
        assert errors[0].startswith(f"{tmp_path / 'mlc.toml'}:{line}:"), errors[0]
        assert "internal error" not in r.err


def test_config_error_shows_the_line_and_column(mlc, tmp_path):
    _project(tmp_path, 'target = "nc5"\n[severity]\n  W401 = "off"\n  W4O5 = "error"\n')
    r = mlc("check", "a.il", cwd=tmp_path)
    assert f"{tmp_path / 'mlc.toml'}:4:3: error[E110]: unknown code `W4O5` in [severity]; did you mean `W405`?" \
        in r.err
    assert '    4 |   W4O5 = "error"' in r.err and "|   ^^^^" in r.err


def test_every_problem_is_reported_in_line_order(mlc, tmp_path):
    _project(tmp_path, 'taget = "nc5"\ncapacity = "big"\n[severity]\nE201 = "off"\n')
    errors = _errors(mlc("check", "a.il", cwd=tmp_path).err)
    assert [e.split(":")[-4] for e in errors] == ["1", "2", "4"], errors


def test_pyproject_tool_mlc(mlc, tmp_path):
    toml = '[tool.black]\nline-length = 99\n\n[tool.mlc]\ntarget = "nc5"\ntaget = "vs"\n[tool.mlc.severity]\nE201 = "off"\n'
    _project(tmp_path, toml, "pyproject.toml")
    r = mlc("check", "a.il", cwd=tmp_path)
    errors = _errors(r.err)
    assert r.code == 2 and len(errors) == 2
    assert errors[0].startswith(f"{tmp_path / 'pyproject.toml'}:6:1: error[E110]: unknown key `taget` in [tool.mlc]")
    assert errors[1].startswith(f"{tmp_path / 'pyproject.toml'}:8:1: error[E110]: E201 is an error")
    # other tools' tables are none of mlc's business
    (tmp_path / "pyproject.toml").write_text('[tool.black]\nline-lenght = 99\n[tool.mlc]\ntarget = "nc5"\n')
    assert mlc("check", "a.il", cwd=tmp_path).code == 0


def test_known_keys_are_accepted(tmp_path):
    """Every key docs/project.md documents (and `encoding`, issue 14 §3) loads."""
    _project(tmp_path, 'target = "vs"\nmodel = "VS1"\ncapacity = 8000\nsources = ["a.il"]\ntests = ["t/*.stim"]\n'
                       'output = "b/p.mlx"\nlisting = "b/p.lst"\nmap = "b/p.map"\nname = "demo"\nencoding = "cp950"\n'
                       '[symbols]\nSTART = "X0"\n[severity]\nW401 = "off"\nw405 = "error"\n')
    cfg = load_config(tmp_path)
    assert cfg.target == "vs" and cfg.capacity == 8000 and cfg.severity == {"W401": "off", "W405": "error"}
    assert cfg.data["encoding"] == "cp950"


def test_key_positions_scan():
    text = ('# top\ntarget = "nc5"  # x\n"quoted key" = 1\ndesc = """\nfake = 1\n"""\n'
            '[severity]\n  W401="off"\nsub.key = 2\n[ tool . "mlc" ]\nsources = [\n  "a.il",\n]\n')
    pos = key_positions(text)
    assert pos[("target",)] == (2, 1, 6)
    assert pos[("quoted key",)][0] == 3
    assert ("fake",) not in pos  # inside a multi-line string
    assert pos[("severity",)] == (7, 2, 8)
    assert pos[("severity", "W401")] == (8, 3, 4)
    assert pos[("severity", "sub", "key")][0] == 9
    assert pos[("tool", "mlc", "sources")][0] == 11


def test_ignore_and_select_refuse_errors_and_unknown_codes(mlc, tmp_path):
    p = _project(tmp_path, 'target = "nc5"\n') / "a.il"
    p.write_text("LD X0\nOTU Y0\nEND\n")
    r = mlc("check", "--ignore", "E201", str(p))
    assert r.code == 2 and "error[E110]: --ignore E201: E201 is an error and cannot be ignored" in r.err
    r = mlc("check", "--ignore", "W41", str(p))
    assert r.code == 2 and "--ignore W41: unknown code; did you mean W401?" in r.err
    r = mlc("check", "--select", "E201", str(p))
    assert r.code == 2 and "E201 is not a lint rule" in r.err
    # a warning may still be ignored, and the error still shows
    r = mlc("check", "--ignore", "w401,W405", str(p))
    assert r.code == 1 and "E201" in r.err


def test_errors_stay_errors_whatever_the_severity_table_says():
    """Issue 21 #6: a Config built in code (not read from a file) cannot turn errors off either."""
    target = load_target("nc5")
    src = SourceText("m.il", "LD X0\nOTU Y0\nOUT Y99999\nEND\n")
    res = check_texts([src], target, Config(severity={"E201": "off", "E205": "warning"}), frozenset({"E201"}))
    assert [(d.code, d.severity) for d in res.diagnostics] == [("E201", "error"), ("E205", "error")]


def test_noqa_does_not_silence_an_error(mlc, tmp_path):
    p = tmp_path / "n.il"
    p.write_text("LD X0\nOTU Y0 ; mlc: noqa E201\nOUT Y1 ; mlc: noqa\nOUT Y1 ; mlc: noqa W401\nEND\n")
    data = json.loads(mlc("check", "--format", "json", str(p)).out)
    assert [(d["code"], d["line"]) for d in data["diagnostics"]] == [("E201", 2)]


@pytest.mark.parametrize("line, code", [("OTU Y0 ; mlc: noqa E201", "E201"), ("OUT Y99999 ; mlc: noqa", "E205")])
def test_build_and_sim_refuse_a_program_with_errors(mlc, tmp_path, line, code):
    """Issue 21 #6: `E201 = "off"` let the instruction vanish from the build (exit 0); `E205 =
    "off"` with OUT Y99999 crashed build and sim. Whatever suppresses it, the error is fatal."""
    p = tmp_path / "b.il"
    p.write_text(f"LD X0\n{line}\nEND\n")
    (tmp_path / "b.stim").write_text("10ms X0=1\n")
    for args, exit_code in ((("build", "b.il", "-o", "b.mlx"), 1), (("sim", "b.il", "--stimulus", "b.stim"), 2)):
        r = mlc(*args, cwd=tmp_path)
        assert r.code == exit_code and f"error[{code}]" in r.err, (args, r.err)
    assert not (tmp_path / "b.mlx").exists()


def test_config_error_is_an_mlc_error(tmp_path):
    (tmp_path / "mlc.toml").write_text("capacity = -1\n")
    with pytest.raises(MlcError) as e:
        load_config(tmp_path)
    assert e.value.exit_code == 2 and e.value.diagnostic.code == "E110"


def test_errors_about_a_keys_value_point_at_its_line(mlc, tmp_path):
    """[symbols] entries (E106) and an empty `sources` (E510) name their own line, in the file read."""
    _project(tmp_path, '[tool.mlc]\nsources = []\n\n[tool.mlc.symbols]\nSTART = "X0"\nX1 = "X2"\n', "pyproject.toml")
    r = mlc("check", "a.il", cwd=tmp_path)
    assert f"{tmp_path / 'pyproject.toml'}:6:1: error[E106]: [symbols] X1 = 'X2'" in r.err, r.err
    r = mlc("build", cwd=tmp_path)
    assert r.code == 2 and f"{tmp_path / 'pyproject.toml'}:2:1: error[E510]" in r.err, r.err


@pytest.mark.parametrize("line, code", [("OTU Y0", "E201"), ("OUT Y99999", "E205")])
def test_a_severity_table_made_in_code_cannot_make_build_and_sim_run_an_invalid_program(tmp_path, line, code):
    """Issue 21 #6 in depth: even a Config that bypasses the file check (E201/E205 "off")
    yields no program image: the instruction neither vanishes nor reaches the simulator."""
    from mlctool.asm import program_from_paths

    p = tmp_path / "b.il"
    p.write_text(f"LD X0\n{line}\nEND\n")
    config = Config(severity={"E201": "off", "E205": "off"})
    image, diags, _ = program_from_paths([str(p)], load_target("nc5"), config)
    assert image is None and [(d.code, d.severity) for d in diags] == [(code, "error")]
