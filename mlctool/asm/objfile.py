"""The object file format (docs/object-format.md): ObjectFile <-> bytes.

One format serves object modules (.mlo: one unit, addresses from 0) and linked programs
(.mlx: every unit at its final address). Layout: a 16-byte header, tagged sections, and a
SHA-256 trailer over everything before it. Integers are LEB128 varints (zigzag for signed
values), strings are indices into the STRS section. Nothing depends on time, host or cwd.
"""

from __future__ import annotations

import hashlib
import math
import re
import struct
from dataclasses import dataclass, field

from mlctool.check.resolve import OperandRules
from mlctool.program import Instr
from mlctool.syntax.operands import CONSTANT_KINDS, FLOAT_KINDS, MAX_STRING, Operand
from mlctool.syntax.source import MAX_LINES
from mlctool.targetapi.model import Target, choose_variant, load_target

MAGIC = b"\x7fMLCOBJ\n"
VERSION = 1
KINDS = ("module", "program")  # .mlo, .mlx
HEADER = struct.Struct("<8sHBBI")  # magic, version, kind, reserved, total length
TRAILER = 32  # SHA-256
SECTIONS = (b"TRGT", b"STRS", b"UNIT", b"CODE", b"SYMS", b"RELO", b"LINE")
FLAG_INSERTED = 1  # instruction inserted by the linker (the FEND before library code)
# Bounds of what a decoded object may hold (docs/object-format.md "Validation"): line
# numbers as a source can have them (syntax/source.py), columns up to MAX_COL (DECISION: a
# statement starts in the first 65,535 characters of its line), at most MAX_DECIMALS digits
# after the point of a float constant as written.
MAX_COL = 65_535
MAX_DECIMALS = 64
_CONTROL = re.compile(r"[\x00-\x08\x0a-\x1f\x7f]")  # every control character but TAB


@dataclass(frozen=True, slots=True)
class Directive:
    """A directive line as written (`.define`, `.export`, `.library`): kept so that
    `objdump --il` can put it back on its line and the round trip gives the same bytes."""

    line: int
    col: int
    text: str


@dataclass(slots=True)
class Unit:
    """One source module inside an object file."""

    path: str  # the source's name relative to the project root (docs/object-format.md)
    library: bool = False
    first: int = 0  # address range [first, end) of its code in this file
    end: int = 0
    exports: tuple[int, ...] = ()
    symbols: dict[str, str] = field(default_factory=dict)  # device symbols: NAME -> operand
    directives: tuple[Directive, ...] = ()


@dataclass(slots=True)
class ObjectFile:
    kind: str  # "module" | "program"
    target: str
    units: list[Unit]
    instrs: list[Instr]  # Instr.file is the path of its unit
    unit_of: list[int]  # unit index of each instruction
    inserted: frozenset[int] = frozenset()  # indices of linker-inserted instructions
    digest: str = ""  # SHA-256 (hex) of the bytes it was decoded from; "" when built in memory

    @property
    def total_steps(self) -> int:
        return sum(i.steps for i in self.instrs)

    def relocations(self) -> list[tuple[int, int]]:
        """(instruction index, P) of every CJ/CALL whose label its own unit does not define."""
        own: set[tuple[int, int]] = {(u, ins.operands[0].number) for ins, u in zip(self.instrs, self.unit_of)
                                     if ins.spec.cls == "label"}
        ends = _end_labels(self.target)  # CJ P63 on VS: END, never a relocation
        return [(k, ins.operands[0].number) for k, (ins, u) in enumerate(zip(self.instrs, self.unit_of))
                if ins.spec.op in ("cj", "call") and not ins.operands[0].index
                and (u, ins.operands[0].number) not in own
                and not (ins.spec.op == "cj" and ins.operands[0].number in ends)]


def _end_labels(target: str) -> frozenset[int]:
    try:
        return load_target(target).end_labels
    except KeyError:
        return frozenset()


class ObjectError(Exception):
    """Bad object bytes; `code` is E501 (not an object), E502 (corrupt) or E503 (mismatch)."""

    def __init__(self, code: str, message: str):
        super().__init__(message)
        self.code = code


# ------------------------------------------------------------------ primitive encoding

