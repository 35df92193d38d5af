"""`save FILE.stim`: a debugging run written back as a stimulus file (a test).

The original stimulus's lines that acted so far are kept as written (directives, models,
inputs and expectations of the scans run); `run` lines are replaced by `run #N` (the scans run).
The user's actions follow in the `#SCAN` form: force/release/write taken at a scan boundary
act at the start of that scan; one taken inside scan k (between instructions) cannot be said
in a stimulus file, which acts between scans only, so it is written at scan k + 1 with a note.
The watched devices' values at each stop between scans become `expect` lines checked after
the last scan completed before the stop.
"""

from __future__ import annotations

from mlctool.debug.session import BOUNDARY, DebugSession
from mlctool.sim.state import DeviceView


def _value(view: DeviceView, v) -> str:
    if isinstance(v, float):
        return repr(v)
    return str(v)


def stimulus_text(s: DebugSession) -> str:
    st = s.sim.st
    upto = s.scan  # scans started before the current position's boundary
    drop = {e.line for e in st.events if e.scan_index(s.period) >= upto}
    out = [f"# written by mlc debug: {upto} scans of {st.path}" if st.path != "<none>"
           else f"# written by mlc debug: {upto} scans"]
    if st.scan_us is None:
        out.append(f"scan {s.period}us")
    for no, line in enumerate(st.lines, 1):
        head = line.strip().split(None, 1)[0].lower() if line.strip() else ""
        if head == "run" or no in drop:
            continue
        out.append(line.rstrip("\n"))
    out.append("")
    out.append("# actions taken in mlc debug")
    for (k, n), actions in sorted(s.actions.items()):
        at = k if n == BOUNDARY else k + 1
        if at >= upto and not (at == upto and n == BOUNDARY):
            continue
        for kind, view, value in actions:
            note = "" if n == BOUNDARY else f"   # taken inside scan {k} after {n} instructions"
            if kind == "force":
                out.append(f"#{at} force {view.name}={_value(view, value)}{note}")
            elif kind == "release":
                out.append(f"#{at} release {view.name}{note}")
            else:
                out.append(f"#{at} {view.name}={_value(view, value)}{note}")
    seen = set()
    for (k, _), values in s.stops:
        if k == 0 or k > upto or k in seen:
            continue
        seen.add(k)
        checks = " ".join(f"{name}={_value(None, v)}" for name, v in values.items())
        out.append(f"#{k - 1} expect {checks}   # watched at a stop")
    out.append(f"run #{upto}")
    return "\n".join(out) + "\n"
