"""`mlc check`: source files -> checked modules and diagnostics.

Pipeline per file: decode -> parse -> resolve (operands vs target tables) -> structure -> lint;
then cross-module label resolution, configured severities and `mlc: noqa` suppressions.

Belongs here: everything `mlc check` decides about a source. Does not belong here: code
generation (asm/), simulation (sim/), formatting (mlctool/fmt.py).
"""

from __future__ import annotations

import dataclasses
import gc
from dataclasses import dataclass, field

from mlctool.check.blocks import check_blocks
from mlctool.check.interrupts import check_interrupts
from mlctool.check.labels import assign_named_labels, restrict_names
from mlctool.check.lint import cross_module_coils, lint_module, referenced_labels, set_without_reset
from mlctool.check.misuse import not_a_source_by_content, not_a_source_by_name
from mlctool.check.operand_rules import check_operand_rules
from mlctool.check.resolve import ResolverCaches, resolve
from mlctool.check.signals import check_signals
from mlctool.check.specials import foreign_specials
from mlctool.check.structure import check_layout, check_rungs
from mlctool.config import Config, severity_of
from mlctool.diagnostics import Diagnostic, Span, diag
from mlctool.program import FormIndex, Module
from mlctool.syntax.operands import SYMBOL, OperandSyntaxError, parse_operand
from mlctool.syntax.parser import parse
from mlctool.syntax.source import SourceText, decode, read_source, source_encoding
from mlctool.targetapi import Target


@dataclass
class CheckResult:
    modules: list[Module]
    diagnostics: list[Diagnostic]
    lines: dict[str, list[str]] = field(default_factory=dict)  # file -> source lines
    sources: list[SourceText] = field(default_factory=list)  # the texts checked

    @property
    def errors(self) -> int:
        return sum(d.severity == "error" for d in self.diagnostics)

    @property
    def warnings(self) -> int:
        return sum(d.severity == "warning" for d in self.diagnostics)


class CheckMemo:
    """What one check keeps for the next check of edited versions of the same files (the
    language server checks a file again at every edit): per file, the parser's memo of lines
    (syntax/parser.py) and the resolver's caches (check/resolve.py ResolverCaches), so that
    only lines not seen before are parsed and resolved; the rules over the whole program
    run again every time. The results are those of a check without a memo
    (tests/lsp/test_incremental.py compares them after random edits).

    The resolver's caches hold while the target's tables and the file's named labels stay
    the same; they are dropped when either changes, and both memos when they grow well past
    the size of their file (a long session of edits)."""

    def __init__(self) -> None:
        self._lines: dict[str, dict] = {}
        self._resolver: dict[str, tuple[tuple, Target, dict, ResolverCaches]] = {}

    def lines(self, src: SourceText) -> dict:
        memo = self._lines.setdefault(src.path, {})
        if len(memo) > 2 * src.text.count("\n") + 10_000:
            memo.clear()
        return memo

    def resolver(self, path: str, target: Target, names: dict[str, int] | None, size: int) -> ResolverCaches:
        # the target object is kept with its key: the ids in the key (and in the caches'
        # keys, id(spec)) stay those of these tables while the entry lives
        key = (id(target.instructions), id(target.devices), target.name, target.model, target.capacity)
        names = dict(names or {})
        kept = self._resolver.get(path)
        if kept is None or kept[0] != key or kept[2] != names or len(kept[3]) > 4 * size + 20_000:
            kept = self._resolver[path] = (key, target, names, ResolverCaches())
        return kept[3]

    def forget(self, path: str) -> None:
        self._lines.pop(path, None)
        self._resolver.pop(path, None)


def check_texts(sources: list[SourceText], target: Target, config: Config | None = None,
                ignore: frozenset[str] = frozenset(), initial: list[Diagnostic] | None = None,
                memo: CheckMemo | None = None) -> CheckResult:
    """Check the sources together, as modules of one program. `memo`: kept between checks
    of edited versions of the same sources (CheckMemo).

    The cyclic garbage collector is paused meanwhile: checking builds many small objects
    (statements, instructions, operands) that all live to the end and form no cycles, and the
    collector walking them again and again took about half the time of checking a 64k-step
    program (issue 19). Memory is what the live objects need either way. Nothing is frozen
    here: a one-shot command freezes what it loaded (mlctool.cli.common.collector_paused);
    `mlc lsp` checks after every edit, and a check that froze the objects alive kept every
    earlier analysis's reference cycles from the collector (issue 30.12: 1.4 MB an edit of a
    10k-line file)."""
    paused = gc.isenabled()
    gc.disable()
    try:
        return _check_texts(sources, target, config, ignore, initial, memo)
    finally:
        if paused:
            gc.enable()