class _Writer:
    def __init__(self) -> None:
        self.buf = bytearray()

    def uint(self, n: int) -> None:
        if 0 <= n < 0x80:  # most numbers: one byte
            self.buf.append(n)
            return
        if n < 0:
            raise ValueError(f"negative unsigned value {n}")
        while True:
            b = n & 0x7F
            n >>= 7
            self.buf.append(b | (0x80 if n else 0))
            if not n:
                return

    def sint(self, n: int) -> None:
        self.uint(n * 2 if n >= 0 else -n * 2 - 1)

    def f64(self, x: float) -> None:
        self.buf += struct.pack("<d", x)


class _Reader:
    def __init__(self, data: bytes) -> None:
        self.data = data
        self.pos = 0

    def bad(self, what: str) -> ObjectError:
        return ObjectError("E502", f"{what} at byte {self.pos}")

    def uint(self) -> int:
        if self.pos < len(self.data) and self.data[self.pos] < 0x80:  # one byte
            self.pos += 1
            return self.data[self.pos - 1]
        n = shift = 0
        while True:
            if self.pos >= len(self.data) or shift > 63:
                raise self.bad("bad number")
            b = self.data[self.pos]
            self.pos += 1
            n |= (b & 0x7F) << shift
            shift += 7
            if not b & 0x80:
                return n

    def sint(self) -> int:
        n = self.uint()
        return n >> 1 if not n & 1 else -(n >> 1) - 1

    def f64(self) -> float:
        if self.pos + 8 > len(self.data):
            raise self.bad("truncated float")
        (x,) = struct.unpack_from("<d", self.data, self.pos)
        self.pos += 8
        return x

    def take(self, n: int) -> bytes:
        if n > len(self.data) - self.pos:
            raise self.bad("truncated data")
        out = self.data[self.pos:self.pos + n]
        self.pos += n
        return out

    def done(self) -> bool:
        return self.pos == len(self.data)


class _Strings:
    """The string table, in order of first use (deterministic)."""

    def __init__(self) -> None:
        self.index: dict[str, int] = {}

    def __call__(self, s: str) -> int:
        return self.index.setdefault(s, len(self.index))


# ------------------------------------------------------------------ encode

def _operand(w: _Writer, s: _Strings, op: Operand) -> None:
    # flags: 1 index, 2 float value, 4 string value, 8 bit of a word (the bit follows), 16 unit
    # word (its unit's string follows: U1G3); operands without a bit or unit encode as before
    is_str = isinstance(op.value, str)
    w.uint(s(op.kind))
    w.uint((1 if op.index else 0) | (2 if isinstance(op.value, float) else 0) | (4 if is_str else 0)
           | (8 if op.is_bit_of_word else 0) | (16 if op.unit else 0))
    w.uint(op.number)
    if isinstance(op.value, float):
        w.f64(op.value)
    elif is_str:
        w.uint(s(op.value))
    else:
        w.sint(op.value)
    w.uint(op.digits)
    w.uint(op.decimals)
    if op.index:
        w.uint(s(op.index[0]))
        w.uint(op.index[1])
    if op.is_bit_of_word:
        w.uint(op.bit)
    if op.unit:
        w.uint(s(op.unit))


