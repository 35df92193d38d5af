"""The worked examples of docs/verify.md: every property of the bundled property files is
proven on its program, and each deliberately broken copy (samples/verify/*_broken.il) is
violated with a counterexample that `mlc sim` replays to the same failing expectation."""

from __future__ import annotations

import json
import re

import pytest

from conftest import ROOT, run_mlc

# (program, its property file, target, the broken copy, the property it breaks)
EXAMPLES = [
    ("samples/nc5/conveyor.il", "samples/nc5/conveyor.props", "nc5", "samples/verify/conveyor_broken.il",
     "belt_stops"),
    ("samples/vs/traffic_light.il", "samples/vs/traffic_light.props", "vs", "samples/verify/traffic_light_broken.il",
     "a_lamps"),
    ("samples/verify/press.il", "samples/verify/press.props", "nc5", "samples/verify/press_broken.il", "estop"),
]


def verify(program: str, props: str, target: str, out) -> tuple[int, dict]:
    r = run_mlc("verify", program, "--props", props, "--target", target, "--json", "--out", str(out), "-q",
                cwd=ROOT)
    assert r.code in (0, 1), r.err
    return r.code, json.loads(r.out)


@pytest.mark.parametrize("example", EXAMPLES, ids=lambda e: e[0].split("/")[-1])
def test_every_documented_property_is_proven(example, tmp_path):
    program, props, target, _, _ = example
    code, body = verify(program, props, target, tmp_path)
    assert code == 0, body
    assert body["results"] and all(r["status"] == "PROVEN" for r in body["results"])
    # a witness of a reachability property replays and holds
    for r in body["results"]:
        if r["kind"] == "reachable":
            sim = run_mlc("sim", program, "--target", target, "--stimulus", r["trace"]["stimulus"], cwd=ROOT)
            assert sim.code == 0, sim.err


@pytest.mark.parametrize("example", EXAMPLES, ids=lambda e: e[3].split("/")[-1])
def test_the_broken_copy_is_violated_and_its_counterexample_replays(example, tmp_path):
    program, props, target, broken, name = example
    code, body = verify(broken, props, target, tmp_path)
    assert code == 1
    result = next(r for r in body["results"] if r["property"] == name)
    assert result["status"] == "VIOLATED"
    stim = result["trace"]["stimulus"]
    text = open(stim, encoding="utf-8").read()
    last = [ln for ln in text.splitlines() if " expect " in ln][-1]
    failing_check = re.search(r"expect (.*?)\s+#", last)[1].split()[-1]
    device = re.split(r"!?=", failing_check)[0]
    sim = run_mlc("sim", broken, "--target", target, "--stimulus", stim, cwd=ROOT)
    assert sim.code == 1
    # the run fails at the counterexample's last expect line, on the property's device, and nowhere else
    line_no = text.splitlines().index(last) + 1
    failures = re.findall(r"\.stim:(\d+):\d+: error\[E603\]: [^:]*: (\S+) expected", sim.err)
    assert failures == [(str(line_no), device)], sim.err
