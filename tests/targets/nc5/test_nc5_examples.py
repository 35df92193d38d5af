"""The manual's worked examples 6.1-6.16 against the virtual NC (issue 27, item 4): the sample
samples/nc5/man_6_<N>_<topic>.il of each example runs its stimulus (.stim beside it), whose
`model nc5` line starts the NC side, on both engines with every expectation held and the
same final state; the stimulus plays no NC -> MLC or HMI -> MLC device (the NC answers, not
the file) and its expectations read the NC. docs/nc5-audit.md "Examples (chapter 6)" names
test_example[6.N] for each example; an example whose sample is not written yet is in
PENDING, and is tested as soon as its sample exists."""

from __future__ import annotations

import re

import pytest
from nc5kit import NC5, nc_written

from conftest import SAMPLES, SIM_ENGINES
from mlctool.asm import program_from_paths
from mlctool.sim.run.run import Simulation, build_models, plan_scans
from mlctool.sim.signals import SIGNAL
from mlctool.sim.stimulus.stimulus import load_stimulus

NC5_SAMPLES = SAMPLES / "nc5"
# the sections of chapter 6 (L5600-L5617), each a sample man_6_<N>_<topic>.il
SECTIONS = {
    "6.1": "mode switching", "6.2": "machining, block functions, feed override", "6.3": "handwheel",
    "6.4": "continuous jog", "6.5": "incremental jog", "6.6": "rapid traverse", "6.7": "homing",
    "6.8": "M/S/T codes", "6.9": "soft limit release, hardware limit release",
    "6.10": "spindle control", "6.11": "spindle gear change", "6.12": "one-key macro call",
    "6.13": "I/O tool magazine", "6.14": "MLC axes", "6.15": "synchronous and transferred axes",
    "6.16": "gantry",
}
# Examples whose sample needs what the virtual NC does not model yet (docs/nc5.md "Not
# simulated yet"): one-key macros, MLC axes, synchronous/transferred/gantry axes.
PENDING: set[str] = set()


def sample(section: str):
    """The example's program, or None when it is not written yet."""
    found = sorted(NC5_SAMPLES.glob(f"man_6_{section.split('.')[1]}_*.il"))
    assert len(found) <= 1, found
    return found[0] if found else None


PRESENT = [s for s in SECTIONS if sample(s) is not None]


def test_every_example_has_a_sample_or_is_pending():
    missing = [s for s in SECTIONS if s not in PENDING and sample(s) is None]
    assert not missing, f"examples without a sample (and not PENDING): {missing}"
    assert len(PRESENT) >= 12


@pytest.mark.parametrize("section", PRESENT)
def test_example(section):
    il = sample(section)
    st, diags = load_stimulus(str(il.with_suffix(".stim")), NC5)
    assert st is not None and not [d for d in diags if d.severity == "error"], diags
    assert st.lines[0].startswith(f"# Manual {section} "), st.lines[0]
    assert [m.kind for m in st.models] == ["nc5"], "the example runs against one virtual NC"
    played = [(e.line, v.name) for e in st.events if e.kind in ("set", "force")
              for v, _ in e.assigns if nc_written(v)]
    assert not played, f"the stimulus plays the NC's own devices: {played}"
    nc_checks = [c for e in st.events if e.kind == "expect" for c in e.checks
                 if c.view.kind.startswith(SIGNAL) or nc_written(c.view)]
    assert len(nc_checks) >= 5, "the expectations must read what the NC does"
    image, diags, _ = program_from_paths([str(il)], NC5)
    assert image is not None, diags
    finals = []
    for engine in SIM_ENGINES:
        st, _ = load_stimulus(str(il.with_suffix(".stim")), NC5)
        models, mdiags = build_models(st, NC5)
        assert not mdiags, mdiags
        period = st.scan_us or 10_000
        r = Simulation(image, NC5, st, models, period, [], False, engine=engine).run(
            plan_scans(st, period, None, None))
        assert r.fault is None, (engine, r.fault)
        assert not r.failed, (engine, [(f.line, f.device, f.expected, f.actual) for f in r.failed])
        assert len(r.expectations) >= 5
        finals.append(r.devices)
    assert finals[0] == finals[1], "the two engines end in different states"


def test_a_wrong_nc_expectation_fails_the_example(tmp_path):
    """The expectations are live: 6.13's tool in the spindle after T5 is 5; expecting 6 fails
    at that line with the NC's value."""
    il = sample("6.13")
    text = il.with_suffix(".stim").read_text(encoding="utf-8")
    line = "370ms   expect D31036=5 Y92=0 M21016=1"
    assert line in text
    for part in il.parent.glob("man_6_13_*.nc"):
        (tmp_path / part.name).write_bytes(part.read_bytes())
    stim = tmp_path / "wrong.stim"
    stim.write_text(text.replace(line, line.replace("D31036=5", "D31036=6")), encoding="utf-8")
    image, _, _ = program_from_paths([str(il)], NC5)
    st, _ = load_stimulus(str(stim), NC5)
    models, _ = build_models(st, NC5)
    r = Simulation(image, NC5, st, models, 10_000, [], False).run(plan_scans(st, 10_000, None, None))
    number = text[:text.index(line)].count("\n") + 1
    assert [(f.line, f.device, f.expected, f.actual) for f in r.failed] == [(number, "D31036", "6", 5)]


def test_sample_names_follow_the_sections():
    for il in NC5_SAMPLES.glob("man_6_*.il"):
        assert re.fullmatch(r"man_6_(\d+)_[a-z0-9_]+", il.stem), il.name
        assert f"6.{il.stem.split('_')[2]}" in SECTIONS, il.name
