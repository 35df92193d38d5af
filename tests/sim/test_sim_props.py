"""Property tests: 16/32-bit arithmetic against Python integers with two's-complement wrap."""

from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st

from simkit import Bench

W16 = st.integers(-(2**15), 2**15 - 1)
W32 = st.integers(-(2**31), 2**31 - 1)


def wrap(v: int, bits: int) -> int:
    v &= (1 << bits) - 1
    return v - (1 << bits) if v >> (bits - 1) else v


def trunc_div(a: int, b: int) -> tuple[int, int]:
    q = abs(a) // abs(b) * (1 if (a < 0) == (b < 0) else -1)
    return q, a - q * b


B16 = Bench("""
LD X0
ADD D0 D1 D10
SUB D0 D1 D11
MUL D0 D1 D12
DIV D0 D1 D14
WAND D0 D1 D16
WOR D0 D1 D17
WXOR D0 D1 D18
MOV D0 D20
INC D20
MOV D0 D21
DEC D21
MOV D0 D22
NEG D22
CML D0 D23
END""")

B32 = Bench("""
LD X0
DADD D0 D2 D10
DSUB D0 D2 D12
DMUL D0 D2 D20
DDIV D0 D2 D30
DWXOR D0 D2 D40
DMOV D0 D42
DINC D42
DMOV D0 D44
DNEG D44
END""")


@settings(max_examples=300, deadline=None)
@given(W16, W16)
def test_16_bit_arithmetic_matches_python(a, b):
    B16.set("D0", a)
    B16.set("D1", b)
    B16.set("X0", 1)
    B16.scan()
    g = B16.get
    assert g("D10") == wrap(a + b, 16)
    assert g("D11") == wrap(a - b, 16)
    assert g("D12:d") == a * b  # the 32-bit product never overflows
    if b:
        q, r = trunc_div(a, b)
        assert (g("D14"), g("D15")) == (wrap(q, 16), r)
    assert (g("D16"), g("D17"), g("D18")) == (a & b, a | b, a ^ b)
    assert (g("D20"), g("D21"), g("D22"), g("D23")) == \
        (wrap(a + 1, 16), wrap(a - 1, 16), wrap(-a, 16), ~a)


@settings(max_examples=300, deadline=None)
@given(W32, W32)
def test_32_bit_arithmetic_matches_python(a, b):
    B32.set("D0:d", a)
    B32.set("D2:d", b)
    B32.set("X0", 1)
    B32.scan()
    g = B32.get
    assert g("D10:d") == wrap(a + b, 32)
    assert g("D12:d") == wrap(a - b, 32)
    product = sum(g(f"D{20 + k}:h") << (16 * k) for k in range(4))
    assert wrap(product, 64) == a * b
    if b:
        q, r = trunc_div(a, b)
        assert (g("D30:d"), g("D32:d")) == (wrap(q, 32), r)
    assert g("D40:d") == a ^ b
    assert (g("D42:d"), g("D44:d")) == (wrap(a + 1, 32), wrap(-a, 32))


@settings(max_examples=200, deadline=None)
@given(st.integers(0, 0xFFFF), st.integers(1, 16))
def test_rotations_are_inverse(v, n):
    b = Bench(f"LD X0\nROR D0 K{n}\nROL D1 K{n}\nEND")
    b.set("D0:h", v)
    b.set("D1:h", v)
    b.set("X0", 1)
    b.scan()
    assert b.get("D0:h") == ((v >> n) | (v << (16 - n))) & 0xFFFF
    assert b.get("D1:h") == ((v << n) | (v >> (16 - n))) & 0xFFFF
