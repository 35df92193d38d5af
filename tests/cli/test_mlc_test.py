"""`mlc test` on the sample project: scenarios, JUnit, coverage (Cobertura), failures, jobs."""

from __future__ import annotations

import json
import re
import shutil
from pathlib import Path

import jsonschema
import pytest
import yaml
from lxml import etree

from tests.conftest import ROOT, SAMPLES, junit_schema, without_times

DATA = ROOT / "tests" / "data"


@pytest.fixture
def project(tmp_path: Path) -> Path:
    dest = tmp_path / "project"
    shutil.copytree(SAMPLES / "project", dest, ignore=shutil.ignore_patterns("build", "out"))
    return dest


def _validate_junit(path: Path) -> etree._Element:
    doc = etree.parse(str(path))
    junit_schema().assertValid(doc)
    return doc.getroot()


def _validate_cobertura(path: Path) -> etree._Element:
    dtd = etree.DTD(str(DATA / "cobertura-coverage-04.dtd"))
    doc = etree.parse(str(path))
    assert dtd.validate(doc), dtd.error_log.filter_from_errors()
    return doc.getroot()


def test_project_passes_with_coverage_and_junit(mlc, project):
    r = mlc("test", "--coverage", "--junit", "out.xml", cwd=project)
    assert r.code == 0, r.out + r.err
    assert re.search(r"^4 passed, 0 failed$", r.out, re.M)
    root = _validate_junit(project / "out.xml")
    suites = root.findall("testsuite")
    assert [s.get("name") for s in suites] == sorted(s.get("name") for s in suites)
    assert len(suites) == 4 and all(s.get("failures") == "0" and s.get("errors") == "0" for s in suites)
    assert sum(int(s.get("tests")) for s in suites) == len(root.findall(".//testcase"))
    cob = _validate_cobertura(project / "coverage.xml")
    assert float(cob.get("line-rate")) >= 0.95 and float(cob.get("branch-rate")) >= 0.9
    files = {c.get("filename") for c in cob.iter("class")}
    assert files == {"src/conveyor.il", "src/pickplace.il"}
    data = json.loads((project / "coverage.json").read_text())
    t = data["totals"]
    assert t["instructions"] == int(cob.get("lines-covered")) and t["instructions_total"] == int(cob.get("lines-valid"))
    assert "TOTAL" in (project / "coverage.txt").read_text()


def test_uncovered_lines_are_named(mlc, project):
    # keep only the short scenario: the pick cycle's later steps are never executed
    for p in (project / "tests").glob("*.stim"):
        if p.name != "bad_step.stim":
            p.unlink()
    r = mlc("test", "--coverage", str(project))
    assert r.code == 0
    text = (project / "coverage.txt").read_text()
    assert "src/pickplace.il:" in text and "never executed" in text
    cob = _validate_cobertura(project / "coverage.xml")
    lines = {(c.get("filename"), int(line.get("number"))): int(line.get("hits"))
             for c in cob.iter("class") for line in c.iter("line")}
    src = (project / "src" / "pickplace.il").read_text().splitlines()
    rst_swing = next(k for k, line in enumerate(src, 1) if line.split()[:2] == ["RST", "SWING"])
    assert lines[("src/pickplace.il", rst_swing)] == 0  # step 4 of the pick cycle never ran
    assert lines[("src/pickplace.il", rst_swing - 1)] > 0  # its condition (LD= STEP K4) was evaluated


def test_broken_test_fails_and_shows_the_expectation(mlc, project):
    stim = project / "tests" / "pick_cycle.stim"
    stim.write_text(stim.read_text().replace("expect Y2=1 Y3=1 D10=2", "expect Y2=1 Y3=1 D10=7"))
    r = mlc("test", "--junit", "out.xml", cwd=project)
    assert r.code == 1
    assert "tests/pick_cycle.stim:" in r.err and "error[E603]" in r.err and "D10 expected 7, actual 2" in r.err
    assert "FAIL" in r.out and "3 passed, 1 failed" in r.out
    root = _validate_junit(project / "out.xml")
    failures = root.findall(".//failure")
    assert len(failures) == 1 and "D10 expected 7" in failures[0].get("message")


def test_jobs_give_the_same_results(mlc, project):
    assert mlc("test", "--junit", "one.xml", "--coverage", "--coverage-dir", "c1", cwd=project).code == 0
    assert mlc("test", "-j", "2", "--junit", "two.xml", "--coverage", "--coverage-dir", "c2", cwd=project).code == 0
    assert without_times((project / "one.xml").read_bytes()) == without_times((project / "two.xml").read_bytes())
    assert (project / "c1" / "coverage.json").read_bytes() == (project / "c2" / "coverage.json").read_bytes()


def test_no_project_is_a_usage_error(mlc, tmp_path):
    r = mlc("test", str(tmp_path))
    assert r.code == 2 and "mlc.toml" in r.err


def test_project_is_formatted(mlc):
    sources = sorted(str(p) for p in (SAMPLES / "project").rglob("*.il"))
    r = mlc("fmt", "--check", *sources)
    assert r.code == 0, r.out


