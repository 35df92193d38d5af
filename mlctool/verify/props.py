"""Property files (`*.props`, docs/verify.md): what `mlc verify` proves of a program, and
the assumptions about its inputs it may make. Errors are diagnostics with line and column
(E700 syntax, E701 unknown device, E702 contradictory assumptions), never exceptions.

A file reads like a stimulus file: one statement a line, `#` comments, devices named as
in stimulus files (`X0`, `D0`, `T0:w`, `K4M0`) or by the program's symbols (`.define`,
mlc.toml `[symbols]`).
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

from mlctool.diagnostics import Diagnostic, Span, diag
from mlctool.limits import long_number, too_long_message
from mlctool.sim.state import DeviceView, NameError_, parse_device_name
from mlctool.sim.stimulus.quantities import StimError, parse_time
from mlctool.sim.stimulus.stimulus import parse_value
from mlctool.syntax.source import read_source
from mlctool.targetapi.model import Target

KINDS = ("never", "always", "response", "reachable", "stable")
MAX_HOLD = 10_000  # scans an input may be held for / a response may take (bounded search)
_TOKEN = re.compile(r"\s*(?:(?P<op>->|<=|>=|!=|[=<>(){},])|(?P<word>(?:[^\s=<>!(){},-]|-(?!>))+))")
_COMMENT = re.compile(r"(?:^|(?<=\s))#.*")
_CMP = ("=", "!=", "<", "<=", ">", ">=")


class PropError(ValueError):
    """A problem at one token: E700 unless `code` says otherwise."""

    def __init__(self, message: str, col: int, length: int = 1, code: str = "E700"):
        super().__init__(message)
        self.message, self.col, self.length, self.code = message, col, length, code


# ------------------------------------------------------------------ expressions

@dataclass(frozen=True)
class Atom:
    """`DEV` (a bit, true when On; a word, true when not 0), `DEV op VALUE|DEV`, `DEV=LO..HI`,
    `DEV in {A, B}`."""

    view: DeviceView
    op: str  # "bit" | = != < <= > >= | "range" | "set"
    value: object = None  # int/float, a DeviceView (compare two devices), (lo, hi), or a frozenset
    text: str = ""
    col: int = 1


@dataclass(frozen=True)
class Not:
    arg: object


@dataclass(frozen=True)
class And:
    args: tuple


@dataclass(frozen=True)
class Or:
    args: tuple


@dataclass(frozen=True)
class Const:
    value: bool


def atoms(e) -> list[Atom]:
    """The atoms of an expression, left to right."""
    if isinstance(e, Atom):
        return [e]
    if isinstance(e, Not):
        return atoms(e.arg)
    if isinstance(e, And | Or):
        return [a for x in e.args for a in atoms(x)]
    return []


def views_of(e) -> list[DeviceView]:
    out: list[DeviceView] = []
    for a in atoms(e):
        for v in (a.view, a.value if isinstance(a.value, DeviceView) else None):
            if v is not None and v not in out:
                out.append(v)
    return out


def holds(atom: Atom, read) -> bool:
    """The atom's truth with device values from `read(view)`."""
    x = read(atom.view)
    op, v = atom.op, atom.value
    if op == "bit":
        return x != 0
    if isinstance(v, DeviceView):
        v = read(v)
    if op == "range":
        return v[0] <= x <= v[1]
    if op == "set":
        return x in v
    return {"=": x == v, "!=": x != v, "<": x < v, "<=": x <= v, ">": x > v, ">=": x >= v}[op]


def evaluate(e, read) -> bool:
    if isinstance(e, Atom):
        return holds(e, read)
    if isinstance(e, Not):
        return not evaluate(e.arg, read)
    if isinstance(e, And):
        return all(evaluate(x, read) for x in e.args)
    if isinstance(e, Or):
        return any(evaluate(x, read) for x in e.args)
    return e.value


# ------------------------------------------------------------------ the file

