"""The edge-operand walk of "checked means runs" (issue 30, tests/test_checked_means_runs.py):
every instruction form of a target's tables written with operands at the edges, each line
checked, the lines the checker accepts run on every engine.

A *snippet* is one instruction form with its operands, and the lines that set what it reads
before it (index registers, source registers) under its own guard relay: `LD M<guard>`, the
setting lines, the instruction, then lines that put the index registers back to 0. The
snippets of a target are packed into programs (each snippet its own guard), the programs are
checked as a whole, and the runner (run_program) turns the guards On and runs a few scans:
a snippet that faults has its guard turned Off and the scan goes on without it. Contacts
(LD/AND/OR forms) run whatever their guard: they read the index register only their own
guarded lines set.

The edges, per operand (`candidates`): for every device kind it takes, the last device of
each allowed range and the ones just before it (so that a block the instruction covers runs
past the end); bit groups K1/K4/K8 ending at the last device and one device later; the
constant range's ends and one past them, 0 and -1; the first device index-modified so the
address is the last device, one past it, -1, and the index register's extremes; each source
register kind holding 0, -1, the width's largest and smallest value and float patterns. The
other operands keep a plain value (`base`). In CI the list is walked as it stands
(deterministic); with a random generator (`make fuzz`) each form also gets draws that put
several operands at their edges at once.
"""

from __future__ import annotations

import bisect
import random
from dataclasses import dataclass, field

from mlctool.syntax.operands import Operand, format_operand
from mlctool.targetapi.model import InstrSpec, OperandSpec, Target

STRUCTURE_CLASSES = frozenset({"anb", "orb", "mps", "mrd", "mpp", "inv", "nop", "label", "free", "bus",
                               "interrupt"})
CONTACT_CLASSES = frozenset({"load", "and", "or"})
FLOW_OPS = frozenset({"cj", "call", "mc"})  # output-class forms that need labels or a nest

# the registers a snippet modifies its operands with, and puts back to 0 after itself
IX16 = 1


@dataclass
class Snippet:
    form: InstrSpec
    ops: tuple[str, ...]
    setup: tuple[str, ...] = ()  # lines before the instruction (same rung, under the guard)
    undo: tuple[str, ...] = ()  # lines after it, under the guard again
    what: str = ""

    @property
    def line(self) -> str:
        return " ".join((self.form.mnemonic, *self.ops))


def forms(t: Target) -> list[InstrSpec]:
    """Every instruction form of the tables once (16/32-bit, pulse, each variant), in table order."""
    seen: dict[int, InstrSpec] = {}
    for spec in t.instructions.values():
        seen.setdefault(id(spec), spec)
    for variants in t.variants.values():
        for spec in variants:
            seen.setdefault(id(spec), spec)
    return list(seen.values())


def _index_register(t: Target, width: int) -> str:
    """The register that index-modifies a `width`-bit operand, and how it is written."""
    if width == 32:
        return t.settings.get("index32", {}).get("register", "V")
    return "Z"


def _set_index(t: Target, width: int, value: int) -> str:
    reg = _index_register(t, width)
    if width == 32:
        return f"DMOV K{value} {reg}{IX16}"
    return f"MOV K{value} {reg}{IX16}"


def _undo_index(t: Target) -> tuple[str, ...]:
    return (f"MOV K0 Z{IX16}", f"MOV K0 V{IX16}")


@dataclass
class Candidate:
    text: str
    setup: tuple[str, ...] = ()
    what: str = ""
    indexed: bool = False
    rank: int = 0  # 0: walked in CI; 1: only with a larger budget (`make fuzz`)


@dataclass
class _Operands:
    t: Target
    spec: InstrSpec
    k: int
    o: OperandSpec
    out: list[Candidate] = field(default_factory=list)

    def add(self, op: Operand, what: str, setup: tuple[str, ...] = (), indexed: bool = False, rank: int = 0) -> None:
        self.out.append(Candidate(format_operand(op), setup, what, indexed, rank))


