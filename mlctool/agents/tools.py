"""The library's own functions as tools for AI agents (`mlc mcp`, docs/agents.md).

Plain functions returning plain data (dicts of JSON values): the MCP server
(agents/mcp_server.py) only registers them. Each takes the program as files (paths from the
server's working folder) or as `source` text, and the target by name (default: mlc.toml's,
else nc5). A request that cannot be served raises ToolError with a sentence for the agent
(the MCP client gets it as the tool's error result); diagnostics of the user's program are
data, not errors.

Bounds: a sim runs at most MAX_SIM_SCANS scans and returns at most MAX_TRACE changes of its
trace window; at most MAX_SESSIONS debug sessions live at once (the oldest is closed).
"""

from __future__ import annotations

import contextlib
import json
import os
import tempfile
from collections import OrderedDict
from pathlib import Path

from mlctool.asm import program_from_paths
from mlctool.codes import CODES
from mlctool.config import load_config
from mlctool.diagnostics import Diagnostic
from mlctool.sim.decode import unsimulated
from mlctool.sim.run.output import json_value, run_diagnostics, to_json
from mlctool.sim.run.run import DEFAULT_SCAN_US, RunTooLong, Simulation, build_models, plan_scans
from mlctool.sim.state import NameError_, parse_device_name
from mlctool.sim.stimulus.stimulus import Stimulus, load_stimulus, parse_stimulus_text
from mlctool.targetapi import available_targets, load_target

MAX_SIM_SCANS = 1_000_000
MAX_TRACE = 5000
MAX_SESSIONS = 8
MAX_SOURCE = 1 << 20  # characters of inline source or stimulus text


class ToolError(ValueError):
    """A request the tool cannot serve: the message is for the agent."""


def _target(name: str | None):
    config = load_config()
    name = name or config.target or "nc5"
    if name not in available_targets():
        raise ToolError(f"unknown target {name!r}; targets: {', '.join(available_targets())}")
    return load_target(name, str(config.data["model"]).upper() if config.data.get("model") else None), config


@contextlib.contextmanager
def _program_paths(files: list[str] | None, source: str | None):
    """The paths of the program: `files` as given, or `source` written to a temporary file."""
    if bool(files) == bool(source):
        raise ToolError("give either files (paths of IL sources) or source (IL text), one of them")
    if files:
        missing = [f for f in files if not os.path.isfile(f)]
        if missing:
            raise ToolError(f"no such file: {', '.join(missing)} (paths are relative to {os.getcwd()})")
        yield list(files)
        return
    if len(source) > MAX_SOURCE:
        raise ToolError(f"source is {len(source)} characters; at most {MAX_SOURCE}")
    with tempfile.TemporaryDirectory(prefix="mlc-agent-") as tmp:
        path = os.path.join(tmp, "source.il")
        Path(path).write_text(source, encoding="utf-8")
        yield [path]


def _diags(diags: list[Diagnostic]) -> list[dict]:
    return [d.as_dict() for d in sorted(diags, key=Diagnostic.sort_key)]


def check(files: list[str] | None = None, source: str | None = None, target: str | None = None) -> dict:
    """`mlc check`: the diagnostics of the program against the target's manual."""
    from mlctool.check import check_files

    tgt, config = _target(target)
    with _program_paths(files, source) as paths:
        result = check_files(paths, tgt, config)
    diags = result.diagnostics
    return {"target": tgt.name, "errors": sum(d.severity == "error" for d in diags),
            "warnings": sum(d.severity == "warning" for d in diags), "diagnostics": _diags(diags)}


def explain(code: str) -> dict:
    """`mlc explain CODE`: what a diagnostic code means."""
    found = CODES.get(code.strip().upper())
    if found is None:
        raise ToolError(f"no diagnostic code {code[:20]!r} (codes look like E601, W401)")
    return {"code": found.code, "severity": found.severity, "summary": found.summary, "doc": found.doc}


