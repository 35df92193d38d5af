"""Coverage of a program by simulation runs: per step, whether it executed (and how often),
and for contacts whether their own value was seen both On and Off. A coil or application
instruction counts as executed when it acted: it ran with its rung condition On; a
multi-input instruction (FBs FUN140 HSPSO, FUN147: EN, PAU, ABT, one block each) with any of
its inputs On; an instruction the manual runs whatever its condition (FUN141 MPARA,
`unconditional` in the target's table) every time it ran; a P-suffix form (MOVP) only in the
scans it executed (its condition's Off->On).

The recorder wraps the reference interpreter's step routines (mlctool/sim/decode.py `probe`),
so coverage runs always use the interpreter. Reports: text, JSON and Cobertura XML with IL
line numbers (contacts are Cobertura branches with two conditions: On and Off).
"""

from __future__ import annotations

import json
import xml.etree.ElementTree as ET
from collections.abc import Callable
from dataclasses import dataclass, field

from mlctool.program import Image
from mlctool.targetapi.model import InstrSpec


class Probe:
    """Collects hits during runs of one Image; several runs may share one probe."""

    def __init__(self, n_steps: int):
        self.hits = [0] * n_steps
        self.seen_on = bytearray(n_steps)
        self.seen_off = bytearray(n_steps)

    def step(self, run: Callable, cls: str) -> Callable:
        """Count a step when it acts: contacts and flow instructions whenever they run, coils
        and application instructions by what their form executes (acted())."""
        hits = self.hits
        if cls == "output":
            def counted_if_acted(m, s):
                if acted(m, s.ins.spec, s.index):
                    hits[s.index] += 1
                return run(m, s)
            return counted_if_acted

        def counted(m, s):
            hits[s.index] += 1
            return run(m, s)
        return counted

    def contact(self, contact: Callable) -> Callable:
        on, off = self.seen_on, self.seen_off

        def observed(m, s):
            v = contact(m, s)
            if v:
                on[s.index] = 1
            else:
                off[s.index] = 1
            return v
        return observed

    def merge(self, other: Probe) -> None:
        for k, h in enumerate(other.hits):
            self.hits[k] += h
            self.seen_on[k] |= other.seen_on[k]
            self.seen_off[k] |= other.seen_off[k]


def acted(m, spec: InstrSpec, index: int) -> bool:
    """Whether an output-class instruction, about to run (outside a P form's gate: the probe
    wraps the whole step, mlctool/sim/decode.py), executes in this scan: unconditional (the
    manual runs it whatever its condition: FBs MPARA) always; a multi-input one (FBs HSPSO,
    FUN147: EN, PAU, ABT, the blocks before it and the rung result) when any input is On; a
    P form (MOVP) on its condition's Off->On (its edge memory still holds the last scan's);
    any other when its condition is On."""
    if spec.unconditional:
        return True
    further = len(spec.inputs) - 1
    if further > 0 and any(m.blocks[-further:]):
        return True
    if spec.pulse:
        return m.acc and not m.edge[index]
    return bool(m.acc)


@dataclass
class LineCoverage:
    line: int
    hits: int
    contacts: int = 0  # contact instructions on the line
    both_ways: int = 0  # ... seen both On and Off
    one_way: int = 0  # ... seen only On or only Off
    text: str = ""

    @property
    def conditions(self) -> int:
        """Covered (On, Off) conditions of the line's contacts."""
        return 2 * self.both_ways + self.one_way


@dataclass
class FileCoverage:
    file: str
    lines: dict[int, LineCoverage] = field(default_factory=dict)

    @property
    def instructions(self) -> tuple[int, int]:
        return sum(1 for x in self.lines.values() if x.hits), len(self.lines)

    @property
    def conditions(self) -> tuple[int, int]:
        """(covered, total) contact conditions, two (On, Off) per contact."""
        return sum(x.conditions for x in self.lines.values()), 2 * sum(x.contacts for x in self.lines.values())


@dataclass
class CoverageReport:
    files: list[FileCoverage]
    steps: list[dict]  # per step: addr, file, line, mnemonic, executed, hits, on, off (contacts)

    def totals(self) -> dict:
        ins = [f.instructions for f in self.files]
        conds = [f.conditions for f in self.files]
        return {"instructions": sum(a for a, _ in ins), "instructions_total": sum(b for _, b in ins),
                "conditions": sum(a for a, _ in conds), "conditions_total": sum(b for _, b in conds)}


