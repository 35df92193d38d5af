"""Application instructions API 09-69 with the manual's worked examples (ch. 3-4)."""

from __future__ import annotations

import math
import struct

import pytest

from simkit import Bench, passed, simulate


def run_once(il: str, **inputs):
    b = Bench("LD X0\n" + il.strip() + "\nEND")
    for k, v in inputs.items():
        b.set(k.replace("_", ":"), v)
    b.set("X0", 1)
    b.scan()
    return b


def f32(x: float) -> float:
    return struct.unpack("<f", struct.pack("<f", x))[0]


def test_mov_example_and_not_executed_when_off():
    # 4.2 MOV: X0 On -> K10 to D0; X0 Off -> D0 unchanged; 32-bit: C64 to (D41, D40)
    b = Bench("LD X0\nMOV K10 D0\nLD X1\nMOV T0 D10\nLD X2\nDMOV D20 D30\nDMOV C64 D40\nEND")
    b.set("D0", 5)
    b.scan()
    assert b.get("D0") == 5
    b.set("X0", 1)
    b.set("X2", 1)
    b.set("D20:d", 70000)
    b.set("C64:d", -123456)
    b.scan()
    assert (b.get("D0"), b.get("D30:d"), b.get("D40:d")) == (10, 70000, -123456)


def test_kn_groups_zero_fill_and_k4_unsigned_in_32_bit():
    # 3.2.6: K2M0 -> D10 bits 0-7, bits 8-15 = 0; 3.3 note: K4Y0 in 32-bit has upper word 0
    b = run_once("MOV K2M0 D10\nDMOV K4M0 D20\nDMOV K8M0 D30\nMOV D40 K1Y0",
                 D10=-1, D40=0x7FF5)
    for k in range(16):
        b.set(f"M{k}", 1)
    b.scan()
    assert b.get("D10") == 255
    assert b.get("D20:d") == 65535
    assert b.get("D30:d") == 65535
    assert [b.get(f"Y{k}") for k in range(5)] == [1, 0, 1, 0, 0]  # only the low 4 bits


def test_fmov_is_a_float_move_not_a_fill():
    b = run_once("FMOV F1.5 D0\nFMOV K3 D2\nFMOV D0 D4", D6=99)
    assert (b.get("D0:f"), b.get("D2:f"), b.get("D4:f"), b.get("D6")) == (1.5, 3.0, 1.5, 99)
    # 3.3: 23.0 = H41B80000, -23.0 = HC1B80000
    b = run_once("FMOV F23 D0\nFMOV F-23 D2")
    assert b.get("D0:d") == 0x41B80000 and b.get("D2:d") & 0xFFFFFFFF == 0xC1B80000


def test_dmov_of_f_constant_stores_its_ieee_bits():
    assert run_once("DMOV F1.5 D0").get("D0:f") == 1.5


def test_cml_bcd_bin():
    b = run_once("CML D10 D12\nDCML K0 D14\nBCD D20 D22\nBIN D24 D26\nDBCD D30 D32\nDBIN D34 D36",
                 D10=0b1010, D20=1234, D24=0x5678, D30_d=12345678, D34_d=0x87654321 - (1 << 32))
    assert b.get("D12") == ~0b1010
    assert b.get("D14:d") == -1
    assert b.get("D22:h") == 0x1234
    assert b.get("D26") == 5678
    assert b.get("D32:d") == 0x12345678
    assert b.get("D36:d") == 87654321


def test_bcd_out_of_range_and_bin_bad_digit_are_not_executed():
    r = simulate("LD X0\nBCD D0 D2\nBIN D4 D6\nEND",
                 "0ms X0=1 D0=10000 D2=7 D4=H00A0 D6=8\n0ms expect D2=7 D6=8\n"
                 "0ms expect alarm OPERATION_ERROR")
    assert passed(r)


def test_add_sub_examples_and_wrap():
    # 4.3 ADD: 3 + (-9) = -6; DADD on (D31, D30) + (D41, D40) -> (D51, D50)
    b = run_once("ADD D0 D10 D20\nDADD D30 D40 D50\nSUB D0 D10 D22\nADD K32767 K1 D24",
                 D0=3, D10=-9, D30_d=100000, D40_d=-1)
    assert (b.get("D20"), b.get("D50:d"), b.get("D22"), b.get("D24")) == (-6, 99999, 12, -32768)


