"""A target's manual tables as plain data, loaded from the folder its TargetPackage names
(registry.py; the built-in ones: mlctool/targets/<name>/*.toml).

Generic code asks the Target; nothing outside a target folder names a target's devices.
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass, field
from functools import cache
from pathlib import Path

from mlctool.syntax.operands import OperandSyntax, device_number
from mlctool.targetapi.registry import UnknownTarget, target_names, target_package

BIT_KINDS = frozenset("XYMA")
GROUP_KINDS = frozenset({"KnX", "KnY", "KnM", "KnA"})
CONST_KINDS = frozenset({"K", "F"})


@dataclass(frozen=True, slots=True)
class Area:
    lo: int
    hi: int
    name: str
    write: str = "ok"  # ok | nc | system | reserved | absent | signals (the target's signal table speaks)
    latched: bool = False


@dataclass(frozen=True, slots=True)
class DeviceKind:
    name: str
    kind: str  # bit | word | timer | counter | pointer
    lo: int
    hi: int
    areas: tuple[Area, ...]
    section: str
    input: bool = False
    width16_only: bool = False
    radix: int = 10  # 8: numbered in octal (X0-X7, X10 ...); index offsets still count ordinals
    bit_of_word: bool = False  # D0.5 bit operands exist (the manual's D.b column)
    # words of numbered units (VS UnG: the buffer memory of special module n): the unit's
    # letter, the units of the model, and the device kind whose operand places they may take
    # in application instructions (the manual's UnG column sits with D,R: `like = "D"`)
    unit_prefix: str = ""
    units: tuple[int, int] = (0, -1)
    like: str = ""

    def name_of(self, number: int) -> str:
        """A device as the manual writes it: X10 for ordinal 8 of an octal kind."""
        return f"{self.name}{device_number(number, self.radix)}"

    def area(self, number: int) -> Area | None:
        for a in self.areas:
            if a.lo <= number <= a.hi:
                return a
        return None


@dataclass(frozen=True, slots=True)
class OperandSpec:
    role: str
    kinds: frozenset[str]
    access: str = "r"  # r | w | rw
    range16: tuple[int, int] | None = None  # constant range, overrides the width's K range
    range32: tuple[int, int] | None = None
    words: tuple[int, int] = (1, 2)  # 16-bit words occupied in the 16-bit / 32-bit form
    bits: int = 1  # consecutive bits occupied by a bit destination
    devices16: tuple[int, int] | None = None  # narrower device-number range per form
    devices32: tuple[int, int] | None = None
    forbid16: tuple[tuple[int, int], ...] = ()  # device numbers not allowed in the 16-bit form
    word_range: tuple[int, int] | None = None  # constant range when operand `word_range_of`
    word_range_of: str | None = None  # ... is a word device (DECO/ENCO n)
    ranges: tuple[tuple[str, tuple[tuple[int, int], ...]], ...] = ()  # per kind: allowed numbers
    index: bool = True  # False: this operand may not be index-modified (VS OUT C200 K.., 2-6-2)
    # how many elements the operand covers when another operand says so (`span = "n"`):
    # (role, rule), rule one of SPAN_RULES: n of them, 2^n (DECO D), n/2 rounded up (bytes
    # two a word), n+1 (a table with its count word); an element is one bit of a bit device,
    # one Kn group, or `words` registers. `span_kinds`: the device kinds it applies to ("bit":
    # bit devices only, a word operand being one word whatever n: DECO/ENCO n <= 4)
    span: tuple[str, str] | None = None
    span_kinds: str = "any"  # any | bit

    def span_count(self, n: int) -> int:
        """The elements the operand covers when its count operand is n."""
        rule = self.span[1] if self.span else "n"
        return SPAN_RULES[rule](n)

    def allowed(self, kind: str) -> tuple[tuple[int, int], ...] | None:
        """Device-number ranges this operand allows for `kind` (None: the device's range)."""
        for k, r in self.ranges:
            if k == kind:
                return r
        return None

    @property
    def writes(self) -> bool:
        return "w" in self.access


@dataclass(frozen=True, slots=True)
class InstrSpec:
    """One mnemonic: a form (16-bit, 32-bit or float) of a manual instruction."""

    mnemonic: str
    api: int | None
    width: int  # 16 or 32
    is_float: bool
    steps: int
    cls: str  # load | and | or | anb | orb | mps | mrd | mpp | inv | nop | output | free | label
    op: str
    operands: tuple[OperandSpec, ...]
    index: bool
    short_steps: bool  # "1~2" steps: 1 in the short ranges, else 2
    table: int  # trailing table entries (VRT), 0 if none
    constraints: tuple[str, ...]  # named cross-operand rules (ZRST), checked generically
    section: str
    notes: tuple[str, ...]
    inputs: tuple[str, ...] = ()  # a multi-input instruction: its inputs, one block each
    pulse: bool = False  # the P-suffix form: executes once per Off->On of its condition
    models: frozenset[str] = frozenset()  # models that have it; empty: every model
    once: bool = False  # the manual allows it once per program (E904)
    # the manual has it execute in every scan whatever its condition (FBs FUN141 MPARA): coverage
    # counts every execution, not only those with the condition On
    unconditional: bool = False
    # "open": starts an exclusive region (an STL step: only one step's coils are live, so the
    # same coil in two regions is no double coil); "close": ends the regions (RET)
    region: str = ""

    def constant_count(self, o: OperandSpec, ops) -> int | None:
        """The count that sizes operand `o` (its `span`: DECO D covers 2^n bits) when the
        count operand is written as a constant K/H, else None (a register, an index: the run
        time's)."""
        c = next((i for i, s in enumerate(self.operands) if o.span and s.role == o.span[0]), None)
        if c is None or c >= len(ops):
            return None
        count = ops[c]
        if count.kind not in ("K", "H") or count.index or not isinstance(count.value, int):
            return None
        return count.value


@dataclass(frozen=True, slots=True)
class Target:
    name: str
    title: str
    manual: str
    capacity: int
    devices: dict[str, DeviceKind]
    instructions: dict[str, InstrSpec]
    settings: dict  # the rest of target.toml (timer bases, limits, decisions)
    model: str | None = None  # the model the tables were cut to (`--model`)
    # mnemonics with several operand shapes (OUT Y0 / OUT T0 K50): every variant, in table order
    variants: dict[str, tuple[InstrSpec, ...]] = field(default_factory=dict)
    # instructions of the family that the chosen model lacks: mnemonic -> spec (for E901)
    unavailable: dict[str, InstrSpec] = field(default_factory=dict)

    def instruction(self, mnemonic: str) -> InstrSpec | None:
        return self.instructions.get(mnemonic.upper())

    def variants_of(self, mnemonic: str) -> tuple[InstrSpec, ...]:
        m = mnemonic.upper()
        if m in self.variants:
            return self.variants[m]
        spec = self.instructions.get(m)
        return (spec,) if spec else ()

    @property
    def models(self) -> tuple[str, ...]:
        return tuple(self.settings.get("models", ()))

    @property
    def operand_syntax(self) -> OperandSyntax:
        # one object per target and model: parse_operand's cache is keyed by its identity.
        # Built from these tables, not by loading the target again: load_target("vs") and
        # load_target("vs", "VS2") are two entries of its cache, and the second would read
        # the TOML files anew (~15 ms of a check)
        key = (self.name, self.model)
        found = _SYNTAX.get(key)
        if found is None:
            found = _SYNTAX[key] = _syntax_of(self)
        return found

    def device_name(self, kind: str, number: int) -> str:
        dev = self.devices.get(kind)
        return dev.name_of(number) if dev else f"{kind}{number}"

    def timer_base(self, number: int) -> dict:
        """The timer_bases entry of a timer: ms, and optionally retentive, skipped."""
        for b in self.settings["timer_bases"]:
            if b["lo"] <= number <= b["hi"]:
                return b
        raise KeyError(number)

    def timer_base_ms(self, number: int) -> int:
        for b in self.settings["timer_bases"]:
            if b["lo"] <= number <= b["hi"]:
                return b["ms"]
        raise KeyError(number)

    def is_counter32(self, number: int) -> bool:
        lo, hi = self.settings["counters32"]
        return lo <= number <= hi

    def short_operand(self, kind: str, number: int) -> bool:
        rng = self.settings.get("short_operand", {}).get(kind)
        return rng is not None and rng[0] <= number <= rng[1]

    def instr_steps(self, spec: InstrSpec, ops) -> int:
        """Steps of one written instruction: the first target.toml `[[step_rules]]` entry whose
        op and first-operand kind (and number range) fit, else the "short" rule (1 in the
        short ranges, else 2), else the table's steps."""
        if not ops:
            return spec.steps
        first = ops[0]
        spans, steps = self.step_spans(spec, first.kind)
        for lo, hi, n in spans:
            if lo <= first.number <= hi:
                return n
        return steps

    def step_spans(self, spec: InstrSpec, kind: str) -> tuple[tuple[tuple[int, int, int], ...], int]:
        """instr_steps for a first operand of `kind`, as (spans, steps): the first (lo, hi, n)
        span holding the operand's number gives n steps, a number in none `steps`. A caller
        that keeps it per form and kind (the checker) does not read the settings at each line."""
        spans = [(rule.get("lo", 0), rule.get("hi", 1 << 31), rule["steps"])
                 for rule in self.settings.get("step_rules", ())
                 if spec.op in rule["ops"] and kind in rule["kinds"]]
        if not spec.short_steps:
            return tuple(spans), spec.steps
        short = self.settings.get("short_operand", {}).get(kind)
        if short is not None:
            spans.append((short[0], short[1], 1))
        return tuple(spans), 2

    @property
    def end_labels(self) -> frozenset[int]:
        """P numbers that stand for END: CJ to one jumps to END without a label (VS 2-10: P63,
        P255); they cannot label a line."""
        return frozenset(self.settings.get("end_labels", ()))

    @property
    def indexable(self) -> frozenset[str]:
        return frozenset(self.settings.get("indexable", ()))

    def krange(self, width: int) -> tuple[int, int]:
        lo, hi = self.settings["k32" if width == 32 else "k16"]
        return lo, hi


def choose_variant(variants: tuple[InstrSpec, ...], count: int, first) -> InstrSpec:
    """Of a mnemonic's variants, the one whose operand count and first operand (an Operand or
    None: its kind and the numbers the variant allows) fit what is written (OUT Y0 /
    OUT T0 K50 / OUT C200 K5); else the first whose first operand kind fits, else the first
    with the count, else the first (its diagnostics then explain the problem)."""
    counted = [v for v in variants if len(v.operands) == count]
    if first is not None:
        for v in counted:
            o = v.operands[0] if v.operands else None
            if o is None or first.kind not in o.kinds:
                continue
            allowed = o.allowed(first.kind)
            narrow = o.devices32 if v.width == 32 else o.devices16
            if (not allowed or any(lo <= first.number <= hi for lo, hi in allowed)) \
                    and (not narrow or narrow[0] <= first.number <= narrow[1]):
                return v
    kind_fits = [v for v in variants if v.operands and first is not None and first.kind in v.operands[0].kinds]
    return (kind_fits or counted or list(variants))[0]


def _pair(v) -> tuple[int, int] | None:
    return (int(v[0]), int(v[1])) if v is not None else None


def _operand(o: dict) -> OperandSpec:
    return OperandSpec(
        role=o["role"],
        kinds=frozenset(o["kinds"].split()),
        access=o.get("access", "r"),
        range16=_pair(o.get("range")),
        range32=_pair(o.get("range32", o.get("range"))),
        words=tuple(o.get("words", (1, 2))),
        bits=o.get("bits", 1),
        devices16=_pair(o.get("devices16")),
        devices32=_pair(o.get("devices32")),
        forbid16=tuple(tuple(r) for r in o.get("forbid16", ())),
        word_range=_pair(o.get("word_range")),
        word_range_of=o.get("word_range_of"),
        ranges=tuple((k, tuple(tuple(r) for r in v)) for k, v in sorted(o.get("ranges", {}).items())),
        index=o.get("index", True),
        span=_span(o.get("span")),
        span_kinds=o.get("span_kinds", "any"),
    )


SPAN_RULES = {"n": lambda n: n, "2^n": lambda n: 2 ** n, "n/2": lambda n: (n + 1) // 2, "n+1": lambda n: n + 1}


def _span(text: str | None) -> tuple[str, str] | None:
    """`span = "n"` (`"2^n"`, `"n/2"`, `"n+1"`, with any role for n): (role, rule)."""
    if text is None:
        return None
    for rule in SPAN_RULES:
        head, _, tail = rule.partition("n")
        if text.startswith(head) and text.endswith(tail) and len(text) > len(head) + len(tail):
            role = text[len(head):len(text) - len(tail)]
            if role.replace("_", "").isalnum() and not role.isdigit():
                return role, rule
    raise ValueError(f"span {text!r}: not one of {', '.join(SPAN_RULES)} (n the role of another operand)")


def _steps(e: dict, convention: dict | None) -> list[int]:
    """Steps per form: as the table gives them, else by the target's step convention
    (target.toml [step_convention]: base + per-operand steps of the form's width)."""
    if "steps" in e:
        return list(e["steps"])
    if convention is None:
        raise KeyError(f"{e['names']}: no steps and the target has no [step_convention]")
    n = len(e.get("operands", ())) + e.get("table", 0)
    return [convention["base"] + n * convention["operand16"], convention["base"] + n * convention["operand32"]]


def _instructions(entries: list[dict], convention: dict | None = None
                  ) -> tuple[dict[str, InstrSpec], dict[str, tuple[InstrSpec, ...]]]:
    """-> (mnemonic -> first spec, mnemonic -> every variant where there are several).

    `pulse = true` adds the P-suffix form of each width (MOVP, DMOVP); several entries may
    share a mnemonic (variants, told apart by their first operand's kind: OUT Y0 / OUT T0 K50)."""
    all_specs: dict[str, list[InstrSpec]] = {}
    for e in entries:
        operands = tuple(_operand(o) for o in e.get("operands", ()))
        notes = tuple(x for x in (e.get("note"), e.get("decision")) if x)
        is_float = bool(e.get("float", False))
        models = frozenset(e.get("models", ()))
        for width, name, steps in zip((16, 32), e["names"], _steps(e, convention), strict=True):
            if not name:
                continue
            for pulse in (False, True) if e.get("pulse") else (False,):
                spec = InstrSpec(
                    mnemonic=name + ("P" if pulse else ""), api=e.get("api"), width=width, is_float=is_float,
                    steps=steps, cls=e["class"], op=e["op"], operands=operands,
                    index=bool(e.get("index", e.get("api") is not None and e["class"] != "free")),
                    short_steps=e.get("steps_rule") == "short", table=e.get("table", 0),
                    constraints=tuple(e.get("constraints", ())),
                    section=e["section"], notes=notes, inputs=tuple(e.get("inputs", ())),
                    pulse=pulse, models=models, once=bool(e.get("once", False)),
                    unconditional=bool(e.get("unconditional", False)),
                    region=e.get("region", ""),
                )
                # aliases name the 16-bit form too (FBs: HSPSO is also written FUN140)
                aliases = e.get("aliases", []) if width == 16 and not pulse else []
                for alias in [spec.mnemonic] + aliases:
                    all_specs.setdefault(alias, []).append(spec)
    first = {k: v[0] for k, v in all_specs.items()}
    variants = {k: tuple(v) for k, v in all_specs.items() if len(v) > 1}
    return first, variants


def _device_range(name: str, v: dict, model: str | None) -> tuple[int, int]:
    rng = v.get("model_range", {}).get(model, v["range"]) if model else v["range"]
    return int(rng[0]), int(rng[1])


class UnknownModel(ValueError):
    """`--model` names no model of the target."""


def _area(a: dict) -> Area:
    return Area(**{k: v for k, v in a.items() if k != "models"})


def load_target(name: str, model: str | None = None) -> Target:
    """The target's tables; with models (target.toml `models`), cut to `model` (default:
    `default_model`): device ranges by `model_range`, instructions by their `models`. One
    Target per name and model however the call spells them (`load_target("vs")`,
    `load_target("vs", None)`, `model="vs1"` and "VS1" are one cache entry each, not several)."""
    return _load_target(name, model.upper() if model else None)


@cache
def _load_target(name: str, model: str | None) -> Target:
    try:
        folder = Path(target_package(name).tables)
    except UnknownTarget:
        raise KeyError(name) from None
    if not (folder / "target.toml").is_file():
        raise KeyError(name)
    settings = tomllib.loads((folder / "target.toml").read_text("utf-8"))
    models = settings.get("models", [])
    if model is not None or models:
        model = (model or settings.get("default_model") or models[0]).upper()
        if model not in models:
            raise UnknownModel(f"target {name} has no model {model!r}"
                               + (f"; models: {', '.join(models)}" if models else ""))
    devices_raw = tomllib.loads((folder / "devices.toml").read_text("utf-8"))
    devices = {}
    for k, v in devices_raw.items():
        if model and "models" in v and model not in v["models"]:
            continue  # the device does not exist on this model (UnG on VS1)
        lo, hi = _device_range(k, v, model)
        devices[k] = DeviceKind(
            name=k, kind=v["kind"], lo=lo, hi=hi,
            areas=tuple(_area(a) for a in v.get("areas", ()) if not model or model in a.get("models", [model])),
            section=v["section"], input=v.get("input", False), width16_only=v.get("width16_only", False),
            radix=v.get("radix", 10), bit_of_word=v.get("bit_of_word", False),
            unit_prefix=v.get("unit_prefix", ""), units=_units(v, model), like=v.get("like", ""),
        )
    entries = tomllib.loads((folder / "instructions.toml").read_text("utf-8"))["instr"]
    instrs, variants = _instructions(entries, settings.get("step_convention"))
    unavailable = {}
    if model:
        unavailable = {k: s for k, s in instrs.items() if s.models and model not in s.models}
        instrs = {k: s for k, s in instrs.items() if k not in unavailable}
        variants = {k: v for k, v in variants.items() if k not in unavailable}
    return Target(settings["name"], settings["title"], settings["manual"], settings["capacity"],
                  devices, instrs, settings, model, variants, unavailable)


def _units(v: dict, model: str | None) -> tuple[int, int]:
    lo, hi = v.get("model_units", {}).get(model or "", v.get("units", (0, -1)))
    return int(lo), int(hi)


_SYNTAX: dict[tuple[str, str | None], OperandSyntax] = {}


def _syntax_of(t: Target) -> OperandSyntax:
    o = t.settings.get("operands", {})
    return OperandSyntax(
        octal=frozenset(k for k, d in t.devices.items() if d.radix == 8),
        hex_constants=bool(o.get("hex_constants", False)),
        float_prefix=o.get("float_prefix", "F"),
        float_exponent=bool(o.get("float_exponent", False)),
        strings=bool(o.get("strings", False)),
        bit_of_word=frozenset(k for k, d in t.devices.items() if d.bit_of_word),
        unit_words=frozenset((d.unit_prefix, k) for k, d in t.devices.items() if d.unit_prefix),
        aliases=tuple(sorted(((a["prefix"].upper(), a["kind"], int(a["base"]), int(a["count"]))
                              for a in o.get("aliases", ())), key=lambda a: -len(a[0]))),
    )


def available_targets() -> list[str]:
    return target_names()
