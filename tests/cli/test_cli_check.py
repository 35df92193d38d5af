"""`mlc check` as a command: formats, exit codes, explain, config, suppressions."""

from __future__ import annotations

import json
import re
from pathlib import Path

import jsonschema
import pytest

from mlctool.codes import CODES
from tests.conftest import ROOT

SCHEMA = json.loads((ROOT / "tests" / "data" / "sarif-schema-2.1.0.json").read_text())

BAD = """LD X0
OUT Y0
MOV K99999 D0
OUT Y0
END
"""


@pytest.fixture
def bad(tmp_path: Path) -> Path:
    p = tmp_path / "bad.il"
    p.write_text(BAD)
    return p


def test_text_output_has_location_code_and_caret(mlc, bad):
    r = mlc("check", str(bad))
    assert r.code == 1
    assert f"{bad}:3:5: error[E206]:" in r.err
    lines = r.err.splitlines()
    k = next(i for i, line in enumerate(lines) if "error[E206]" in line)
    assert lines[k + 1].endswith("| MOV K99999 D0")
    caret = lines[k + 2]
    assert caret.index("^") - caret.index("|") - 2 == 4 and caret.count("^") == len("K99999")
    assert "1 error, 1 warning" in r.err


def test_json_output(mlc, bad):
    r = mlc("check", "--format", "json", str(bad))
    assert r.code == 1
    data = json.loads(r.out)
    assert data["errors"] == 1 and data["warnings"] == 1
    by_code = {d["code"]: d for d in data["diagnostics"]}
    e = by_code["E206"]
    assert (e["file"], e["line"], e["column"], e["end_line"], e["end_column"], e["severity"]) == \
        (str(bad), 3, 5, 3, 11, "error")
    assert by_code["W401"]["line"] == 4
    assert set(e) >= {"file", "line", "column", "end_line", "end_column", "severity", "code", "message"}


def test_sarif_validates_against_schema(mlc, bad):
    r = mlc("check", "--format", "sarif", str(bad))
    assert r.code == 1
    doc = json.loads(r.out)
    jsonschema.validate(doc, SCHEMA)
    run = doc["runs"][0]
    rule_ids = [rule["id"] for rule in run["tool"]["driver"]["rules"]]
    assert rule_ids == list(CODES)
    res = {x["ruleId"]: x for x in run["results"]}
    assert res["E206"]["level"] == "error" and res["W401"]["level"] == "warning"
    region = res["E206"]["locations"][0]["physicalLocation"]["region"]
    assert (region["startLine"], region["startColumn"]) == (3, 5)
    assert rule_ids[res["E206"]["ruleIndex"]] == "E206"
    for rule in run["tool"]["driver"]["rules"]:
        assert rule["help"]["text"].strip()


def test_clean_file_exits_zero_and_warnings_with_werror(mlc, tmp_path):
    ok = tmp_path / "ok.il"
    ok.write_text("LD X0\nOUT Y0\nEND\n")
    assert mlc("check", str(ok)).code == 0
    warn = tmp_path / "warn.il"
    warn.write_text("LD X0\nOUT Y0\nOUT Y0\nEND\n")
    assert mlc("check", str(warn)).code == 0
    assert mlc("check", "--werror", str(warn)).code == 1
    assert mlc("check", "--werror", "--ignore", "W401", str(warn)).code == 0
    assert mlc("check", "--werror", "--no-lint", str(warn)).code == 0


def test_missing_file_is_usage_error(mlc, tmp_path):
    r = mlc("check", str(tmp_path / "nope.il"))
    assert r.code == 2
    assert "E100" in r.err and "Traceback" not in r.err


def test_unknown_target_is_usage_error(mlc, bad):
    r = mlc("check", "--target", "s7", str(bad))
    assert r.code == 2 and "unknown target 's7'" in r.err