@dataclass
class Property:
    kind: str  # never | always | response | reachable | stable
    line: int
    col: int
    text: str  # the statement as written
    name: str  # `name:` before it, else "line N"
    expr: object = None  # never/always/reachable/stable: the expression; response: the trigger
    response: object = None
    scans: int = 0  # response: within N scans; stable: for N scans
    time_us: int | None = None  # response `within TIME` (scans worked out for the scan time)

    def bad_expr(self):
        """always/never: the expression a violating state satisfies."""
        return self.expr if self.kind == "never" else Not(self.expr)


@dataclass
class Input:
    """An input the search chooses each scan: its view, its values, how it may change."""

    view: DeviceView
    values: tuple  # the values it may take
    constant: bool = False  # chosen at the first scan, kept
    hold: int = 1  # once changed, kept for at least this many scans
    line: int = 0
    col: int = 1


@dataclass
class Props:
    path: str
    lines: list[str]
    properties: list[Property] = field(default_factory=list)
    inputs: dict[DeviceView, Input] = field(default_factory=dict)  # declared (free/constant/range/...)
    constraints: list[tuple[object, int, int]] = field(default_factory=list)  # (expr, line, col) over inputs
    onehot: list[tuple[tuple[DeviceView, ...], int, int]] = field(default_factory=list)
    initial: list[tuple[DeviceView, int | float, int, int]] = field(default_factory=list)
    scan_us: int | None = None
    free_declared: bool = False  # an `assume free` line: only the inputs named are free