def build(files: list[str] | None = None, source: str | None = None, target: str | None = None) -> dict:
    """`mlc build` without writing: whether the program links, its size and modules."""
    tgt, config = _target(target)
    with _program_paths(files, source) as paths:
        image, diags, _ = program_from_paths(paths, tgt, config)
    out = {"target": tgt.name, "ok": image is not None, "diagnostics": _diags(diags)}
    if image is not None:
        out.update(steps=image.total_steps, instructions=len(image.instrs),
                   modules=[{"path": p, "first": a, "end": b} for p, a, b in image.modules],
                   symbols=dict(image.symbols))
    return out


def _image(paths, tgt, config):
    image, diags, _ = program_from_paths(paths, tgt, config)
    if image is None:
        return None, [d for d in diags if d.severity == "error"]
    return image, unsimulated(image, tgt)


def _stimulus(stimulus: str | None, stimulus_text: str | None, tgt):
    if stimulus and stimulus_text:
        raise ToolError("give stimulus (a path) or stimulus_text, not both")
    if stimulus_text is not None:
        if len(stimulus_text) > MAX_SOURCE:
            raise ToolError(f"stimulus_text is {len(stimulus_text)} characters; at most {MAX_SOURCE}")
        return parse_stimulus_text("<stimulus>", stimulus_text, tgt)
    if stimulus:
        if not os.path.isfile(stimulus):
            raise ToolError(f"no such file: {stimulus} (paths are relative to {os.getcwd()})")
        return load_stimulus(stimulus, tgt)
    return Stimulus("<none>", []), []


def sim(files: list[str] | None = None, source: str | None = None, stimulus: str | None = None,
        stimulus_text: str | None = None, target: str | None = None, watch: list[str] | None = None,
        trace_from_ms: float | None = None, trace_to_ms: float | None = None) -> dict:
    """`mlc sim --json`: run the program against a stimulus (a file, or its text); the
    expectations' outcome, the fault, the watched devices' final values and, with
    trace_from_ms/trace_to_ms, their changes in that window."""
    tgt, config = _target(target)
    with _program_paths(files, source) as paths:
        image, errors = _image(paths, tgt, config)
    if image is None or errors:
        return {"ok": False, "stage": "build", "diagnostics": _diags(errors)}
    st, stim_diags = _stimulus(stimulus, stimulus_text, tgt)
    views = []
    for name in watch or []:
        try:
            views.append(parse_device_name(name, tgt))
        except NameError_ as e:
            raise ToolError(str(e)) from None
    models, model_diags = build_models(st, tgt, views) if st is not None else ([], [])
    bad = [d for d in stim_diags + model_diags if d.severity == "error"]
    if st is None or bad:
        return {"ok": False, "stage": "stimulus", "diagnostics": _diags(bad or stim_diags)}
    period = st.scan_us or DEFAULT_SCAN_US
    try:
        n = plan_scans(st, period, None, None)
    except RunTooLong as e:
        raise ToolError(str(e)) from None
    if n > MAX_SIM_SCANS:
        raise ToolError(f"the stimulus asks for {n:,} scans; the tool runs at most {MAX_SIM_SCANS:,}")
    tracing = trace_from_ms is not None or trace_to_ms is not None
    simulation = Simulation(image, tgt, st, models, period, views, trace=tracing)
    result = simulation.run(n)
    doc = json.loads(to_json(result))
    doc["ok"] = result.ok
    doc["diagnostics"] = _diags(run_diagnostics(result, st.path))
    if views:
        doc["devices"] = {v.name: json_value(result.devices.get(v.name)) for v in views}
    else:
        doc.pop("devices")
    if tracing:
        doc["trace"] = _window(result, views, trace_from_ms, trace_to_ms)
    return doc


def _window(result, views, start_ms, end_ms) -> dict:
    lo = -1 if start_ms is None else start_ms * 1000
    hi = float("inf") if end_ms is None else end_ms * 1000
    shown = {v.name for v in views}
    changes, cut = [], False
    for t, items in result.trace:
        if not lo <= t <= hi:
            continue
        row = {result.views[i].name: json_value(v) for i, v in items
               if not shown or result.views[i].name in shown}
        if row:
            if len(changes) >= MAX_TRACE:
                cut = True
                break
            changes.append({"time_ms": t / 1000, **row})
    return {"changes": changes, "cut": cut}