def report(image: Image, probe: Probe) -> CoverageReport:
    """Fold per-step hits into per-source-line coverage. END is left out: it is where the
    program text ends, not an instruction a test can reach when FEND ends the scan."""
    by_file: dict[str, FileCoverage] = {}
    steps = []
    for k, ins in enumerate(image.instrs):
        if ins.spec.op == "end":
            continue
        is_contact = ins.spec.cls in ("load", "and", "or")
        on, off = bool(probe.seen_on[k]), bool(probe.seen_off[k])
        steps.append({"addr": ins.addr, "file": ins.file, "line": ins.line, "mnemonic": ins.mnemonic,
                      "hits": probe.hits[k], **({"on": on, "off": off} if is_contact else {})})
        fc = by_file.setdefault(ins.file, FileCoverage(ins.file))
        lc = fc.lines.get(ins.line)
        if lc is None:
            lc = fc.lines[ins.line] = LineCoverage(ins.line, 0, text=" ".join((ins.mnemonic, *ins.texts)))
        lc.hits += probe.hits[k]
        if is_contact:
            lc.contacts += 1
            lc.both_ways += on and off
            lc.one_way += on != off
    return CoverageReport([by_file[f] for f in sorted(by_file)], steps)


def _pct(a: int, b: int) -> str:
    return f"{100 * a / b:.1f}%" if b else "100.0%"


def to_text(rep: CoverageReport, source_lines: dict[str, list[str]] | None = None) -> str:
    out = ["file                                   instructions        contact conditions"]
    for f in rep.files:
        a, b = f.instructions
        c, d = f.conditions
        out.append(f"{f.file:38} {a:5}/{b:<5} {_pct(a, b):>7}   {c:5}/{d:<5} {_pct(c, d):>7}")
    t = rep.totals()
    out.append(f"{'TOTAL':38} {t['instructions']:5}/{t['instructions_total']:<5} "
               f"{_pct(t['instructions'], t['instructions_total']):>7}   {t['conditions']:5}/"
               f"{t['conditions_total']:<5} {_pct(t['conditions'], t['conditions_total']):>7}")
    missed = [(f.file, x) for f in rep.files for x in sorted(f.lines.values(), key=lambda x: x.line)
              if not x.hits or x.both_ways < x.contacts]
    if missed:
        out.append("")
        out.append("not fully covered:")
        for file, x in missed:
            why = "never executed" if not x.hits else "contact seen only " + (
                "On" if _only_on(rep, file, x.line) else "Off")
            out.append(f"  {file}:{x.line}: {x.text}  ({why})")
    return "\n".join(out) + "\n"


def _only_on(rep: CoverageReport, file: str, line: int) -> bool:
    return any(s.get("on") and not s.get("off") for s in rep.steps if s["file"] == file and s["line"] == line)


def to_json(rep: CoverageReport) -> str:
    data = {
        "totals": rep.totals(),
        "files": [{"file": f.file, "instructions": list(f.instructions), "conditions": list(f.conditions),
                   "lines": [{"line": x.line, "hits": x.hits, "contacts": x.contacts, "both_ways": x.both_ways}
                             for x in sorted(f.lines.values(), key=lambda x: x.line)]}
                  for f in rep.files],
        "steps": rep.steps,
    }
    return json.dumps(data, indent=2, ensure_ascii=False) + "\n"


def to_cobertura(rep: CoverageReport, source_root: str = ".") -> str:
    """Cobertura XML (the DTD 'coverage-04'), lines = IL source lines."""
    t = rep.totals()

    def rate(a, b):
        return f"{a / b:.4f}" if b else "1.0000"

    root = ET.Element("coverage", {
        "line-rate": rate(t["instructions"], t["instructions_total"]),
        "branch-rate": rate(t["conditions"], t["conditions_total"]),
        "lines-covered": str(t["instructions"]), "lines-valid": str(t["instructions_total"]),
        "branches-covered": str(t["conditions"]), "branches-valid": str(t["conditions_total"]),
        "complexity": "0", "version": "mlctool", "timestamp": "0"})
    sources = ET.SubElement(root, "sources")
    ET.SubElement(sources, "source").text = source_root
    packages = ET.SubElement(root, "packages")
    pkg = ET.SubElement(packages, "package", {
        "name": "plc", "line-rate": rate(t["instructions"], t["instructions_total"]),
        "branch-rate": rate(t["conditions"], t["conditions_total"]), "complexity": "0"})
    classes = ET.SubElement(pkg, "classes")
    for f in rep.files:
        a, b = f.instructions
        c, d = f.conditions
        cls = ET.SubElement(classes, "class", {"name": f.file, "filename": f.file,
                                               "line-rate": rate(a, b), "branch-rate": rate(c, d),
                                               "complexity": "0"})
        ET.SubElement(cls, "methods")
        lines = ET.SubElement(cls, "lines")
        for x in sorted(f.lines.values(), key=lambda x: x.line):
            attrs = {"number": str(x.line), "hits": str(x.hits), "branch": "true" if x.contacts else "false"}
            if x.contacts:
                attrs["condition-coverage"] = (f"{100 * x.conditions // (2 * x.contacts)}% "
                                               f"({x.conditions}/{2 * x.contacts})")
            ET.SubElement(lines, "line", attrs)
    ET.indent(root)
    return ('<?xml version="1.0" ?>\n<!DOCTYPE coverage SYSTEM '
            '"http://cobertura.sourceforge.net/xml/coverage-04.dtd">\n' + ET.tostring(root, encoding="unicode") + "\n")
