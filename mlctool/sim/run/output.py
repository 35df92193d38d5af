"""Result rendering: the JSON document and the human summary lines."""

from __future__ import annotations

import json
import math
from collections.abc import Sequence

from mlctool.diagnostics import Diagnostic, Span, diag
from mlctool.sim.run.run import RunResult
from mlctool.sim.state import to_f32


def f32_text(x: float) -> str:
    """Shortest decimal that reads back as the same single-precision value."""
    if math.isnan(x):
        return "nan"
    if math.isinf(x):
        return "inf" if x > 0 else "-inf"
    for p in range(1, 18):
        s = f"{x:.{p}g}"
        if to_f32(float(s)) == x:
            return s
    return repr(x)  # pragma: no cover


def json_value(v):
    if isinstance(v, float):
        s = f32_text(v)
        return float(s) if s not in ("nan", "inf", "-inf") else s
    return v


def ms(us: int) -> int | float:
    return us // 1000 if us % 1000 == 0 else us / 1000


def to_json(r: RunResult, warnings: Sequence[Diagnostic] = ()) -> str:
    """`warnings`: the program's W608 (sim/run/unmodelled.py), the same for every run of it."""
    failures = [
        {"line": f.line, "time_ms": ms(f.time_us), "scan": f.scan, "device": f.device,
         "expected": f.expected, "actual": json_value(f.actual), "last_write": f.writer,
         **({"note": f.note} if f.note else {})}
        for f in r.failed
    ]
    doc = {
        "time_ms": ms(r.time_us),
        "scans": r.scans,
        "devices": {k: json_value(v) for k, v in r.devices.items()},
        "expectations": {
            "passed": sum(e.passed for e in r.expectations),
            "failed": sum(not e.passed for e in r.expectations),
            "failures": failures,
        },
        "alarms": [
            {"name": a.name, "time_ms": ms(a.time_us), "scan": a.scan, "address": a.addr,
             "file": a.file, "line": a.line, "message": a.message, "expected": a.expected}
            for a in r.alarms
        ],
        "fault": None if r.fault is None else {
            "message": r.fault.message, "time_ms": ms(r.fault.time_us), "scan": r.fault.scan,
            "address": r.fault.addr, "file": r.fault.file, "line": r.fault.line,
            "instruction": r.fault.source,
        },
        "warnings": [d.as_dict() for d in [*warnings, *run_warnings(r)]],
    }
    return json.dumps(doc, indent=2, ensure_ascii=False) + "\n"


def failure_message(f) -> str:
    actual = f32_text(f.actual) if isinstance(f.actual, float) else f.actual
    msg = (f"at {ms(f.time_us)} ms (scan {f.scan}): {f.device} expected {f.expected}, "
           f"actual {actual}")
    if f.writer:
        msg += f"; last written by {f.writer}"
    if f.note:
        msg += f"; {f.note}"
    return msg


def summary(r: RunResult) -> str:
    passed = sum(e.passed for e in r.expectations)
    failed = len(r.expectations) - passed
    return (f"sim: {r.scans} scans, {ms(r.time_us)} ms virtual time; expectations: "
            f"{passed} passed, {failed} failed" + ("; program fault" if r.fault else ""))


def run_warnings(r: RunResult) -> list[Diagnostic]:
    """The run-time warnings (W330 ...) at their instructions, the models' (W345) at their lines."""
    return [diag(w.file, Span.at(w.line), w.code, f"at {w.time_us / 1000:g} ms (scan {w.scan})"
                 + (f", step {w.addr}" if w.addr is not None else "") + f": {w.message}") for w in r.warnings]


def run_diagnostics(r: RunResult, stim_path: str) -> list[Diagnostic]:
    """Failed expectations (at their stimulus line), unexpected alarms, the fault and the
    run-time warnings."""
    diags: list[Diagnostic] = run_warnings(r)
    for f in r.failed:
        diags.append(diag(stim_path, Span.at(f.line, f.col, len(f.text)), "E603", failure_message(f)))
    for a in r.alarms:
        if not a.expected:
            diags.append(diag(a.file, Span.at(a.line), "E604",
                              f"alarm {a.name} at {a.time_us / 1000:g} ms (scan {a.scan}), step {a.addr}: "
                              f"{a.message}", "name it in the stimulus with `expect alarm "
                              f"{a.name}` if it is intended"))
    if r.fault:
        f = r.fault
        diags.append(diag(f.file, Span.at(f.line), "E604",
                          f"program fault at {f.time_us / 1000:g} ms (scan {f.scan}), step {f.addr}"
                          f"{' (' + f.source + ')' if f.source else ''}: {f.message}; run stopped"))
    return diags