def encode(obj: ObjectFile) -> bytes:
    s = _Strings()
    sections: dict[bytes, _Writer] = {tag: _Writer() for tag in SECTIONS}
    unit_index = {u.path: k for k, u in enumerate(obj.units)}

    w = sections[b"UNIT"]
    w.uint(len(obj.units))
    for u in obj.units:
        w.uint(s(u.path))
        w.uint(1 if u.library else 0)
        w.uint(u.first)
        w.uint(u.end)
        w.uint(len(u.directives))
        for d in u.directives:
            w.uint(d.line)
            w.uint(d.col)
            w.uint(s(d.text))

    w = sections[b"CODE"]
    w.uint(len(obj.instrs))
    for k, ins in enumerate(obj.instrs):
        w.uint(s(ins.spec.mnemonic))  # the instruction id
        w.uint(FLAG_INSERTED if k in obj.inserted else 0)
        w.uint(ins.steps)
        w.uint(ins.addr)
        w.uint(len(ins.operands))
        for op in ins.operands:
            _operand(w, s, op)
        w.uint(len(ins.texts))
        for t in ins.texts:
            w.uint(s(t))
        w.uint(len(ins.table))
        for v in ins.table:
            w.sint(v)

    w = sections[b"SYMS"]
    labels = [(u, ins.operands[0].number, ins.addr) for ins, u in zip(obj.instrs, obj.unit_of)
              if ins.spec.cls == "label"]
    w.uint(len(labels))
    for u, p, addr in labels:
        w.uint(u)
        w.uint(p)
        w.uint(addr)
        w.uint(1 if p in obj.units[u].exports else 0)
    syms = [(k, name, value) for k, u in enumerate(obj.units) for name, value in u.symbols.items()]
    w.uint(len(syms))
    for k, name, value in syms:
        w.uint(k)
        w.uint(s(name))
        w.uint(s(value))

    w = sections[b"RELO"]
    relocs = obj.relocations()
    w.uint(len(relocs))
    for k, p in relocs:
        w.uint(k)
        w.uint(p)

    w = sections[b"LINE"]
    w.uint(len(obj.instrs))
    for ins in obj.instrs:
        w.uint(ins.addr)
        w.uint(unit_index[ins.file])
        w.uint(ins.line)
        w.uint(ins.col)

    w = sections[b"TRGT"]
    w.uint(s(obj.target))

    strings = _Writer()
    strings.uint(len(s.index))
    for text in s.index:
        raw = text.encode("utf-8")
        strings.uint(len(raw))
        strings.buf += raw
    sections[b"STRS"] = strings

    body = bytearray()
    for tag in SECTIONS:
        payload = sections[tag].buf
        body += tag + struct.pack("<I", len(payload)) + payload
    total = HEADER.size + len(body) + TRAILER
    head = HEADER.pack(MAGIC, VERSION, KINDS.index(obj.kind), 0, total)
    data = head + bytes(body)
    return data + hashlib.sha256(data).digest()


# ------------------------------------------------------------------ decode

def check_envelope(data: bytes) -> tuple[str, dict[bytes, bytes]]:
    """Magic, version, length and checksum; returns (kind, sections)."""
    if len(data) < len(MAGIC) or data[:len(MAGIC)] != MAGIC:
        raise ObjectError("E501", "not an mlctool object file (no object magic)")
    if len(data) < HEADER.size + TRAILER:
        raise ObjectError("E502", f"truncated: {len(data)} bytes")
    _magic, version, kind, _reserved, total = HEADER.unpack_from(data)
    if version != VERSION:
        raise ObjectError("E503", f"object format version {version}; this mlctool reads version {VERSION}")
    if total != len(data):
        raise ObjectError("E502", f"truncated or padded: header says {total} bytes, file has {len(data)}")
    if hashlib.sha256(data[:-TRAILER]).digest() != data[-TRAILER:]:
        raise ObjectError("E502", "integrity check failed (SHA-256 mismatch)")
    if kind >= len(KINDS):
        raise ObjectError("E502", f"unknown object kind {kind}")
    r = _Reader(data[HEADER.size:-TRAILER])
    sections: dict[bytes, bytes] = {}
    while not r.done():
        tag = r.take(4)
        (n,) = struct.unpack("<I", r.take(4))
        sections[tag] = r.take(n)
    missing = [t.decode() for t in SECTIONS if t not in sections]
    if missing:
        raise ObjectError("E502", f"missing section {missing[0]}")
    return KINDS[kind], sections


def _read_strings(payload: bytes) -> list[str]:
    r = _Reader(payload)
    out = []
    for _ in range(r.uint()):
        try:
            out.append(r.take(r.uint()).decode("utf-8"))
        except UnicodeDecodeError as e:
            raise r.bad("bad string") from e
    return out


class _Decoder:
    def __init__(self, sections: dict[bytes, bytes], target: Target):
        self.sections = sections
        self.target = target
        self.strings = _read_strings(sections[b"STRS"])

    def reader(self, tag: bytes) -> _Reader:
        return _Reader(self.sections[tag])

    def str(self, r: _Reader) -> str:
        k = r.uint()
        if k >= len(self.strings):
            raise r.bad("bad string index")
        return self.strings[k]


def _validate(k: int, spec, operands, texts, table, steps, target) -> None:
    """The shape the target's tables give an instruction, so a well-formed but wrong object
    (written by another tool, or crafted) cannot reach the simulator."""
    ok = (len(operands) == len(spec.operands) and len(texts) == len(operands)
          and len(table) == spec.table and steps == target.instr_steps(spec, operands))
    if not ok:
        raise ObjectError("E502", f"instruction {k} ({spec.mnemonic}) does not have the form "
                          "the target's tables give it")