class _Parser:
    def __init__(self, path: str, text: str, target: Target, symbols: dict[str, str]):
        self.props = Props(path, text.split("\n"))
        self.target = target
        self.symbols = symbols
        self.upper = {k.upper(): v for k, v in symbols.items()}
        self.diags: list[Diagnostic] = []

    def run(self) -> Props:
        for no, raw in enumerate(self.props.lines, 1):
            body = _COMMENT.sub("", raw).rstrip()  # (`#` inside a name is no comment: DB#100)
            if not body.strip():
                continue
            long = long_number(body)
            if long:
                self.diags.append(diag(self.props.path, Span.at(no, long.start() + 1, len(long[0])), "E700",
                                       too_long_message(f"line {no}", len(long[0]))))
                continue
            try:
                self.line(no, body)
            except PropError as e:
                self.diags.append(diag(self.props.path, Span.at(no, e.col, e.length), e.code, e.message))
        return self.props

    # -- tokens
    def tokens(self, body: str) -> list[tuple[str, int]]:
        out, pos = [], 0
        while pos < len(body):
            m = _TOKEN.match(body, pos)
            if not m or m.end() == pos:
                if body[pos:].strip():
                    raise PropError(f"unexpected {body[pos:].strip()[0]!r}", pos + 1 + len(body[pos:]) - len(body[pos:].lstrip()))
                break
            tok = m["op"] or m["word"]
            out.append((tok, m.start(m.lastgroup) + 1))
            pos = m.end()
        return out

    def line(self, no: int, body: str) -> None:
        toks = self.tokens(body)
        name = ""
        first, col = toks[0]
        if first.endswith(":") and len(toks) > 1 and first[:-1].isidentifier():
            name, toks = first[:-1], toks[1:]
            first, col = toks[0]
        word = first.lower()
        if word == "scan":
            if len(toks) != 2:
                raise PropError("expected `scan PERIOD` (e.g. scan 10ms)", col, len(first))
            self.props.scan_us = self.time(toks[1], positive=True)
            return
        if word == "assume":
            if name:
                raise PropError("an assumption takes no name", 1)
            self.assume(no, toks[1:], col)
            return
        if word not in KINDS:
            from mlctool.suggest import did_you_mean

            raise PropError(f"{first!r} starts no statement (never, always, response, reachable, stable, assume, "
                            "scan)" + did_you_mean(first, (*KINDS, "assume", "scan"), "`"), col, len(first))
        prop = Property(word, no, col, body[col - 1:].strip(), name or f"line {no}")
        rest = toks[1:]
        if not rest:
            raise PropError(f"`{word}` needs an expression", col, len(first))
        if word == "response":
            arrow = next((k for k, (t, _) in enumerate(rest) if t == "->"), None)
            within = next((k for k, (t, _) in enumerate(rest) if t.lower() == "within"), None)
            if arrow is None or within is None or within < arrow:
                raise PropError("expected `response TRIGGER -> RESPONSE within N scans` (or `within TIME`)", col,
                                len(first))
            prop.expr = self.expr_of(rest[:arrow], rest[arrow][1])
            prop.response = self.expr_of(rest[arrow + 1:within], rest[within][1])
            prop.scans, prop.time_us = self.count(rest[within + 1:], rest[within], "within")
        elif word == "stable":
            at = next((k for k, (t, _) in enumerate(rest) if t.lower() == "for"), None)
            if at is None:
                raise PropError("expected `stable EXPR for N scans`", col, len(first))
            prop.expr = self.expr_of(rest[:at], rest[at][1])
            prop.scans, time_us = self.count(rest[at + 1:], rest[at], "for")
            if time_us is not None:
                raise PropError("`stable ... for` takes a number of scans (e.g. for 3 scans)", rest[at + 1][1])
            if prop.scans < 1:
                raise PropError("`stable ... for` needs at least 1 scan", rest[at + 1][1])
        else:
            prop.expr = self.expr_of(rest, len(body) + 1)
        self.props.properties.append(prop)

    def count(self, toks, after: tuple[str, int], word: str) -> tuple[int, int | None]:
        """`N scans` or a TIME (response only)."""
        if len(toks) == 2 and toks[1][0].lower() in ("scan", "scans") and toks[0][0].isdigit():
            n = int(toks[0][0])
            if n > MAX_HOLD:
                raise PropError(f"{n} scans: at most {MAX_HOLD:,}", toks[0][1], len(toks[0][0]))
            return n, None
        if len(toks) == 1 and word == "within":
            return 0, self.time(toks[0], positive=False)
        where = toks[0] if toks else after
        raise PropError(f"expected `{word} N scans`" + (" or a time (within 100ms)" if word == "within" else ""),
                        where[1], len(where[0]))

    def time(self, tok: tuple[str, int], positive: bool) -> int:
        try:
            us = parse_time(tok[0])
        except StimError as e:
            raise PropError(e.message, tok[1], len(tok[0])) from None
        if positive and us <= 0:
            raise PropError("the scan time must be positive", tok[1], len(tok[0]))
        return us

    # -- devices
    def view(self, tok: tuple[str, int]) -> DeviceView:
        text, col = tok
        operand = self.symbols.get(text) or self.upper.get(text.upper()) or text
        try:
            return parse_device_name(operand, self.target)
        except NameError_ as e:
            from mlctool.suggest import did_you_mean

            near = did_you_mean(text, self.symbols, "'") if self.symbols else ""
            raise PropError(f"{e}{near}" if text == operand else f"{text} ({operand}): {e}", col, len(text),
                            "E701") from None

    def value(self, tok: tuple[str, int], view: DeviceView):
        try:
            return parse_value(tok[0], view)
        except StimError as e:
            raise PropError(e.message, tok[1], len(tok[0])) from None

    # -- expressions: or > and > not > atom
    def expr_of(self, toks, end_col: int):
        if not toks:
            raise PropError("expected an expression", end_col)
        self.toks, self.k, self.end_col = toks, 0, end_col
        e = self.or_()
        if self.k < len(toks):
            t, c = toks[self.k]
            raise PropError(f"unexpected {t!r} after the expression", c, len(t))
        return e

    def peek(self) -> str:
        return self.toks[self.k][0].lower() if self.k < len(self.toks) else ""

    def take(self) -> tuple[str, int]:
        if self.k >= len(self.toks):
            raise PropError("the expression ends too soon", self.end_col)
        self.k += 1
        return self.toks[self.k - 1]

    def or_(self):
        args = [self.and_()]
        while self.peek() == "or":
            self.take()
            args.append(self.and_())
        return args[0] if len(args) == 1 else Or(tuple(args))

    def and_(self):
        args = [self.not_()]
        while self.peek() == "and":
            self.take()
            args.append(self.not_())
        return args[0] if len(args) == 1 else And(tuple(args))

    def not_(self):
        if self.peek() == "not":
            self.take()
            return Not(self.not_())
        return self.atom()

    def atom(self):
        t, c = self.take()
        low = t.lower()
        if t == "(":
            e = self.or_()
            if self.peek() != ")":
                raise PropError("expected `)`", self.toks[self.k][1] if self.k < len(self.toks) else self.end_col)
            self.take()
            return e
        if low in ("true", "false"):
            return Const(low == "true")
        if low in ("and", "or", "not", "in") or t in _CMP or t in ("->", ")", "{", "}", ","):
            raise PropError(f"expected a device, not {t!r}", c, len(t))
        view = self.view((t, c))
        op = self.peek()
        if op in _CMP:
            self.take()
            rt, rc = self.take()
            if rt in _CMP or rt in ("->", "(", ")", "{", "}", ","):
                raise PropError(f"expected a value or a device after {op!r}, not {rt!r}", rc, len(rt))
            text = f"{t}{op}{rt}"
            if ".." in rt and op == "=":
                lo, hi = rt.split("..", 1)
                a, b = self.value((lo, rc), view), self.value((hi, rc + len(lo) + 2), view)
                if a > b:
                    raise PropError(f"empty range {rt}", rc, len(rt))
                return Atom(view, "range", (a, b), text, c)
            if rt[:1].isdigit() or rt[:1] in "-+." or (rt[:1] in "KkHh" and rt[1:2].isdigit()
                                                       and not self._is_name(rt)):
                return Atom(view, op, self.value((rt, rc), view), text, c)
            return Atom(view, op, self.view((rt, rc)), text, c)
        if op == "in":
            self.take()
            lo_tok = self.take()
            if lo_tok[0] == "{":
                values = []
                while True:
                    values.append(self.value(self.take(), view))
                    nxt = self.take()
                    if nxt[0] == "}":
                        break
                    if nxt[0] != ",":
                        raise PropError("expected `,` or `}` in a set", nxt[1], len(nxt[0]))
                return Atom(view, "set", frozenset(values), f"{t} in {{{', '.join(map(str, sorted(values)))}}}", c)
            if ".." not in lo_tok[0]:
                raise PropError("expected LOW..HIGH or {A, B, ...} after `in`", lo_tok[1], len(lo_tok[0]))
            lo, hi = lo_tok[0].split("..", 1)
            a, b = self.value((lo, lo_tok[1]), view), self.value((hi, lo_tok[1] + len(lo) + 2), view)
            if a > b:
                raise PropError(f"empty range {lo_tok[0]}", lo_tok[1], len(lo_tok[0]), "E702")
            return Atom(view, "range", (a, b), f"{t} in {lo_tok[0]}", c)
        return Atom(view, "bit", None, t, c)

    def _is_name(self, text: str) -> bool:
        """K4M0 is a bit group, K10 a value."""
        return text in self.symbols or bool(re.fullmatch(r"[Kk][1-8][A-Za-z][0-9]+", text))

    # -- assumptions
    def assume(self, no: int, toks, col: int) -> None:
        if not toks:
            raise PropError("`assume` needs what it assumes (free, constant, onehot, hold, initial, DEV=V, "
                            "DEV in LOW..HIGH, or an expression over inputs)", col, 6)
        form, fcol = toks[0][0].lower(), toks[0][1]
        p = self.props
        if form in ("free", "constant"):
            p.free_declared |= form == "free"
            for t in toks[1:]:
                view = self.input_view(t)
                inp = self.declare(view, no, t[1])
                inp.constant |= form == "constant"
            if len(toks) == 1:
                raise PropError(f"`assume {form}` needs devices", fcol, len(toks[0][0]))
        elif form == "onehot":
            views = tuple(self.input_view(t) for t in toks[1:])
            if len(views) < 2:
                raise PropError("`assume onehot` needs two devices or more", fcol, len(toks[0][0]))
            for v, t in zip(views, toks[1:], strict=True):
                if v.view != "bit":
                    raise PropError(f"{t[0]}: onehot takes bits", t[1], len(t[0]))
                self.declare(v, no, t[1])
            p.onehot.append((views, no, fcol))
        elif form == "hold":
            at = next((k for k, (t, _) in enumerate(toks) if t.lower() == "for"), None)
            if at is None or at == 1:
                raise PropError("expected `assume hold DEV ... for N scans`", fcol, len(toks[0][0]))
            n, _ = self.count(toks[at + 1:], toks[at], "for")
            if n < 1:
                raise PropError("hold for at least 1 scan", toks[at + 1][1])
            for t in toks[1:at]:
                inp = self.declare(self.input_view(t), no, t[1])
                inp.hold = max(inp.hold, n)
        elif form == "initial":
            if len(toks) < 2 or len(toks) % 3 != 1:
                raise PropError("expected `assume initial DEV=VALUE ...`", fcol, len(toks[0][0]))
            for k in range(1, len(toks), 3):
                (d, dc), (eq, ec), v = toks[k:k + 3]
                if eq != "=":
                    raise PropError("expected DEV=VALUE", ec, len(eq))
                view = self.view((d, dc))
                value = self.value(v, view)
                for other, was, line, _ in p.initial:
                    if other == view and was != value:
                        raise PropError(f"{d}: initial {value} contradicts {was} on line {line}", dc, len(d), "E702")
                p.initial.append((view, value, no, dc))
        else:
            e = self.expr_of(toks, toks[-1][1] + len(toks[-1][0]))
            if isinstance(e, Atom) and e.op in ("=", "range", "set") and not isinstance(e.value, DeviceView):
                view = self.input_view((toks[0][0], toks[0][1]), any_word=True)
                inp = self.declare(view, no, toks[0][1])
                values = (e.value,) if e.op == "=" else (tuple(range(e.value[0], e.value[1] + 1))
                                                         if e.op == "range" else tuple(sorted(e.value)))
                if isinstance(e.value, tuple) and e.value[1] - e.value[0] > 65535:
                    raise PropError("a range of at most 65536 values", toks[0][1], len(toks[0][0]))
                kept = values if inp.values is _UNSET else tuple(v for v in inp.values if v in values)
                if not kept:
                    raise PropError(f"{toks[0][0]}: no value left ({e.text} contradicts an earlier assumption)",
                                    toks[0][1], len(toks[0][0]), "E702")
                inp.values = kept
            else:
                for v in views_of(e):
                    self.input_view((v.name, fcol))
                    self.declare(v, no, fcol)
                p.constraints.append((e, no, fcol))

    def input_view(self, tok: tuple[str, int], any_word: bool = False) -> DeviceView:
        """An input the search may choose: an input bit (X) or, with a range or set, a word."""
        view = self.view(tok)
        dev = self.target.devices.get(view.gdev if view.view == "group" else view.kind)
        if view.view == "bit" and dev is not None and dev.input:
            return view
        if any_word and view.view in ("w", "h", "d", "group") and view.kind not in "TC":
            return view
        what = "an input bit" + (" or a word given a range or set" if not any_word else " or a word")
        raise PropError(f"{tok[0]} is not {what} (the search chooses inputs; other devices follow the program)",
                        tok[1], len(tok[0]))

    def declare(self, view: DeviceView, no: int, col: int) -> Input:
        inp = self.props.inputs.get(view)
        if inp is None:
            inp = self.props.inputs[view] = Input(view, _BITS if view.view == "bit" else _UNSET, line=no, col=col)
        return inp


_BITS = (0, 1)
_UNSET = ()  # a word input before its range/set


def parse_props_text(path: str, text: str, target: Target,
                     symbols: dict[str, str] | None = None) -> tuple[Props, list[Diagnostic]]:
    p = _Parser(path, text, target, symbols or {})
    props = p.run()
    for view, inp in props.inputs.items():
        if view.view != "bit" and not inp.values:
            p.diags.append(diag(path, Span.at(inp.line, inp.col, len(view.name)), "E700",
                                f"{view.name}: a word input needs its values (assume {view.name} in LOW..HIGH)"))
    return props, p.diags


def load_props(path: str, target: Target, symbols: dict[str, str] | None = None
               ) -> tuple[Props | None, list[Diagnostic]]:
    src, diags = read_source(path)
    if src is None:
        return None, diags
    return parse_props_text(path, src.text, target, symbols)
