"""The results of `mlc verify` over property files as a person and a CI read them: the text
table, JSON, SARIF findings (a violated property at its line: E704; undecided: W705), JUnit,
and each counterexample or witness as a stimulus file with its VCD, replayed on the simulator
before it is written (the replay must end as the engine said: the check that fails is the
property's)."""

from __future__ import annotations

import json
import os
import re
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field

from mlctool.diagnostics import Diagnostic, MlcError, Span, diag
from mlctool.program import Image
from mlctool.sim.campaign.junit import classname
from mlctool.sim.run.run import Simulation, plan_scans
from mlctool.sim.stimulus.stimulus import parse_stimulus_text
from mlctool.targetapi.model import Target
from mlctool.verify.builtin import check_props
from mlctool.verify.props import load_props
from mlctool.verify.results import PROVEN, UNKNOWN, VIOLATED, Verdict, describe, stim_text, to_dict
from mlctool.verify.run import VerifyError, verify


@dataclass
class Outcome:
    verdicts: list[tuple[str, Verdict]] = field(default_factory=list)  # (props path, verdict)
    errors: list[Diagnostic] = field(default_factory=list)
    findings: list[Diagnostic] = field(default_factory=list)
    lines: dict[str, list[str]] = field(default_factory=dict)
    files: dict[str, str] = field(default_factory=dict)  # path -> text (stim, VCD)
    artifacts: dict[tuple[str, str], tuple[str, ...]] = field(default_factory=dict)  # (props, name) -> paths

    @property
    def exit_code(self) -> int:
        if self.errors:
            return 2
        return 0 if all(v.ok for _, v in self.verdicts) else 1

    def text(self) -> str:
        out = []
        for path, v in self.verdicts:
            out.append(describe(v).replace(f"{v.prop.name}:", f"{path}:{v.prop.line} {v.prop.name}:", 1))
            files = self.artifacts.get((path, v.prop.name))
            if files:
                what = {VIOLATED: "counterexample", UNKNOWN: "the fault"}.get(v.status, "witness")
                out.append(f"         {what}: {files[0]} ({v.trace.scan + 1} scans), waveform {files[1]}"
                           + (f", report {files[2]}" if len(files) > 2 else ""))
        counts = {s: sum(v.status == s for _, v in self.verdicts) for s in (PROVEN, VIOLATED, UNKNOWN)}
        out.append(f"{len(self.verdicts)} properties: {counts[PROVEN]} proven, {counts[VIOLATED]} violated, "
                   f"{counts[UNKNOWN]} unknown")
        return "\n".join(out) + "\n"

    def json(self) -> str:
        results = []
        for path, v in self.verdicts:
            files = self.artifacts.get((path, v.prop.name))
            results.append({"file": path, **to_dict(v, files[0] if files else None)})
        return json.dumps({"results": results, "ok": self.exit_code == 0}, indent=2) + "\n"

    def junit(self, suite_name: str) -> str:
        root = ET.Element("testsuites", name=suite_name,
                          time=f"{sum(v.stats.seconds for _, v in self.verdicts):.6f}")
        by_file: dict[str, list[Verdict]] = {}
        for path, v in self.verdicts:
            by_file.setdefault(path, []).append(v)
        for path, vs in by_file.items():
            ts = ET.SubElement(root, "testsuite", name=path, tests=str(len(vs)),
                               failures=str(sum(v.status == VIOLATED for v in vs)),
                               errors=str(sum(v.status == UNKNOWN for v in vs)),
                               time=f"{sum(v.stats.seconds for v in vs):.6f}", file=path)
            for v in vs:
                tc = ET.SubElement(ts, "testcase", classname=classname(path), name=f"{v.prop.name}: {v.prop.text}",
                                   time=f"{v.stats.seconds:.6f}", file=path, line=str(v.prop.line))
                if v.status != PROVEN:
                    tag = "failure" if v.status == VIOLATED else "error"
                    node = ET.SubElement(tc, tag, message=_finding_message(v, self.artifacts.get((path, v.prop.name))),
                                         type="E704" if v.status == VIOLATED else "W705")
                    node.text = f"{path}:{v.prop.line}:{v.prop.col}: {node.get('message')}"
                ET.SubElement(tc, "system-out").text = describe(v)
        ET.indent(root)
        return '<?xml version="1.0" encoding="UTF-8"?>\n' + ET.tostring(root, encoding="unicode") + "\n"


def _finding_message(v: Verdict, files) -> str:
    if v.status == VIOLATED:
        if v.trace is None:
            return f"{v.prop.kind} {v.prop.name}: no reachable state satisfies it ({v.method})"
        return (f"{v.prop.kind} property {v.prop.name} is violated after {v.trace.scan + 1} scans"
                + (f"; counterexample {files[0]} (mlc sim PROGRAM --stimulus {files[0]})" if files else ""))
    return f"{v.prop.name} is undecided: {v.reason or v.method}"


def _project_error(config, key: str, message: str) -> MlcError:
    """mlc.toml `[verify]` names no file or an unknown check: E110 at the key, exit 2."""
    return MlcError(diag(*config.locate("verify", key), "E110", message), 2)


def project_checks(config) -> list[tuple[str, str, int]]:
    """The built-in checks mlc.toml `[verify] checks` asks for, with where it asks."""
    from mlctool.verify.builtin import CHECKS

    names = (config.data.get("verify") or {}).get("checks", [])
    if not names:
        return []
    path, span = config.locate("verify", "checks")
    for name in names:
        if name not in CHECKS:
            from mlctool.suggest import did_you_mean

            raise _project_error(config, "checks", f"mlc.toml [verify] checks: unknown check {name!r}"
                                 + (did_you_mean(name, CHECKS, "'") or f"; checks: {', '.join(CHECKS)}"))
    return [(name, os.path.relpath(path) if os.path.isabs(path) else path, span.line) for name in names]