def _bad(what: str) -> ObjectError:
    return ObjectError("E502", what)


def _plain(text: str, what: str) -> None:
    if _CONTROL.search(text):
        raise _bad(f"{what} {text!r} holds a control character")


def _position(line: int, col: int, what: str) -> None:
    if not (0 <= line <= MAX_LINES and 0 <= col <= MAX_COL):
        raise _bad(f"{what} at line {line}, column {col}: outside lines 0-{MAX_LINES}, columns 0-{MAX_COL}")


def _operand_shape(op: Operand, where: str) -> None:
    """What the encoder can have written for an operand, before any rule reads it."""
    if op.kind in ("K", "H") and type(op.value) is not int \
            or op.kind in FLOAT_KINDS and (type(op.value) is not float or not math.isfinite(op.value)) \
            or op.kind == "$" and (type(op.value) is not str or len(op.value) > MAX_STRING) \
            or op.kind not in CONSTANT_KINDS and op.value != 0:
        raise _bad(f"{where}: a {op.kind!r} operand with value {op.value!r:.40}")
    if op.decimals > MAX_DECIMALS or op.digits > 8 or op.bit > 15:
        raise _bad(f"{where}: operand digits {op.digits}, decimals {op.decimals}, bit {op.bit} out of range")
    for text in (op.kind, op.unit, *(op.index[:1] if op.index else ()), *([op.value] if op.kind == "$" else [])):
        _plain(text, f"{where}: operand text")


def validate(obj: ObjectFile, target: Target) -> None:
    """Everything decode() rebuilt, against `target`: operands as `mlc check` takes them
    (kinds, device numbers, index registers, constants), labels and exports in the pointer
    range, positions within the bounds of a source, names without control characters. An
    object whose seal is valid but whose contents are not (crafted, or written by another
    tool) stops here with E502, before the simulator or objdump read it."""
    rules = OperandRules(target)
    for u in obj.units:
        if not u.path:
            raise _bad("a unit without a name")
        _plain(u.path, "module name")
        for d in u.directives:
            _position(d.line, d.col, f"directive of {u.path!r}")
            _plain(d.text, "directive")
        for name, value in u.symbols.items():
            _plain(name, "symbol name")
            _plain(value, "symbol value")
    labels = next((s for s in target.instructions.values() if s.cls == "label"), None)
    # an instruction's spec and operands checked once per distinct pair: decode() shares equal
    # operands, so the pair is known by the objects' ids (alive in `obj` meanwhile)
    checked: set[tuple] = set()
    for k, ins in enumerate(obj.instrs):
        if not (0 <= ins.line <= MAX_LINES and 0 <= ins.col <= MAX_COL):
            _position(ins.line, ins.col, f"instruction {k} ({ins.mnemonic})")
        for text in ins.texts:
            if _CONTROL.search(text):
                _plain(text, f"instruction {k} ({ins.mnemonic}): operand as written")
        form = (id(ins.spec), *map(id, ins.operands))
        if form not in checked:
            where = f"instruction {k} ({ins.mnemonic})"
            for op in ins.operands:
                _operand_shape(op, where)
            problems = rules.errors(ins.spec, ins.operands)
            if problems:
                raise _bad(f"{where}: {problems[0]}")
            checked.add(form)
        if ins.table:
            where = f"instruction {k} ({ins.mnemonic})"
            lo, hi = target.krange(ins.spec.width)
            if not all(lo <= v <= hi for v in ins.table):
                raise _bad(f"{where}: a table entry outside K{lo}..K{hi}")
    if labels is not None:
        for u in obj.units:
            for p in u.exports:
                problems = rules.errors(labels, (Operand("P", number=p),))
                if problems:
                    raise _bad(f"export of {u.path!r}: {problems[0]}")


def decode(data: bytes, target: Target) -> ObjectFile:
    """Bytes -> ObjectFile, Instr objects rebuilt against `target`. Raises ObjectError.

    An object this mlctool has decoded and validated for this target before (the same bytes:
    its SHA-256 seal) is rebuilt from the on-disk cache (mlctool/cache.py) instead: a 64k-step
    program in ~0.1 s instead of ~0.6 s. Only objects that passed validate() get an entry, and
    a damaged or foreign entry is ignored (decoded and validated again)."""
    kind, sections = check_envelope(data)
    digest = data[-TRAILER:].hex()  # the seal check_envelope verified
    key = _cache_key(digest, target)
    if key is not None:
        obj = _from_cache(key, target, digest)
        if obj is not None:
            return obj
    try:
        obj = _decode(kind, sections, target)
        validate(obj, target)
        obj.digest = digest
    except ObjectError:
        raise
    except (ValueError, IndexError, KeyError, OverflowError, TypeError, struct.error) as e:
        raise ObjectError("E502", f"malformed contents ({type(e).__name__})") from e
    if key is not None:
        _to_cache(key, obj, target)
    return obj


