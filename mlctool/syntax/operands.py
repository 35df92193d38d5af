"""Operand text -> Operand: devices, bit groups, constants, pointers, index suffixes.

Purely syntactic: whether a device kind or number is legal is the checker's business
(mlctool/check/operands.py), which asks the target.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from functools import lru_cache

CONSTANT_KINDS = frozenset({"K", "H", "F", "E", "$"})  # decimal, hex, float (NC5 F / VS E), string
FLOAT_KINDS = frozenset({"F", "E"})
BIT_OF_WORD = ".b"  # kind suffix of a bit-of-word operand: D0.5 has kind "D.b"


@dataclass(frozen=True, slots=True, eq=False)  # identity hash: a cheap lru_cache key
class OperandSyntax:
    """What a target's operands may look like beyond the common core (from its manual).

    The core is: devices `X0`, bit groups `K2M0`, decimal constants `K10`, index suffixes
    `D0V1`, and `F1.5` float constants when `float_prefix` is "F".
    """

    octal: frozenset[str] = frozenset()  # device kinds numbered in octal (X0-X7, X10 ...)
    hex_constants: bool = False  # H1F
    float_prefix: str = "F"  # letter of float constants: F12.3 (NC5), E1.5 (VS)
    float_exponent: bool = False  # E1.0235+2 (mantissa, signed decimal exponent)
    strings: bool = False  # "ABC" string constants
    bit_of_word: frozenset[str] = frozenset()  # word kinds with bit operands D0.F
    # words of a numbered unit, written prefix + unit + kind + number: ("U", "G") for the VS
    # special-module buffer memory U1G3 (unit 1, BFM#3); only the word number is indexable
    unit_words: frozenset[tuple[str, str]] = frozenset()
    # other names of devices (the manual's mnemonics): (prefix, kind, base, count); EC1D6 is
    # ("EC1D", "D", 9260, 20) -> D9266. Read as the device itself; listings write the device.
    aliases: tuple[tuple[str, str, int, int], ...] = ()


DEFAULT_SYNTAX = OperandSyntax()


@dataclass(frozen=True, slots=True)
class Operand:
    kind: str  # a device letter (X Y M A T C D V Z P ...), a constant kind (K H F E $),
    #            "KnX"/"KnY"/... for bit groups, "D.b"/"R.b" for a bit of a word
    number: int = 0  # device number (ordinal: X10 in octal is 8); for Kn groups the first bit device's
    value: int | float | str = 0  # K/H/F/E/$ constants
    digits: int = 0  # n of a Kn group
    index: tuple[str, int] | None = None  # ("V", 0) for a D5V0 style suffix
    decimals: int = 0  # digits after the point of an F constant as written
    bit: int = 0  # bit number of a bit-of-word operand (D0.F: 15)
    radix: int = 10  # how the device number is written (8 for octal X/Y)
    unit: str = ""  # unit of a unit word as written (U1G3: "U1"); "" for every other operand

    @property
    def is_const(self) -> bool:
        return self.kind in CONSTANT_KINDS

    @property
    def is_float(self) -> bool:
        return self.kind in FLOAT_KINDS

    @property
    def unit_number(self) -> int:
        """1 for U1G3; 0 when the operand has no unit."""
        return int(self.unit[1:]) if self.unit else 0

    @property
    def is_group(self) -> bool:
        return self.kind.startswith("Kn")

    @property
    def is_bit_of_word(self) -> bool:
        return self.kind.endswith(BIT_OF_WORD)

    @property
    def device(self) -> str:
        """The device kind a group or device lives in (X for K2X0, D for D0.5)."""
        if self.is_group:
            return self.kind[2:]
        return self.kind[:-len(BIT_OF_WORD)] if self.is_bit_of_word else self.kind

    def __str__(self) -> str:
        return format_operand(self)


class OperandSyntaxError(ValueError):
    pass


INDEX_REGISTERS = ("V", "Z")  # the index registers an operand can name (never the device of a Kn bit group)
_INDEX = r"(?:(?P<ix>[VZ])(?P<ixn>[0-9]+))?"
_GROUP = re.compile(r"K(?P<n>[0-9]+)(?P<dev>[A-Z])(?P<num>[0-9]+)" + _INDEX)
_K = re.compile(r"K(?P<val>[+-]?[0-9]+)" + _INDEX)
_H = re.compile(r"H(?P<val>[0-9A-F]+)" + _INDEX)
_FLOAT = r"(?P<val>[+-]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+))"
_EXPONENT = r"(?:(?P<exp>[+-][0-9]+))?"
_DEV = re.compile(r"(?P<dev>[A-Z])(?P<num>[0-9]+)" + _INDEX)
_BIT_OF_WORD = re.compile(r"(?P<dev>[A-Z])(?P<num>[0-9]+)\.(?P<bit>[0-9A-F])")
# a bit of a word with an index register, before or after the bit (D0.1Z0, D0Z0.1): not an
# operand (VS 5-1: D.b and R.b may not be index-modified), reported as such, not as a symbol
_INDEXED_BIT_OF_WORD = re.compile(r"[A-Z][0-9]+(?:\.[0-9A-F][VZ][0-9]+|[VZ][0-9]+\.[0-9A-F])")
_UNIT_WORD = re.compile(r"(?P<u>[A-Z])(?P<un>[0-9]+)(?P<dev>[A-Z])(?P<num>[0-9]+)" + _INDEX)
_STRING = re.compile(r'"(?P<val>[^"]*)"')
_HEX_DIGITS = re.compile(r"H[0-9A-F]+")
MAX_STRING = 32  # longest string constant any target takes (VS $+: 32 characters)


def _index(m) -> tuple[str, int] | None:
    return (m["ix"], int(m["ixn"])) if m["ix"] else None


def _number(digits: str, kind: str, syntax: OperandSyntax, text: str) -> tuple[int, int]:
    """(ordinal, radix) of a device number as written."""
    if kind in syntax.octal:
        if "8" in digits or "9" in digits:
            raise OperandSyntaxError(f"{text!r}: {kind} devices are numbered in octal "
                                     f"({kind}0-{kind}7, {kind}10 ...); digits 8 and 9 do not occur")
        return int(digits, 8), 8
    return int(digits), 10


def _alias(t: str, syntax: OperandSyntax, text: str) -> Operand | None:
    """EC1D6 -> D9266: a mnemonic of the target's for a device (longest prefix first)."""
    for prefix, kind, base, count in syntax.aliases:
        if t.startswith(prefix) and (m := re.fullmatch(r"(?P<num>[0-9]+)" + _INDEX, t[len(prefix):])):
            n = int(m["num"])
            if n >= count:
                raise OperandSyntaxError(f"{text!r}: {prefix}0-{prefix}{count - 1} only")
            return Operand(kind, number=base + n, index=_index(m))
    return None