def _ranges(t: Target, spec: InstrSpec, o: OperandSpec, kind: str) -> list[tuple[int, int]]:
    dev = t.devices[kind]
    spans = list(o.allowed(kind) or ((dev.lo, dev.hi),))
    narrow = o.devices32 if spec.width == 32 else o.devices16
    if narrow:
        spans = [(max(a, narrow[0]), min(b, narrow[1])) for a, b in spans if max(a, narrow[0]) <= min(b, narrow[1])]
    return spans or [(dev.lo, dev.hi)]


def _device_op(t: Target, kind: str, number: int, index: tuple[str, int] | None = None) -> Operand:
    dev = t.devices[kind]
    if dev.unit_prefix:
        return Operand(kind, number=number, index=index, unit=f"{dev.unit_prefix}{dev.units[0]}")
    return Operand(kind, number=number, index=index, radix=dev.radix)


def _krange(t: Target, spec: InstrSpec, o: OperandSpec) -> tuple[int, int]:
    rng = o.range32 if spec.width == 32 else o.range16
    return rng or t.krange(spec.width)


def base(t: Target, spec: InstrSpec, k: int, o: OperandSpec) -> Operand:
    """A plain operand of the form at position k: a constant inside its range, else the first
    allowed device kind at a number of its own (k tenths into its first allowed range)."""
    kinds = sorted(o.kinds)
    for c in ("K", "H"):
        if c in o.kinds and not o.writes:
            lo, hi = _krange(t, spec, o)
            v = max(lo, min(hi, 1))
            if o.word_range and o.word_range_of:
                v = max(o.word_range[0], min(o.word_range[1], v))
            return Operand(c, value=v)
    order = [k2 for k2 in kinds if k2 in t.devices and t.devices[k2].kind != "pointer"]
    # plain word devices first, then bits, then the rest
    order.sort(key=lambda k2: (t.devices[k2].kind != "word" or bool(t.devices[k2].unit_prefix)
                               or k2 in ("V", "Z"), t.devices[k2].kind != "bit", k2))
    for kind in order:
        dev = t.devices[kind]
        if o.writes and dev.input:
            continue
        lo, hi = _ranges(t, spec, o, kind)[0]
        if kind in ("V", "Z"):
            number = min(hi, max(lo, 2))
        else:
            number = min(hi, lo + 100 * k + (8 if dev.radix == 8 else 10) * 3)
            number = max(lo, number)
        if dev.kind == "counter" and t.is_counter32(number) != (spec.width == 32) and not o.devices16:
            continue
        return _device_op(t, kind, number)
    for g in sorted(o.kinds):
        if g.startswith("Kn") and g[2:] in t.devices:
            return Operand(g, number=t.devices[g[2:]].lo, digits=4 if spec.width == 16 else 8)
    for c in ("F", "E"):
        if c in o.kinds:
            return Operand(c, value=1.5, decimals=1)
    if "$" in o.kinds:
        return Operand("$", value="AB")
    for kind in kinds:
        if kind in t.devices:
            dev = t.devices[kind]
            return _device_op(t, kind, dev.lo)
        if kind.endswith(".b"):
            return Operand(kind, number=t.devices[kind[:-2]].lo, bit=0)
    raise ValueError(f"{spec.mnemonic}: no base operand for {o.role}")


def _profile_values(width: int, is_float: bool) -> list[tuple[int, str]]:
    if width == 32:
        out = [(0, "0"), (-1, "-1"), (2**31 - 1, "max"), (-(2**31), "min")]
        if is_float:
            out += [(0x7F800000, "+inf"), (0x7FC00000, "NaN"), (0xFF7FFFFF - 2**32, "-max float"), (1, "subnormal")]
        return out
    return [(0, "0"), (-1, "-1"), (32767, "max"), (-32768, "min")]


def _set_register(op: Operand, width: int, value: int) -> str:
    return f"{'DMOV' if width == 32 else 'MOV'} K{value} {format_operand(op)}"