def project_props(config) -> list[str]:
    """The property files mlc.toml `[verify] properties` names (globs, from the project's
    folder), relative to the current folder."""
    import glob

    table = config.data.get("verify") or {}
    found: list[str] = []
    root = str(config.root) if config.root is not None else "."
    for pattern in table.get("properties", []):
        full = os.path.join(root, pattern)
        hits = sorted(glob.glob(full)) if glob.has_magic(full) else [full] if os.path.isfile(full) else []
        if not hits:
            raise _project_error(config, "properties", f"mlc.toml [verify] properties: {pattern!r} names no file")
        found += [os.path.relpath(h) for h in hits]
    return found


def run_files(image: Image, target: Target, paths: list[str], engine: str, max_states: int,
              seconds: float | None, out_dir: str, checks: list[tuple[str, str, int]] = (),
              sources: dict[str, list[str]] | None = None) -> Outcome:
    """Every property of the files `paths`, then the built-in checks `checks` ((name, where
    they were asked for: a path and its line)), verified and reported. With the program's
    source lines (`sources`), each counterexample gets a report page too (docs/ladder.md)."""
    import time

    outcome = Outcome()
    deadline = None if seconds is None else time.monotonic() + seconds
    jobs = []
    for path in paths:
        props, diags = load_props(path, target, image.symbols)
        if props is not None:
            outcome.lines[path] = props.lines
        if props is None or any(d.severity == "error" for d in diags):
            outcome.errors += diags
            continue
        jobs.append((path, props, os.path.splitext(os.path.basename(path))[0], True))
    for name, where, line in checks:
        props = check_props(image, target, name, where, line)
        if props.properties:
            jobs.append((where, props, name, False))  # (a built-in check's witnesses are not written)
    for path, props, stem, witnesses in jobs:
        left = None if deadline is None else max(0.0, deadline - time.monotonic())
        try:
            verdicts, _space, period = verify(image, target, props, engine, max_states, left)
        except VerifyError as e:
            outcome.errors += e.diagnostics
            continue
        for v in verdicts:
            outcome.verdicts.append((path, v))
            files = None
            if v.trace is not None and (witnesses or v.status == VIOLATED):
                files = _artifacts(image, target, path, stem, v, period, out_dir, outcome, sources)
            if v.status != PROVEN:
                code = "E704" if v.status == VIOLATED else "W705"
                outcome.findings.append(diag(path, Span.at(v.prop.line, v.prop.col, len(v.prop.text)), code,
                                             _finding_message(v, files)))
    return outcome


def _artifacts(image: Image, target: Target, path: str, stem: str, v: Verdict, period: int, out_dir: str,
               outcome: Outcome, sources: dict[str, list[str]] | None) -> tuple[str, ...]:
    name = re.sub(r"[^A-Za-z0-9_.-]+", "_", v.prop.name).strip("_") or "property"
    base = os.path.join(out_dir, f"{stem}.{name}")
    stim_path, vcd_path = base + ".stim", base + ".vcd"
    values = replay_values(image, target, v, period)
    text = stim_text(v, period, path, lambda view: values.get(view.name, 0))
    st, diags = parse_stimulus_text(stim_path, text, target)
    if any(d.severity == "error" for d in diags):  # pragma: no cover - our own text
        raise VerifyError(diags)
    sim = Simulation(image, target, st, [], st.scan_us, [], trace=True)
    lamps = None
    if sources is not None:  # the report page: the ladder lit scan by scan up to the failure
        from mlctool.ladder.report import ScanLamps

        lamps = ScanLamps(sim, sources)
    result = sim.run(plan_scans(st, st.scan_us, None, None))
    from mlctool.sim.run.vcd import to_vcd

    outcome.files[stim_path] = text
    outcome.files[vcd_path] = to_vcd(result, image, target)
    found = (stim_path, vcd_path)
    if lamps is not None:
        from mlctool.ladder.report import report_html

        html_path = base + ".html"
        outcome.files[html_path] = report_html(sim, result, lamps, [], f"{v.prop.name}: {v.prop.text}")
        found += (html_path,)
    outcome.artifacts[(path, v.prop.name)] = found
    return found


def replay_values(image: Image, target: Target, v: Verdict, period: int) -> dict[str, int | float]:
    """Device values after the trace's last scan (for expect checks a property's atom cannot
    spell by itself: a compare of two devices, a value outside a range)."""
    t = v.trace
    lines = [f"scan {period}us"]
    for k, vec in enumerate(t.vectors):
        items = [f"{view.name}={x}" for view, x in zip(t.views, vec, strict=True)]
        if k == 0:
            items = [f"{view.name}={x}" for view, x in t.initial] + items
        if items:
            lines.append(f"#{k} " + " ".join(items))
    lines.append(f"run #{t.scan + 1}")
    st, _ = parse_stimulus_text("<trace>", "\n".join(lines) + "\n", target)
    from mlctool.verify.props import views_of

    watch = views_of(v.prop.expr) + (views_of(v.prop.response) if v.prop.response is not None else [])
    sim = Simulation(image, target, st, [], period, watch, trace=False)
    result = sim.run(t.scan + 1)
    return dict(result.devices)