# ------------------------------------------------------------------ the decoded-object cache

_CACHE_KIND = "object"


def _cache_key(digest: str, target: Target) -> bytes | None:
    from mlctool import cache

    if not cache.enabled():
        return None
    return cache.key(_CACHE_KIND, digest, cache.target_identity(target))


def _to_cache(key: bytes, obj: ObjectFile, target: Target) -> None:
    """The validated object as plain values: each operand once, instructions as indices."""
    from mlctool import cache

    operand_index: dict[int, int] = {}
    operands: list[tuple] = []
    specs: dict[tuple[str, int], int] = {}  # (mnemonic, index among its variants) -> spec number
    variant_of: dict[int, tuple[str, int]] = {}
    rows = []
    for ins in obj.instrs:
        ops = []
        for op in ins.operands:
            k = operand_index.get(id(op))
            if k is None:
                k = operand_index[id(op)] = len(operands)
                operands.append((op.kind, op.number, op.value, op.digits, op.index, op.decimals, op.bit,
                                 op.radix, op.unit))
            ops.append(k)
        named = variant_of.get(id(ins.spec))
        if named is None:
            variants = target.variants_of(ins.spec.mnemonic)
            j = next((j for j, v in enumerate(variants) if v is ins.spec), None)
            if j is None:
                return  # a spec the target does not hand out: not kept
            named = variant_of[id(ins.spec)] = (ins.spec.mnemonic, j)
        sk = specs.setdefault(named, len(specs))
        rows.append((sk, tuple(ops), ins.texts, ins.steps, ins.addr, ins.line, ins.col, ins.table))
    units = [(u.path, u.library, u.first, u.end, u.exports, u.symbols,
              tuple((d.line, d.col, d.text) for d in u.directives)) for u in obj.units]
    cache.store(_CACHE_KIND, key, (obj.kind, obj.target, units, list(specs), operands, rows,
                                   obj.unit_of, sorted(obj.inserted)))


def _from_cache(key: bytes, target: Target, digest: str) -> ObjectFile | None:
    """The object _to_cache kept under `key`, or None (no entry, or one that does not fit)."""
    from mlctool import cache

    value = cache.load(_CACHE_KIND, key, lambda v: isinstance(v, tuple) and len(v) == 8)
    if value is None:
        return None
    try:
        kind, target_name, unit_rows, spec_names, operand_rows, rows, unit_of, inserted = value
        specs = [target.variants_of(mnemonic)[j] for mnemonic, j in spec_names]
        operands = [Operand(*row) for row in operand_rows]
        units = [Unit(path, library, first, end, exports, symbols, tuple(Directive(*d) for d in directives))
                 for path, library, first, end, exports, symbols, directives in unit_rows]
        paths = [u.path for u in units]
        instrs = [Instr(specs[sk], tuple([operands[k] for k in ops]), texts, steps, addr, paths[unit], line,
                        col, table)
                  for (sk, ops, texts, steps, addr, line, col, table), unit in zip(rows, unit_of, strict=True)]
        return ObjectFile(kind, target_name, units, instrs, list(unit_of), frozenset(inserted), digest)
    except (ValueError, TypeError, IndexError, KeyError):
        return None