def candidates(t: Target, spec: InstrSpec, k: int) -> list[Candidate]:
    """The edge operands of position k of a form, in order of interest."""
    o = spec.operands[k]
    c = _Operands(t, spec, k, o)
    width = spec.width
    indexable = spec.index and o.index
    first_word = first_bit = first_group = None
    for kind in sorted(o.kinds):
        if kind in ("K", "H"):
            lo, hi = _krange(t, spec, o)
            values = [lo, hi, lo - 1, hi + 1, 0, -1]
            if o.word_range:
                values += [o.word_range[1], o.word_range[1] + 1]
            for j, v in enumerate(dict.fromkeys(values)):
                if kind == "H" and v < 0:
                    continue
                c.add(Operand(kind, value=v), f"{kind}{v}", rank=int(kind == "H" or j >= 4))
            if indexable and kind in t.indexable:
                for ix in (32767, -32768):
                    c.add(Operand(kind, value=hi, index=(_index_register(t, width), IX16)), f"{kind}{hi} index {ix}",
                          (_set_index(t, width, ix),), True)
        elif kind in ("F", "E"):
            fmax = t.settings.get("f_max", 3.4028234e38)
            for v, dec in ((0.0, 1), (-1.5, 1), (fmax, 3), (-fmax, 3), (1e-30, 0)):
                if kind == "F" and (dec == 0 or not fmax):
                    continue
                c.add(Operand(kind, value=v, decimals=dec), f"{kind}{v}")
        elif kind == "$":
            for s in ("", "A", "ABCDEFGHIJKLMNOPQRSTUVWXYZ012345"):
                c.add(Operand("$", value=s), f'"{s}"')
        elif kind.startswith("Kn"):
            dev = t.devices.get(kind[2:])
            if dev is None:
                continue
            first = first_group is None
            first_group = first_group or kind
            for digits in ((1, 4) if width == 16 else (1, 4, 8)):
                n = 4 * digits
                for start in (dev.hi - n + 1, dev.hi - n + 2):
                    c.add(Operand(kind, number=start, digits=digits, radix=dev.radix), f"K{digits}{kind[2:]} to the end",
                          rank=int(not first or digits == 1))
        elif kind.endswith(".b"):
            dev = t.devices.get(kind[:-2])
            if dev is not None:
                c.add(Operand(kind, number=dev.hi, bit=15), f"{kind} last")
        elif kind in t.devices:
            dev = t.devices[kind]
            if dev.kind == "pointer":
                continue
            first = (first_bit if dev.kind == "bit" else first_word) is None
            if dev.kind == "bit":
                first_bit = first_bit or kind
            elif dev.kind in ("word", "timer", "counter") and kind not in ("V", "Z"):
                first_word = first_word or kind
            for lo, hi in _ranges(t, spec, o, kind):
                for j, number in enumerate(dict.fromkeys((hi, hi - 1, hi - 3, hi - 7))):
                    if lo <= number:
                        c.add(_device_op(t, kind, number), f"{kind} {number} of {lo}-{hi}",
                              rank=int(j > (1 if first else 0)))
            for a in dev.areas:
                if a.write == "absent":
                    c.add(_device_op(t, kind, a.lo - 1), f"{kind} before the gap {a.lo}", rank=1)
    # index modification: the address at the last device, one past it, -1, and the extremes
    reg = _index_register(t, width)
    for kind in (first_word, first_bit, first_group):
        if kind is None or not indexable or kind not in t.indexable:
            continue
        dev = t.devices[kind[2:] if kind.startswith("Kn") else kind]
        lo, hi = _ranges(t, spec, o, kind[2:] if kind.startswith("Kn") else kind)[0]
        start = lo
        big = (2**31 - 1, -(2**31)) if width == 32 else (32767, -32768)
        for j, v in enumerate((hi - start, hi - start + 1, -start - 1, *big)):
            if kind.startswith("Kn"):
                op = Operand(kind, number=start, digits=4 if width == 16 else 8, radix=dev.radix, index=(reg, IX16))
            else:
                op = _device_op(t, kind, start, (reg, IX16))
            c.add(op, f"{format_operand(op)} with {reg}{IX16}={v}", (_set_index(t, width, v),), True,
                  rank=int(kind != (first_word or first_bit or first_group) and j != 1))
    # source registers holding the width's extremes
    if "r" in o.access:
        for kind in sorted(o.kinds):
            dev = t.devices.get(kind)
            if dev is None or dev.kind not in ("word",) or dev.unit_prefix or kind in ("V", "Z"):
                continue
            lo, hi = _ranges(t, spec, o, kind)[0]
            op = _device_op(t, kind, min(hi, lo + 100 * k + 30) if hi - lo > 200 else lo)
            for j, (value, name) in enumerate(_profile_values(width, spec.is_float)):
                c.add(op, f"{format_operand(op)}={name}", (_set_register(op, width, value),), rank=int(j == 0))
            break
    return c.out


