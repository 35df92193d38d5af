"""`mlc verify` as a command: exit codes, JSON, SARIF, JUnit, the budget's UNKNOWN, bad
input at its line, the engines forced, mlc.toml [verify] and `mlc test` running properties
beside scenarios."""

from __future__ import annotations

import json
import shutil
import xml.etree.ElementTree as ET

import pytest

from conftest import ROOT, run_mlc

PRESS = ROOT / "samples" / "verify" / "press.il"


@pytest.fixture
def press(tmp_path):
    shutil.copy(PRESS, tmp_path / "press.il")
    shutil.copy(ROOT / "samples" / "verify" / "press_broken.il", tmp_path / "broken.il")
    (tmp_path / "p.props").write_text("scan 10ms\nguard: never RAM and not GUARD\n"
                                      "estop: response ESTOP -> not RAM within 1 scans\n", "utf-8")
    return tmp_path


def test_json_sarif_junit_of_a_violation(press):
    r = run_mlc("verify", "broken.il", "--props", "p.props", "--json", "--sarif", "v.sarif", "--junit", "v.xml",
                "--out", "cx", cwd=press)
    assert r.code == 1, r.err
    body = json.loads(r.out)
    by = {x["property"]: x for x in body["results"]}
    assert by["guard"]["status"] == "PROVEN" and by["estop"]["status"] == "VIOLATED" and not body["ok"]
    assert by["estop"]["trace"]["stimulus"] == "cx/p.estop.stim" and (press / "cx" / "p.estop.vcd").is_file()
    assert by["estop"]["line"] == 3 and by["estop"]["trace"]["scans"] == 2
    sarif = json.loads((press / "v.sarif").read_text("utf-8"))
    results = sarif["runs"][0]["results"]
    assert [(x["ruleId"], x["locations"][0]["physicalLocation"]["region"]["startLine"]) for x in results] == \
        [("E704", 3)]
    suite = ET.parse(press / "v.xml").getroot().find("testsuite")
    assert suite.get("tests") == "2" and suite.get("failures") == "1"
    assert "error[E704]" in r.err and "p.props:3:" in r.err


def test_all_proven_exits_0_and_writes_nothing(press):
    r = run_mlc("verify", "press.il", "--props", "p.props", "--out", "cx", cwd=press)
    assert r.code == 0, r.err
    assert "2 properties: 2 proven, 0 violated, 0 unknown" in r.out
    assert not (press / "cx").exists()


def test_the_budget_gives_unknown_with_figures(press):
    r = run_mlc("verify", "press.il", "--props", "p.props", "--engine", "explicit", "--max-states", "20", "--json",
                cwd=press)
    assert r.code == 1
    results = json.loads(r.out)["results"]
    assert {x["status"] for x in results} == {"UNKNOWN"}
    assert all("--max-states 20 reached" in x["reason"] and x["stats"]["states"] > 20 for x in results)
    assert "warning[W705]" in r.err


@pytest.mark.parametrize("text,code,where", [
    ("never RAMM and GUARD\n", "E701", "p.props:1:7"),
    ("never RAM and\n", "E700", "p.props:1:14"),
    ("assume X0=1\nassume X0=0\nnever RAM\n", "E702", "p.props:2:8"),
])
def test_bad_property_files_exit_2_at_their_place(press, text, code, where):
    (press / "p.props").write_text(text, "utf-8")
    r = run_mlc("verify", "press.il", "--props", "p.props", cwd=press)
    assert r.code == 2
    assert f"{where}: error[{code}]" in r.err, r.err


def test_symbolic_names_what_it_does_not_model(tmp_path):
    (tmp_path / "c.il").write_text("LD X0\nCNT C0 K3\nLD C0\nOUT Y0\nEND\n", "utf-8")
    (tmp_path / "p.props").write_text("never Y0 and X1\n", "utf-8")
    r = run_mlc("verify", "c.il", "--props", "p.props", "--engine", "symbolic", cwd=tmp_path)
    assert r.code == 2
    assert "E703" in r.err and "CNT C0 K3" in r.err and "--engine explicit" in r.err
    assert run_mlc("verify", "c.il", "--props", "p.props", "--engine", "explicit", cwd=tmp_path).code == 1


def test_index_modified_operands_are_refused_by_the_explicit_engine(tmp_path):
    (tmp_path / "z.il").write_text("LD X0\nMOV K1 D0Z0\nEND\n", "utf-8")
    (tmp_path / "p.props").write_text("always D0 < 5\n", "utf-8")
    r = run_mlc("verify", "z.il", "--props", "p.props", "--engine", "explicit", cwd=tmp_path)
    assert r.code == 2 and "E703" in r.err and "MOV K1 D0Z0" in r.err


def test_a_time_limit_answers_unknown_not_a_hang(tmp_path):
    # a counter that counts every rising edge of X0 to 30000: more states than a second reaches
    (tmp_path / "c.il").write_text("LDP X0\nADD D0 K1 D0\nEND\n", "utf-8")
    (tmp_path / "p.props").write_text("always D0 >= -32768\n", "utf-8")
    r = run_mlc("verify", "c.il", "--props", "p.props", "--engine", "explicit", "--max-wall", "1s", "--json",
                cwd=tmp_path)
    assert r.code == 1
    result = json.loads(r.out)["results"][0]
    assert result["status"] == "UNKNOWN" and "--max-wall" in result["reason"]


def test_mlc_test_runs_the_project_properties(press):
    (press / "tests").mkdir()
    (press / "tests" / "run.stim").write_text("0ms X2=1 X0=1\n#1 X0=0\n#2 expect Y0=1\nrun #3\n", "utf-8")
    (press / "mlc.toml").write_text('target = "nc5"\nsources = ["broken.il"]\ntests = ["tests/*.stim"]\n'
                                    '[verify]\nproperties = ["*.props"]\n', "utf-8")
    r = run_mlc("test", "--json", "--junit", "j.xml", cwd=press)
    assert r.code == 1, r.err
    body = json.loads(r.out)
    assert body["passed"] == 1
    assert [(x["property"], x["status"]) for x in body["properties"]] == [("guard", "PROVEN"), ("estop", "VIOLATED")]
    suites = [s.get("name") for s in ET.parse(press / "j.xml").getroot()]
    assert suites == ["tests/run.stim", "p.props"]
    (press / "mlc.toml").write_text('target = "nc5"\nsources = ["press.il"]\ntests = ["tests/*.stim"]\n'
                                    '[verify]\nproperties = ["*.props"]\n', "utf-8")
    r = run_mlc("test", cwd=press)
    assert r.code == 0, r.out + r.err
    assert "2 proven" in r.out
    r = run_mlc("verify", cwd=press)  # no FILE, no --props: the project's
    assert r.code == 0 and "2 properties: 2 proven" in r.out


def test_a_missing_project_property_file_is_e110(press):
    (press / "mlc.toml").write_text('target = "nc5"\nsources = ["press.il"]\n[verify]\nproperties = ["no/*.props"]\n',
                                    "utf-8")
    r = run_mlc("verify", cwd=press)
    assert r.code == 2 and "E110" in r.err and "no/*.props" in r.err