def test_noqa_suppression(mlc, tmp_path):
    p = tmp_path / "s.il"
    p.write_text("LD X0\nOUT Y0\nOUT Y0 ; mlc: noqa W401\nOUT Y0 // mlc: noqa E206\nEND\n")
    data = json.loads(mlc("check", "--format", "json", str(p)).out)
    assert [(d["code"], d["line"]) for d in data["diagnostics"]] == [("W401", 4)]
    p.write_text("LD X0\nOUT Y0\nOUT Y0 ; mlc: noqa\nEND\n")
    assert json.loads(mlc("check", "--format", "json", str(p)).out)["diagnostics"] == []


def test_config_changes_severity(mlc, tmp_path):
    (tmp_path / "mlc.toml").write_text('target = "nc5"\n[severity]\nW401 = "error"\nW405 = "off"\n')
    p = tmp_path / "c.il"
    p.write_text("LD X0\nOUT Y0\nOUT Y0\nSET M1\nEND\n")
    r = mlc("check", "--format", "json", "c.il", cwd=tmp_path)
    data = json.loads(r.out)
    assert r.code == 1
    assert [(d["code"], d["severity"]) for d in data["diagnostics"]] == [("W401", "error")]


def test_pyproject_tool_section(mlc, tmp_path):
    (tmp_path / "pyproject.toml").write_text('[tool.mlc]\n[tool.mlc.severity]\nW401 = "off"\n')
    (tmp_path / "c.il").write_text("LD X0\nOUT Y0\nOUT Y0\nEND\n")
    assert json.loads(mlc("check", "--format", "json", "c.il", cwd=tmp_path).out)["diagnostics"] == []


def test_bad_config_value(mlc, tmp_path):
    (tmp_path / "mlc.toml").write_text('[severity]\nW401 = "loud"\n')
    (tmp_path / "c.il").write_text("END\n")
    r = mlc("check", "c.il", cwd=tmp_path)
    assert r.code == 2 and "W401" in r.err


@pytest.mark.parametrize("code", list(CODES))
def test_explain_every_code(mlc, code):
    r = mlc("explain", code.lower())
    assert r.code == 0
    assert r.out.startswith(f"{code} (")
    assert len(r.out.strip().splitlines()) >= 3


def test_every_code_check_can_emit_is_documented():
    """Every code literal passed to diag()/report()/err() in the sources exists in codes.toml."""
    used = set()
    for path in (ROOT / "mlctool").rglob("*.py"):
        used |= set(re.findall(r'"([EW][0-9]{3})"', path.read_text()))
    assert used, "no codes found"
    assert used <= set(CODES), sorted(used - set(CODES))


def test_explain_unknown_code(mlc):
    r = mlc("explain", "X999")
    assert r.code == 2


def test_explain_a_device_prints_its_signal_row(mlc):
    """`mlc explain M21000`: the NC5 manual's row of a special M (5.2.1 L3509, 5.3.2)."""
    r = mlc("explain", "m21000")
    assert r.code == 0
    lines = r.out.splitlines()
    assert lines[0] == "M21000 - 程式啟動 cycle start, MLC->NC, channel 1, 5.3.2"
    for field in ("manual name  程式啟動", "English      cycle start", "direction    MLC->NC",
                  "access       R/W", "type         bit", "channel      1 (pattern M2x000)",
                  "section      5.3.2 (row of 5.2.1, manual line 3509)"):
        assert any(line.strip().startswith(field) for line in lines), field
    r = mlc("explain", "D31024")
    assert r.code == 0 and "R: the NC writes it" in r.out and "32-bit" in r.out
    r = mlc("explain", "M20000")
    assert r.code == 2 and "undefined number of the MLC->NC range M20000-M28999" in r.err
    r = mlc("explain", "--target", "vs", "M21000")
    assert r.code == 2 and "target vs has no signal table" in r.err


def test_targets_and_version(mlc):
    r = mlc("targets")
    assert r.code == 0 and "nc5" in r.out
    # the manual by its title and edition; its file only where it is (not in a clone)
    assert "manual: 台達 NC5 系列 MLC 應用技術手冊 V1.0 (2022-06)" in r.out
    manual = ROOT.parent / "shared" / "manuals" / "000_a33d4a328dc57a96.txt"
    assert ("000_a33d4a328dc57a96.txt" in r.out) == manual.is_file()
    v = mlc("--version")
    assert v.code == 0 and "0.1.0" in v.out


