"""Statements -> Module: directives, symbols, mnemonics, operand legality, steps, addresses.

Every rule here reads the target's tables; nothing names an instruction.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from mlctool.check.constraints import constraint_problems
from mlctool.check.interrupts import pointer_named, pointer_numbered
from mlctool.check.labels import cjk_width, is_label_name, is_symbol_name
from mlctool.diagnostics import Diagnostic, Span, diag
from mlctool.program import Instr, Module
from mlctool.syntax.operands import (
    BIT_OF_WORD,
    CJK_CHAR,
    CONSTANT_KINDS,
    DEFAULT_SYNTAX,
    INDEX_REGISTERS,
    Operand,
    OperandSyntax,
    OperandSyntaxError,
    name_width,
    parse_operand,
)
from mlctool.syntax.parser import ParsedFile, Statement, Word
from mlctool.targetapi.model import GROUP_KINDS, InstrSpec, OperandSpec, Target, choose_variant

_LABEL = re.compile(r"P([0-9]+)", re.IGNORECASE)


@dataclass(slots=True)
class _Arg:
    """An operand position (-1: the mnemonic) and its text, for problems found while resolving."""

    idx: int
    text: str


class ResolverCaches:
    """What the resolver learns about lines, operands and instruction forms. Each entry
    depends only on its key, the target's tables and the file's named labels (resolve()'s
    `names`): a caller that keeps one between checks of edited versions of a file (the
    language server, through check.CheckMemo) re-resolves only the lines it has not seen."""

    __slots__ = ("lines", "operands", "legal_spans", "plain_forms", "texts", "mnemonics", "steps")

    def __init__(self) -> None:
        self.lines: dict = {}
        self.operands: dict = {}
        self.legal_spans: dict = {}
        self.plain_forms: dict = {}
        self.texts: dict = {}
        self.mnemonics: dict = {}
        self.steps: dict = {}

    def __len__(self) -> int:
        return len(self.lines) + len(self.texts)


class _Resolver:
    # False: every line takes resolve_line's whole way and is keyed by its words, never by
    # its text (tests/check/test_check_cache.py compares both ways on generated programs)
    shortcuts = True

    def __init__(self, parsed: ParsedFile, target: Target, names: dict[str, int] | None = None,
                 caches: ResolverCaches | None = None):
        self.p = parsed
        self.t = target
        self.path = parsed.path
        self.diags: list[Diagnostic] = list(parsed.diagnostics)
        self.module = Module(parsed.path, target.name, [])
        self.addr = 0
        self.numbered: tuple[int, int, int] | None = None  # the last step number: (number, address, line)
        self.label_spec = next(s for s in target.instructions.values() if s.cls == "label")
        caches = ResolverCaches() if caches is None else caches
        self.cache = caches.lines  # (mnemonic, operand texts) -> resolution of the line
        self.operand_cache = caches.operands  # (instruction form, position, text) -> (ok, problems)
        self.legal_spans = caches.legal_spans  # (instruction form, position, kind) -> numbers passing
        self.plain_forms = caches.plain_forms  # id(instruction form) -> plain_form()
        self.line_cache = caches.texts  # line text -> (cache entry, what its Instr is made of: run())
        self.mnemonics = caches.mnemonics  # mnemonic -> its plain form for plain_line(), or (None, ...)
        self.step_memo = caches.steps  # (id(instruction form), first operand's kind) -> Target.step_spans
        self._problems: list = []
        self.refused: set[str] = set()  # `.define` names refused as reading as an operand (E106)
        self.syntax = target.operand_syntax
        self.names = names or {}  # named labels of this file -> P number (check/labels.py)
        self.named_labels = bool(target.settings.get("named_labels"))
        # ops whose steps depend on the operand beyond the short rule (target.toml [[step_rules]])
        self.step_rule_ops = frozenset(op for rule in target.settings.get("step_rules", ()) for op in rule["ops"])

    # -- reporting
    def err(self, line: int, w: Word, code: str, msg: str, *notes: str) -> None:
        self.diags.append(diag(self.path, Span(line, w.col, line, w.end_col), code, msg, *notes))

    # -- statements
    def run(self) -> tuple[Module, list[Diagnostic]]:
        # The loop of instruction() for the usual line (resolved without a word, no step
        # number written) is spelled out here with locals: it runs once per line.
        # While no symbol is defined, a line's text alone fixes its resolution: the text is
        # the key of line_cache, which also keeps the operand texts the instruction records.
        # A line's entry holds what its Instr is made of when it resolved without a word
        # (`made`, else None: place() reports its problems).
        cache = self.cache
        by_text = self.line_cache if self.shortcuts else None
        lines = self.p.lines
        symbols = self.module.symbols  # filled in place by .define as the lines go
        add = self.module.instrs.append
        path = self.path
        plain = self.plain_line if self.shortcuts else _no_plain_line
        addr = self.addr  # (self.addr again around the methods that emit)
        for st in self.p.statements:
            if st.kind != "instr":
                self.addr = addr
                if st.kind == "directive":
                    self.directive(st)
                else:
                    self.label(st, st.name)
                addr = self.addr
                continue
            if symbols or by_text is None:
                written = tuple([w.text for w in st.operands])
                key = (st.name.text.upper(), tuple([symbols.get(t.upper(), t) for t in written]))
                res = cache.get(key)
                if res is None:
                    res = cache[key] = plain(*key) or self.resolved(*key)
                made = _made(res, written)
            else:
                hit = by_text.get(lines[st.line - 1])
                if hit is None:
                    written = tuple([w.text for w in st.operands])
                    name = st.name.text.upper()
                    res = plain(name, written)
                    if res is None:  # (the usual line needs no entry of its words: its text has one)
                        key = (name, written)
                        res = cache.get(key)
                        if res is None:
                            res = cache[key] = self.resolved(name, written)
                    hit = by_text[lines[st.line - 1]] = (res, _made(res, written))
                res, made = hit
            if made is None or st.step is not None:
                self.addr = addr
                self.place(st, tuple([w.text for w in st.operands]), res)
                addr = self.addr
                continue
            spec, operands, texts, steps, table = made
            add(Instr(spec, operands, texts, steps, addr, path, st.line, st.name.col, table))
            addr += steps
        self.addr = addr
        return self.module, self.diags

    def directive(self, st: Statement) -> None:
        name = st.name.text.lower()
        ops = st.operands
        if name == ".define" and len(ops) == 2:
            sym, val = ops
            if not is_symbol_name(sym.text, self.t) or self._is_operand(sym.text, self.syntax):
                self.err(st.line, sym, "E106", f"{sym.text!r} cannot be a symbol name: it reads as an operand",
                         "its uses are not reported again; choose a name that is no device, constant or label")
                self.refused.add(sym.text.upper())
            elif (wide := self.wide_name_over(sym.text)) is not None:
                self.err(st.line, sym, "E106", f"symbol name {sym.text!r} is {wide} long: a name with Chinese "
                         f"characters has at most {self.t.settings['named_labels'].get('max_length', 16)} "
                         f"(a character counts {cjk_width(self.t)})")
            elif sym.text.upper() in self.module.symbols:
                self.err(st.line, sym, "E106", f"symbol {sym.text!r} is already defined")
            elif not self._is_operand(val.text, self.syntax):
                self.err(st.line, val, "E106", f"{val.text!r} is not a valid operand for symbol {sym.text!r}")
            elif not (op := parse_operand(val.text, self.syntax)).is_const and op.device not in self.t.devices:
                self.err(st.line, val, "E106", f"{val.text!r}: no device {op.device} on target {self.t.name}")
            else:
                self.module.symbols[sym.text.upper()] = val.text
        elif name == ".export" and ops:
            for w in ops:
                m = _LABEL.fullmatch(self.module.symbols.get(w.text.upper(), w.text))
                if m:
                    self.module.exports.add(int(m[1]))
                else:
                    self.err(st.line, w, "E105", f".export takes P labels, not {w.text!r}")
        elif name == ".library" and not ops:
            self.module.library = True
        elif name == ".dialect" and len(ops) == 1:
            self.dialect(st, ops[0])
        elif name == ".table" and _table_kinds(self.t):  # a communication-table row (check/tables.py)
            from mlctool.check.tables import parse_row

            for p in parse_row(self.t, [w.text for w in ops], self.module.symbols)[1]:
                self.err(st.line, st.name if p.index < 0 else ops[p.index], p.code, p.message)
        else:
            self.err(st.line, st.name, "E105", f"unknown or malformed directive {st.name.text!r}",
                     "directives: .define NAME OPERAND, .export P10, .library, .dialect fx")

    def dialect(self, st: Statement, w: Word) -> None:
        """`.dialect fx`: the program comes from that family (`mlc import` writes it); its specials
        decide W217, another family's numbers are ordinary devices (check/specials.py)."""
        from mlctool.targetapi.specials import families

        known = families(self.t.name)
        if w.text.lower() not in known:
            self.err(st.line, w, "E105", f".dialect {w.text}: target {self.t.name} knows "
                     + (f"the dialects {', '.join(sorted(known))}" if known else "no other family's dialect"))
        else:
            self.module.dialect = w.text.lower()

    def wide_name_over(self, text: str) -> int | None:
        """The counted length of a `.define` name with Chinese characters past the target's name
        limit (the manual's table names, 2-11: 8 Chinese characters or 16 letters); None if it fits.
        DECISION: plain ASCII symbol names keep having no limit (mlctool's own directive)."""
        wide = cjk_width(self.t)
        if not wide or not CJK_CHAR.search(text):
            return None
        size = name_width(text, wide)
        return size if size > int(self.t.settings["named_labels"].get("max_length", 16)) else None

    @staticmethod
    def _is_operand(text: str, syntax: OperandSyntax = DEFAULT_SYNTAX) -> bool:
        try:
            parse_operand(text, syntax)
        except OperandSyntaxError:
            return False
        return True

    def label(self, st: Statement, w: Word) -> None:
        pointer = pointer_named(w.text, self.t)
        if pointer is not None:  # an interrupt pointer: a label class of its own (I numbers)
            spec = next(s for s in self.t.instructions.values() if s.cls == "interrupt")
            self.emit(st, spec, (Operand("I", number=pointer.number),), (pointer.name,))
            return
        m = _LABEL.fullmatch(w.text)
        if not m and w.text.upper() in self.names:
            self.emit(st, self.label_spec, (Operand("P", number=self.names[w.text.upper()]),), (w.text,))
            return
        if not m:
            if not (self.named_labels and is_label_name(w.text, self.t)):  # else reported by labels.py
                dev = self.t.devices[next(iter(self.label_spec.operands[0].kinds))]
                self.err(st.line, w, "E103", f"label {w.text!r} is not a P pointer ({dev.name}{dev.lo}-"
                         f"{dev.name}{dev.hi}" + (" or a label name" if self.named_labels else "") + ")")
            return
        dev = self.t.devices[next(iter(self.label_spec.operands[0].kinds))]
        if not dev.lo <= int(m[1]) <= dev.hi:
            self.err(st.line, w, "E205", f"label {w.text} out of range {dev.name}{dev.lo}-{dev.name}{dev.hi}")
            self.emit_invalid(st, self.label_spec)  # it still ends the rung before it
            return
        self.emit(st, self.label_spec, (Operand("P", number=int(m[1])),), (w.text.upper(),))

    def instruction(self, st: Statement) -> None:
        # Resolution depends only on the mnemonic and the operand texts (after symbol
        # substitution), so identical lines are resolved once: large programs repeat a lot.
        # (run() has this inline for speed.)
        symbols = self.module.symbols
        written = tuple([w.text for w in st.operands])
        texts = tuple([symbols.get(t.upper(), t) for t in written]) if symbols else written
        key = (st.name.text.upper(), texts)
        res = self.cache.get(key)
        if res is None:
            res = self.cache[key] = self.resolved(*key)
        self.place(st, written, res)

    def resolved(self, name: str, texts: tuple[str, ...]) -> tuple:
        """What the cache keeps of a line: (spec, operands, table, ok, problems, steps)."""
        self._problems = []
        spec, operands, table, ok = self.resolve_line(name, texts)
        steps = self.steps(spec, operands) if ok and spec is not None else 0
        return spec, operands, table, ok, tuple(self._problems), steps

    def plain_line(self, name: str, texts: tuple[str, ...]) -> tuple | None:
        """resolved()'s answer for the usual line, the shortest way: a mnemonic of one plain
        form (plain_form) and operands that are each plainly legal (plainly_legal's spans)
        or were checked before without a word (operand_cache). None: any other line, which
        resolved() takes (tests/check/test_check_cache.py compares both ways)."""
        form = self.mnemonics.get(name)
        if form is None:
            form = self.mnemonics[name] = self._plain_mnemonic(name)
        spec, spans_by_kind, form_id, stepped = form
        if spec is None or len(texts) != len(spans_by_kind):
            return None
        syntax = self.syntax
        operands = []
        k = 0
        for text in texts:
            try:
                op = parse_operand(text, syntax)
            except OperandSyntaxError:
                return None
            legal = False
            if not (op.index or op.unit or op.digits):  # as plainly_legal, and K/H constants by value
                kinds = spans_by_kind[k]
                spans = kinds.get(op.kind)
                if spans is None:
                    spans = kinds[op.kind] = self.plain_spans(spec, spec.operands[k], op.kind)
                n = op.value if op.kind in _VALUED else op.number
                for lo, hi in spans:
                    if lo <= n <= hi:
                        legal = True
                        break
            if not legal:
                hit = self.operand_cache.get((form_id, k, text))
                if hit is None or not hit[0] or hit[1]:
                    return None
            operands.append(op)
            k += 1
        ops = tuple(operands)
        if stepped and ops:  # steps(): Target.instr_steps, its spans kept per form and kind
            first = ops[0]
            key = (form_id, first.kind)
            by_number = self.step_memo.get(key)
            if by_number is None:
                by_number = self.step_memo[key] = self.t.step_spans(spec, first.kind)
            spans, steps = by_number
            n = first.number
            for lo, hi, s in spans:
                if lo <= n <= hi:
                    steps = s
                    break
        else:
            steps = spec.steps
        return spec, ops, (), True, (), steps

    def _plain_mnemonic(self, name: str) -> tuple:
        """(the form, a dict of legal spans per device kind for each operand position, its id,
        whether its steps depend on its operands), or (None, ...) for a mnemonic of several
        forms or of a form that is not plain."""
        variants = self.t.variants_of(name)
        if len(variants) != 1 or not self.plain_form(variants[0]):
            return None, (), 0, False
        spec = variants[0]
        return spec, tuple({} for _ in spec.operands), id(spec), spec.short_steps or spec.op in self.step_rule_ops

    def place(self, st: Statement, written: tuple[str, ...], res: tuple) -> None:
        """A resolved line into the module: its problems at its words, then the instruction."""
        spec, operands, table, ok, problems, steps = res
        for idx, code, msg, notes in problems:
            if idx >= 0 and st.operands[idx].text.upper() in self.refused:
                continue  # a use of a refused symbol name (E106 at its .define says why): no cascade
            self.err(st.line, st.name if idx < 0 else st.operands[idx], code, msg, *notes)
        if spec is None:
            if ok:  # a bare P label written as an instruction
                self.label(st, st.name)
            return
        if ok:
            n = len(spec.operands)
            self.emit(st, spec, operands, written if len(written) == n else written[:n], table, steps)
        else:
            self.emit_invalid(st, spec)

    def report(self, arg: _Arg, code: str, msg: str, *notes: str) -> None:
        self._problems.append((arg.idx, code, msg, notes))

    def resolve_line(self, name: str, texts: tuple[str, ...]):
        """-> (spec, operands, table, ok); problems go to self.report."""
        variants = self.t.variants_of(name)
        if self.shortcuts and len(variants) == 1:  # the usual line: no _Arg, no variant to choose
            spec = variants[0]
            if len(texts) == len(spec.operands) and self.plain_form(spec):
                operands = self.plainly_resolved(spec, texts)
                if operands is not None:
                    return spec, operands, (), True
        mnemonic = _Arg(-1, name)
        if not variants:
            if (_LABEL.fullmatch(name) or pointer_named(name, self.t)) and not texts:
                return None, (), (), True
            missing = self.t.unavailable.get(name.upper())
            if missing is not None:
                self.report(mnemonic, "E901", f"{missing.mnemonic} is not available on model {self.t.model} "
                            f"(models: {', '.join(sorted(missing.models))}; {missing.section})",
                            "choose the model with --model or `model` in mlc.toml")
            else:
                suggestion, notes = unknown_instruction_hint(self.t, name.upper())
                self.report(mnemonic, "E201", f"unknown instruction {name!r} for target {self.t.name}{suggestion}",
                            *notes)
            return None, (), (), False
        spec = variants[0] if len(variants) == 1 else self.choose_variant(variants, texts)
        if self.shortcuts and len(variants) > 1 and len(texts) == len(spec.operands) and self.plain_form(spec):
            operands = self.plainly_resolved(spec, texts)
            if operands is not None:
                return spec, operands, (), True
        n = len(spec.operands)
        if len(texts) != n and not (spec.table and n < len(texts) <= n + spec.table):
            form = " ".join([spec.mnemonic] + [o.role for o in spec.operands])
            extra = n + spec.table  # VRT: the table entries may follow the operands
            where = _Arg(extra, "") if len(texts) > extra else mnemonic
            self.report(where, "E202", f"{spec.mnemonic} takes {n} operand{'s' if n != 1 else ''}, "
                        f"got {len(texts)}", f"form: {form}")
            return spec, (), (), False
        args = [_Arg(k, t) for k, t in enumerate(texts)]
        operands: list[Operand] = []
        for a in args:
            pointer = a.idx < n and "P" in spec.operands[a.idx].kinds
            if pointer and a.text.upper() in self.names:  # a named label: its P number
                operands.append(Operand("P", number=self.names[a.text.upper()]))
                continue
            interrupt = a.idx < n and "I" in spec.operands[a.idx].kinds and pointer_named(a.text, self.t)
            if interrupt:  # DHSCS K5 C235 IHC0: the pointer's I number (target.toml [interrupts])
                operands.append(Operand("I", number=interrupt.number))
                continue
            try:
                operands.append(parse_operand(a.text, self.syntax))
            except OperandSyntaxError as e:
                if pointer and self.named_labels and is_label_name(a.text, self.t):
                    self.report(a, "E304", f"{spec.mnemonic} {a.text}: no such label")
                    continue
                # a specific message (octal X8, hex H on NC5, ...) beats "undefined symbol"
                generic = str(e).endswith("is not a device, constant or pointer")
                if is_symbol_name(a.text, self.t) and len(a.text) > 1 and generic:
                    self.report(a, "E215", f"undefined symbol {a.text!r}")
                else:
                    self.report(a, "E203", str(e))
        if len(operands) != len(args):
            return spec, (), (), False
        ok = True
        for k, (spec_o, op, a) in enumerate(zip(spec.operands, operands, args, strict=False)):
            if spec_o.word_range_of:  # its rule reads another operand: not cacheable alone
                ok = self.check_operand(spec, spec_o, op, a, operands) and ok
                continue
            if self.plainly_legal(spec, k, spec_o, op):
                continue
            # one operand's verdict depends only on the instruction form, position and text
            key = (id(spec), k, a.text)
            hit = self.operand_cache.get(key)
            if hit is None:
                mark = len(self._problems)
                good = self.check_operand(spec, spec_o, op, a, operands)
                hit = self.operand_cache[key] = (good, tuple(self._problems[mark:]))
            else:
                self._problems.extend(hit[1])
            ok = hit[0] and ok
        lo, hi = self.t.krange(spec.width) if len(operands) > n else (0, 0)
        for o, a in zip(operands[n:], args[n:], strict=True):
            if o.kind != "K" or o.index:
                self.report(a, "E204", f"{spec.mnemonic} table entries are K constants")
                ok = False
            elif not lo <= o.value <= hi:
                self.report(a, "E206", f"table entry {a.text} outside K{lo}..K{hi}")
                ok = False
        ok = self.check_constraints(spec, operands, args) and ok
        table = tuple(int(o.value) for o in operands[n:]) + (0,) * (spec.table - len(operands[n:])) if spec.table else ()
        return spec, tuple(operands[:n]), table, ok

    def plain_form(self, spec: InstrSpec) -> bool:
        """An instruction form whose operands are checked one by one: no table, no rule
        across operands, no label or interrupt pointers (those read the names)."""
        plain = self.plain_forms.get(id(spec))
        if plain is None:
            plain = self.plain_forms[id(spec)] = not (
                spec.table or spec.constraints
                or any(o.word_range_of or o.span or "P" in o.kinds or "I" in o.kinds for o in spec.operands))
        return plain

    def plainly_resolved(self, spec: InstrSpec, texts: tuple[str, ...]) -> tuple[Operand, ...] | None:
        """The operands of a line of a plain form, when each one is plainly legal or was
        checked before without a word (operand_cache); None: resolve_line's whole way, which
        finds the same operands and says what is wrong (tests/check/test_check_fastpath.py)."""
        operands = []
        for k, text in enumerate(texts):
            try:
                op = parse_operand(text, self.syntax)
            except OperandSyntaxError:
                return None
            if not self.plainly_legal(spec, k, spec.operands[k], op):
                hit = self.operand_cache.get((id(spec), k, text))
                if hit is None or not hit[0] or hit[1]:
                    return None
            operands.append(op)
        return tuple(operands)

    def choose_variant(self, variants: tuple[InstrSpec, ...], texts: tuple[str, ...]) -> InstrSpec:
        try:
            first = parse_operand(texts[0], self.syntax) if texts else None
        except OperandSyntaxError:
            first = None
        return choose_variant(variants, len(texts), first)

    def emit_invalid(self, st: Statement, spec: InstrSpec) -> None:
        """Keep a line with operand errors for the rung checks, without operands."""
        self.module.instrs.append(Instr(spec, (), (), spec.steps, self.addr, self.path, st.line,
                                        st.name.col, valid=False))
        self.addr += spec.steps

    def check_operand(self, spec: InstrSpec, o: OperandSpec, op: Operand, w: _Arg,
                      all_ops: list[Operand]) -> bool:
        t = self.t
        width = spec.width
        dev = t.devices.get(op.device) if not op.is_const else None
        if not op.is_const and dev is None:
            self.report(w, "E203", f"{w.text!r}: no device {op.device} on target {t.name}")
            return False
        # writes to inputs and constants
        if o.writes and (op.is_const or (dev is not None and dev.input)):
            # "writes its D operand" read as register D: name the role as what it is, a destination
            nth = _ORDINAL.get(next((k for k, s in enumerate(spec.operands, 1) if s is o), 0), "an")
            what = "a constant" if op.is_const else "an input (written by the hardware only)"
            self.report(w, "E210", f"{w.text} is {what}: the {nth} operand of {spec.mnemonic} is its destination")
            return False
        if dev is not None and (dev.unit_prefix or op.unit) and not self.unit_word_ok(spec, o, op, dev, w):
            return False
        if op.kind not in o.kinds and not (op.unit and dev.like in o.kinds):
            allowed = " ".join(sorted(o.kinds))
            self.report(w, "E204", f"{spec.mnemonic} operand {o.role} cannot be {_kind_name(op)}",
                     f"allowed: {allowed} ({spec.section})")
            return False
        if op.is_float and width != 32:
            self.report(w, "E204", f"an {op.kind} constant needs a 32-bit instruction; {spec.mnemonic} is 16-bit")
            return False
        # index modification
        if op.index:
            ix, ixn = op.index
            if ix not in INDEX_REGISTERS or ix not in t.devices:  # only an object can say another (crafted)
                self.report(w, "E209", f"{w.text}: {ix!s:.10} is not an index register of target {t.name}")
                return False
            if not spec.index or not o.index or op.kind not in t.indexable:
                self.report(w, "E209", f"{w.text}: {spec.mnemonic} operand {o.role} cannot be index-modified")
                return False
            ix32 = t.settings.get("index32", {}).get("register", "V")  # NC5: V (1.8.2); VS: Z (2-9)
            if width == 32 and ix != ix32:
                self.report(w, "E209", f"{w.text}: 32-bit instructions index with {ix32} only")
                return False
            ixdev = t.devices[ix]
            if not ixdev.lo <= ixn <= ixdev.hi:
                self.report(w, "E205", f"{ix}{ixn} out of range {ix}{ixdev.lo}-{ix}{ixdev.hi}")
                return False
        if op.is_const:
            return self.check_const(w, spec, o, op, all_ops)
        # device number ranges
        if not dev.lo <= op.number <= dev.hi:
            self.report(w, "E205", f"{dev.name_of(op.number)} out of range {dev.name_of(dev.lo)}-{dev.name_of(dev.hi)}"
                        + (f" on model {t.model}" if t.model else ""))
            return False
        if op.is_bit_of_word and not dev.bit_of_word:
            self.report(w, "E203", f"{w.text!r}: {op.device} words have no bit operands on target {t.name}")
            return False
        allowed = o.allowed(op.kind)
        if allowed and not any(lo <= op.number <= hi for lo, hi in allowed):
            spans = ", ".join(f"{_device_name(t, dev, lo)}-{_device_name(t, dev, hi)}" for lo, hi in allowed)
            self.report(w, "E205", f"{spec.mnemonic} operand {o.role} takes {spans}, not {w.text}")
            return False
        narrow = o.devices32 if width == 32 else o.devices16
        if narrow and not narrow[0] <= op.number <= narrow[1]:
            self.report(w, "E211", f"{spec.mnemonic} takes {dev.name_of(narrow[0])}-{dev.name_of(narrow[1])}, not {w.text}")
            return False
        if dev.width16_only and width == 32:
            self.report(w, "E211", f"{op.kind} devices may be operands of 16-bit instructions only; "
                     f"{spec.mnemonic} is 32-bit")
            return False
        # 3.2.5 item 5: C64-C79 as data only in 32-bit instructions. Not for the counter
        # instructions (CNT/DCNT name their counter, checked by devices16/32 above) nor for
        # ranges of counters whose widths are checked as a whole (ZRST C64 C77, 4.5).
        if (op.kind == "C" and spec.api is not None and width == 16 and not (o.devices16 or o.devices32)
                and "no-counter-width-mix" not in spec.constraints and t.is_counter32(op.number)):
            d_form = f"D{spec.mnemonic}"
            self.report(w, "E211", f"32-bit counter {w.text} may be used only by 32-bit instructions (3.2.5)"
                        + (f"; use {d_form}" if d_form in t.instructions else ""))
            return False
        for lo, hi in (o.forbid16 if width == 16 else ()):
            if lo <= op.number <= hi:
                self.report(w, "E216", f"{spec.mnemonic} cannot take {w.text} ({op.kind}{lo}-{op.kind}{hi} excluded)")
                return False
        if op.is_group:
            maxn = 8 if width == 32 else 4
            if not 1 <= op.digits <= maxn:
                self.report(w, "E207", f"K{op.digits}{op.device}: n must be 1-{maxn} in a {width}-bit instruction")
                return False
            # a group standing for several registers (MUL D, SER D) is as many groups in a row
            words = o.words[1] if width == 32 else o.words[0]
            last = op.number + 4 * op.digits * max(1, words // (width // 16)) - 1
            first = op.number
        else:
            first = op.number
            last = op.number + self.extent(spec, o, op) - 1
        if last > dev.hi:
            self.report(w, "E208" if not op.is_group else "E207",
                     f"{w.text} would occupy {dev.name_of(first)}-{dev.name_of(last)}, past {dev.name_of(dev.hi)}")
            return False
        self.check_areas(w, o, dev, first, last)
        return True

    def plainly_legal(self, spec: InstrSpec, k: int, o: OperandSpec, op: Operand) -> bool:
        """A fast yes for the common operand: a plain device (no index, group, bit or unit)
        whose number lies where check_operand would find nothing to say. The numbers are
        worked out once per instruction form, position and device kind (legal_numbers);
        anything else takes check_operand. tests/check/test_check_fastpath.py compares the two."""
        if op.index or op.unit or op.digits:  # (constants and bits of words: legal_numbers)
            return False
        key = (id(spec), k, op.kind)
        spans = self.legal_spans.get(key)
        if spans is None:
            spans = self.legal_spans[key] = self.legal_numbers(spec, o, op.kind)
        n = op.number
        for lo, hi in spans:
            if lo <= n <= hi:
                return True
        return False

    def plain_spans(self, spec: InstrSpec, o: OperandSpec, kind: str) -> tuple[tuple[int, int], ...]:
        """What plain_line passes without check_operand: the device numbers of legal_numbers,
        or for K and H constants (not index-modified) the values of legal_values."""
        if kind in _VALUED:
            return self.legal_values(spec, o, kind)
        return self.legal_numbers(spec, o, kind)

    def legal_values(self, spec: InstrSpec, o: OperandSpec, kind: str) -> tuple[tuple[int, int], ...]:
        """The values of a K or H constant, not index-modified, that check_operand (check_const)
        passes without a word: the operand's constant range, where it takes `kind` and is
        read, not written; none where its range depends on another operand (word_range_of).
        tests/check/test_check_fastpath.py compares the two."""
        if kind not in _VALUED or kind not in o.kinds or o.writes or o.word_range_of:
            return ()
        rng = o.range32 if spec.width == 32 else o.range16
        if rng is None and kind == "H":  # as check_const: hex constants are the width's bit patterns
            rng = (0, 0xFFFFFFFF if spec.width == 32 else 0xFFFF)
        return (rng or self.t.krange(spec.width),)

    def legal_numbers(self, spec: InstrSpec, o: OperandSpec, kind: str) -> tuple[tuple[int, int], ...]:
        """The device numbers of `kind` that check_operand passes without a word, as spans.
        Counters are left out: their extent and the 3.2.5 rule depend on the number; so are
        constants and bits of words (kinds that are no device)."""
        if kind in CONSTANT_KINDS or kind.endswith(BIT_OF_WORD):
            return ()
        dev = self.t.devices.get(kind)
        if (dev is None or dev.unit_prefix or dev.kind == "counter" or kind not in o.kinds
                or (o.writes and dev.input) or (dev.width16_only and spec.width == 32)):
            return ()
        e = self.extent(spec, o, Operand(kind, number=dev.lo))
        spans = [(dev.lo, dev.hi - e + 1)]
        allowed = o.allowed(kind)
        if allowed:
            spans = _intersect(spans, allowed)
        narrow = o.devices32 if spec.width == 32 else o.devices16
        if narrow:
            spans = _intersect(spans, (narrow,))
        cut = list(o.forbid16) if spec.width == 16 else []
        for a in dev.areas:  # the areas check_areas has something to say about
            if a.write in ("reserved", "absent") or (a.write in ("nc", "system") and o.writes):
                cut.append((a.lo - e + 1, a.hi))
        for lo, hi in cut:
            spans = [piece for s_lo, s_hi in spans
                     for piece in ((s_lo, min(s_hi, lo - 1)), (max(s_lo, hi + 1), s_hi)) if piece[0] <= piece[1]]
        return tuple(spans)

    def unit_word_ok(self, spec: InstrSpec, o: OperandSpec, op: Operand, dev, w) -> bool:
        """A unit word (VS UnG) names its unit (U1G3, not G3), a unit of the model, and stands
        only where an application instruction takes its `like` device (docs/vs.md)."""
        lo, hi = dev.units
        name = f"{dev.unit_prefix}n{dev.name}"
        if not op.unit:
            self.report(w, "E203", f"{w.text!r}: {dev.name} is written with its unit: {name} "
                        f"({dev.unit_prefix}1{dev.name}{op.number}, {dev.section})")
            return False
        if hi < lo:
            self.report(w, "E205", f"{w.text}: there are no {name} units on model {self.t.model} ({dev.section})")
            return False
        if not lo <= op.unit_number <= hi:
            self.report(w, "E205", f"{w.text}: unit {op.unit} outside {dev.unit_prefix}{lo}-{dev.unit_prefix}{hi}"
                        + (f" on model {self.t.model}" if self.t.model else ""))
            return False
        if spec.api is None or dev.like not in o.kinds:
            self.report(w, "E204", f"{spec.mnemonic} operand {o.role} cannot be {name} buffer memory {w.text}",
                        f"{name} stands where an application instruction takes {dev.like} ({dev.section})")
            return False
        return True

    def extent(self, spec: InstrSpec, o: OperandSpec, op: Operand) -> int:
        dev = self.t.devices[op.device]
        if dev.kind in ("bit",) or op.is_bit_of_word or spec.cls in ("load", "and", "or") and dev.kind in ("timer", "counter") \
                and spec.api is None:
            return o.bits
        words = o.words[1] if spec.width == 32 else o.words[0]
        if dev.kind == "pointer":
            return 1
        if dev.kind == "counter" and self.t.is_counter32(op.number):
            return max(1, words // 2)  # C200-C255 / C64-C79 hold 32 bits each (DMUL D: 4 words, 2 counters)
        if op.kind in ("V", "Z"):
            # a 32-bit V/Z operand is one index register (its pair); a result longer than the
            # form's width (MUL D: 2 words, DMUL D: 4) goes into consecutive registers
            return 1 if words <= spec.width // 16 else words
        return words

    def check_span(self, spec: InstrSpec, o: OperandSpec, ops: list[Operand], w: _Arg, k: int) -> bool:
        """An operand that covers as many elements as another operand counts (`span`: DECO D
        2^n bits): when the count is a constant and the operand a device as written, its last
        element must exist (E208). A count in a register or an index-modified operand is the
        run time's (the engine's fault, E604)."""
        role, rule = o.span
        op = ops[k]
        if op.is_const or op.index or op.unit or op.is_bit_of_word:
            return True
        value = spec.constant_count(o, ops)
        dev = self.t.devices.get(op.device)
        if dev is None or value is None:
            return True
        if o.span_kinds == "bit" and (dev.kind != "bit" or op.is_group):
            return True
        if value < 1 or value > 1 << 20:
            return True  # (its own range check says what is wrong with it)
        n = o.span_count(value) if rule != "2^n" or value <= 16 else 1 << 17
        if op.is_group:
            size = n * 4 * op.digits
        elif op.kind in ("V", "Z"):  # a block of index registers is consecutive registers
            size = n * (o.words[1] if spec.width == 32 else o.words[0])
        else:
            size = n * self.extent(spec, o, op)
        last = op.number + size - 1
        if last <= dev.hi:
            return True
        what = f"{role} = {value}" + (f", {rule.replace('n', role)} = {n}" if rule != "n" else "")
        self.report(w, "E208", f"{w.text} would occupy {dev.name_of(op.number)}-{dev.name_of(last)}, past "
                    f"{dev.name_of(dev.hi)}: {what} (the instruction covers that many, {spec.section})")
        return False

    def check_const(self, w, spec, o: OperandSpec, op: Operand, all_ops) -> bool:
        if op.is_float:
            fmax = self.t.settings.get("f_max", 3.4028234e38)  # default: IEEE-754 single precision
            dec = self.t.settings.get("f_decimals", 99)
            if abs(op.value) > fmax or op.decimals > dec:
                self.report(w, "E206", f"{op.kind} constant {w.text} outside +-{fmax}"
                            + (f" with at most {dec} decimals" if dec < 99 else ""))
                return False
            return True
        if op.kind == "$":
            return True
        rng = (o.range32 if spec.width == 32 else o.range16)
        if rng is None and op.kind == "H":  # hex constants are the width's bit patterns
            rng = (0, 0xFFFFFFFF if spec.width == 32 else 0xFFFF)
        rng = rng or self.t.krange(spec.width)
        if not rng[0] <= op.value <= rng[1]:
            self.report(w, "E206", f"{spec.mnemonic} operand {o.role}: {w.text} outside K{rng[0]}..K{rng[1]}"
                        + (f" ({spec.section})" if o.range16 or o.range32 else ""))
            return False
        if o.word_range and o.word_range_of:
            k = next(i for i, s in enumerate(spec.operands) if s.role == o.word_range_of)
            other = all_ops[k]
            if not other.is_const and not other.is_group and self.t.devices[other.device].kind != "bit":
                if not o.word_range[0] <= op.value <= o.word_range[1]:
                    self.report(w, "E216", f"{spec.mnemonic} n must be K{o.word_range[0]}-K{o.word_range[1]} "
                             f"when {o.word_range_of} is a word device")
                    return False
        return True

    def check_areas(self, w, o: OperandSpec, dev, first: int, last: int) -> None:
        for a in dev.areas:  # areas do not overlap
            if a.hi < first or a.lo > last or a.write in ("ok", "signals"):  # signals: check/signals.py
                continue
            if a.write == "absent":
                self.report(w, "E205", f"{w.text}: {dev.name_of(a.lo)}-{dev.name_of(a.hi)} do not exist ({a.name})")
            elif a.write == "system" and o.writes:
                self.report(w, "W212", f"{w.text} is read-only: the system writes it ({a.name})")
            elif a.write == "reserved":
                self.report(w, "W213", f"{w.text} lies in the {a.name} area {dev.name}{a.lo}-{dev.name}{a.hi}")
            elif a.write == "nc" and o.writes:
                self.report(w, "W212", f"{w.text} is written by the NC ({a.name} {dev.name}{a.lo}-{dev.name}{a.hi})")

    def check_constraints(self, spec: InstrSpec, ops: list[Operand], args: list[_Arg]) -> bool:
        ok = True
        if len(ops) == len(args):
            for k, o in enumerate(spec.operands):
                if o.span is not None and k < len(ops):
                    ok = self.check_span(spec, o, ops, args[k], k) and ok
            for k, code, msg in constraint_problems(self.t, spec, ops, [a.text for a in args]):
                self.report(args[k], code, msg)
                ok = ok and not code.startswith("E")
        if "same-kind" in spec.constraints and len(ops) >= 2 and ops[0].kind != ops[1].kind:
            self.report(args[1], "E214", f"{spec.mnemonic} range ends must be one device kind "
                     f"({ops[0].kind} and {ops[1].kind})")
            ok = False
        if ok and "no-counter-width-mix" in spec.constraints and ops[0].kind == "C":
            a, b = sorted((ops[0].number, ops[1].number))
            if self.t.is_counter32(a) != self.t.is_counter32(b):
                self.report(args[1], "E214", f"{spec.mnemonic} cannot mix 16-bit and 32-bit counters")
                ok = False
        if ok and "ascending" in spec.constraints and ops[0].kind == ops[1].kind \
                and not (ops[0].index or ops[1].index) and ops[0].number > ops[1].number:
            self.report(args[1], "W220", f"{spec.mnemonic} {args[0].text} {args[1].text}: the first "
                        f"number is above the last, so only {args[0].text} is reset ({spec.section})")
        return self.check_operand_relations(spec, ops, args) and ok

    def check_operand_relations(self, spec: InstrSpec, ops: list[Operand], args: list[_Arg]) -> bool:
        """Relations between operands a page states (VS 6-3 SMOV, BMOV; 6-5 rotate and shift):
        a Kn size the instruction needs, counts that bound each other, operands of one
        attribute and size. Only constants and devices as written are judged."""
        ok = True
        rules = spec.constraints
        if "full-width-kn" in rules and ops[0].is_group:
            need = 8 if spec.width == 32 else 4
            if ops[0].digits != need:
                self.report(args[0], "E220", f"{spec.mnemonic} takes K{need}{ops[0].device} "
                            f"(a whole {spec.width}-bit word), not {args[0].text} ({spec.section})")
                ok = False

        def const(k: int) -> int | None:
            o = ops[k] if k < len(ops) else None
            return int(o.value) if o is not None and o.kind in ("K", "H") and not o.index else None

        def bound(small: int, big: int, rel: str) -> None:
            nonlocal ok
            a, b = const(small), const(big)
            if a is not None and b is not None and a > b:
                names = [o.role for o in spec.operands]
                self.report(args[small], "E221", f"{spec.mnemonic} needs {names[small]} {rel} "
                            f"{names[big]}: {args[small].text} > {args[big].text} ({spec.section})")
                ok = False
        for rule, setting, taken in (("timer-preset", "timer_preset_range", 0),
                                     ("counter-preset", "counter16_preset_range", 1)):
            rng = self.t.settings.get(setting)
            v = const(1)
            if rule in rules and rng and v is not None and not rng[0] <= v <= rng[1]:
                self.report(args[1], "W221", f"preset {args[1].text} is outside K{rng[0]}-K{rng[1]}: "
                            f"the PLC takes it as K{taken} ({spec.section})")
        if "nonzero-divisor" in rules and const(1) == 0:  # VS 6-4 DIV: "當除數等于 0時，PLC認定為運算錯誤"
            self.report(args[1], "E206", f"{spec.mnemonic} by {args[1].text}: a divisor of 0 is an operation "
                        f"error, the CPU does not divide ({spec.section})")
            ok = False
        v = const(0)
        if "bcd-source" in rules and v is not None and any((v >> (4 * k)) & 0xF > 9 for k in range(spec.width // 4)):
            self.report(args[0], "E206", f"{spec.mnemonic} {args[0].text}: not a BCD value, an operation error "
                        f"({spec.section})")
            ok = False
        if "n2-within-n1" in rules:  # SFTR/SFTL/WSFR/WSFL n2 = 1-n1
            bound(3, 2, "<=")
        if "smov-digits" in rules:  # SMOV m2 = 1-m1, n = m2-4
            bound(2, 1, "<=")
            bound(2, 4, "<=")
        if "same-kn" in rules or "same-kn-bits" in rules:
            s, d = ops[0], ops[1]
            if s.is_group and d.is_group and s.digits != d.digits:
                self.report(args[1], "E222", f"{spec.mnemonic} needs one Kn size for S and D: "
                            f"{args[0].text} and {args[1].text} ({spec.section})")
                ok = False
            elif "same-kn" in rules and not s.is_const and s.is_group != d.is_group:
                self.report(args[1], "E222", f"{spec.mnemonic} needs S and D both word devices or both "
                            f"Kn bit groups: {args[0].text} and {args[1].text} ({spec.section})")
                ok = False
        return ok

    def steps(self, spec: InstrSpec, ops) -> int:
        if spec.short_steps and ops or spec.op in self.step_rule_ops:
            return self.t.instr_steps(spec, ops)
        return spec.steps

    def step_number(self, st: Statement) -> None:
        """W107 where a leading step number disagrees: the first against the computed address,
        each later one by its distance from the previous number (the steps of the lines between),
        so one instruction counted otherwise is one warning, not one on every line after it."""
        number = int(st.step.text)
        last, self.numbered = self.numbered, (number, self.addr, st.line)
        if last is None:
            if number != self.addr:
                self.err(st.line, st.step, "W107", f"step number {st.step.text} but the computed address is {self.addr}")
            return
        said, computed = number - last[0], self.addr - last[1]
        if said != computed:
            self.err(st.line, st.step, "W107", f"step number {st.step.text}: the lines from step {last[0]} (line "
                     f"{last[2]}) are {said} steps by the numbering, {computed} by target {self.t.name}'s step "
                     f"counts (computed address {self.addr})")

    def emit(self, st: Statement, spec: InstrSpec, ops, texts, table=(), steps: int | None = None) -> None:
        if steps is None:
            steps = self.steps(spec, ops)
        if st.step is not None:
            self.step_number(st)
        col = st.name.col
        self.module.instrs.append(Instr(spec, ops, texts, steps, self.addr, self.path, st.line, col, table))
        self.addr += steps


def _table_kinds(t: Target):
    """check/tables.py's table_kinds; the module is imported at the first `.table` row: most
    programs have none, and its dataclasses cost every start of `mlc check` a millisecond or
    two (issue 19)."""
    from mlctool.check.tables import table_kinds

    return table_kinds(t)


def _made(res: tuple, written: tuple[str, ...]) -> tuple | None:
    """What the Instr of a line resolved as `res` is made of, (spec, operands, operand texts,
    steps, table), when the line resolved without a word; else None."""
    spec, operands, table, ok, problems, steps = res
    if problems or not ok or spec is None:
        return None
    n = len(operands)
    return spec, operands, written if len(written) == n else written[:n], steps, table


def _no_plain_line(name: str, texts: tuple[str, ...]) -> None:
    """plain_line with the shortcuts off: every line takes resolved()'s whole way."""
    return None


_HINTS: dict[tuple[str, str | None, str], tuple[str, tuple[str, ...]]] = {}


def unknown_instruction_hint(t: Target, name: str) -> tuple[str, tuple[str, ...]]:
    """What to say about an unknown mnemonic: (a "; did you mean X?" for the message, notes).
    Computed once per target and spelling (a file of 100k bad lines asks once per name)."""
    key = (t.name, t.model, name)
    hint = _HINTS.get(key)
    if hint is None:
        if len(_HINTS) > 4096:
            _HINTS.clear()
        hint = _HINTS[key] = _unknown_instruction_hint(t, name)
    return hint


def _unknown_instruction_hint(t: Target, name: str) -> tuple[str, tuple[str, ...]]:
    # another family's mnemonic (TMR on VS): the family's note, then the target's form written
    # out; else the right spelling, the missing pulse form, or that form alone
    family = _family_hint(t, name)
    notes = () if family else _spelling_hint(t, name) or _pulse_hint(t, name)
    notes = notes or family + _form_hint(t, name)
    if notes:
        return "", notes
    from mlctool.suggest import did_you_mean

    return did_you_mean(name, [*t.instructions, *t.variants, *t.unavailable], cutoff=0.65), ()


def _form_hint(t: Target, name: str) -> tuple[str, ...]:
    """TMR/CNT (NC5's timer and counter instructions) on a target that drives its timers and
    counters with another mnemonic (VS: `OUT T0 K10`, `OUT C0 K3`): the target's form of the
    same routine (its `op`), with example operands, instead of a near spelling (TTMR, INT)."""
    forms = [s for specs in t.variants.values() for s in specs] + list(t.instructions.values())
    found = [s for s in forms if s.op == name.lower() and s.mnemonic != name and s.operands]
    if not found:
        return ()
    s = found[0]
    example = " ".join([s.mnemonic] + [_example_operand(o) for o in s.operands])
    return (f"target {t.name} writes {name}'s instruction as `{example}` ({s.section})",)


def _example_operand(o) -> str:
    """A written operand of an operand spec: a constant where it takes one, else its first
    device kind numbered 0."""
    return "K10" if "K" in o.kinds else f"{sorted(o.kinds)[0]}0"


def _pulse_hint(t: Target, name: str) -> tuple[str, ...]:
    """MOVP on a target without P (pulse) forms (NC5, manual 3.2.4): say what it offers instead."""
    base = t.instructions.get(name[:-1]) if name.endswith("P") else None
    if base is None or base.cls != "output" or any(s.pulse for s in t.instructions.values()):
        return ()
    edges = [s.mnemonic for s in t.instructions.values() if s.op == "contact_rise"]
    relays = [s.mnemonic for s in t.instructions.values() if s.op == "pls"]
    where = t.settings.get("continuous_execution_section")
    offer = "/".join(edges) + (f" or a {'/'.join(relays)} relay" if relays else "")
    return (f"{t.title} has no P (pulse) forms: {base.mnemonic} runs on every scan while its condition is on"
            + (f" (manual {where})" if where else "")
            + f"; to run it once per rising edge, drive it with {offer}",)


class OperandRules:
    """The checker's operand rules (kinds, device ranges, index registers, constant ranges,
    cross-operand constraints) for operands that arrive resolved: an object file read back
    (asm/objfile.py) must hold nothing `mlc check` would refuse."""

    def __init__(self, target: Target):
        self._r = _Resolver(ParsedFile("<object>", [], [], []), target)
        self._seen: dict = {}  # (form, operands) -> errors: programs repeat a lot

    def errors(self, spec: InstrSpec, operands: tuple[Operand, ...]) -> list[str]:
        """The E-level problems of `operands` as operands of `spec` (W-level ones are kept)."""
        key = (id(spec), operands)
        hit = self._seen.get(key)
        if hit is None:
            hit = self._seen[key] = self._errors(spec, operands)
        return hit

    def _errors(self, spec: InstrSpec, operands: tuple[Operand, ...]) -> list[str]:
        r = self._r
        r._problems = []
        ops = list(operands)
        args = [_Arg(k, str(op)) for k, op in enumerate(ops)]
        ok = all([r.check_operand(spec, o, op, a, ops)
                  for o, op, a in zip(spec.operands, ops, args, strict=True)])
        if ok:
            r.check_constraints(spec, ops, args)
        return [msg for _idx, code, msg, _notes in r._problems if code.startswith("E")]


def _family_hint(t: Target, name: str) -> tuple[str, ...]:
    """Delta DVP's TMR T0 K10 (or FX's DRVI) in IL for the VS: the target's instruction of that
    function (targets/<name>/specials.toml `mnemonics`), not the nearest spelling (TTMR)."""
    from mlctool.targetapi.specials import families

    for fam in families(t.name).values():
        if name in fam.mnemonics:
            return (f"{name} is {fam.title}'s; target {t.name} writes it {fam.mnemonics[name]} with the same operands "
                    f"(`mlc import --from {'delta' if fam.name == 'dvp' else 'gxworks2'}` rewrites an export)",)
    return ()


def _spelling_hint(t: Target, name: str) -> tuple[str, ...]:
    """DLD>= on a target that writes the 32-bit form LDD>= (FX family): name the right one."""
    if not name.startswith("D"):
        return ()
    short = t.instructions.get(name[1:])
    if short is None or short.api is None:
        return ()
    for s in t.instructions.values():
        if s.api == short.api and s.width == 32 and s.cls == short.cls and s.pulse == short.pulse \
                and s.mnemonic != name:
            return (f"the 32-bit form of {short.mnemonic} is written {s.mnemonic} on target {t.name}",)
    return ()


def _device_name(t: Target, dev, number: int) -> str:
    """As the manual writes it: X10 for an octal ordinal, IHC0 for an interrupt pointer's I number."""
    if dev.name == "I":
        p = pointer_numbered(number, t)
        if p is not None:
            return p.name
    return dev.name_of(number)


def _intersect(spans, limits) -> list[tuple[int, int]]:
    return [(max(a, c), min(b, d)) for a, b in spans for c, d in limits if max(a, c) <= min(b, d)]


_VALUED = frozenset({"K", "H"})  # constants plain_line judges by their value
_ORDINAL = {1: "first", 2: "second", 3: "third", 4: "fourth", 5: "fifth", 6: "sixth", 7: "seventh"}


def _kind_name(op: Operand) -> str:
    if op.kind in ("K", "H"):
        return f"a {op.kind} constant"
    if op.is_float:
        return f"an {op.kind} constant"
    if op.kind == "$":
        return "a string constant"
    if op.is_bit_of_word:
        return f"a bit of a {op.device} word"
    if op.kind in GROUP_KINDS:
        return f"a bit group {op.kind}"
    return f"{op.kind} device"


def resolve(parsed: ParsedFile, target: Target, predefined: dict[str, str] | None = None,
            names: dict[str, int] | None = None, caches: ResolverCaches | None = None
            ) -> tuple[Module, list[Diagnostic]]:
    """`predefined`: device symbols every module starts with (mlc.toml [symbols]); `names`:
    the file's named labels -> P numbers (check/labels.py); `caches`: kept from an earlier
    resolution of the file with the same target tables and names (ResolverCaches)."""
    r = _Resolver(parsed, target, names, caches)
    r.module.symbols.update(predefined or {})
    return r.run()