def walked(spec: InstrSpec) -> bool:
    """A form the walk writes as a line of its own (not a label, a block operator, program
    flow, a multi-input instruction or one whose operands are all pointers: those need the
    program around them)."""
    return not (spec.cls in STRUCTURE_CLASSES or spec.op in FLOW_OPS or spec.inputs
                or any(o.kinds <= {"P", "I", "N", "Q"} for o in spec.operands))


def snippets(t: Target, rnd: random.Random | None = None, draws: int = 0, full: bool = False) -> list[Snippet]:
    """The edge snippets of every walked form: its base, then each operand at each of its
    edges (`full`: every edge; else the rank-0 ones, and for a form that repeats another's
    routine and operands, a P-suffix twin, its first three); with `rnd`, `draws` random
    combinations per form besides."""
    out: list[Snippet] = []
    seen: set = set()
    for spec in forms(t):
        if not walked(spec):
            continue
        twin = (spec.op, spec.width, spec.operands) in seen
        seen.add((spec.op, spec.width, spec.operands))
        bases = [base(t, spec, k, o) for k, o in enumerate(spec.operands)]
        plain = tuple(format_operand(b) for b in bases)
        out.append(Snippet(spec, plain, what="base"))
        per_op = [[c for c in candidates(t, spec, k) if full or c.rank == 0] for k in range(len(spec.operands))]
        if twin and not full:
            per_op = [cands[:3] for cands in per_op]
        for k, cands in enumerate(per_op):
            for cand in cands:
                ops = list(plain)
                ops[k] = cand.text
                setup = cand.setup
                out.append(Snippet(spec, tuple(ops), setup, _undo_index(t) if cand.indexed else (),
                                   f"{spec.operands[k].role}: {cand.what}"))
        if rnd is not None and per_op:
            for _ in range(draws):
                ops, setup, indexed, what = [], [], False, []
                for k, cands in enumerate(per_op):
                    if cands and rnd.random() < 0.6:
                        cand = rnd.choice(cands)
                        if cand.indexed and indexed:
                            cand = Candidate(plain[k])
                        ops.append(cand.text)
                        setup += cand.setup
                        indexed = indexed or cand.indexed
                        what.append(f"{spec.operands[k].role}: {cand.what}")
                    else:
                        ops.append(plain[k])
                out.append(Snippet(spec, tuple(ops), tuple(setup), _undo_index(t) if indexed else (),
                                   "; ".join(what) or "base"))
    return out


def snippet_lines(s: Snippet, guard: str, sink: str) -> list[str]:
    """The lines of a snippet under guard relay `guard` (a contact form drives `sink`)."""
    lines = [f"LD {guard}", *s.setup] if s.setup or s.form.cls not in CONTACT_CLASSES else []
    if s.form.cls == "load":
        lines += [s.line, f"AND {guard}", f"OUT {sink}"]
    elif s.form.cls in ("and", "or"):
        lines += [f"LD {guard}", s.line, f"OUT {sink}"]
    else:
        lines.append(s.line)
    if s.undo:
        lines += [f"LD {guard}", *s.undo]
    return lines