def _decode(kind: str, sections: dict[bytes, bytes], target: Target) -> ObjectFile:
    d = _Decoder(sections, target)
    r = d.reader(b"TRGT")
    target_name = d.str(r)
    if target_name != target.name:
        raise ObjectError("E503", f"object is for target {target_name!r}, not {target.name!r}")

    r = d.reader(b"UNIT")
    units = []
    for _ in range(r.uint()):
        path = d.str(r)
        library = bool(r.uint())
        first, end = r.uint(), r.uint()
        directives = tuple(Directive(r.uint(), r.uint(), d.str(r)) for _ in range(r.uint()))
        units.append(Unit(path, library, first, end, (), {}, directives))

    lines = _varints(sections[b"LINE"])
    if not lines or (len(lines) - 1) != 4 * lines[0]:
        raise ObjectError("E502", "malformed line table")
    instrs, unit_of, inserted = _decode_code(sections[b"CODE"], d.strings, target, lines, units)
    addr = 0
    for k, ins in enumerate(instrs):
        if ins.addr != addr:
            raise ObjectError("E502", f"instruction {k} at step {ins.addr}, expected {addr}")
        addr += ins.steps
    if any(not 0 <= u.first <= u.end <= addr for u in units) or (kind == "module" and len(units) != 1):
        raise ObjectError("E502", "unit address ranges do not fit the code")

    r = d.reader(b"SYMS")
    for _ in range(r.uint()):
        unit, p, _addr, exported = r.uint(), r.uint(), r.uint(), r.uint()
        if exported:
            units[unit].exports += (p,)
    for _ in range(r.uint()):
        unit = r.uint()
        name = d.str(r)  # (a subscript assignment would read the value first)
        units[unit].symbols[name] = d.str(r)
    return ObjectFile(kind, target_name, units, instrs, unit_of, frozenset(inserted))


def _varints(payload: bytes) -> list[int]:
    """Every LEB128 number of a section that holds nothing else, in one pass over its bytes."""
    out = []
    n = shift = 0
    for b in payload:
        if b < 0x80:
            out.append(n | b << shift)
            n = shift = 0
        else:
            n |= (b & 0x7F) << shift
            shift += 7
            if shift > 63:
                raise ObjectError("E502", "bad number in a section")
    if shift:
        raise ObjectError("E502", "truncated number at the end of a section")
    return out


def _long_uint(data: bytes, pos: int) -> tuple[int, int]:
    """The LEB128 number at `pos` whose first byte has its high bit set: (value, next pos)."""
    n = shift = 0
    while True:
        if pos >= len(data) or shift > 63:
            raise ObjectError("E502", f"bad number at byte {pos}")
        b = data[pos]
        pos += 1
        n |= (b & 0x7F) << shift
        shift += 7
        if not b & 0x80:
            return n, pos


