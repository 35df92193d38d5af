"""JUnit XML (mlctool/sim/campaign/junit.py): classnames without dots, real durations, file/line on
each test case; valid against junit-10.xsd extended by file/line only."""

from __future__ import annotations

import re
import shutil

import pytest
from lxml import etree

from conftest import ROOT, SAMPLES, junit_schema, run_mlc

PLAIN_SCHEMA = etree.XMLSchema(etree.parse(str(ROOT / "tests" / "data" / "junit-10.xsd")))


@pytest.fixture
def project(tmp_path):
    dest = tmp_path / "project"
    shutil.copytree(SAMPLES / "project", dest, ignore=shutil.ignore_patterns("build", "out"))
    return dest


def _check(doc, stim_dir):
    junit_schema().assertValid(doc)
    for case in doc.iter("testcase"):  # the only deviation from the plain schema: file and line
        del case.attrib["file"], case.attrib["line"]
    PLAIN_SCHEMA.assertValid(doc)


def _parse(path):
    return etree.parse(str(path))


def test_mlc_test_junit(project):
    stim = project / "tests" / "pick_cycle.stim"
    stim.write_text(stim.read_text().replace("expect Y2=1 Y3=1 D10=2", "expect Y2=1 Y3=1 D10=7"))
    assert run_mlc("test", "--junit", "out.xml", cwd=project).code == 1
    doc = _parse(project / "out.xml")
    root = doc.getroot()
    suites = root.findall("testsuite")
    assert {s.get("file") for s in suites} == {s.get("name") for s in suites}
    for suite in suites:
        lines = (project / suite.get("name")).read_text().splitlines()
        for case in suite.findall("testcase"):
            assert "." not in case.get("classname")
            assert case.get("file") == suite.get("name")
            line = int(case.get("line"))
            assert case.get("name").startswith(f"line {line}: ") and "expect" in lines[line - 1]
    pick = next(s for s in suites if s.get("name") == "tests/pick_cycle.stim")
    assert {c.get("classname") for c in pick.iter("testcase")} == {"tests/pick_cycle_stim"}
    failed = [c for c in pick.iter("testcase") if c.find("failure") is not None]
    assert len(failed) == 1 and "D10=7" in stim.read_text().splitlines()[int(failed[0].get("line")) - 1]
    # real durations: the scenarios took time, the cases add up to no more than their suite
    times = [float(s.get("time")) for s in suites]
    assert all(t > 0 for t in times) and float(root.get("time")) == pytest.approx(sum(times), abs=1e-5)
    for suite in suites:
        cases = sum(float(c.get("time")) for c in suite.iter("testcase"))
        assert 0 < cases <= float(suite.get("time")) + 1e-5
    _check(doc, project)


def test_batch_and_single_sim_junit(project):
    src = ["src/conveyor.il", "src/pickplace.il"]
    assert run_mlc("sim", *src, "--stimulus", "tests/*.stim", "--junit", "all.xml", cwd=project).code == 0
    assert run_mlc("sim", *src, "--stimulus", "tests/bad_step.stim", "--junit", "one.xml", cwd=project).code == 0
    for name in ("all.xml", "one.xml"):
        doc = _parse(project / name)
        cases = list(doc.iter("testcase"))
        assert cases and all(re.fullmatch(r"tests/\w+_stim", c.get("classname")) for c in cases)
        assert all(float(s.get("time")) > 0 for s in doc.iter("testsuite"))
        _check(doc, project)


def test_a_stimulus_error_is_a_test_case_at_its_line(tmp_path):
    (tmp_path / "p.il").write_text("LD X0\nOUT Y0\nEND\n")
    (tmp_path / "s.v2.stim").write_text("0ms X0=1\n10ms frobnicate\n")
    r = run_mlc("sim", "p.il", "--stimulus", "*.stim", "--junit", "j.xml", cwd=tmp_path)
    assert r.code == 2
    doc = _parse(tmp_path / "j.xml")
    [case] = doc.iter("testcase")
    assert case.get("classname") == "s_v2_stim" and case.get("file") == "s.v2.stim" and case.get("line") == "2"
    assert case.find("error") is not None
    _check(doc, tmp_path)