def test_mul_16_bit_gives_32_bit_product_and_dmul_64_bit():
    b = run_once("MUL D0 D10 D20\nDMUL D30 D40 D50", D0=-300, D10=300,
                 D30_d=100000, D40_d=-300000)
    assert b.get("D20:d") == -90000
    p = 100000 * -300000
    words = [b.get(f"D{50 + k}:h") for k in range(4)]
    assert sum(w << (16 * k) for k, w in enumerate(words)) == p & (2**64 - 1)


def test_div_quotient_remainder_and_divide_by_zero():
    b = run_once("DIV D0 D10 D20\nDDIV D30 D40 D50", D0=-7, D10=2, D30_d=100001, D40_d=10)
    assert (b.get("D20"), b.get("D21")) == (-3, -1)  # truncation toward zero
    assert (b.get("D50:d"), b.get("D52:d")) == (10000, 1)
    r = simulate("LD X0\nDIV K10 K0 D20\nEND",
                 "0ms X0=1 D20=5\n0ms expect D20=5\n0ms expect alarm MLC_ARITH_ERROR")
    assert passed(r)


def test_inc_dec_wrap_every_scan():
    b = Bench("LD X0\nINC D0\nDEC D1\nDINC D2\nDDEC D4\nEND")
    b.set("D0", 32767)
    b.set("D1", -32768)
    b.set("D2:d", 2147483647)
    b.set("D4:d", -2147483648)
    b.set("X0", 1)
    b.scan()
    assert (b.get("D0"), b.get("D1"), b.get("D2:d"), b.get("D4:d")) == \
        (-32768, 32767, -2147483648, 2147483647)
    b.scan(3)
    assert b.get("D0") == -32765  # continuous execution: +1 every scan


def test_wand_wor_wxor_neg():
    b = run_once("WAND D0 D2 D4\nWOR D0 D2 D6\nWXOR D0 D2 D8\nNEG D10\nDWAND K-1 D12 D14\nDNEG D16",
                 D0=0b1100, D2=0b1010, D10=-25, D12_d=123456, D16_d=70000)
    assert (b.get("D4"), b.get("D6"), b.get("D8")) == (0b1000, 0b1110, 0b0110)
    assert (b.get("D10"), b.get("D14:d"), b.get("D16:d")) == (25, 123456, -70000)


def test_ror_rol_by_4_bits():
    # 4.4: D10's 16 bits rotated by one group of 4
    b = run_once("ROR D10 K4\nROL D11 K4\nDROR D12 K8\nDROL D14 K16",
                 D10=0x1234, D11=0x1234, D12_d=0x12345678, D14_d=0x12345678)
    assert (b.get("D10:h"), b.get("D11:h")) == (0x4123, 0x2341)
    assert (b.get("D12:d"), b.get("D14:d")) == (0x78123456, 0x56781234)


def test_zrst_ranges_and_reversed_operands():
    b = run_once("ZRST M300 M399\nZRST D0 D100\nZRST D210 D205\nZRST A0 A127",
                 M300=1, M399=1, M400=1, D0=1, D100=2, D101=3, D205=4, D206=5, A127=1)
    assert (b.get("M300"), b.get("M399"), b.get("M400")) == (0, 0, 1)
    assert (b.get("D0"), b.get("D100"), b.get("D101")) == (0, 0, 3)
    assert (b.get("D205"), b.get("D206"), b.get("A127")) == (0, 5, 0)  # D1 > D2: only D2


def test_deco_examples():
    # 4.5 DECO example 1: X0, X1 On, X2 Off -> 3 -> M103 On among M100-M107
    b = run_once("DECO X0 M100 K3\nDECO D10 D20 K3", X0=1, X1=1, M105=1, D10=0b110, D20=-1)
    assert [b.get(f"M{100 + k}") for k in range(8)] == [0, 0, 0, 1, 0, 0, 0, 0]
    assert b.get("D20") == 1 << 6  # example 2: b15-b8 become 0


def test_enco_examples():
    b = run_once("ENCO M0 D0 K3\nENCO D10 D20 K3", M5=1, D0=-1, D10=0x0110, D20=-1)
    assert b.get("D0") == 5
    assert b.get("D20") == 4  # b8-b15 of D10 are ignored
    r = simulate("LD X0\nENCO M0 D0 K3\nEND", "0ms X0=1 D0=9\n0ms expect D0=9\n"
                 "0ms expect alarm OPERATION_ERROR")
    assert passed(r)


def test_bon_example_holds_when_off():
    b = Bench("LD X0\nBON D0 M0 K15\nEND")
    b.set("D0", -32768)
    b.set("X0", 1)
    b.scan()
    assert b.get("M0") == 1
    b.set("X0", 0)
    b.set("D0", 0)
    b.scan()
    assert b.get("M0") == 1