def test_utf16_with_bom_is_read(mlc, tmp_path):
    p = tmp_path / "u16.il"
    p.write_bytes("LD X0\r\nOUT Y0\r\nEND\r\n".encode("utf-16"))
    assert mlc("check", str(p)).code == 0


def test_invalid_utf8_and_nul(mlc, tmp_path):
    p = tmp_path / "bin.il"
    p.write_bytes(b"LD X0\nOUT \xff\xfeY0\nEND\n")
    r = mlc("check", "--format", "json", str(p))
    d = json.loads(r.out)["diagnostics"][0]
    assert r.code == 2 and (d["code"], d["line"], d["column"]) == ("E102", 2, 5)
    p.write_bytes(b"LD X0\n\x00\x01\x02")
    d = json.loads(mlc("check", "--format", "json", str(p)).out)["diagnostics"][0]
    assert (d["code"], d["line"], d["column"]) == ("E101", 2, 1)


def test_docs_list_every_code():
    text = (ROOT / "docs" / "check.md").read_text()
    missing = [c for c in CODES if f"`{c}`" not in text]
    assert not missing, missing


def test_independent_programs_do_not_share_coils_but_libraries_do(mlc, tmp_path):
    (tmp_path / "a.il").write_text("LD X0\nOUT Y0\nEND\n")
    (tmp_path / "b.il").write_text("LD X1\nOUT Y0\nEND\n")
    data = json.loads(mlc("check", "--format", "json", "a.il", "b.il", cwd=tmp_path).out)
    assert data["diagnostics"] == []
    (tmp_path / "lib.il").write_text(".library\n.export P1\nP1\nLD X2\nOUT Y0\nSRET\n")
    (tmp_path / "c.il").write_text("LD X1\nCALL P1\nFEND\nEND\n")
    data = json.loads(mlc("check", "--format", "json", "a.il", "c.il", "lib.il", cwd=tmp_path).out)
    assert [(d["file"], d["line"], d["code"]) for d in data["diagnostics"]] == [("lib.il", 5, "W401")]


def test_select_lint_rules(mlc, tmp_path):
    p = tmp_path / "l.il"
    p.write_text("LD X0\nOUT Y0\nOUT Y0\nSET M1\nMOV K99999 D0\nEND\n")
    codes = lambda *a: [d["code"] for d in json.loads(mlc("check", "--format", "json", *a, str(p)).out)["diagnostics"]]  # noqa: E731
    assert codes() == ["W401", "W405", "E206"]
    assert codes("--select", "W405") == ["W405", "E206"]
    assert codes("--select", "W401,W405") == ["W401", "W405", "E206"]
    r = mlc("check", "--select", "E206", str(p))
    assert r.code == 2 and "E110" in r.err and "E206 is not a lint rule" in r.err


def test_text_output_summarises_beyond_50_per_code_json_and_sarif_never(mlc, tmp_path):
    p = tmp_path / "many.il"
    p.write_text("LD X0\nOUT M0\n" * 120 + "MOV K99999 D0\nEND\n")  # 119 W401, one E206
    r = mlc("check", str(p))
    assert r.code == 1
    assert r.err.count("warning[W401]") == 50 and r.err.count("error[E206]") == 1
    assert "... and 69 more W401 (use --show-all to see them)\n1 error, 119 warnings" in r.err
    full = mlc("check", "--show-all", str(p))
    assert full.err.count("warning[W401]") == 119 and "more W401" not in full.err
    assert len(json.loads(mlc("check", "--format", "json", str(p)).out)["diagnostics"]) == 120
    sarif = json.loads(mlc("check", "--format", "sarif", str(p)).out)
    assert len(sarif["runs"][0]["results"]) == 120


def test_explain_without_a_code_lists_every_code(mlc):
    r = mlc("explain")
    assert r.code == 0
    listed = [line.split()[0] for line in r.out.splitlines()[:-1]]
    assert sorted(listed) == sorted(CODES) and len(listed) == len(CODES)
    assert "W401  warning  double coil" in r.out