def test_ci_workflows_parse_and_their_sarif_validates(mlc, project):
    """docs/ci.md: the workflows are valid YAML, use real mlc commands, and the SARIF the
    GitHub workflow uploads validates against the SARIF 2.1.0 schema."""
    from mlctool.cli import all_commands

    text = (ROOT / "docs" / "ci.md").read_text()
    blocks = re.findall(r"```yaml\n(.*?)```", text, re.S)
    docs = [yaml.safe_load(b) for b in blocks]
    commands = [re.sub(r"^.*?mlc ", "", line.strip()).split()[0] for b in blocks for line in b.splitlines()
                if re.search(r"(run:|-)\s+mlc ", line)]
    assert commands and set(commands) <= set(all_commands()), commands
    gh = next(d for d in docs if isinstance(d, dict) and "jobs" in d)
    steps = gh["jobs"]["plc"]["steps"]
    check = next(s["run"] for s in steps if s.get("name") == "check")
    assert check.startswith("mlc check --format sarif")
    r = mlc("check", "--format", "sarif", cwd=project)  # the project's sources, as the workflow runs it
    assert r.code == 0
    schema = json.loads((DATA / "sarif-schema-2.1.0.json").read_text())
    jsonschema.validate(json.loads(r.out), schema)
    hooks = yaml.safe_load((ROOT / ".pre-commit-hooks.yaml").read_text())
    assert {h["id"] for h in hooks} == {"mlc-check", "mlc-fmt", "mlc-fmt-check"}
    assert all(h["entry"].split()[1] in all_commands() for h in hooks)


# ------------------------------------------------------------------ -k, --json, failure files

def _break_pick_cycle(project):
    stim = project / "tests" / "pick_cycle.stim"
    stim.write_text(stim.read_text().replace("expect Y2=1 Y3=1 D10=2", "expect Y2=1 Y3=1 D10=7"))


def test_k_selects_scenarios_by_substring_or_glob(mlc, project):
    r = mlc("test", "--json", "-k", "pick", str(project))
    assert r.code == 0 and list(json.loads(r.out)["scenarios"]) == ["tests/pick_cycle.stim"]
    r = mlc("test", "--json", "-k", "tests/b*", "-k", "stop_*.stim", str(project))
    assert list(json.loads(r.out)["scenarios"]) == ["tests/bad_step.stim", "tests/batch_full.stim",
                                                    "tests/stop_and_guard.stim"]
    r = mlc("test", "-k", "nothing-like-it", str(project))
    assert r.code == 2 and "no scenario matches -k nothing-like-it" in r.err and "tests/pick_cycle.stim" in r.err


def test_json_holds_each_scenario_as_mlc_sim_json_does(mlc, project):
    _break_pick_cycle(project)
    r = mlc("test", "--json", str(project))
    assert r.code == 1
    doc = json.loads(r.out)  # stdout is the JSON alone: no table
    assert (doc["passed"], doc["failed"]) == (3, 1)
    one = mlc("sim", "src/conveyor.il", "src/pickplace.il", "--stimulus", "tests/pick_cycle.stim", "--json",
              cwd=project)
    assert doc["scenarios"]["tests/pick_cycle.stim"] == json.loads(one.out)
    assert doc["artifacts"] == {"tests/pick_cycle.stim": ["mlc-test-out/tests-pick_cycle.vcd",
                                                          "mlc-test-out/tests-pick_cycle.html"]}


def test_a_failing_scenario_writes_its_waveform_and_report_beside_the_junit(mlc, project):
    _break_pick_cycle(project)
    r = mlc("test", "--junit", "ci/junit.xml", cwd=project)
    assert r.code == 1
    vcd, html = project / "ci" / "tests-pick_cycle.vcd", project / "ci" / "tests-pick_cycle.html"
    assert "tests/pick_cycle.stim: failed; waveform ci/tests-pick_cycle.vcd, report ci/tests-pick_cycle.html" in r.err
    assert "$timescale" in vcd.read_text() and "D10" in vcd.read_text()
    assert "<html" in html.read_text("utf-8").lower() and (project / "ci" / "tests-pick_cycle.gtkw").is_file()
    # the page shows the failure: its row, the first-failure line, and opens at its scan
    page = html.read_text("utf-8")
    row = re.search(r'<tr class="fail" data-scan="(\d+)" id="first-failure">.*?<td>D10</td><td>7</td><td>2</td>', page)
    assert row and 'type="range" min="0" max="' in page and f'value="{row[1]}" aria-label="scan"' in page
    assert "<b>First failure</b>" in page and "D10 expected 7, actual 2" in page
    assert sorted(p.name for p in (project / "ci").iterdir()) == [
        "junit.xml", "tests-pick_cycle.gtkw", "tests-pick_cycle.html", "tests-pick_cycle.vcd"]  # passing: none
    root = _validate_junit(project / "ci" / "junit.xml")
    suite = next(s for s in root.findall("testsuite") if s.get("name") == "tests/pick_cycle.stim")
    out = suite.find("system-out").text
    assert "waveform: ci/tests-pick_cycle.vcd" in out and "report: ci/tests-pick_cycle.html" in out
    assert not (project / "mlc-test-out").exists()
    # without --junit: the default folder, or --out
    assert mlc("test", "--out", "fails", cwd=project).code == 1
    assert (project / "fails" / "tests-pick_cycle.vcd").is_file()
    assert mlc("test", str(project)).code == 1 and (project / "mlc-test-out" / "tests-pick_cycle.html").is_file()


def test_a_passing_run_writes_no_failure_files(mlc, project):
    assert mlc("test", "--junit", "ci/junit.xml", cwd=project).code == 0
    assert sorted(p.name for p in (project / "ci").iterdir()) == ["junit.xml"]
    assert not (project / "mlc-test-out").exists()
