"""JUnit XML: one <testsuite> per stimulus file, one <testcase> per expectation line.

Decisions (docs/stimulus.md "Outputs"):
- `classname` is the stimulus path with its dots made underscores (`tests/pick_cycle.stim`
  -> `tests/pick_cycle_stim`): Jenkins splits a classname at its last dot into package and
  class, which would file the scenario under a class named `stim`.
- `time` is wall time in seconds: a suite's is its scenario's (load and run), a test case's the
  simulation since the previous expectation was checked (scenarios run together as lanes
  share the group's time evenly among their cases). Durations differ from run to run; every
  other byte is deterministic.
- Each test case has `file` and `line` (the stimulus line, or the diagnostic's place), which
  GitLab, pytest's xunit1 files and Jenkins' JUnit plugin read; the suite has `file` too. The
  output validates against Jenkins xUnit's junit-10.xsd (tests/data) extended by just those two
  optional testcase attributes.
"""

from __future__ import annotations

import os
import xml.etree.ElementTree as ET

from mlctool.sim.campaign.suite import Scenario
from mlctool.sim.run.output import failure_message, ms

_KIND = {".vcd": "waveform", ".html": "report"}


def classname(path: str) -> str:
    name = path.replace(os.sep, "/")
    while name.startswith("./"):
        name = name[2:]
    return name.replace(".", "_")


def _seconds(s: float) -> str:
    return f"{max(s, 0.0):.6f}"


def to_junit(scenarios: list[Scenario], suite_name: str) -> str:
    """One <testsuite> per stimulus file, one <testcase> per expectation line."""
    root = ET.Element("testsuites", name=suite_name, time=_seconds(sum(sc.seconds for sc in scenarios)))
    for sc in scenarios:
        r = sc.result
        cases = r.expectations if r else []
        # faults, alarms, bad stimulus (a run-time warning goes to system-out)
        problems = [d for d in sc.diagnostics if d.code != "E603" and d.severity == "error"]
        warned = [d for d in sc.diagnostics if d.severity == "warning"]
        ts = ET.SubElement(root, "testsuite", name=sc.stim, tests=str(len(cases) + len(problems)),
                           failures=str(sum(not e.passed for e in cases)), errors=str(len(problems)),
                           time=_seconds(sc.seconds), file=sc.stim)
        cls = classname(sc.stim)
        measured = any(e.seconds for e in cases)
        share = sc.seconds / max(1, len(cases) + len(problems))
        for e in cases:
            tc = ET.SubElement(ts, "testcase", classname=cls, name=f"line {e.line}: {e.text}",
                               time=_seconds(e.seconds if measured else share), file=sc.stim, line=str(e.line))
            for f in e.failures:
                node = ET.SubElement(tc, "failure", message=failure_message(f), type="E603")
                node.text = f"{sc.stim}:{f.line}:{f.col}: {failure_message(f)}"
        for d in problems:
            tc = ET.SubElement(ts, "testcase", classname=cls, name=f"{d.code} {d.file}:{d.span.line}",
                               time=_seconds(0.0 if measured else share), file=d.file, line=str(d.span.line))
            ET.SubElement(tc, "error", message=d.message, type=d.code).text = \
                f"{d.file}:{d.span.line}:{d.span.col}: {d.message}"
        if r is not None:
            out = f"{r.scans} scans, {ms(r.time_us)} ms virtual time"
            out += "".join(f"\n{_KIND[os.path.splitext(a)[1]]}: {a}" for a in sc.artifacts)  # a failure's files
            out += "".join(f"\nwarning[{d.code}] {d.file}:{d.span.line}: {d.message}" for d in warned)
            ET.SubElement(ts, "system-out").text = out
    ET.indent(root)
    return '<?xml version="1.0" encoding="UTF-8"?>\n' + ET.tostring(root, encoding="unicode") + "\n"