def test_comparison_contact_examples():
    # 4.7 LD※: K200 = C10 -> Y10; K-30 > D200 and X1 -> SET Y11; K678493 > C64 or M3 -> M50
    b = Bench("""
LD= K200 C10
OUT Y10
LD> K-30 D200
AND X1
SET Y11
DLD> K678493 C64
OR M3
OUT M50
LD X0
AND<> D0 K-10
OUT Y12
LD X0
DOR>= D100 K100000
OUT Y13
END""")
    b.set("C10:w", 200)
    b.set("D200", -31)
    b.set("X1", 1)
    b.set("C64:d", 678492)
    b.set("D100:d", 100000)
    b.scan()
    assert [b.get(d) for d in ("Y10", "Y11", "M50", "Y12", "Y13")] == [1, 1, 1, 0, 1]


def test_vrt_manual_example():
    # 4.7 VRT: S = M30, n = 4; M30 = M31 = On -> index 3 -> table(0, +3) = 50 -> D1062
    b = run_once("VRT M30 K4 D1062 K0 K20 K32 K50 K79 K126 K200 K320 K500 K790",
                 M30=1, M31=1)
    assert b.get("D1062") == 50
    b.set("M32", 1)
    b.scan()
    assert b.get("D1062") == 320  # index 7


@pytest.mark.parametrize("instr,a,b,expect", [
    ("FADD", 1.5, 2.25, 3.75), ("FSUB", 1.234, 1.0, f32(f32(1.234) - 1.0)),
    ("FMUL", 1.234, 3.0, f32(f32(1.234) * 3.0)), ("FDIV", 1.0, 3.0, f32(1 / 3)),
])
def test_float_arithmetic_single_precision(instr, a, b, expect):
    r = run_once(f"{instr} D0 D2 D10", D0_f=a, D2_f=b)
    assert r.get("D10:f") == expect


def test_float_constant_operand_and_accumulation():
    # 4.8 FADD example 2: (D11, D10) + F1.234 -> (D21, D20); S1 = D accumulates each scan
    b = run_once("FADD D10 F1.234 D20\nFADD D30 F0.5 D30", D10_f=1.0)
    assert b.get("D20:f") == f32(1.0 + f32(1.234))
    b.scan(3)
    assert b.get("D30:f") == 2.0


def test_fdiv_by_zero_not_executed():
    r = simulate("LD X0\nFDIV D0 D2 D10\nEND", "0ms X0=1 D0:f=1 D2:f=0 D10:f=7\n"
                 "0ms expect D10:f=7\n0ms expect alarm OPERATION_ERROR")
    assert passed(r)


def test_fcmp_fint_fdot_frad_fdeg():
    b = run_once("FCMP D0 F2.5 M10\nFINT D2 D20\nFINT D4 D22\nFDOT D6 D24\nFRAD F180 D26\nFDEG D28 D30",
                 D0_f=1.0, D2_f=-2.75, D4_f=2.75, D6_d=-70000, D28_f=f32(math.pi))
    assert [b.get(f"M{k}") for k in (10, 11, 12)] == [0, 0, 1]  # (>, =, <)
    assert (b.get("D20:d"), b.get("D22:d")) == (-2, 2)  # fraction discarded
    assert b.get("D24:f") == -70000.0
    assert b.get("D26:f") == f32(math.pi)
    assert abs(b.get("D30:f") - 180.0) < 1e-4


def test_fcmp_holds_when_not_executed():
    b = Bench("LD X0\nFCMP F1 F1 M10\nEND")
    b.set("X0", 1)
    b.scan()
    b.set("X0", 0)
    b.scan()
    assert b.get("M11") == 1


def test_wrtl_rdtl_servo_table():
    b = run_once("WRTL K3 D0\nRDTL K3 M5\nRDTL K4 D10", D0=150)
    assert b.m.servo_limit == {3: 150}
    assert b.get("M5") == 0
    b.m.servo_at_limit[3] = 1
    b.m.servo_at_limit[4] = 1
    b.scan()
    assert (b.get("M5"), b.get("D10")) == (1, 1)


def test_word_ops_on_timer_and_counter_operands():
    b = run_once("ADD T0 K5 D0\nMOV K7 C3\nDMOV K70000 T10", T0_w=10)
    assert (b.get("D0"), b.get("C3:w"), b.get("T10:w"), b.get("T11:w")) == (15, 7, 4464, 1)