def _check_texts(sources: list[SourceText], target: Target, config: Config | None,
                 ignore: frozenset[str], initial: list[Diagnostic] | None, memo: CheckMemo | None) -> CheckResult:
    config = config or Config()
    if config.capacity:
        target = dataclasses.replace(target, capacity=int(config.capacity))
    diags: list[Diagnostic] = list(initial or [])
    modules: list[Module] = []
    lines: dict[str, list[str]] = {}
    noqa: dict[str, dict] = {}
    symbols, found = project_symbols(config)
    diags += found
    parsed_files = [restrict_names(parse(src, memo=memo.lines(src) if memo else None), target) for src in sources]
    names, found = assign_named_labels(parsed_files, target)
    diags += found
    for parsed in parsed_files:
        lines[parsed.path] = parsed.lines
        noqa[parsed.path] = parsed.noqa
        own = names.get(parsed.path)
        caches = memo.resolver(parsed.path, target, own, len(parsed.lines)) if memo else None
        module, found = resolve(parsed, target, symbols, own, caches)
        modules.append(module)
        diags += found
    # rung checks see every line; the rest only lines whose operands resolved
    # lines lost to syntax errors or unknown mnemonics: rung/END checks around them would echo them
    broken = broken_lines(modules, diags)
    for m in modules:
        diags += check_rungs(m, target, broken[m.path])
    valid = [dataclasses.replace(m, instrs=[i for i in m.instrs if i.valid]) for m in modules]
    # labels across modules
    exported: dict[int, str] = {}
    for m in valid:
        own = m.labels()
        for p in sorted(m.exports):
            if p not in own:
                diags.append(diag(m.path, Span.at(1), "E304", f".export P{p}: the module does not define P{p}"))
            elif p in exported:
                ins = m.instrs[own[p]]
                diags.append(diag(m.path, Span.at(ins.line, ins.col), "E303", f"P{p} is also exported by {exported[p]}"))
            else:
                exported[p] = m.path
    # where each instruction form is, per module, for the rules below
    index = {id(m): FormIndex(m.instrs) for m in valid}
    refs, calls = referenced_labels(valid, [index[id(m)] for m in valid])
    for m in valid:
        forms = index[id(m)]
        diags += check_layout(m, target, {p: f for p, f in exported.items() if f != m.path}, calls,
                              broken[m.path], forms)
        diags += check_blocks(m, target, forms)
        diags += check_operand_rules(m, target)
        diags += check_interrupts(m, target)
        diags += check_signals(m, target, lines[m.path], config.data)
        diags += lint_module(m, target, refs, forms)
    # Each main module is its own program together with the libraries; independent main
    # programs checked in one call do not share coils.
    libs = [m for m in valid if m.library]
    programs = [[m, *libs] for m in valid if not m.library] or [libs]
    for program in programs:
        diags += set_without_reset(program, [index[id(m)] for m in program])
        diags += foreign_specials(program, target)
        if len(program) > 1:
            diags += cross_module_coils(program)
    return CheckResult(modules, _finish(diags, config, ignore, noqa), lines, list(sources))


def broken_lines(modules: list[Module], diags: list[Diagnostic]) -> dict[str, frozenset[int]]:
    """The lines of each module lost to a syntax error (E103) or an unknown mnemonic (E201).

    Collected in mutable sets and frozen once: a frozenset grown by `|=` is copied at every
    step, which made checking quadratic in the number of errors (issue 21: 200k bad lines
    took 859 s)."""
    found: dict[str, set[int]] = {m.path: set() for m in modules}
    for d in diags:
        if d.code in ("E103", "E201"):
            lines = found.get(d.file)
            if lines is not None:
                lines.add(d.span.line)
    return {path: frozenset(lines) for path, lines in found.items()}


def project_symbols(config: Config) -> tuple[dict[str, str], list[Diagnostic]]:
    """mlc.toml `[symbols]` NAME = "OPERAND": device symbols of every module (docs/project.md)."""
    table = config.data.get("symbols", {})
    if not isinstance(table, dict):
        return {}, [diag(*config.locate("symbols"), "E106", "[symbols] must be a table of NAME = \"OPERAND\"")]
    out, diags = {}, []
    for name, value in table.items():
        if not (isinstance(value, str) and SYMBOL.fullmatch(name) and _operand_ok(value)) or _operand_ok(name):
            diags.append(diag(*config.locate("symbols", name), "E106", f"[symbols] {name} = {value!r}: "
                              "a symbol name (not an operand) and an operand are needed"))
        else:
            out[name.upper()] = value
    return out, diags


def _operand_ok(text: str) -> bool:
    try:
        parse_operand(text)
    except OperandSyntaxError:
        return False
    return True


def _finish(diags, config: Config, ignore, noqa) -> list[Diagnostic]:
    out = []
    for d in diags:
        sev = severity_of(d.code, d.severity, config, ignore)
        if sev == "off":
            continue
        sup = noqa.get(d.file, {}).get(d.span.line, False)
        # a noqa silences warnings only: an error means the program cannot be built (severity_of)
        if d.severity != "error" and (sup is None or (sup and d.code in sup)):
            continue
        out.append(d if sev == d.severity else d.with_severity(sev))
    return sorted(set(out), key=Diagnostic.sort_key)


def check_files(paths: list[str], target: Target, config: Config | None = None,
                ignore: frozenset[str] = frozenset()) -> CheckResult:
    sources: list[SourceText] = []
    encoding, initial = source_encoding(config)
    if initial:  # an unknown encoding name: nothing can be read
        return check_texts([], target, config, ignore, initial)
    for p in paths:
        wrong = not_a_source_by_name(p)  # a .stim or an object given as a source
        if wrong is not None:
            initial.append(wrong)
            continue
        src, found = read_source(p, encoding)
        initial += found
        if src is not None:
            wrong = not_a_source_by_content(src)  # a GX Works2 export
            if wrong is not None:
                initial.append(wrong)
            else:
                sources.append(src)
    return check_texts(sources, target, config, ignore, initial)


__all__ = ["CheckMemo", "CheckResult", "check_files", "check_texts", "decode"]
