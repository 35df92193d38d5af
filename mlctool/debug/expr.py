"""Device expressions of the debugger: `D0 > 100 && Y0`, `T3:w >= 20`, `!(X0 || X1)`.

Devices are named as in stimulus files (mlctool/sim/state.py parse_device_name: X0, T3:w,
D0:d, D0:f, K4M0, ...) or by a program symbol; numbers as stimulus values (decimal, K10,
H0F, 1.5). A bare device is true when it is not 0. Operators, loosest first: `||`, `&&`,
`!`, comparisons (`==` or `=`, `!=`, `<`, `<=`, `>`, `>=`), `+ -`, `* / %`, unary `-`.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Mapping

from mlctool.sim.state import DeviceView, Machine, NameError_, parse_device_name

_TOKEN = re.compile(r"\s*(?:(?P<op>\|\||&&|==|!=|<=|>=|[<>=!()+\-*/%])|(?P<num>(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)"
                    r"(?:[eE][-+]?[0-9]+)?(?![\w#.:])|[Hh][0-9A-Fa-f]+(?=\s|$|[)<>=!&|+\-*/%])"
                    r"|[Kk]-?[0-9]+(?=\s|$|[)<>=!&|+\-*/%]))|(?P<name>[^\s()<>=!&|+\-*/%]+))")


class ExprError(ValueError):
    """A malformed expression: the message says where."""


Value = Callable[[Machine], int | float]


def _num(text: str) -> int | float:
    u = text.upper()
    if u.startswith("H"):
        return int(u[1:], 16)
    if u.startswith("K"):
        return int(u[1:])
    return float(text) if any(c in text for c in ".eE") else int(text)


class Expr:
    """A parsed expression: `value(m)` evaluates it on a machine; `devices` it reads."""

    def __init__(self, text: str, target, symbols: Mapping[str, str] | None = None):
        self.text = text
        self.devices: list[DeviceView] = []
        self._target = target
        self._symbols = symbols or {}
        self._toks = self._tokenize(text)
        self._i = 0
        if not self._toks:
            raise ExprError("empty expression")
        self.value: Value = self._or()
        if self._i < len(self._toks):
            raise ExprError(f"unexpected {self._toks[self._i][1]!r} in {text!r}")

    def truth(self, m: Machine) -> bool:
        return bool(self.value(m))

    @staticmethod
    def _tokenize(text: str) -> list[tuple[str, str]]:
        out, pos = [], 0
        text = text.rstrip()
        while pos < len(text):
            mt = _TOKEN.match(text, pos)
            if not mt or mt.end() == pos:
                raise ExprError(f"cannot read {text[pos:]!r}")
            kind = mt.lastgroup
            out.append((kind, mt[kind]))
            pos = mt.end()
        return out

    def _peek(self) -> str | None:
        return self._toks[self._i][1] if self._i < len(self._toks) else None

    def _take(self) -> tuple[str, str]:
        if self._i >= len(self._toks):
            raise ExprError(f"{self.text!r} ends too early")
        self._i += 1
        return self._toks[self._i - 1]

    def _binary(self, ops: dict[str, Callable], sub: Callable[[], Value]) -> Value:
        left = sub()
        while self._peek() in ops:
            fn = ops[self._take()[1]]
            right = sub()
            left = (lambda a, b, f: lambda m: f(a(m), b(m)))(left, right, fn)
        return left

    def _or(self) -> Value:
        return self._binary({"||": lambda a, b: 1 if a or b else 0}, self._and)

    def _and(self) -> Value:
        return self._binary({"&&": lambda a, b: 1 if a and b else 0}, self._not)

    def _not(self) -> Value:
        if self._peek() == "!":
            self._take()
            inner = self._not()
            return lambda m: 0 if inner(m) else 1
        return self._cmp()

    def _cmp(self) -> Value:
        ops = {"==": lambda a, b: int(a == b), "=": lambda a, b: int(a == b), "!=": lambda a, b: int(a != b),
               "<": lambda a, b: int(a < b), "<=": lambda a, b: int(a <= b),
               ">": lambda a, b: int(a > b), ">=": lambda a, b: int(a >= b)}
        return self._binary(ops, self._sum)

    def _sum(self) -> Value:
        return self._binary({"+": lambda a, b: a + b, "-": lambda a, b: a - b}, self._prod)

    def _prod(self) -> Value:
        def div(a, b):
            if b == 0:
                return 0  # as the PLC's DIV by zero leaves nothing to compare: 0, not a crash
            return a / b if isinstance(a, float) or isinstance(b, float) else int(a / b)
        return self._binary({"*": lambda a, b: a * b, "/": div,
                             "%": lambda a, b: a % b if b else 0}, self._unary)

    def _unary(self) -> Value:
        if self._peek() == "-":
            self._take()
            inner = self._unary()
            return lambda m: -inner(m)
        return self._atom()

    def _atom(self) -> Value:
        kind, text = self._take()
        if text == "(":
            inner = self._or()
            if self._peek() != ")":
                raise ExprError(f"missing ')' in {self.text!r}")
            self._take()
            return inner
        if kind == "num":
            v = _num(text)
            return lambda m: v
        if kind == "name":
            view = resolve_device(text, self._target, self._symbols)
            self.devices.append(view)
            return view.read
        raise ExprError(f"unexpected {text!r} in {self.text!r}")


def resolve_device(text: str, target, symbols: Mapping[str, str] | None = None) -> DeviceView:
    """A device name or a program symbol -> its view; ExprError with the reason otherwise."""
    name = text.strip()
    if symbols and name in symbols:
        name = symbols[name]
    try:
        return parse_device_name(name, target)
    except NameError_ as e:
        raise ExprError(str(e)) from None