# ---------------------------------------------------------------------------- programs

# the guards are inputs: no instruction writes them (E210), so no snippet's block turns another
# snippet's guard On or Off; a program holds as many snippets as the target has inputs
GUARD = "X"

# errors that are about the program, not the line: a second PR (once per program), an output
# a second instruction must not use: the snippet goes into the next program
PROGRAM_WIDE = frozenset({"E904", "E233", "E235", "E240"})


@dataclass
class Packed:
    """A checked program of snippets: the image, each snippet's guard relay and lines."""

    target: Target
    image: object
    snippets: list[Snippet]
    guards: list[int]  # M number of each snippet's guard
    lines: list[tuple[int, int]]  # (first, last) source line of each snippet
    text: str

    def snippet_at(self, line: int) -> int | None:
        k = bisect.bisect_right(self.lines, (line, 1 << 60)) - 1
        return k if k >= 0 and self.lines[k][0] <= line <= self.lines[k][1] else None


@dataclass
class Checked:
    programs: list[Packed]
    rejected: dict[str, int]  # diagnostic code -> snippets the checker rejected with it
    accepted: int


def _text(t: Target, snips: list[Snippet], guards: list[int], sink: str) -> tuple[str, list[tuple[int, int]]]:
    lines: list[str] = []
    spans = []
    for s, g in zip(snips, guards):
        first = len(lines) + 1
        lines += snippet_lines(s, t.device_name(GUARD, g), sink)
        spans.append((first, len(lines)))
    lines.append("END")
    return "\n".join(lines) + "\n", spans


def check_and_pack(t: Target, snips: list[Snippet], sink: str, folder) -> Checked:
    """The snippets the checker accepts, packed into checked programs, one snippet per input."""
    from mlctool.asm import program_from_paths
    from mlctool.config import Config

    config = Config(capacity=1 << 30)
    rejected: dict[str, int] = {}
    programs: list[Packed] = []
    pending = list(snips)
    guards = range(t.devices[GUARD].lo, t.devices[GUARD].hi + 1)
    n = 0
    while pending:
        chunk, later = pending[:len(guards)], pending[len(guards):]
        while chunk:
            gs = list(guards[:len(chunk)])
            text, spans = _text(t, chunk, gs, sink)
            path = folder / f"{t.name}{t.model or ''}-{n}.il"
            path.write_text(text, "utf-8")
            image, diags, _ = program_from_paths([str(path)], t, config)
            errors = [d for d in diags if d.severity == "error"]
            if not errors:
                assert image is not None
                programs.append(Packed(t, image, chunk, gs, spans, text))
                n += 1
                break
            by_snippet: dict[int, set[str]] = {}
            for d in errors:
                k = next((k for k, (a, b) in enumerate(spans) if a <= d.span.line <= b), None)
                assert k is not None, f"{path}:{d.span.line}: {d.code} {d.message}"
                by_snippet.setdefault(k, set()).add(d.code)
            keep = []
            for k, s in enumerate(chunk):
                codes = by_snippet.get(k)
                if codes is None:
                    keep.append(s)
                elif codes <= PROGRAM_WIDE and len(chunk) > 1:
                    later.append(s)
                else:
                    for c in codes:
                        rejected[c] = rejected.get(c, 0) + 1
            chunk = keep
        pending = later
    return Checked(programs, rejected, sum(len(p.snippets) for p in programs))


# ---------------------------------------------------------------------------- runs

@dataclass
class Outcome:
    engine: str
    faults: dict[int, str] = field(default_factory=dict)  # snippet -> fault message (E604)
    crashes: dict[int, str] = field(default_factory=dict)  # snippet -> exception (exit 3)
    ran: str = ""  # the engine that ran (native falls back to compiled where it cannot build)
    unguarded: set[int] = field(default_factory=set)  # snippets that fault with their guard Off