@lru_cache(maxsize=65536)
def parse_operand(text: str, syntax: OperandSyntax = DEFAULT_SYNTAX) -> Operand:
    """Parse one operand as written (case-insensitive). Raises OperandSyntaxError.

    A plain device (`M1005`, `D5V0`) whose first letter no other form of the target claims,
    and a plain decimal constant (`K10`) where K is no other form's, are read at once;
    everything else goes through every form in order (full_parse_operand;
    tests/syntax/test_parser.py checks that both agree)."""
    t = text.upper()
    if len(t) <= 40:
        first, digits = t[:1], t[1:]
        if first not in _claimed_initials(syntax):
            if digits.isascii() and digits.isdigit() and "A" <= first <= "Z":  # M1005: no regex needed
                number, radix = _number(digits, first, syntax, text) if first in syntax.octal else (int(digits), 10)
                return _device(first, number, None, radix)
            if m := _DEV.fullmatch(t):  # D5V0
                kind, digits, ix = m.group("dev", "num", "ix")
                number, radix = _number(digits, kind, syntax, text) if kind in syntax.octal else (int(digits), 10)
                return _device(kind, number, (ix, int(m["ixn"])) if ix else None, radix)
        elif first == "K" and digits.isascii() and digits.isdigit() and _plain_k(syntax):
            return _k_constant(int(digits))
    return full_parse_operand(text, syntax)


_new = object.__new__
# the slots' own setters (a field added to Operand needs its line in _device: tests/syntax/test_parser.py)
(_set_kind, _set_number, _set_value, _set_digits, _set_index, _set_decimals, _set_bit, _set_radix,
 _set_unit) = (Operand.__dict__[f].__set__ for f in ("kind", "number", "value", "digits", "index", "decimals",
                                                     "bit", "radix", "unit"))


