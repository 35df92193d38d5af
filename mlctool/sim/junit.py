"""JUnit XML: one test case per expectation line of the stimulus file."""

from __future__ import annotations

import xml.etree.ElementTree as ET

from mlctool.sim.output import failure_message, ms
from mlctool.sim.run import RunResult


def to_junit(r: RunResult, stim_path: str, suite: str) -> str:
    failed = sum(not e.passed for e in r.expectations)
    root = ET.Element("testsuites")
    ts = ET.SubElement(root, "testsuite", name=suite, tests=str(len(r.expectations)),
                       failures=str(failed), errors="1" if r.fault else "0", time="0")
    for e in r.expectations:
        tc = ET.SubElement(ts, "testcase", classname=stim_path,
                           name=f"line {e.line}: {e.text}", time="0", file=stim_path, line=str(e.line))
        for f in e.failures:
            node = ET.SubElement(tc, "failure", message=failure_message(f), type="E603")
            node.text = f"{stim_path}:{f.line}:{f.col}: {failure_message(f)}"
    if r.fault:
        tc = ET.SubElement(ts, "testcase", classname=stim_path, name="program runs without fault",
                           time="0")
        err = ET.SubElement(tc, "error", message=r.fault.message, type="E604")
        err.text = (f"{r.fault.file}:{r.fault.line}: step {r.fault.addr} at {ms(r.fault.time_us)} ms "
                    f"(scan {r.fault.scan}): {r.fault.message}")
    ET.indent(root)
    return '<?xml version="1.0" encoding="UTF-8"?>\n' + ET.tostring(root, encoding="unicode") + "\n"