def ladder(files: list[str] | None = None, source: str | None = None, target: str | None = None,
           comments: bool = False) -> dict:
    """`mlc ladder -o x.svg`: the program as ladder diagrams, one SVG document."""
    from mlctool.ladder import sheets_from_files
    from mlctool.ladder.svg import sheets_svg

    tgt, config = _target(target)
    with _program_paths(files, source) as paths:
        sheets, diags, _ = sheets_from_files(paths, tgt, config)
    errors = [d for d in diags if d.severity == "error"]
    if errors:
        return {"ok": False, "diagnostics": _diags(errors)}
    return {"ok": True, "svg": sheets_svg(sheets, comments)}


class Sessions:
    """Debug sessions by id, at most MAX_SESSIONS (the oldest is closed for a new one)."""

    def __init__(self) -> None:
        self.sessions: OrderedDict[str, object] = OrderedDict()
        self.next_id = 1

    def start(self, files: list[str] | None = None, source: str | None = None, stimulus: str | None = None,
              target: str | None = None) -> dict:
        """A debug session at scan 0 (mlc debug): step, read, force, back."""
        from mlctool.debug.load import LoadError, load_session

        tgt, config = _target(target)
        if stimulus and not os.path.isfile(stimulus):
            raise ToolError(f"no such file: {stimulus}")
        with _program_paths(files, source) as paths:
            try:
                session = load_session(paths, stimulus, tgt, config)
            except LoadError as e:
                return {"ok": False, "diagnostics": _diags(e.diagnostics)}
        sid = f"s{self.next_id}"
        self.next_id += 1
        self.sessions[sid] = session
        while len(self.sessions) > MAX_SESSIONS:
            self.sessions.popitem(last=False)
        return {"ok": True, "session": sid, **_where(session)}

    def get(self, sid: str):
        session = self.sessions.get(sid)
        if session is None:
            raise ToolError(f"no debug session {sid[:20]!r}; open ones: {', '.join(self.sessions) or 'none'}")
        return session

    def step(self, session: str, scans: bool = False, count: int = 1) -> dict:
        """Step `count` instructions, or whole scans with scans=true."""
        from mlctool.debug.session import DebugError

        s = self.get(session)
        if not 1 <= count <= 100_000:
            raise ToolError("count is 1-100000")
        stop = None
        try:
            for _ in range(count):
                stop = s.step_scan() if scans else s.step()
                if stop.reason not in ("step", "goto"):
                    break
        except DebugError as e:
            raise ToolError(str(e)) from None
        return {"stop": stop.reason, "text": stop.text, **_where(s)}

    def back(self, session: str, scans: bool = False) -> dict:
        """One instruction (or scan) back in time."""
        from mlctool.debug.session import DebugError

        s = self.get(session)
        try:
            stop = s.back_scan() if scans else s.back()
        except DebugError as e:
            raise ToolError(str(e)) from None
        return {"stop": stop.reason, "text": stop.text, **_where(s)}

    def read(self, session: str, devices: list[str]) -> dict:
        """The devices' values where the session stands."""
        from mlctool.debug.session import DebugError

        s = self.get(session)
        out = {}
        for name in devices[:1000]:
            try:
                view = s.view(name)
            except DebugError as e:
                raise ToolError(str(e)) from None
            out[view.name] = json_value(view.read(s.m))
        return {"values": out, **_where(s)}

    def force(self, session: str, device: str, value: str | None = None) -> dict:
        """Force a device to a value (kept over scans, as `force` in mlc debug); no value
        releases it."""
        from mlctool.debug.session import DebugError

        s = self.get(session)
        try:
            view = s.view(device)
            if value is None:
                s.release(view)
            else:
                s.force(view, s.value_for(view, str(value)))
        except DebugError as e:
            raise ToolError(str(e)) from None
        return {"device": view.name, "forced": value is not None, "value": json_value(view.read(s.m)), **_where(s)}

    def stop(self, session: str) -> dict:
        self.get(session)
        del self.sessions[session]
        return {"closed": session}


def _where(session) -> dict:
    scan, n = session.position
    return {"scan": scan, "instruction": n, "time_ms": session.time_us / 1000, "where": session.where()}
