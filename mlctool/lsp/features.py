"""The language features as plain functions of an Analysis (mlctool/lsp/project.py) and a
position; server.py only converts between these and the protocol.

Positions here are 1-based lines and columns as in the rest of mlctool; server.py converts.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from types import SimpleNamespace
from typing import NamedTuple

from mlctool.codes import CODES
from mlctool.diagnostics import Diagnostic
from mlctool.limits import is_decimal
from mlctool.lsp.project import LABEL, Analysis, Place
from mlctool.syntax.operands import SYMBOL, OperandSyntaxError, parse_operand
from mlctool.targetapi.model import InstrSpec, Target
from mlctool.targetapi.signals import device_signal, signals_of

_DID_YOU_MEAN = re.compile(r"did you mean ['\"`]?([^'\"`?\s]+)['\"`]?\?")
_NOQA = re.compile(r"\bmlc:\s*noqa\b", re.IGNORECASE)


@dataclass(frozen=True)
class Found:
    """The word under the cursor and what it is."""

    place: Place
    role: str  # mnemonic | operand | label | define | directive


def word_at(a: Analysis, path: str, line: int, col: int) -> Found | None:
    st = a.index.statement_at(path, line)
    if st is None:
        return None
    words = [(st.name, "label" if st.kind == "label" or (LABEL.fullmatch(st.name.text) and not st.operands)
              else st.kind if st.kind == "directive" else "mnemonic")]
    if st.kind == "directive" and st.name.text.lower() == ".define" and st.operands:
        words.append((st.operands[0], "define"))
        words += [(w, "operand") for w in st.operands[1:]]
    else:
        words += [(w, "operand") for w in st.operands]
    for w, role in words:
        if w.col <= col <= w.end_col:
            return Found(Place(path, line, w.col, w.end_col, w.text), role)
    return None


# ------------------------------------------------------------------------------------ hover
def hover(a: Analysis, path: str, line: int, col: int) -> tuple[str, Place] | None:
    found = word_at(a, path, line, col)
    target = a.project.target
    if found is None or target is None:
        return None
    text = found.place.text
    pointer = interrupt_at(a, path, line, col)
    if pointer is not None:
        return (_pointer_doc(a, pointer), found.place)
    if found.role == "mnemonic":
        specs = target.variants_of(text)
        return (instruction_doc(target, specs), found.place) if specs else None
    if found.role == "label" or (found.role == "operand" and _is_label(a, path, text)):
        return (_label_doc(a, path, text), found.place)
    if found.role in ("operand", "define"):
        doc = _operand_doc(a, path, text)
        return (doc, found.place) if doc else None
    return None


def instruction_doc(target: Target, specs: tuple[InstrSpec, ...]) -> str:
    spec = specs[0]
    head = f"**{spec.mnemonic}**" + (f" (API {spec.api})" if spec.api is not None else "")
    out = [head + f": {spec.width}-bit{', float' if spec.is_float else ''}"
           + (", pulse (once per Off->On)" if spec.pulse else ""),
           f"Manual: {spec.section} ({target.settings.get('manual_title') or target.title})"]
    other = _other_width(target, spec)
    steps = f"{spec.steps}" + ("~" + str(spec.steps + 1) if spec.short_steps else "")
    out.append(f"Steps: {steps} ({spec.width}-bit)" + (f", {other.steps} ({other.width}-bit {other.mnemonic})"
                                                     if other else ""))
    for spec_v in specs:
        if spec_v.operands:
            out.append("Operands: " + ", ".join(
                f"`{o.role}` {'/'.join(sorted(o.kinds))}{' (written)' if 'w' in o.access else ''}"
                for o in spec_v.operands))
        else:
            out.append("Operands: none")
    out.append(f"Class: {spec.cls} ({spec.op})")
    out += [f"- {n}" for n in spec.notes]
    return "\n\n".join(out)


def _other_width(target: Target, spec: InstrSpec) -> InstrSpec | None:
    for s in target.instructions.values():
        if s is not spec and s.op == spec.op and s.section == spec.section and s.width != spec.width \
                and s.pulse == spec.pulse and s.operands == spec.operands:
            return s
    return None


def resolve_symbol(a: Analysis, path: str, name: str) -> tuple[str, Place | None] | None:
    """(operand text, where defined) of a symbol seen from `path`: its .define, else mlc.toml."""
    key = name.upper()
    idx = a.index
    if key in idx.define_values.get(path, {}):
        return idx.define_values[path][key], idx.defines[path][key]
    table = a.project.config.data.get("symbols", {})
    if isinstance(table, dict):
        for k, v in table.items():
            if k.upper() == key and isinstance(v, str):
                file, span = a.project.config.locate("symbols", k)
                return v, Place(file, span.line, span.col, span.end_col, k)
    return None


def _operand_doc(a: Analysis, path: str, text: str) -> str | None:
    target = a.project.target
    sym = resolve_symbol(a, path, text)
    operand_text = sym[0] if sym else text
    try:
        op = parse_operand(operand_text, target.operand_syntax)
    except OperandSyntaxError:
        return f"`{text}`: undefined symbol" if SYMBOL.fullmatch(text) else None
    out = []
    if sym:
        out.append(f"**{text}** = `{operand_text}` (symbol)")
    if op.is_const:
        out.append(f"`{operand_text}`: constant {op.value!r}")
        return "\n\n".join(out)
    dev = target.devices.get(op.kind)
    if dev is None:
        return "\n\n".join(out) or None
    name = operand_text.upper()
    area = dev.area(op.number)
    line = f"**{name}**: {dev.kind} device {dev.name}{dev.lo}-{dev.name_of(dev.hi)[len(dev.name):]}"
    if area is not None:
        line += f", {area.name}" + (", latched" if area.latched else ", not latched") \
            + ({"nc": ", written by the NC", "reserved": ", reserved"}.get(area.write, ""))
    out.append(line + f" (manual {dev.section})")
    signal = device_signal(target, op.device, op.number) if not op.is_group and not op.index else None
    if signal is not None:  # the manual's row of a special M/D (NC5 ch. 5)
        out.append(f"**{signal.describe()}**")
        out.append("\n".join(f"- {key}: {value}" for key, value in signal.rows()))
    names = [n for n, v in a.index.define_values.get(path, {}).items() if v.upper() == name]
    if names and not sym:
        out.append("Symbol: " + ", ".join(names))
    out += device_use_lines(a, name)
    return "\n\n".join(out)


def device_use_lines(a: Analysis, name: str) -> list[str]:
    """'Written at: ...', 'Read at: ...' of a device (upper case, as the manual writes it)."""
    out = []
    reads, writes = device_uses(a, name)
    for verb, places in (("Written", writes), ("Read", reads)):
        if places:
            shown = [f"{_short(a, p.path)}:{p.line}" for p in places[:8]]
            more = f" and {len(places) - 8} more" if len(places) > 8 else ""
            out.append(f"{verb} at: " + ", ".join(shown) + more)
    if not reads and not writes:
        out.append("Not used by the project's code.")
    return out


def _short(a: Analysis, path: str) -> str:
    root = a.project.root
    if root is not None and path.startswith(str(root)):
        return path[len(str(root)) + 1:]
    return path.rsplit("/", 1)[-1]


def device_uses(a: Analysis, device: str) -> tuple[list[Place], list[Place]]:
    """(reads, writes) of one device over the checked modules, from the link map's
    cross-reference (so a DMOV to D0 writes D1 too)."""
    cache = getattr(a, "_xref", None)
    if cache is None:
        from mlctool.asm.mapfile import xref

        cache = {}
        for m in a.result.modules:
            instrs = [i for i in m.instrs if i.valid]
            at = {i.addr: i for i in instrs}
            for dev, (reads, writes) in xref(SimpleNamespace(instrs=instrs), a.project.target).items():
                r, w = cache.setdefault(dev, ([], []))
                r += [Place(m.path, at[x].line, at[x].col, at[x].col, dev) for x in reads]
                w += [Place(m.path, at[x].line, at[x].col, at[x].col, dev) for x in writes]
        a._xref = cache
    return cache.get(device, ([], []))


def _is_label(a: Analysis, path: str, text: str) -> bool:
    key = text.upper()
    if LABEL.fullmatch(text):
        return True
    return any(key in labels for labels in a.index.labels.values())


def _label_doc(a: Analysis, path: str, text: str) -> str:
    where = label_definition(a, path, text)
    if where is None:
        return f"**{text.upper()}**: label not defined in the project"
    exported = text.upper() in a.index.exports.get(where.path, set())
    return (f"**{text.upper()}**: label defined at {_short(a, where.path)}:{where.line}"
            + (" (exported)" if exported else ""))


# ------------------------------------------------------------------ definition, references
def label_definition(a: Analysis, path: str, text: str) -> Place | None:
    key = text.upper()
    own = a.index.labels.get(path, {})
    if key in own:
        return own[key]
    for p, labels in a.index.labels.items():
        if key in labels and key in a.index.exports.get(p, set()):
            return labels[key]
    return None


def definition(a: Analysis, path: str, line: int, col: int) -> Place | None:
    found = word_at(a, path, line, col)
    if found is None:
        return None
    if found.role == "define":
        return found.place
    pointer = interrupt_at(a, path, line, col)
    if pointer is not None:
        homes = interrupt_pointers(a).get(pointer, ([], []))[0]
        return next((h for h in homes if h.path == path), homes[0] if homes else None)
    text = found.place.text
    if found.role == "label" or (found.role == "operand" and _is_label(a, path, text)):
        return label_definition(a, path, text)
    if found.role == "operand":
        sym = resolve_symbol(a, path, text)
        return sym[1] if sym else None
    return None


def references(a: Analysis, path: str, line: int, col: int, include_declaration: bool = True
               ) -> list[Place]:
    pointer = interrupt_at(a, path, line, col)
    if pointer is not None:  # one set of pointers for the whole program: every module
        homes, uses = interrupt_pointers(a).get(pointer, ([], []))
        return (homes if include_declaration else []) + uses
    found = word_at(a, path, line, col)
    if found is None or found.role in ("mnemonic", "directive"):
        return []
    text = found.place.text
    key = text.upper()
    idx = a.index
    if found.role == "label" or (found.role == "operand" and _is_label(a, path, text)):
        home = label_definition(a, path, text)
        if home is None:
            files = [path]
        elif key in idx.exports.get(home.path, set()):
            files = [p for p in idx.parsed if p == home.path or key not in idx.labels.get(p, {})]
        else:
            files = [home.path]
        out = [home] if home is not None and include_declaration else []
    else:
        sym = resolve_symbol(a, path, text)
        if sym is None:
            return []
        home = sym[1]
        if home is not None and home.path in idx.parsed:
            files = [home.path]
        else:  # an mlc.toml symbol: every module that does not define the name itself
            files = [p for p in idx.parsed if key not in idx.defines.get(p, {})]
        out = [home] if home is not None and include_declaration else []
    for p in files:
        out += [u for u in idx.uses.get(p, []) if u.text.upper() == key]
    return out


def rename_check(a: Analysis, path: str, line: int, col: int, new_name: str) -> str | None:
    """Why `new_name` cannot replace the name under the cursor (None: it can)."""
    pointer = interrupt_at(a, path, line, col)
    if pointer is not None:
        return _pointer_rename_check(a, pointer, new_name)
    found = word_at(a, path, line, col)
    if found is None or found.role in ("mnemonic", "directive"):
        return "nothing to rename here: put the cursor on a .define symbol or a label"
    text = found.place.text
    is_label = found.role == "label" or (found.role == "operand" and _is_label(a, path, text))
    if is_label:
        if not (LABEL.fullmatch(new_name) or SYMBOL.fullmatch(new_name)):
            return f"{new_name!r} is not a label (P0, P1 ... or a name)"
        return None
    if resolve_symbol(a, path, text) is None:
        return f"{text!r} is not a symbol: only .define symbols and labels are renamed"
    try:
        parse_operand(new_name, a.project.target.operand_syntax)
        return f"{new_name!r} reads as an operand: a symbol needs another name"
    except OperandSyntaxError:
        pass
    if not SYMBOL.fullmatch(new_name):
        return f"{new_name!r} is not a symbol name (letters, digits, _ and .)"
    return None


# ----------------------------------------------------------------------- interrupt pointers
def interrupt_at(a: Analysis, path: str, line: int, col: int) -> str | None:
    """The interrupt pointer under the cursor (`IX0P:` labelling a routine, `IX0P` alone on
    its line, or an operand such as DHSCS's IHC0), upper case; None elsewhere."""
    target = a.project.target
    found = word_at(a, path, line, col)
    if target is None or found is None or found.role not in ("label", "mnemonic", "operand"):
        return None
    if found.role == "mnemonic":
        st = a.index.statement_at(path, line)
        if st is None or st.operands:
            return None
    return found.place.text.upper() if _pointer(target, found.place.text) else None


def interrupt_pointers(a: Analysis) -> dict[str, tuple[list[Place], list[Place]]]:
    """NAME -> (the lines it labels, the operands naming it) over every module: the pointers
    are the PLC's (one interrupt table), not a module's, so no `.export` is involved."""
    cache = getattr(a, "_pointers", None)
    if cache is not None:
        return cache
    cache = {}
    target = a.project.target
    if target is not None and (target.settings.get("interrupts") or {}).get("families"):
        for path, pf in a.index.parsed.items():
            for st in pf.statements:
                if st.kind == "directive":
                    continue
                if (st.kind == "label" or not st.operands) and _pointer(target, st.name.text):
                    cache.setdefault(st.name.text.upper(), ([], []))[0].append(_word_place(path, st.line, st.name))
                    continue
                for w in st.operands:
                    if _pointer(target, w.text):
                        cache.setdefault(w.text.upper(), ([], []))[1].append(_word_place(path, st.line, w))
    a._pointers = cache
    return cache


def _word_place(path: str, line: int, w) -> Place:
    return Place(path, line, w.col, w.end_col, w.text)


def _pointer_doc(a: Analysis, name: str) -> str:
    from mlctool.check.interrupts import disable_relay

    target = a.project.target
    p = _pointer(target, name)
    source = {"input": f"input {p.family.get('device', 'X')}{p.unit}"
                       + {"P": ", rising edge", "F": ", falling edge"}.get(p.suffix, ""),
              "timer": f"timer, every {p.unit} ms", "counter": f"high-speed counter compare (DHSCS ... IHC{p.unit})",
              "hardware": f"hardware high-speed counter {p.unit}"}.get(p.source, p.source)
    section = target.settings["interrupts"].get("section", "")
    out = [f"**{name}**: interrupt pointer, {source} (I{p.number}; manual {section})"]
    out.append(f"Requests disabled while {target.device_name('M', disable_relay(p))} is On")
    homes, uses = interrupt_pointers(a).get(name, ([], []))
    if homes:
        out.append("Routine at: " + ", ".join(f"{_short(a, h.path)}:{h.line}" for h in homes))
    else:
        out.append("No routine: the program does not label one with it")
    if uses:
        out.append("Named at: " + ", ".join(f"{_short(a, u.path)}:{u.line}" for u in uses))
    return "\n\n".join(out)


def _pointer_rename_check(a: Analysis, old: str, new_name: str) -> str | None:
    target = a.project.target
    new = _pointer(target, new_name)
    if new is None:
        names = ", ".join(f"{f['prefix']}{'n' * f['digits']}{'/'.join(f.get('suffixes', {}))}"
                          for f in (target.settings.get("interrupts") or {}).get("families", []))
        return f"{new_name!r} is not an interrupt pointer of target {target.name} ({names})"
    if new.name in interrupt_pointers(a) and new.name != old:
        homes, uses = interrupt_pointers(a)[new.name]
        where = (homes or uses)[0]
        return f"{new.name} is used already ({_short(a, where.path)}:{where.line})"
    uses = interrupt_pointers(a).get(old, ([], []))[1]
    if uses and _pointer(target, old).family is not new.family:
        return (f"{old} is named by an instruction ({_short(a, uses[0].path)}:{uses[0].line}) that takes "
                f"{_pointer(target, old).family['prefix']} pointers only: {new.name} is another kind")
    return None


# ------------------------------------------------------------------------------ completion
@dataclass(frozen=True)
class Completion:
    label: str
    kind: str  # instruction | device | symbol | label
    detail: str
    snippet: str | None = None
    doc: str = ""


def completions(a: Analysis, path: str, line: int, col: int, line_text: str) -> list[Completion]:
    target = a.project.target
    if target is None:
        return []
    before = line_text[:col - 1]
    code = before.split(";", 1)[0]
    if code.lstrip().startswith("."):
        return []
    words = code.split()
    first_word = not words or (len(words) == 1 and not code.endswith((" ", "\t")))
    if words and is_decimal(words[0]):  # a leading step number
        first_word = len(words) == 1 and code.endswith((" ", "\t")) or (len(words) == 2 and not code.endswith((" ", "\t")))
    if first_word:
        out = []
        for name, spec in sorted(target.instructions.items()):
            roles = [o.role for o in spec.operands]
            snippet = name if not roles else name + " " + " ".join(
                f"${{{k}:{r}}}" for k, r in enumerate(roles, 1))
            out.append(Completion(name, "instruction", f"{spec.section}: {spec.steps} steps", snippet))
        return out
    out = []
    idx = a.index
    for name, value in sorted(idx.define_values.get(path, {}).items()):
        out.append(Completion(name, "symbol", f"= {value}"))
    table = a.project.config.data.get("symbols", {})
    if isinstance(table, dict):
        for name, value in sorted(table.items()):
            if name.upper() not in idx.define_values.get(path, {}):
                out.append(Completion(name, "symbol", f"= {value} (mlc.toml)"))
    seen = set()
    for p, labels in idx.labels.items():
        for name in labels:
            if (p == path or name in idx.exports.get(p, set())) and name not in seen:
                seen.add(name)
                out.append(Completion(name, "label", f"label ({_short(a, p)})"))
    for dev in target.devices.values():
        out.append(Completion(dev.name, "device", f"{dev.kind} {dev.name}{dev.lo}-"
                              f"{dev.name_of(dev.hi)[len(dev.name):]} ({dev.section})"))
    typed = _TYPED_DEVICE.search(code)
    if typed:
        out += signal_completions(a, typed[0].upper())
    return out


_TYPED_DEVICE = re.compile(r"(?<![\w.])[A-Za-z][0-9]+$")


def signal_completions(a: Analysis, typed: str) -> list[Completion]:
    """The target's signals (NC5 special M/D) whose device starts as typed (M21 -> M21000 ...),
    on the project's channels, each with its one-line description."""
    table = signals_of(a.project.target)
    if table is None:
        return []
    count = table.channel_count(a.project.config.data)
    out = []
    for s in table.signals:
        for channel in range(table.channels[0], count + 1) if "x" in s.device else (0,):
            device = f"{s.kind}{s.number(channel)}"
            if device.startswith(typed):
                at = table.at(s.kind, s.number(channel))
                out.append(Completion(device, "device", at.describe(), doc=s.decision))
    return out


# -------------------------------------------------------------------------- document symbols
@dataclass
class Symbol:
    name: str
    kind: str  # label | interrupt | define | rung
    line: int
    end_line: int
    col: int = 1
    end_col: int = 1
    children: list[Symbol] | None = None


def document_symbols(a: Analysis, path: str) -> list[Symbol]:
    parsed = a.index.parsed.get(path)
    if parsed is None:
        return []
    target = a.project.target
    lines = parsed.lines
    out: list[Symbol] = []
    current: Symbol | None = None
    by_line = {st.line: st for st in parsed.statements}
    comment: tuple[int, str] | None = None
    for number, raw in enumerate(lines, 1):
        st = by_line.get(number)
        stripped = raw.strip()
        if st is None:
            if stripped.startswith((";", "//")):
                if comment is None:
                    comment = (number, stripped.lstrip(";/ ").strip())
            elif not stripped:
                comment = None
            continue
        if st.kind == "directive":
            if st.name.text.lower() == ".define" and st.operands:
                w = st.operands[0]
                out.append(Symbol(w.text, "define", number, number, w.col, w.end_col))
            comment = None
            continue
        pointer = target is not None and not st.operands and _pointer(target, st.name.text)
        if st.kind == "label" or (LABEL.fullmatch(st.name.text) and not st.operands) or pointer:
            if current is not None:
                current.end_line = number - 1
            current = Symbol(st.name.text.upper(), "interrupt" if pointer else "label", number, len(lines),
                             st.name.col, st.name.end_col, [])
            out.append(current)
            comment = None
            continue
        if comment is not None:
            rung = Symbol(comment[1] or "rung", "rung", comment[0], number, 1, len(raw) + 1)
            (current.children if current is not None else out).append(rung)
            comment = None
    return out


# ------------------------------------------------------------------------------ formatting
def formatted(a: Analysis, path: str) -> str | None:
    from mlctool.fmt import format_source

    src = a.sources.get(path)
    if src is None or a.project.target is None:
        return None
    new, _ = format_source(src, a.project.target)
    return None if new is None or new == src.text else new


# ---------------------------------------------------------------------------- code actions
@dataclass(frozen=True)
class Edit:
    line: int
    col: int
    end_line: int
    end_col: int
    new_text: str


@dataclass(frozen=True)
class Fix:
    title: str
    line: int  # the diagnostic's line
    code: str
    edits: tuple[Edit, ...]
    preferred: bool = False


def fixes(a: Analysis, path: str, diags: list[Diagnostic], lines: list[str]) -> list[Fix]:
    out = []
    for d in diags:
        m = _DID_YOU_MEAN.search(d.message)
        if m is not None and d.span.line == d.span.end_line:
            out.append(Fix(f"Replace with {m[1]}", d.span.line, d.code,
                           (Edit(d.span.line, d.span.col, d.span.line, d.span.end_col, m[1]),), True))
        if d.code == "E201":
            out += pulse_rewrites(a, path, d, lines)
        if d.severity == "warning" and 0 < d.span.line <= len(lines):
            text = lines[d.span.line - 1]
            if not _NOQA.search(text):
                end = len(text) + 1
                out.append(Fix(f"Silence {d.code} on this line (; mlc: noqa {d.code})", d.span.line, d.code,
                               (Edit(d.span.line, end, d.span.line, end, f"  ; mlc: noqa {d.code}"),)))
    return out


# the classes of a rung's condition and outputs (targetapi InstrSpec.cls); anything else ends it
_RUNG_CLASSES = frozenset({"load", "and", "or", "inv", "anb", "orb", "mps", "mrd", "mpp", "output"})


def pulse_rewrites(a: Analysis, path: str, d: Diagnostic, lines: list[str]) -> list[Fix]:
    """A P (pulse) form on a target without them (`MOVP` on NC5, E201 with the note of
    check/resolve.py's _pulse_hint): the rewrites that keep its meaning, run once per rising
    edge of its condition. Offered only where the rewrite changes nothing else: the P form
    is the last instruction of its rung (the next one starts another rung).
    - the condition is one contact `LD dev` / `LDI dev`: `LDP dev` / `LDF dev` and the plain form;
    - any condition: a PLS relay the project never uses (`PLS M14999`, `LD M14999`) before the
      plain form."""
    from mlctool.check.resolve import _pulse_hint

    target = a.project.target
    parsed = a.index.parsed.get(path)
    if target is None or parsed is None:
        return []
    statements = [st for st in parsed.statements if st.kind != "directive"]
    k = next((n for n, st in enumerate(statements) if st.line == d.span.line), None)
    if k is None or statements[k].kind != "instr":
        return []
    st = statements[k]
    name = st.name.text.upper()
    base = target.instructions.get(name[:-1])
    if base is None or not _pulse_hint(target, name):
        return []

    def cls(n: int) -> str | None:
        if not 0 <= n < len(statements) or statements[n].kind != "instr":
            return None
        specs = target.variants_of(statements[n].name.text)
        return specs[0].cls if specs else "unknown"

    after = cls(k + 1)
    if k + 1 < len(statements) and after not in ("load", "free", "label", "interrupt", "bus", None):
        return []  # an output or contact after it shares its condition: not only its rung changes
    first = k  # the rung's first statement: back over its condition and outputs to its load
    while cls(first - 1) in _RUNG_CLASSES and not (cls(first - 1) == "output" and cls(first) == "load"):
        first -= 1
    rung = statements[first:k]
    if not rung:
        return []
    mps = sum(cls(n) == "mps" for n in range(first, k)) - sum(cls(n) == "mpp" for n in range(first, k))
    if mps:
        return []  # inside an MPS branch: the stack's result belongs to the branches after it
    plain = _renamed(st, lines, base.mnemonic)
    out: list[Fix] = []
    load = rung[0]
    if len(rung) == 1 and len(load.operands) == 1:
        op = target.variants_of(load.name.text)[0].op
        edge = {"contact": "contact_rise", "contact_not": "contact_fall"}.get(op)
        spec = next((s for s in target.instructions.values() if s.cls == "load" and s.op == edge), None)
        if spec is not None:
            out.append(Fix(f"Rewrite as {spec.mnemonic} {load.operands[0].text} / {base.mnemonic} "
                           f"(once per rising edge)", st.line, d.code,
                           (_renamed(load, lines, spec.mnemonic), plain), True))
    relay = _free_relay(a, target)
    pls = next((s for s in target.instructions.values() if s.op == "pls"), None)
    ld = next((s for s in target.instructions.values() if s.cls == "load" and s.op == "contact"), None)
    if relay and pls and ld and st.step is None:
        raw = lines[st.line - 1]
        indent = raw[:st.name.col - 1]
        gap = st.operands[0].col - st.name.end_col if st.operands else 1
        width = len(st.name.text) + gap if gap > 1 else 0

        def line(mnemonic: str, operand: str) -> str:
            return indent + (mnemonic.ljust(width - 1) if width else mnemonic) + " " + operand + "\n"

        # one edit from the line's start (an insertion and a replacement at one position
        # would be two edits whose order clients may disagree on)
        edit = Edit(st.line, 1, plain.end_line, plain.end_col,
                    line(pls.mnemonic, relay) + line(ld.mnemonic, relay) + indent + plain.new_text)
        out.append(Fix(f"Rewrite with a {pls.mnemonic} relay: {pls.mnemonic} {relay} / {ld.mnemonic} {relay} / "
                       f"{base.mnemonic} ({relay} is unused)", st.line, d.code, (edit,)))
    return out


def _renamed(st, lines: list[str], mnemonic: str) -> Edit:
    """The statement's mnemonic replaced, its operands kept in their column where there is room."""
    w = st.name
    raw = lines[st.line - 1]
    rest = raw[w.end_col - 1:]
    gap = len(rest) - len(rest.lstrip(" "))
    shift = len(w.text) - len(mnemonic)
    if st.operands and gap > 1 and gap + shift >= 1:
        return Edit(st.line, w.col, st.line, w.end_col + gap, mnemonic + " " * (gap + shift))
    return Edit(st.line, w.col, st.line, w.end_col, mnemonic)


def _free_relay(a: Analysis, target: Target) -> str | None:
    """The highest M relay of the first writable, not latched area that no module of the
    project names (a PLS relay needs its own bit)."""
    dev = target.devices.get("M")
    if dev is None:
        return None
    area = next((x for x in dev.areas if x.write == "ok" and not x.latched), None)
    if area is None:
        return None
    used: set[int] = set()
    for places in a.index.uses.values():  # every operand word, .define values among them
        for place in places:
            try:
                op = parse_operand(place.text, target.operand_syntax)
            except OperandSyntaxError:
                continue
            if op.device == "M":  # a group K4M0 (in a 32-bit form too) covers up to 32 bits
                used.update(range(op.number, op.number + (32 if op.is_group else 1)))
    return next((dev.name_of(n) for n in range(area.hi, area.lo - 1, -1) if n not in used), None)


def explain(code: str) -> str:
    c = CODES.get(code)
    return f"{c.code}: {c.summary}\n\n{c.doc.strip()}" if c else ""


# ------------------------------------------------------------------- folding, inlay hints
def folding_ranges(a: Analysis, path: str) -> list[tuple[int, int, str]]:
    """(first line, last line, kind): each label's routine up to the next label (its last
    code line), and runs of two or more comment lines."""
    parsed = a.index.parsed.get(path)
    if parsed is None:
        return []
    out: list[tuple[int, int, str]] = []
    code_lines = [st.line for st in parsed.statements]
    starts = [st.line for st in parsed.statements
              if st.kind == "label" or (LABEL.fullmatch(st.name.text) and not st.operands)]
    for k, first in enumerate(starts):
        stop = starts[k + 1] if k + 1 < len(starts) else len(parsed.lines) + 1
        last = max((n for n in code_lines if first < n < stop), default=first)
        if last > first:
            out.append((first, last, "region"))
    out += _step_ladder_blocks(a, parsed)
    run_start = None
    for number, raw in enumerate([*parsed.lines, ""], 1):
        is_comment = raw.strip().startswith((";", "//"))
        if is_comment and run_start is None:
            run_start = number
        elif not is_comment and run_start is not None:
            if number - 1 > run_start:
                out.append((run_start, number - 1, "comment"))
            run_start = None
    return sorted(out)


def _step_ladder_blocks(a: Analysis, parsed) -> list[tuple[int, int, str]]:
    """Each step of a step ladder (`STL S20`, an instruction that opens a region: VS 2-11)
    up to its last code line before the next step, its RET, a label or the file's end."""
    target = a.project.target
    if target is None:
        return []
    out: list[tuple[int, int, str]] = []
    start: int | None = None
    last = 0
    for st in parsed.statements:
        if st.kind == "directive":
            continue
        specs = target.variants_of(st.name.text) if st.kind == "instr" else ()
        region = specs[0].region if specs else ""
        ends = st.kind == "label" or region in ("open", "close") or (specs and specs[0].op in ("end", "fend"))
        if start is not None and ends:
            if last > start:
                out.append((start, last, "region"))
            start = None
        if region == "open":
            start = st.line
        last = st.line
    if start is not None and last > start:
        out.append((start, last, "region"))
    return out


def step_addresses(a: Analysis, path: str, first: int, last: int) -> list[tuple[int, int]]:
    """(line, step address) of each instruction of the module between the lines (inclusive),
    as `mlc build` places it in its module (the listing's addresses before linking)."""
    for m in a.result.modules:
        if m.path == path:
            return [(i.line, i.addr) for i in m.instrs if first <= i.line <= last]
    return []


# ------------------------------------------------------------------------- semantic tokens
# The legend (server.py sends it once): standard LSP token types where one fits, so every
# theme colours them; the device's kind rides on modifiers (editors/vscode maps them to scopes).
TOKEN_TYPES = ("keyword", "macro", "variable", "number", "string", "label", "comment")
TOKEN_MODIFIERS = ("declaration", "bit", "word", "timer", "counter", "pointer", "input", "latched",
                   "symbol", "interrupt")
_COMMENT_START = re.compile(r";|//")


class Token(NamedTuple):  # a tuple: a 10k-line file has some 20k of them
    line: int  # 1-based
    col: int  # 1-based
    length: int
    type: str  # one of TOKEN_TYPES
    modifiers: tuple[str, ...] = ()


def semantic_tokens(a: Analysis, path: str) -> list[Token]:
    """The file's words by what they are: instruction (keyword), directive (macro), device
    (variable, with its kind: bit/word/timer/counter, input, latched), constant (number,
    string), label or interrupt pointer (label), `.define` symbol (what it stands for, with the
    `symbol` modifier), comment; in line and column order."""
    parsed = a.index.parsed.get(path)
    target = a.project.target
    if parsed is None:
        return []
    by_line = {st.line: st for st in parsed.statements}
    seen: dict[str, tuple[str, tuple[str, ...]] | None] = {}  # operand text -> its token kind
    has_pointers = target is not None and bool((target.settings.get("interrupts") or {}).get("families"))

    def operand(text: str) -> tuple[str, tuple[str, ...]] | None:
        key = text.upper()
        if key not in seen:
            seen[key] = _operand_token(a, path, text) if target is not None else None
        return seen[key]

    out: list[Token] = []
    for number, raw in enumerate(parsed.lines, 1):
        st = by_line.get(number)
        code_end = 1
        if st is not None:
            if st.step is not None:
                out.append(Token(number, st.step.col, len(st.step.text), "number"))
            name = st.name
            operands = st.operands
            if st.kind == "directive":
                out.append(Token(number, name.col, len(name.text), "macro"))
                if name.text.lower() == ".define" and operands:
                    first = operands[0]
                    kind = operand(operands[1].text) if len(operands) > 1 else None
                    mods = (kind[1] if kind else ()) + ("symbol", "declaration")
                    out.append(Token(number, first.col, len(first.text), kind[0] if kind else "variable", mods))
                    operands = operands[1:]
            elif st.kind == "label" or (LABEL.fullmatch(name.text) and not operands):
                out.append(Token(number, name.col, len(name.text), "label", ("declaration",)))
            elif has_pointers and not operands and _pointer(target, name.text):
                out.append(Token(number, name.col, len(name.text), "label", ("declaration", "interrupt")))
            else:
                out.append(Token(number, name.col, len(name.text), "keyword"))
            for w in operands:
                kind = operand(w.text)
                if kind is not None:
                    out.append(Token(number, w.col, len(w.text), *kind))
            last = st.operands[-1] if st.operands else name
            code_end = last.end_col
        m = _COMMENT_START.search(raw, code_end - 1)
        if m is not None:
            out.append(Token(number, m.start() + 1, len(raw.rstrip()) - m.start(), "comment"))
    return out


def _pointer(target: Target, text: str):
    from mlctool.check.interrupts import pointer_named

    return pointer_named(text, target)


def _operand_token(a: Analysis, path: str, text: str) -> tuple[str, tuple[str, ...]] | None:
    target = a.project.target
    if target.settings.get("interrupts") and _pointer(target, text):
        return "label", ("interrupt",)
    sym = resolve_symbol(a, path, text)
    if sym is None and _is_label(a, path, text):
        return "label", ()
    try:
        op = parse_operand(sym[0] if sym else text, target.operand_syntax)
    except OperandSyntaxError:
        return None  # undefined: the diagnostic says so; the grammar colours it
    extra = ("symbol",) if sym else ()
    if op.is_const:
        return ("string" if op.kind == "$" else "number"), extra
    dev = target.devices.get(op.device)
    if dev is None:
        return None
    if dev.kind == "pointer":
        return "label", extra
    area = dev.area(op.number)
    mods = (dev.kind,) + (("input",) if dev.input else ()) + (("latched",) if area is not None and area.latched
                                                            else ())
    return "variable", mods + extra


# ------------------------------------------------------------------------ workspace symbols
@dataclass(frozen=True, slots=True)
class WorkspaceSymbol:
    name: str
    kind: str  # subroutine | label | interrupt | define
    place: Place
    module: str  # the file as the project names it (relative to mlc.toml)


def workspace_symbols(a: Analysis, query: str) -> list[WorkspaceSymbol]:
    """The project's labels (subroutines: the ones a CALL names; interrupt routines: the
    target's interrupt pointers), `.define` symbols of every module and `[symbols]` of
    mlc.toml, whose name holds the query's characters in order (case ignored)."""
    target = a.project.target
    idx = a.index
    called: set[str] = set()
    if target is not None:
        for pf in idx.parsed.values():
            for st in pf.statements:
                if st.kind == "instr" and st.operands and any(
                        s.op == "call" for s in target.variants_of(st.name.text)):
                    called.add(st.operands[0].text.upper())
    out: list[WorkspaceSymbol] = []
    for path in idx.parsed:
        module = _short(a, path)
        for name, place in idx.labels.get(path, {}).items():
            kind = ("interrupt" if target is not None and _pointer(target, name)
                    else "subroutine" if name in called else "label")
            out.append(WorkspaceSymbol(place.text, kind, place, module))
        out += [WorkspaceSymbol(place.text, "define", place, module) for place in idx.defines.get(path, {}).values()]
    table = a.project.config.data.get("symbols", {})
    if isinstance(table, dict):
        for name in table:
            file, span = a.project.config.locate("symbols", name)
            out.append(WorkspaceSymbol(name, "define", Place(file, span.line, span.col, span.end_col, name),
                                       _short(a, file)))
    return [s for s in out if _fuzzy(query, s.name)]


def _fuzzy(query: str, name: str) -> bool:
    """Every character of the query in the name, in order (VS Code's own filter does the rest)."""
    rest = iter(name.upper())
    return all(c in rest for c in query.upper() if not c.isspace())
