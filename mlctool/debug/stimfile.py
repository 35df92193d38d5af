"""`save FILE.stim`: a debugging run written back as a stimulus file (a test).

The original stimulus's lines that acted so far are kept as written (directives, models,
inputs and expectations of the scans run); `run` lines are replaced by `run #N` (the scans run).
The user's actions follow in the `#SCAN` form: force/release/write taken at a scan boundary
act at the start of that scan; one taken inside scan k (between instructions) cannot be said
in a stimulus file, which acts between scans only, so it is written at scan k + 1 with a note.
The watched devices' values at each stop between scans become `expect` lines checked after
the last scan completed before the stop. An expectation of the stimulus that failed in the
session is dropped (a comment line names it and what failed), so the file replays green.

Where it may be written (`save_stimulus`): inside the session's folder only (the project's,
else the folder the debugger started in), never onto an input of the session, atomically; a
symbolic link is written through (it stays a link) when its target is allowed (docs/debug.md).
"""

from __future__ import annotations

import os

from mlctool.debug.session import BOUNDARY, DebugError, DebugSession
from mlctool.diagnostics import MlcError
from mlctool.fileio import Outputs
from mlctool.sim.state import DeviceView


def _value(view: DeviceView, v) -> str:
    if isinstance(v, float):
        return repr(v)
    return str(v)


def failed_expectations(s: DebugSession) -> dict[int, str]:
    """The stimulus lines whose expectation failed in the scans `save` writes -> what failed."""
    failed: dict[int, str] = {}
    for (k, line), what in sorted(s.failed_expects.items()):
        if k < s.scan:
            failed.setdefault(line, what)
    return failed


def stimulus_text(s: DebugSession) -> str:
    st = s.sim.st
    upto = s.scan  # scans started before the current position's boundary
    drop = {e.line for e in st.events if e.scan_index(s.period) >= upto}
    failed = failed_expectations(s)
    out = [f"# written by mlc debug: {upto} scans of {st.path}" if st.path != "<none>"
           else f"# written by mlc debug: {upto} scans"]
    if st.scan_us is None:
        out.append(f"scan {s.period}us")
    for no, line in enumerate(st.lines, 1):
        head = line.strip().split(None, 1)[0].lower() if line.strip() else ""
        if head == "run" or no in drop:
            continue
        if no in failed:
            out.append(f"# dropped, failed in mlc debug ({failed[no]}): {line.strip()}")
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


def save_stimulus(s: DebugSession, path: str) -> str:
    """`save PATH`: the stimulus text written to PATH (relative to the session's current
    folder) under the rule of the module doc; the sentence to show. DebugError when refused."""
    if not path or "\0" in path:
        raise DebugError("save FILE.stim")
    folder = os.path.realpath(s.folder)
    real = os.path.realpath(os.path.join(s.cwd, path))  # through every link, the last one too
    if not real.startswith(folder.rstrip(os.sep) + os.sep):
        raise DebugError(f"save: {path} is outside {folder} ({s.folder_is}): save writes only there")
    text = stimulus_text(s)
    try:
        plan = Outputs()  # the inputs it must not overwrite: fileio's register
        plan.add(real, "save")
        plan.validate()
        plan.write({real: text})
    except MlcError as e:
        raise DebugError(f"{e.diagnostic.code}: {e.diagnostic.message}") from None
    said = f"wrote {path}" + (f" (the link's target {real})" if os.path.islink(os.path.join(s.cwd, path)) else "")
    failed = failed_expectations(s)
    if failed:
        said += (f"; dropped {len(failed)} expectation(s) that failed in this session, a comment in the file "
                 f"names each: {', '.join(f'{s.sim.st.path}:{no}' for no in failed)}")
    return said