def _device(kind: str, number: int, index: tuple[str, int] | None, radix: int) -> Operand:
    """Operand(kind, number=number, index=index, radix=radix), built without the frozen
    dataclass's __init__, which stores each field through object.__setattr__: half the cost of
    reading a plain device, the operand most lines hold (issue 19)."""
    op = _new(Operand)
    _set_kind(op, kind)
    _set_number(op, number)
    _set_value(op, 0)
    _set_digits(op, 0)
    _set_index(op, index)
    _set_decimals(op, 0)
    _set_bit(op, 0)
    _set_radix(op, radix)
    _set_unit(op, "")
    return op


def _k_constant(value: int) -> Operand:
    """Operand("K", value=value), built as _device builds a device."""
    op = _new(Operand)
    _set_kind(op, "K")
    _set_number(op, 0)
    _set_value(op, value)
    _set_digits(op, 0)
    _set_index(op, None)
    _set_decimals(op, 0)
    _set_bit(op, 0)
    _set_radix(op, 10)
    _set_unit(op, "")
    return op


@lru_cache(maxsize=64)
def _plain_k(syntax: OperandSyntax) -> bool:
    """Whether K followed by digits only is a decimal constant and nothing else: no alias or
    unit word of the target starts with K (a float prefix is never K)."""
    return "K" not in {p[0] for p, *_ in syntax.aliases} | {u for u, _ in syntax.unit_words} | {syntax.float_prefix}


@lru_cache(maxsize=64)
def _claimed_initials(syntax: OperandSyntax) -> frozenset[str]:
    """First letters with which a text matching _DEV may be something else than that device:
    K constants and groups, H constants, float constants, aliases (EC1D6), unit words (U1G3)."""
    return frozenset({"K", "H", syntax.float_prefix} | {p[0] for p, *_ in syntax.aliases}
                     | {u for u, _ in syntax.unit_words})


def full_parse_operand(text: str, syntax: OperandSyntax = DEFAULT_SYNTAX) -> Operand:
    """parse_operand without its shortcut: every operand form, in order."""
    if syntax.strings and (m := _STRING.fullmatch(text)):
        if len(m["val"]) > MAX_STRING:
            raise OperandSyntaxError(f"string constant longer than {MAX_STRING} characters")
        return Operand("$", value=m["val"])
    t = text.upper()
    if len(t) > 40:
        raise OperandSyntaxError("operand is too long")
    if syntax.unit_words and (m := _UNIT_WORD.fullmatch(t)) and (m["u"], m["dev"]) in syntax.unit_words:
        return Operand(m["dev"], number=int(m["num"]), index=_index(m), unit=f'{m["u"]}{int(m["un"])}')
    if syntax.aliases and (op := _alias(t, syntax, text)) is not None:
        return op
    # K20V0 is the constant K20 modified by V0 (3.4's example), not a bit group of "V"
    if (m := _GROUP.fullmatch(t)) and m["dev"] not in INDEX_REGISTERS:
        number, radix = _number(m["num"], m["dev"], syntax, text)
        return Operand("Kn" + m["dev"], number=number, digits=int(m["n"]), index=_index(m), radix=radix)
    if m := _K.fullmatch(t):
        return Operand("K", value=int(m["val"]), index=_index(m))
    if syntax.hex_constants and (m := _H.fullmatch(t)):
        if len(m["val"]) > 8:
            raise OperandSyntaxError(f"{text!r}: a hexadecimal constant has at most 8 digits")
        return Operand("H", value=int(m["val"], 16), index=_index(m))
    prefix = syntax.float_prefix
    if t.startswith(prefix) and (m := re.fullmatch(prefix + _FLOAT + (_EXPONENT if syntax.float_exponent else ""), t)):
        # imported here: only float constants need it (start-up, issue 19)
        from decimal import Decimal, InvalidOperation

        try:
            d = Decimal(m["val"])
        except InvalidOperation as e:  # pragma: no cover - the regex admits only decimals
            raise OperandSyntaxError(f"bad float constant {text!r}") from e
        decimals = max(0, -d.as_tuple().exponent) if "." in m["val"] else 0
        exp = int(m["exp"]) if syntax.float_exponent and m["exp"] else 0
        if exp:
            if abs(exp) > 60:
                raise OperandSyntaxError(f"{text!r}: exponent out of range")
            d = d.scaleb(exp)
        # decimals as written matter only where a target limits them (NC5 F: 3); the exponent form has none
        return Operand(prefix, value=float(d), decimals=0 if syntax.float_exponent else decimals)
    if not syntax.hex_constants and _HEX_DIGITS.fullmatch(t):  # H10 is no device either
        raise OperandSyntaxError(f"{text!r}: this target has no hexadecimal H constants; write K{int(t[1:], 16)}")
    if m := _DEV.fullmatch(t):
        number, radix = _number(m["num"], m["dev"], syntax, text)
        return Operand(m["dev"], number=number, index=_index(m), radix=radix)
    if syntax.bit_of_word and (m := _BIT_OF_WORD.fullmatch(t)):
        if m["dev"] not in syntax.bit_of_word:
            raise OperandSyntaxError(f"{text!r}: only {'/'.join(sorted(syntax.bit_of_word))} words have bit operands")
        return Operand(m["dev"] + BIT_OF_WORD, number=int(m["num"]), bit=int(m["bit"], 16))
    if syntax.bit_of_word and _INDEXED_BIT_OF_WORD.fullmatch(t):
        raise OperandSyntaxError(f"{text!r}: a bit of a word ({'/'.join(k + '.b' for k in sorted(syntax.bit_of_word))}) "
                                 "cannot be index-modified")
    if re.fullmatch(r"[+-]?[0-9]+", t):
        raise OperandSyntaxError(f"{text!r}: a constant needs the K prefix (K{t})")
    raise OperandSyntaxError(f"{text!r} is not a device, constant or pointer")


