"""Memory card data bank DBRD/DBWR (6-11 FNC 90/91, 2-8) on the simulated bank `DB#n` that
the stimulus presets and checks (docs/stimulus.md), and its operation errors."""

from __future__ import annotations

import pytest
from test_vs_sim import codes

from mlctool.sim.stimulus.stimulus import parse_stimulus_text
from vskit import VS, run


def test_dbrd_page_example_reads_100_words_from_the_address_in_d1_d0():
    # 6-11 FNC 90: DBRDP D0 D1000 K100, X20 OFF -> ON with (D1,D0) = 100: bank 100-199 into
    # D1000-D1099; X20 Off: not executed, D keeps what it read; P: once per rising edge
    run("LD X20\nDBRDP D0 D1000 K100\n",
        "0ms DB#100=11 DB#101=-2 DB#199=H7FFF DB#200=9 DB#99=8 D0:d=100 D1100=-1 D999=-1\n"
        "10ms X20=1\n"
        "10ms expect D1000=11 D1001=-2 D1002=0 D1099=32767 D1100=-1 D999=-1\n"
        "20ms DB#100=5\n30ms expect D1000=11\n"
        "40ms X20=0\n50ms DB#101=6\n60ms expect D1001=-2\n"
        "70ms X20=1\n70ms expect D1000=5 D1001=6\n")


def test_dbwr_page_example_writes_100_words_to_the_address_in_d1_d0():
    # 6-11 FNC 91: DBWRP D1000 D0 K100, (D1,D0) = 100: D1000-D1099 to bank 100-199
    run("LD X20\nDBWRP D1000 D0 K100\n",
        "0ms D0:d=100 D1000=7 D1001=-8 D1099=H8000 D1100=5\n10ms X20=1\n"
        "10ms expect DB#100=7 DB#101=-8 DB#199:h=H8000 DB#200=0 DB#99=0\n")


def test_32_bit_addresses_the_pair_and_the_far_end_of_the_bank():
    # S/D are 32-bit: K100000 as a constant, D11:D10 = 655359 (the last address); n from D20
    run("LD X0\nDBWR D0 K100000 K2\nLD X1\nDBWR D5 D10 D20\nLD X2\nDBRD K655358 D30 K2\n",
        "0ms D0=3 D1=4 D5=-9 D10:d=655359 D20=1 DB#655358=12\n10ms X0=1 X1=1 X2=1\n"
        "10ms expect DB#100000=3 DB#100001=4 DB#100000:d=262147 DB#655359=-9 D30=12 D31=-9\n")


def test_an_indexed_constant_address_takes_the_32_bit_index_v_z():
    # the pages: an indexed K/H address uses both V and Z (2-9: written Zn, Vn high, Zn low):
    # K5Z0 with (V0, Z0) = (1, 4) addresses 5 + 65540 = 65545
    run("LD X0\nDBWR D0 K5Z0 K1\n", "0ms V0=1 Z0=4 D0=42 X0=1\n0ms expect DB#65545=42 DB#9=0\n")


def test_the_bank_keeps_its_data_over_a_power_cycle():
    # 2-8: the card's flash keeps its data without power; D1000 (general) clears (X20 Off:
    # an On condition would write the cleared D1000 at the first scan after power-on)
    run("LD X20\nDBWRP D1000 K5 K1\nLD X21\nDBRDP K5 D2000 K1\n",
        "0ms D1000=1234\n10ms X20=1\n20ms X20=0\n20ms power-cycle\n20ms expect D1000=0 DB#5=1234\n"
        "30ms X21=1\n30ms expect D2000=1234\n")


@pytest.mark.parametrize("il, stim", [
    ("LD X0\nDBRD K655300 D0 K100\n", ""),      # 655300 + 99 passes 655359
    ("LD X0\nDBWR D0 K-1 K1\n", ""),            # K-1 is refused by the checker: from a register
    ("LD X0\nDBRD D10 D0 D20\n", "0ms D20=0"),  # n = 0 (a register): outside 1-32767
    ("LD X0\nDBRD D10 D0 D20\n", "0ms D20=-5"),
    ("LD X0\nDBRD D10 D0 K1\n", "0ms D10:d=655360"),
    ("LD X0\nDBRD K0 D9450 K100\n", ""),         # D9450-D9549 passes D9511
    ("LD X0\nDBWR D9500 K0 K20\n", ""),
])
def test_operation_errors_leave_everything_unchanged(il, stim):
    if "K-1" in il:
        assert "E206" in codes(il + "END\n")
        il, stim = "LD X0\nDBWR D0 D10 K1\n", "0ms D10:d=-1"
    r = run(il, f"{stim}\n0ms DB#0=77 D0=5 D9450=5\n0ms X0=1\n"
                "0ms expect alarm OPERATION_ERROR\n0ms expect M9067=1 D9067=6706 D0=5 D9450=5 DB#0=77\n",
            alarms=True)
    assert [a.name for a in r.alarms][:1] == ["OPERATION_ERROR"]


def test_checker_ranges_of_the_bank_address_and_n():
    assert codes("LD X0\nDBRD K655359 D0 K1\nDBWRP D0 K0 K32767\nEND\n") == []
    assert "E206" in codes("LD X0\nDBRD K655360 D0 K1\nEND\n")
    assert "E206" in codes("LD X0\nDBWR D0 K0 K0\nEND\n")


def test_stimulus_names_of_the_bank_are_checked_with_line_and_column():
    cases = {"0ms DB#655360=1": ("E602", 5), "0ms DB#655359:d=1": ("E602", 5),
             "0ms DB#4:x=1": ("E602", 5), "0ms DB#0=70000": ("E601", 5),
             "0ms X0=1\n10ms expect DB#=1": ("E602", 13)}
    for text, (code, col) in cases.items():
        _, diags = parse_stimulus_text("t.stim", text, VS)
        assert [(d.code, d.span.col) for d in diags] == [(code, col)], (text, diags)
        assert diags[0].span.line == text.count("\n") + 1
