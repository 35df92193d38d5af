"""samples/nc5-mill, the flagship project (issue 27 item 4): a 3-axis mill's MLC program whose
scenarios run against the virtual NC. `mlc test` passes on both engines; its scenarios drive
the NC and play none of its devices; broken/, the same program and wiring, fails on purpose
with the message the scenario's header and docs/nc5.md give; `make demo` runs both."""

from __future__ import annotations

import json
import re
import tomllib

import pytest
from nc5kit import NC5, nc_written

from conftest import ROOT, SIM_ENGINES, run_mlc
from mlctool.sim.stimulus.stimulus import load_stimulus

MILL = ROOT / "samples" / "nc5-mill"
BROKEN = MILL / "broken"
STIMS = sorted((MILL / "tests").glob("*.stim"))


@pytest.mark.parametrize("engine", SIM_ENGINES)
def test_the_mill_passes_mlc_test(engine, monkeypatch):
    monkeypatch.setenv("MLC_SIM_ENGINE", engine)
    r = run_mlc("test", str(MILL), "--json")
    assert r.code == 0, r.err
    doc = json.loads(r.out)
    assert doc["failed"] == 0 and doc["passed"] == len(STIMS) >= 4
    for path, scenario in doc["scenarios"].items():
        assert scenario["fault"] is None and scenario["expectations"]["passed"] >= 10, path


@pytest.mark.parametrize("stim", STIMS, ids=lambda p: p.stem)
def test_a_mill_scenario_drives_the_virtual_nc(stim):
    st, diags = load_stimulus(str(stim), NC5)
    assert st is not None and not diags, diags
    assert [m.kind for m in st.models] == ["nc5"]
    assert (stim.parent / st.models[0].params["program"][0]).is_file()
    played = [(e.line, v.name) for e in st.events if e.kind in ("set", "force")
              for v, _ in e.assigns if nc_written(v)]
    assert not played, f"the scenario plays the NC's own devices: {played}"


def test_the_broken_scenario_fails_with_its_documented_message(tmp_path):
    stim = BROKEN / "tests" / "deep_slot.stim"
    documented = re.search(r"^#\s+(tests/deep_slot\.stim:\d+:\d+: error\[E603\]: .*)$",
                           stim.read_text(encoding="utf-8"), re.M)[1]
    r = run_mlc("test", str(BROKEN), "--out", str(tmp_path))
    assert r.code == 1
    assert documented in r.err, r.err
    assert [line for line in r.err.splitlines() if "error[" in line] == [documented]  # the only failure
    assert "0 passed, 1 failed" in r.out
    assert (tmp_path / "tests-deep_slot.vcd").is_file() and (tmp_path / "tests-deep_slot.html").is_file()
    assert documented in (ROOT / "docs" / "nc5.md").read_text(encoding="utf-8")


def test_the_broken_project_is_the_mill():
    """Same sources, same wiring: only its scenario differs."""
    mill = tomllib.loads((MILL / "mlc.toml").read_text(encoding="utf-8"))
    broken = tomllib.loads((BROKEN / "mlc.toml").read_text(encoding="utf-8"))
    assert broken["symbols"] == mill["symbols"]
    assert [(BROKEN / s).resolve() for s in broken["sources"]] == [(MILL / s).resolve() for s in mill["sources"]]


def test_make_demo_runs_the_mill_and_its_failure():
    demo = (ROOT / "Makefile").read_text(encoding="utf-8").split("\ndemo:", 1)[1].split("\n\n", 1)[0]
    assert "mlc test samples/nc5-mill --junit" in demo
    assert "mlc test samples/nc5-mill/broken" in demo and "test $$? -eq 1" in demo