def run_program(p: Packed, engine: str, phases: list[set[int]] | None = None, scans: int = 3) -> Outcome:
    """`scans` scans of the program per phase, each phase with the guards of its snippets On
    (default: one phase, every snippet). On the reference interpreter a snippet that faults or
    raises is skipped and the scan goes on at the next snippet; on the compiled and native
    engines (which run a scan as a whole) its guard is turned Off and the scan runs again.
    Either way its guard stays Off from then on, and the index registers are put back to 0."""
    from mlctool.sim.run.run import Simulation
    from mlctool.sim.scan import DEFAULT_WATCHDOG, Fault, begin_scan, end_of_scan, run_steps
    from mlctool.sim.stimulus.stimulus import parse_stimulus_text

    t = p.target
    st, _ = parse_stimulus_text("walk.stim", "", t)
    sim = Simulation(p.image, t, st, [], 10_000, [], False, engine=engine)
    out = Outcome(engine, ran=getattr(sim.scan, "engine", engine))
    m = sim.m
    steps = sim.prog.steps
    snippet_of_step = [p.snippet_at(s.ins.line) for s in steps]
    first_step: dict[int, int] = {}
    for k, i in enumerate(snippet_of_step):
        if i is not None:
            first_step.setdefault(i, k)
    off: set[int] = set()

    def failed(i: int | None, message: str, crash: bool) -> bool:
        """Record it; False: the snippet runs with its guard Off (it cannot be skipped)."""
        if i is None:
            raise AssertionError(f"{message}: outside the snippets")
        (out.crashes if crash else out.faults)[i] = message
        if i in off:
            out.unguarded.add(i)
            return False
        off.add(i)
        for reg in ("Z", "V"):
            for n in range(len(m.words[reg])):
                m.words[reg][n] = 0
        return True

    def guards(on: set[int]) -> None:
        bits = m.bits[GUARD]
        for i, g in enumerate(p.guards):
            bits[g] = 1 if i in on and i not in off else 0

    scan_no = 0
    for on in phases or [set(range(len(p.snippets)))]:
        for _ in range(scans):
            sim.catch_up(scan_no)
            sim.apply_inputs(scan_no)
            scan_no += 1
            if engine == "interp":
                guards(on)
                begin_scan(m)
                pc = 0
                while True:
                    try:
                        run_steps(sim.prog, m, pc, 0, DEFAULT_WATCHDOG)
                        break
                    except Fault as f:
                        i = snippet_of_step[f.step.index] if f.step is not None else None
                        failed(i, f.message, False)
                    except Exception as e:  # noqa: BLE001 - what the walk looks for
                        i = snippet_of_step[m.pc]
                        failed(i, _described(e), True)
                    pc = first_step.get(i + 1, len(steps) - 1)
                    m.acc = False
                    m.blocks.clear()
                    m.stack.clear()
                end_of_scan(m)
                continue
            for _ in range(len(p.snippets) + 1):
                guards(on)
                try:
                    sim.scan(DEFAULT_WATCHDOG)
                    break
                except Fault as f:
                    skipped = failed(snippet_of_step[f.step.index] if f.step is not None else None, f.message, False)
                except Exception as e:  # noqa: BLE001 - what the walk looks for
                    step = sim.scan._fault_step(e)
                    skipped = failed(None if step is None else snippet_of_step[step.index], _described(e), True)
                if not skipped:
                    break
    return out


def _described(e: BaseException) -> str:
    import traceback

    return "".join(traceback.format_exception_only(e)).strip()


# ---------------------------------------------------------------------------- program flow

# forms the walk leaves to their own tests: they need tables beside the program (Q tables of
# the VS serial and positioning instructions, tests/targets/vs/) or a positioning program
# and several input blocks (FBs FUN140/147, tests/targets/fbs/)
NOT_WALKED = {"vs": {"CPUL", "LINK", "MBUS", "DTRD", "DTRDP", "DTBL"}, "fbs": {"HSPSO", "MHSPO"}}