def _decode_code(data: bytes, strings: list[str], target: Target, lines: list[int],
                 units: list[Unit]) -> tuple[list[Instr], list[int], set[int]]:
    """The CODE section in one loop (a 64k-step program has ~750 k numbers in it): each number
    read inline (one byte below 0x80, _long_uint otherwise); equal operands decoded once and
    shared (Operand is frozen); an instruction's form (spec, operands, steps) checked by
    _validate once per distinct form. Same results and errors as reading field by field."""
    pos = 0
    v = data[pos]
    pos += 1
    if v > 0x7F:
        v, pos = _long_uint(data, pos - 1)
    count = v
    if count != lines[0]:
        raise ObjectError("E502", f"{count} instructions but {lines[0]} line-table entries")
    specs: dict[int, tuple] = {}  # string index of the mnemonic -> (spec, variants)
    radix: dict[int, int] = {}  # string index of an operand kind -> its radix
    operands_of: dict[tuple, Operand] = {}  # the numbers of an operand -> the Operand
    forms: dict[tuple, tuple] = {}  # (mnemonic, steps, operand keys, texts, table) -> (spec, operands)
    paths = [u.path for u in units]
    instrs: list[Instr] = []
    unit_of: list[int] = []
    inserted = set()
    f64 = struct.Struct("<d").unpack_from
    for k in range(count):
        v = data[pos]
        pos += 1
        if v > 0x7F:
            v, pos = _long_uint(data, pos - 1)
        mn = v
        hit = specs.get(mn)
        if hit is None:
            if mn >= len(strings):
                raise ObjectError("E502", f"bad string index at byte {pos}")
            mnemonic = strings[mn]
            spec = target.instruction(mnemonic)
            if spec is None or spec.mnemonic != mnemonic:
                raise ObjectError("E503", f"instruction {mnemonic!r} does not exist on target {target.name}"
                                  + (f" model {target.model}" if target.model else ""))
            variants = target.variants_of(mnemonic)
            hit = specs[mn] = (spec, variants if len(variants) > 1 else None)
        fields = []  # flags, steps, addr, operand count: four numbers
        for _ in range(4):
            v = data[pos]
            pos += 1
            if v > 0x7F:
                v, pos = _long_uint(data, pos - 1)
            fields.append(v)
        flags, steps, addr, nops = fields
        if flags & FLAG_INSERTED:
            inserted.add(k)
        keys = []
        ops = []
        for _ in range(nops):
            start = pos
            num = []  # kind, flags, number
            for _ in range(3):
                v = data[pos]
                pos += 1
                if v > 0x7F:
                    v, pos = _long_uint(data, pos - 1)
                num.append(v)
            oflags = num[1]
            if oflags & 2:
                if pos + 8 > len(data):
                    raise ObjectError("E502", f"truncated float at byte {pos}")
                pos += 8
            v = data[pos]  # the value (string index or zigzag integer), or digits after a float
            pos += 1
            if v > 0x7F:
                v, pos = _long_uint(data, pos - 1)
            rest = 2 + (2 if oflags & 1 else 0) + (1 if oflags & 8 else 0) + (1 if oflags & 16 else 0)
            if oflags & 2:
                rest -= 1  # that number was the digits
            for _ in range(rest):
                v = data[pos]
                pos += 1
                if v > 0x7F:
                    v, pos = _long_uint(data, pos - 1)
            key = data[start:pos]  # an operand's bytes say all of it
            op = operands_of.get(key)
            if op is None:
                op = operands_of[key] = _operand_from(key, strings, target, radix, f64)
            keys.append(key)
            ops.append(op)
        v = data[pos]
        pos += 1
        if v > 0x7F:
            v, pos = _long_uint(data, pos - 1)
        texts = []
        for _ in range(v):
            t = data[pos]
            pos += 1
            if t > 0x7F:
                t, pos = _long_uint(data, pos - 1)
            texts.append(strings[t])  # IndexError: malformed contents (decode)
        v = data[pos]
        pos += 1
        if v > 0x7F:
            v, pos = _long_uint(data, pos - 1)
        table = []
        for _ in range(v):
            t = data[pos]
            pos += 1
            if t > 0x7F:
                t, pos = _long_uint(data, pos - 1)
            table.append(t >> 1 if not t & 1 else -(t >> 1) - 1)
        form = (mn, steps, tuple(keys), len(texts), tuple(table))
        known = forms.get(form)
        if known is None:
            spec, variants = hit
            operands = tuple(ops)
            if variants is not None:  # OUT Y0 / OUT T0 K50: the operands tell the variant
                spec = choose_variant(variants, len(operands), operands[0] if operands else None)
            _validate(k, spec, operands, texts, table, steps, target)
            known = forms[form] = (spec, operands, tuple(table))
        spec, operands, table_t = known
        at = 1 + 4 * k
        laddr, unit, line, col = lines[at:at + 4]
        if laddr != addr or unit >= len(units):
            raise ObjectError("E502", f"line table disagrees with code at instruction {k}")
        instrs.append(Instr(spec, operands, tuple(texts), steps, addr, paths[unit], line, col, table_t))
        unit_of.append(unit)
    return instrs, unit_of, inserted


def _operand_from(raw: bytes, strings: list[str], target: Target, radix: dict[int, int], f64) -> Operand:
    """One operand's bytes (as _operand wrote them) -> Operand."""
    r = _Reader(raw)
    k = r.uint()
    flags = r.uint()
    number = r.uint()
    value = r.f64() if flags & 2 else strings[r.uint()] if flags & 4 else r.sint()
    digits = r.uint()
    decimals = r.uint()
    index = (strings[r.uint()], r.uint()) if flags & 1 else None
    bit = r.uint() if flags & 8 else 0
    unit = strings[r.uint()] if flags & 16 else ""
    kind = strings[k]
    rdx = radix.get(k)
    if rdx is None:
        dev = target.devices.get(kind[2:] if kind.startswith("Kn") else kind)
        rdx = radix[k] = dev.radix if dev is not None else 10  # how the target writes the number (octal X/Y)
    return Operand(kind, number, value, digits, index, decimals, bit, rdx, unit)


def read_header_target(data: bytes) -> str:
    """The target named by a verified object (for commands that default to it)."""
    _kind, sections = check_envelope(data)
    try:
        strings = _read_strings(sections[b"STRS"])
        return strings[_Reader(sections[b"TRGT"]).uint()]
    except (IndexError, ValueError) as e:
        raise ObjectError("E502", "malformed target section") from e