def device_number(number: int, radix: int) -> str:
    """A device number as the manual writes it (octal X/Y on FX-family targets)."""
    return format(number, "o") if radix == 8 else str(number)


def format_operand(op: Operand) -> str:
    ix = f"{op.index[0]}{op.index[1]}" if op.index else ""
    if op.kind == "K":
        return f"K{op.value}{ix}"
    if op.kind == "H":
        return f"H{op.value:X}{ix}"
    if op.kind == "$":
        return f'"{op.value}"'
    if op.kind == "F":
        return "F" + (f"{op.value:.{op.decimals}f}" if op.decimals else f"{op.value:.0f}")
    if op.kind == "E":  # shortest text that reads back to the same value
        r = repr(float(op.value))
        if "e" in r:
            mantissa, exp = r.split("e")
            return f"E{mantissa}{int(exp):+d}"
        return "E" + (r[:-2] if r.endswith(".0") else r)
    if op.is_group:
        return f"K{op.digits}{op.device}{device_number(op.number, op.radix)}{ix}"
    if op.is_bit_of_word:
        return f"{op.device}{op.number}.{op.bit:X}"
    if op.unit:
        return f"{op.unit}{op.kind}{op.number}{ix}"
    return f"{op.kind}{device_number(op.number, op.radix)}{ix}"


SYMBOL = re.compile(r"[A-Za-z_][A-Za-z0-9_.]*")

# Han ideographs of the BMP (CJK Unified Ideographs, Extension A, Compatibility Ideographs):
# the Chinese characters VS names may hold (2-10 "8個中文字或16個英文數字"). The same ranges
# stand in grammars/il.lark's MNEMONIC and OPERAND (tests/check/test_cjk_names.py compares them).
# Only targets whose target.toml `named_labels` has `cjk_width` accept them (check/labels.py).
CJK_RANGES = r"\u3400-\u4DBF\u4E00-\u9FFF\uF900-\uFAFF"


class LazyPattern:
    """A regex compiled when first used. A class of the Han ranges takes ~2 ms to compile
    (re builds its 64k-entry map in Python), at every start of mlc; most runs read ASCII
    sources only and never use one."""

    __slots__ = ("_source", "_compiled")

    def __init__(self, source: str):
        self._source = source
        self._compiled: re.Pattern | None = None

    @property
    def pattern(self) -> re.Pattern:
        if self._compiled is None:
            self._compiled = re.compile(self._source)
        return self._compiled

    def search(self, text: str, *args) -> re.Match | None:
        return self.pattern.search(text, *args)

    def fullmatch(self, text: str, *args) -> re.Match | None:
        return self.pattern.fullmatch(text, *args)

    def findall(self, text: str, *args) -> list:
        return self.pattern.findall(text, *args)


CJK_CHAR = LazyPattern(f"[{CJK_RANGES}]")
WIDE_SYMBOL = LazyPattern(f"[A-Za-z_{CJK_RANGES}][A-Za-z0-9_.{CJK_RANGES}]*")


def name_width(text: str, cjk_width: int) -> int:
    """Length of a name by the manual's count: a Han ideograph counts `cjk_width` (VS: 2, so
    16 units are 16 letters/digits, 8 ideographs, or a mix like 變頻器1通訊 = 11)."""
    return len(text) + (cjk_width - 1) * len(CJK_CHAR.findall(text))