def flow_programs(t: Target) -> list[str]:
    """Small whole programs for the forms that need the program around them: labels at the
    last pointer, jumps and calls index-modified to it, one past it, -1 and the extremes, FOR
    counts at their extremes (a constant, a register, an index), nesting one past the limit,
    the block and stack operators, and on VS master control, a step ladder at the last step
    relay, interrupts. Those of a target's forms only (the checker may refuse some: fine)."""
    has = set(t.instructions)
    p_hi = max(n for n in range(t.devices["P"].hi + 1) if n not in t.end_labels)
    stack = "LD X0\nMPS\nAND X1\nOUT M1\nMRD\nOUT M2\nMPP\nOUT M3\n" if "MPS" in has else ""
    out = [stack + "LD X0\nLD X1\nANB\nLD X2\nORB\n" + ("INV\n" if "INV" in has else "") + "OUT M4\n"
           + ("NOP\n" if "NOP" in has else "") + "END\n",
           f"LD X0\nOUT M1\nP{p_hi}:\nEND\n"]
    if "CJ" not in has:
        return out
    out += [f"LD X0\nCJ P{p_hi}\nLD X0\nMOV K1 D0\nP{p_hi}:\nEND\n",
            f"LD X0\nCALL P{p_hi}\nFEND\nP{p_hi}:\nLD X0\nMOV K1 D0\nSRET\nEND\n"]
    for v in (p_hi, p_hi + 1, -1, 32767, -32768):
        out += [f"LD X0\nMOV K{v} Z1\nCJ P0Z1\nP0:\nLD X0\nMOV K1 D0\nP{p_hi}:\nEND\n",
                f"LD X0\nMOV K{v} Z1\nCALL P0Z1\nFEND\nP0:\nSRET\nP{p_hi}:\nSRET\nEND\n"]
        if "CJP" in has:
            out.append(f"LD X0\nMOV K{v} Z1\nCJP P0Z1\nCALLP P{p_hi}\nFEND\nP0:\nSRET\nP{p_hi}:\nSRET\nEND\n")
    for v in (32767, -32768, 0, 1):
        out += [f"FOR K{v}\nLD X0\nINC D0\nNEXT\nEND\n", f"LD X0\nMOV K{v} D9\nFOR D9\nLD X0\nINC D0\nNEXT\nEND\n"]
    depth = t.settings["for_depth"]
    out.append("FOR K2\n" * depth + "LD X0\nINC D0\n" + "NEXT\n" * depth + "END\n")
    calls = t.settings["call_depth"]
    out.append("LD X0\nCALL P1\nFEND\n" + "".join(f"P{k}:\nLD X0\nCALL P{k + 1}\nSRET\n" for k in range(1, calls))
               + f"P{calls}:\nSRET\nEND\n")
    if "MC" in has:
        n_hi = t.devices["N"].hi
        out.append("".join(f"LD X0\nMC N{n}\n" for n in range(n_hi + 1)) + "LD X1\nOUT M1\nMCR N0\nEND\n")
    if "STL" in has:
        stl = t.instructions["STL"].operands[0]
        s_hi = (stl.allowed("S") or ((0, t.devices["S"].hi),))[-1][1]
        out.append(f"LD X0\nSET S{s_hi}\nSTL S{s_hi}\nLD X1\nOUT M1\nRET\nEND\n")
    if "EI" in has:
        out.append("EI\nLD X0\nOUT M1\nDI\nWDT\nWDTP\nFEND\nITA10:\nLD X0\nMOV K1 D0\nIRET\n"
                   "IX0P:\nLD X0\nINC D1\nIRET\nEND\n")
    return out


def flow_forms(t: Target, text: str) -> set[str]:
    """The forms a flow program writes: its mnemonics, and P / I for its label lines."""
    out = set()
    for line in text.splitlines():
        word = line.split()[0]
        out.add(("P" if word[0] == "P" else "I") if word.endswith(":") else word)
    return out
