"""Positioning files for the CLI: check sources, build register images, dump images as text.

The `mlc check` / `mlc build` / `mlc objdump` commands hand files to these functions by
extension (.pos FUN140, .mpos FUN147 sources; .json/.csv register images). They return data
and diagnostics; writing and exit codes stay with the CLI.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field

from mlctool.config import Config, severity_of
from mlctool.diagnostics import Diagnostic, Span, diag
from mlctool.fileio import open_input
from mlctool.syntax.source import read_source, source_encoding
from mlctool.targets.fbs.image import ImageError, parse_sr, read_image, to_csv, to_json
from mlctool.targets.fbs.lang import parse_program
from mlctool.targets.fbs.model import PosProgram, tables
from mlctool.targets.fbs.table import TableError, decode, encode, program_text

IMAGE_SUFFIXES = (".json", ".csv")


def is_image(path: str) -> bool:
    return path.lower().endswith(IMAGE_SUFFIXES)


@dataclass
class Checked:
    programs: dict[str, PosProgram] = field(default_factory=dict)
    diagnostics: list[Diagnostic] = field(default_factory=list)
    lines: dict[str, list[str]] = field(default_factory=dict)

    @property
    def errors(self) -> int:
        return sum(d.severity == "error" for d in self.diagnostics)


def check_positioning(paths: list[str], config: Config | None = None,
                      ignore: frozenset[str] = frozenset()) -> Checked:
    out = Checked()
    encoding, out.diagnostics = source_encoding(config)
    if out.diagnostics:
        return out
    for path in paths:
        src, problems = read_source(path, encoding)
        out.diagnostics += problems
        if src is None:
            continue
        out.lines[path] = src.text.split("\n")
        program, diags = parse_program(path, src.text, tables().dialect_for(path), _pulse_modes(config))
        out.programs[path] = program
        for d in diags:
            sev = severity_of(d.code, d.severity, config, ignore)
            if sev != "off":
                out.diagnostics.append(d if sev == d.severity else d.with_severity(sev))
    return out


def _pulse_modes(config: Config | None) -> tuple[str, ...]:
    """mlc.toml `pulse_modes` in the target's spelling ("P/R" -> "PR"); axes not listed keep
    the packaged U/D, which FUN147 allows, so they need not be named."""
    modes = config.data.get("pulse_modes") if config is not None else None
    return tuple(m.replace("/", "") for m in modes or ())


def build_image(program: PosProgram, output: str, sr_text: str | None) -> str:
    """The register image of `program` for `output` (.json or .csv). Raises ImageError."""
    words = encode(program)
    sr = parse_sr(sr_text or "R0", len(words))
    if output.lower().endswith(".csv"):
        return to_csv(words, sr)
    return to_json(words, sr, tables().dialects[program.dialect].instruction)


def load_image(path: str) -> tuple[PosProgram | None, str, Diagnostic | None]:
    """Read and decode an image file -> (program, SR name, problem)."""
    try:
        with open_input(path, "r", encoding="utf-8-sig") as f:
            text = f.read(16 * 1024 * 1024)
    except (OSError, UnicodeDecodeError) as e:
        return None, "", diag(path, Span.at(1), "E100", f"cannot read: {getattr(e, 'strerror', None) or e}")
    try:
        words, sr = read_image(text)
    except ImageError as e:
        return None, "", diag(path, Span.at(1), "F034", f"not a positioning register image: {e}")
    try:
        return decode(words), sr, None
    except TableError as e:
        # CSV: register k is on line k + 2 (after the header row); JSON: no useful line
        line = e.offset + 2 if path.lower().endswith(".csv") else 1
        return None, sr, diag(path, Span.at(line), e.code, f"SR+{e.offset}: {e.message}")


def dump_text(program: PosProgram, sr: str) -> str:
    d = tables().dialects[program.dialect]
    n = len(program.steps)
    head = f"; {d.instruction} table at {sr}: {n} step{'s' if n != 1 else ''}, {d.table_words(n)} registers\n"
    return head + program_text(program)


def dump_json(program: PosProgram, sr: str) -> str:
    d = tables().dialects[program.dialect]
    doc = {"instruction": d.instruction, "sr": sr, "steps": len(program.steps),
           "registers": d.table_words(len(program.steps)), "program": program_text(program)}
    return json.dumps(doc, indent=1, ensure_ascii=False) + "\n"


def table_preload(spec: str) -> tuple[tuple[str, int, list[int]] | None, list[Diagnostic]]:
    """`mlc sim --table [SR=]FILE`: a positioning source (.pos/.mpos, SR required) or a
    register image (.json/.csv, SR from the image unless given) -> (kind, first, words).
    File problems are diagnostics; a malformed SPEC raises ValueError (a usage error)."""
    sr_text, _, path = spec.rpartition("=")
    if is_image(path):
        try:
            with open_input(path, "r", encoding="utf-8-sig") as f:
                words, sr_image = read_image(f.read(16 * 1024 * 1024))
        except (OSError, UnicodeDecodeError) as e:
            return None, [diag(path, Span.at(1), "E100", f"cannot read: {getattr(e, 'strerror', None) or e}")]
        except ImageError as e:
            return None, [diag(path, Span.at(1), "F034", f"not a positioning register image: {e}")]
        sr_text = sr_text or sr_image
    elif tables().dialect_for(path) is not None:
        checked = check_positioning([path])
        if checked.errors or path not in checked.programs:
            return None, checked.diagnostics
        words = encode(checked.programs[path])
        if not sr_text:
            raise ValueError(f"{spec}: give the table's first register, e.g. R5000={path}")
    else:
        raise ValueError(f"{spec}: a .pos/.mpos source or a .json/.csv register image")
    try:
        sr = parse_sr(sr_text, len(words))
    except ImageError as e:
        raise ValueError(str(e).replace("--sr ", "")) from None
    return (sr.kind, sr.number, words), []
