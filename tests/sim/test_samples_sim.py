"""Every NC5 sample program runs its stimulus file with every expectation held (issue 4
acceptance: `mlc sim samples/nc5/<each>.il --stimulus <its .stim>` exits 0), on both
simulator engines; and the expectations of the manual's examples are live: one value changed
in a copy makes the run fail."""

from __future__ import annotations

import json
import re

import pytest

from conftest import SAMPLES, SIM_ENGINES, run_mlc

NC5 = SAMPLES / "nc5"
PROGRAMS = sorted(NC5.glob("*.il"))


def test_every_sample_program_has_a_stimulus_beside_it():
    assert len(PROGRAMS) >= 38
    missing = [p.name for p in PROGRAMS if not p.with_suffix(".stim").is_file()]
    assert not missing, missing


@pytest.mark.parametrize("il", [p for p in PROGRAMS if p.name.startswith("man_")], ids=lambda p: p.stem)
def test_manual_example_stimulus_cites_its_section(il):
    head = il.with_suffix(".stim").read_text(encoding="utf-8").splitlines()[0]
    section = re.match(r"man_(\d)_(\d)", il.stem)
    assert head.startswith("# Manual ") and f"{section[1]}.{section[2]}" in head, head


@pytest.mark.parametrize("engine", SIM_ENGINES)
@pytest.mark.parametrize("il", PROGRAMS, ids=lambda p: p.stem)
def test_sample_runs_its_stimulus(il, engine):
    r = run_mlc("sim", str(il), "--stimulus", str(il.with_suffix(".stim")), "--engine", engine, "--json")
    assert r.code == 0, r.err
    doc = json.loads(r.out)
    assert doc["expectations"]["failed"] == 0
    assert doc["expectations"]["passed"] >= 3  # a stimulus that checks nothing proves nothing
    assert doc["fault"] is None


# (sample, the first expect line's text, its device, the manual's value, a wrong value)
WRONG = [
    ("man_4_3_arith", "expect D70=-32768", "D70", "-32768", "32767"),  # API-17: 32,767 + 1
    ("man_4_1_for", "expect D0=3 D1=12", "D1", "12", "11"),  # API-08 example 1: 3 x 4 = 12
    ("man_4_7_vrt", "expect D1062=50", "D1062", "50", "79"),  # API-57: entry (0, +3) = 50
]


@pytest.mark.parametrize("sample,line,dev,right,wrong", WRONG, ids=[w[0] for w in WRONG])
def test_one_wrong_expected_value_fails_the_run(tmp_path, sample, line, dev, right, wrong):
    text = (NC5 / f"{sample}.stim").read_text(encoding="utf-8")
    assert line in text
    bad = line.replace(f"{dev}={right}", f"{dev}={wrong}")
    stim = tmp_path / f"{sample}.stim"
    stim.write_text(text.replace(line, bad, 1), encoding="utf-8")
    r = run_mlc("sim", str(NC5 / f"{sample}.il"), "--stimulus", str(stim))
    assert r.code == 1
    assert "error[E603]" in r.err and f"{dev} expected {wrong}, actual {right}" in r.err, r.err
    assert "1 failed" in r.out
