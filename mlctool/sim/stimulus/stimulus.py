"""Stimulus files (docs/stimulus.md): timed inputs, expectations, forces, power cycles,
device models, the scan period and the run length. Errors are diagnostics with line and
column (E601 syntax, E602 unknown device), never exceptions.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from fractions import Fraction

from mlctool.diagnostics import Diagnostic, Span, diag
from mlctool.limits import integer, long_number, real, too_long_message
from mlctool.sim.signals import SIGNAL
from mlctool.sim.state import DeviceView, NameError_, parse_device_name, to_f32
from mlctool.sim.stimulus.quantities import (
    MAX_SCANS,
    MAX_TIME_US,
    TIME_BOUND,
    StimError,
    parse_frequency,
    parse_time,
)
from mlctool.syntax.source import read_source
from mlctool.targetapi.model import Target

_TOKEN = re.compile(r"\S+")
_SCAN_NO = re.compile(r"#[0-9]+")
# Every line of a text, as (lead, when, gap, item) of the common line `#250 X0=1` / `100ms X0=1`
# (Parser.set_line), four empty strings for any other line: one findall per file, one tuple per
# line of text.split("\n") (`.` and the classes below match no \n; `$` is before each \n and at
# the end). Every part is too short to hold a number of more than MAX_DIGITS digits
# (mlctool/limits.py), so long_number() cannot find one.
_LINES = re.compile(r"^(?:([ \t]*)(#[0-9]{1,9}|[0-9][0-9.]{0,14}[A-Za-z]{1,3})([ \t]+)"
                    r"([A-Za-z][^\s=#]{0,15}=[^\s=#]{1,16})[ \t]*|.*)$", re.M)
_RUN_SCANS = re.compile(r"run[ \t]+#([0-9]{1,9})[ \t]*")  # the usual last line
KEYWORDS = ("expect", "force", "release", "power-cycle")
DIRECTIVES = ("scan", "run", "model", "port")  # the words that may start a line instead of a time


@dataclass(frozen=True, slots=True)
class Check:
    """One `DEV=V`, `DEV!=V` or `DEV=LO..HI` of an expect line."""

    view: DeviceView
    op: str  # "=" | "!=" | "range"
    value: int | float
    high: int | float | None
    text: str
    col: int

    def holds(self, actual: int | float) -> bool:
        if self.op == "range":
            return self.value <= actual <= self.high
        equal = (actual == self.value) if not (self.view.is_float and math.isnan(self.value)) \
            else math.isnan(actual)
        return equal if self.op == "=" else not equal

    def expected_text(self) -> str:
        if self.op == "range":
            return f"{self.value}..{self.high}"
        return ("!= " if self.op == "!=" else "") + str(self.value)


@dataclass(slots=True)
class Event:
    scan: int | None  # "#250" form
    time_us: int | None
    kind: str  # set | expect | alarm | force | release | power
    line: int
    col: int
    text: str
    # tuples (none by default; a set line's shares its NameCache entry): a batch holds ~20
    # events a file for the whole run, and lists (two per event) were half its objects the
    # garbage collector walks
    assigns: tuple[tuple[DeviceView, int | float], ...] = ()
    checks: tuple[Check, ...] = ()
    alarm: str = ""
    port: str = ""  # receive: the PLC's serial port (CP1...) and the bytes sent to it
    data: bytes = b""

    def scan_index(self, period_us: int) -> int:
        """Events at time t act at the first scan that starts at or after t."""
        return self.scan if self.scan is not None else -(-self.time_us // period_us)


@dataclass(slots=True)
class ModelSpec:
    kind: str
    params: dict[str, tuple[str, int]]  # key -> (value text, column)
    line: int
    col: int


# A set line as the parser keeps it until its Event is asked for (Stimulus.entries):
# (line, scan, time_us, col, when, item, assigns) -> Event(scan, time_us, "set", line, col,
# f"{when} {item}", assigns). A tuple costs a seventh of an Event to make; a batch of 1024
# files of 20 lines made 20 k Events that the bool lanes never read.
SetLine = tuple


@dataclass(slots=True)
class Stimulus:
    path: str
    lines: list[str]
    scan_us: int | None = None
    run_time_us: int | None = None
    run_scans: int | None = None
    # the events in line order, set lines possibly as SetLine tuples: read them as `events`
    entries: list[Event | SetLine] = field(default_factory=list)
    models: list[ModelSpec] = field(default_factory=list)
    ports: list = field(default_factory=list)  # serial_stim.PortSpec of `port CPn ...` lines
    compact: bool = False  # some entries are SetLine tuples

    @property
    def events(self) -> list[Event]:
        """The events in line order (the set lines kept as tuples made Events on first read)."""
        if self.compact:
            self.entries = [e if type(e) is not tuple else Event(e[1], e[2], "set", e[0], e[3], f"{e[4]} {e[5]}", e[6])
                            for e in self.entries]
            self.compact = False
        return self.entries

    def devices(self) -> set[DeviceView]:
        out: set[DeviceView] = set()
        for e in self.events:
            out.update(v for v, _ in e.assigns)
            out.update(c.view for c in e.checks)
        return out


def parse_value(text: str, view: DeviceView) -> int | float:
    """Value for a device view: decimal (optional K), H hex (raw pattern), float for :f."""
    t = text.strip()
    u = t.upper()
    if view.view == "bit" and u in ("ON", "OFF"):
        return 1 if u == "ON" else 0
    try:
        if u.startswith("H"):
            raw = integer(u[1:], 16)
            bits = view.width
            if raw >= 1 << bits:
                raise StimError(f"{t} does not fit {bits} bits")
            if view.is_float:
                from mlctool.sim.state import bits_f32
                return bits_f32(raw)
            signed = view.view in ("w", "d") and view.kind in "DVZ" or view.kind == "C" and view.view == "d"
            return raw - (1 << bits) if signed and raw >> (bits - 1) else raw
        if view.is_float:
            x = real(t[1:] if u.startswith("F") else t, finite=False)  # expect D0:f=inf
            return to_f32(x)
        v = integer(u[1:] if u.startswith("K") else u)
    except ValueError:
        kind = "a float" if view.is_float else "an integer (decimal, K10 or H0F)"
        raise StimError(f"{t!r} is not {kind} for {view.name}") from None
    lo, hi = _range(view)
    if not lo <= v <= hi:
        raise StimError(f"{view.name} takes {lo}..{hi}, not {v}")
    return v


def _range(view: DeviceView) -> tuple[int, int]:
    if view.view == "bit":
        return 0, 1
    if view.view == "group":
        n = 4 * view.digits
        return -(1 << (n - 1)), (1 << n) - 1
    if view.kind == "T" or view.view == "h" or (view.kind == "C" and view.view == "w"):
        return 0, 0xFFFF
    if view.view == "d":
        return -(1 << 31), (1 << 31) - 1
    return -32768, 32767


class NameCache:
    """Device names and assignments already read, for the stimulus files of one batch (one
    target): `M5` and `M5=1` are read once, not once per file. Only successes are kept, and a
    view or value depends on nothing but its text and the target, so a cached result is the
    one the parser would compute again."""

    def __init__(self, target: Target):
        self.target = target
        self.views: dict[str, DeviceView] = {}
        # `M5=1` of a set line -> the line's Event.assigns, ((view, value),), shared
        self.items: dict[str, tuple[tuple[DeviceView, int | float]]] = {}


class _Parser:
    def __init__(self, path: str, text: str, target: Target, cache: NameCache | None = None):
        self.text = text
        self.st = Stimulus(path, text.split("\n"))
        self.target = target
        self.diags: list[Diagnostic] = []
        self.last_time = 0
        if cache is None or cache.target is not target:
            cache = NameCache(target)
        self.views = cache.views
        self.items = cache.items

    def err(self, line: int, col: int, length: int, code: str, msg: str) -> None:
        self.diags.append(diag(self.st.path, Span.at(line, col, length), code, msg))

    def run(self) -> Stimulus:
        entries, items = self.st.entries, self.items
        self.st.compact = True  # (set lines are SetLine tuples)
        parts = _LINES.findall(self.text)
        for no, (raw, (lead, when, gap, item)) in enumerate(zip(self.st.lines, parts, strict=True), 1):
            if when:
                # the most common line of all, `#250 M5=1` with `M5=1` read before (NameCache),
                # inline: the Event set_line gives
                assign = items.get(item) if when[0] == "#" else None
                col = len(lead) + len(when) + len(gap) + 1
                if assign is not None and (scan := int(when[1:])) <= MAX_SCANS:
                    entries.append((no, scan, None, col, when, item, assign))
                    continue
                if self.set_line(no, when, col, item):
                    continue
            elif not raw:
                continue
            elif raw[0] == "r" and (run := _RUN_SCANS.fullmatch(raw)) and int(run[1]) <= MAX_SCANS:
                self.st.run_scans = int(run[1])  # `run #1000`, as line() reads it
                continue
            body = _strip_comment(raw)
            toks = [(m.group(), m.start() + 1) for m in _TOKEN.finditer(body)]
            if not toks:
                continue
            long = long_number(body)
            if long:  # bounded before any conversion (mlctool/limits.py): times, devices, values
                self.err(no, long.start() + 1, len(long[0]), "E601",
                         too_long_message(f"line {no}", len(long[0])))
                continue
            try:
                self.line(no, toks)
            except StimError as e:
                tok_text, col = toks[min(e.col_offset, len(toks) - 1)]
                self.err(no, col, len(tok_text), e.code, e.message)
        return self.st

    def line(self, no: int, toks: list[tuple[str, int]]) -> None:
        head = toks[0][0].lower()
        if head == "scan":
            self.need(toks, 2, "scan PERIOD, e.g. `scan 10ms`")
            us = self.at(1, lambda: parse_time(toks[1][0]))
            if us <= 0:
                raise StimError("the scan period must be positive", 1)
            self.st.scan_us = us
            return
        if head == "run":
            self.need(toks, 2, "run TIME or run #SCANS, e.g. `run 4s`")
            arg = toks[1][0]
            if arg.startswith("#"):
                self.st.run_scans = self.at(1, lambda: _scan_number(arg))
            else:
                self.st.run_time_us = self.at(1, lambda: parse_time(arg))
            return
        if head == "model":
            self.model(no, toks)
            return
        if head == "port":
            from mlctool.sim.stimulus.serial_stim import parse_port

            spec = parse_port(toks)
            if any(p.name == spec.name for p in self.st.ports):
                raise StimError(f"{spec.name}: one `port` line per port", 1)
            self.st.ports.append(spec)
            return
        when = toks[0][0]
        scan, time_us = None, None
        if when.startswith("#"):
            scan = _scan_number(when)
        elif when.startswith("+"):
            time_us = self.last_time + parse_time(when[1:])
            if time_us > MAX_TIME_US:  # relative times add up: the sum is bounded too
                raise StimError(f"{when!r} after {self.last_time} us is past the bound of virtual time, "
                                f"{TIME_BOUND}")
        else:
            try:
                time_us = parse_time(when)
            except StimError as e:  # `sacn 10ms`: a mistyped directive, not a bad time
                raise StimError(e.message + _near(when, DIRECTIVES), 0, e.code) from None
        if time_us is not None:
            self.last_time = time_us
        if len(toks) < 2:
            raise StimError("a time needs an action: DEV=VALUE, expect ..., force ..., release ..., "
                            "power-cycle")
        self.action(Event(scan, time_us, "set", no, toks[1][1], " ".join(t for t, _ in toks)), toks[1:])

    def set_line(self, no: int, when: str, col: int, item: str) -> bool:
        """The most common line, `#250 X0=1` or `100ms X0=1` (_LINES; `item` at column `col`),
        read without tokenizing: the same Event as line() gives, through the same view() and
        value(). False (nothing recorded) when any part is wrong: line() then reads it again
        and reports it."""
        try:
            if when[0] == "#":
                scan, time_us = int(when[1:]), None  # at most 9 digits (_LINES)
                if scan > MAX_SCANS:
                    return False
            else:
                scan, time_us = None, parse_time(when)
            assign = self.items.get(item)
            if assign is None:
                name, value = item.split("=", 1)
                view = self.view(name, 1)
                if view.kind.startswith(SIGNAL):
                    return False
                assign = self.items[item] = ((view, self.at(1, lambda: parse_value(value, view))),)
        except StimError:
            return False
        if time_us is not None:
            self.last_time = time_us
        self.st.entries.append((no, scan, time_us, col, when, item, assign))
        return True

    @staticmethod
    def at(offset: int, fn):
        try:
            return fn()
        except StimError as e:
            raise StimError(e.message, offset, e.code) from None

    @staticmethod
    def need(toks, n: int, form: str) -> None:
        if len(toks) != n:
            raise StimError(f"expected {form}", min(n, len(toks) - 1))

    def action(self, ev: Event, toks: list[tuple[str, int]]) -> None:
        word = toks[0][0].lower()
        off = 1  # token offset of toks[0] within the line
        if word == "power-cycle":
            if len(toks) > 1:
                raise StimError("power-cycle takes no arguments", off + 1)
            ev.kind = "power"
        elif word == "expect":
            if len(toks) < 2:
                raise StimError("expect needs DEV=VALUE items or `alarm NAME`", off)
            if toks[1][0].lower() == "alarm":
                if len(toks) != 3 or not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", toks[2][0]):
                    raise StimError("expected `expect alarm NAME`, e.g. expect alarm MLC_ARITH_ERROR", off + 1)
                ev.kind, ev.alarm = "alarm", toks[2][0].upper()
            else:
                ev.kind = "expect"
                ev.checks = tuple(self.check(t, col, off + 1 + k) for k, (t, col) in enumerate(toks[1:]))
        elif len(toks) > 1 and toks[1][0].lower() == "pulses":
            self.pulses(ev, toks, off)
        elif len(toks) > 1 and toks[1][0].lower() == "receive":
            from mlctool.sim.stimulus.serial_stim import parse_receive

            if ev.time_us is None:
                raise StimError("bytes arrive at a time (e.g. 20ms), not at a scan number", 0)
            ev.kind = "receive"
            ev.port, ev.data = parse_receive(toks, off)
        elif word == "release":
            if len(toks) < 2:
                raise StimError("release needs device names", off)
            ev.kind = "release"
            ev.assigns = tuple((self.view(t, off + 1 + k), 0) for k, (t, _) in enumerate(toks[1:]))
        else:
            items = toks
            if word == "force":
                ev.kind = "force"
                items = toks[1:]
                if not items:
                    raise StimError("force needs DEV=VALUE items", off)
                off += 1
            assigns = []
            for k, (t, _) in enumerate(items):
                if "=" not in t or t.startswith("="):
                    hint = _near(t, KEYWORDS) if k == 0 and word != "force" else ""  # `expcet X0=1`
                    after = _near(items[1][0], ("pulses", "receive")) if k == 0 and len(items) > 1 else ""
                    if after:  # `X0 puls 1kHz`
                        raise StimError(f"{items[1][0]!r}: expected DEV=VALUE, `pulses` or `receive`" + after,
                                        off + 1)
                    raise StimError(f"{t!r}: expected DEV=VALUE, expect, force, release or "
                                    "power-cycle" + hint, off + k)
                name, value = t.split("=", 1)
                view = self.view(name, off + k)
                if view.kind.startswith(SIGNAL):
                    raise StimError(f"{name}: a model signal is the device's own state: expect "
                                    "it, it cannot be set or forced", off + k, "E602")
                assigns.append((view, self.at(off + k, lambda v=value, w=view: parse_value(v, w))))
            ev.assigns = tuple(assigns)
        self.st.entries.append(ev)

    def pulses(self, ev: Event, toks: list[tuple[str, int]], off: int) -> None:
        """`X0 pulses 1kHz [until TIME | for TIME]`: a pulse train on an input (sim/hardware/pulses.py)."""
        form = "expected `DEV pulses FREQUENCY [until TIME | for TIME]`, e.g. X0 pulses 1kHz until 500ms"
        # `A/B pulses [-]FREQ`: an A/B phase pair (pulses.Quadrature); minus: B leads A
        names = toks[0][0].split("/")
        if len(names) > 2 or not all(names):
            raise StimError(f"{toks[0][0]}: expected DEV or an A/B pair (e.g. X0/X1)", off)
        views = [self.view(name, off) for name in names]
        for name, view in zip(names, views):
            dev = self.target.devices.get(view.kind)
            if view.view != "bit" or dev is None or not dev.input:
                raise StimError(f"{name}: pulse trains drive inputs (e.g. X0)", off)
        if len(views) == 2 and (views[0].kind, views[0].number) == (views[1].kind, views[1].number):
            raise StimError(f"{toks[0][0]}: A and B must be two inputs", off)
        view = views[0]
        if len(toks) not in (3, 5):
            raise StimError(form, min(len(toks) - 1, 3) + off)
        if ev.time_us is None:
            raise StimError("a pulse train starts at a time (e.g. 0ms), not at a scan number", 0)
        freq = toks[2][0]
        sign = -1 if freq.startswith("-") and len(views) == 2 else 1
        hz = self.at(off + 2, lambda: parse_frequency(freq[1:] if sign < 0 else freq))
        end = None
        if len(toks) == 5:
            word = toks[3][0].lower()
            if word not in ("until", "for"):
                raise StimError(form, off + 3)
            span = self.at(off + 4, lambda: parse_time(toks[4][0]))
            end = span if word == "until" else ev.time_us + span
            if end <= ev.time_us:
                raise StimError(f"{toks[4][0]}: the train must end after it starts", off + 4)
        period = None if hz == 0 else Fraction(1_000_000) / hz
        ev.kind = "pulses"
        ev.assigns = ((view, (ev.time_us, period, end) + ((views[1], sign) if len(views) == 2 else ())),)

    def view(self, name: str, offset: int) -> DeviceView:
        view = self.views.get(name)
        if view is not None:
            return view
        try:
            view = self.views[name] = parse_device_name(name, self.target)
            return view
        except NameError_ as e:
            raise StimError(str(e), offset, "E602") from None


    def check(self, t: str, col: int, offset: int) -> Check:
        m = re.fullmatch(r"([^=!]+)(!=|=)(.+)", t)
        if not m:
            raise StimError(f"{t!r}: expected DEV=VALUE, DEV!=VALUE or DEV=LOW..HIGH", offset)
        view = self.view(m[1], offset)
        value = m[3]
        if ".." in value and m[2] == "=":
            lo, hi = value.split("..", 1)
            a = self.at(offset, lambda: parse_value(lo, view))
            b = self.at(offset, lambda: parse_value(hi, view))
            if a > b:
                raise StimError(f"empty range {value}", offset)
            return Check(view, "range", a, b, t, col)
        return Check(view, m[2], self.at(offset, lambda: parse_value(value, view)), None, t, col)

    def model(self, no: int, toks: list[tuple[str, int]]) -> None:
        if len(toks) < 2:
            raise StimError("expected `model KIND key=value ...`", 0)
        params: dict[str, tuple[str, int]] = {}
        for k, (t, col) in enumerate(toks[2:], 2):
            if "=" not in t:
                raise StimError(f"{t!r}: model parameters are key=value", k)
            key, value = t.split("=", 1)
            params[key.lower()] = (value, col)
        self.st.models.append(ModelSpec(toks[1][0].lower(), params, no, toks[1][1]))


def _near(word: str, known: tuple[str, ...]) -> str:
    """'; did you mean `expect`?' for a mistyped keyword (only asked once a line is wrong)."""
    from mlctool.suggest import closest

    hit = closest(word, known)
    return f"; did you mean `{hit.lower()}`?" if hit and hit.lower() != word.lower() else ""


def _strip_comment(raw: str) -> str:
    """`#` starts a comment, except `#250` (a scan number) at the start of a line or after `run`."""
    hashes = raw.count("#")
    if not hashes:  # the line up to its last token (\S and str.isspace agree on blanks)
        return raw.rstrip()
    if hashes == 1:
        first = raw.split(None, 1)
        if first and first[0].startswith("#"):  # `#250 X0=1`, or a comment line
            return raw.rstrip() if _SCAN_NO.fullmatch(first[0]) else ""
    out = []
    for m in _TOKEN.finditer(raw):
        t = m.group()
        if t.startswith("#"):
            first = not out
            after_run = len(out) == 1 and out[0].lower() == "run"
            if not (_SCAN_NO.fullmatch(t) and (first or after_run)):
                break
        out.append(t)
    return _rejoin(raw, len(out))


def _rejoin(raw: str, count: int) -> str:
    """The first `count` tokens of raw with their original columns."""
    end = 0
    for k, m in enumerate(_TOKEN.finditer(raw)):
        if k == count:
            break
        end = m.end()
    return raw[:end]


def _scan_number(text: str) -> int:
    if not _SCAN_NO.fullmatch(text):
        raise StimError(f"{text!r} is not a scan number (e.g. #250)")
    if len(text) > 11 or int(text[1:]) > MAX_SCANS:
        raise StimError(f"{text!r} is past the bound of a run, {MAX_SCANS:,} scans")
    return int(text[1:])


def parse_stimulus_text(path: str, text: str, target: Target,
                        cache: NameCache | None = None) -> tuple[Stimulus, list[Diagnostic]]:
    """`cache`: names and values read by earlier files of the same batch (NameCache)."""
    p = _Parser(path, text, target, cache)
    st = p.run()
    return st, p.diags


def load_stimulus(path: str, target: Target,
                  cache: NameCache | None = None) -> tuple[Stimulus | None, list[Diagnostic]]:
    src, diags = read_source(path)
    if src is None:
        return None, diags
    return parse_stimulus_text(path, src.text, target, cache)


__all__ = ["MAX_SCANS", "MAX_TIME_US", "Check", "Event", "ModelSpec", "NameCache", "Stimulus", "StimError", "load_stimulus",
           "parse_stimulus_text", "parse_time", "parse_value"]
