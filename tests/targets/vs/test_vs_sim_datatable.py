"""Data tables DTRD (6-11 FNC 93, 2-10 table pointers) from `.table TABLE DTRD WORD ...` rows:
the rows' words in order, addresses from 0 (docs/vs.md)."""

from __future__ import annotations

import pytest
from test_vs_sim import codes

from vskit import run

TABLE = (".define RECIPE Q3\n"
         ".table RECIPE DTRD K10 K20 K30 H8000\n"   # addresses 0-3
         ".table RECIPE DTRD K-1 HFFFF K7\n"       # 4-6
         ".table Q0 DTRD K100 K200\n")


def test_dtrd_page_example_reads_n_words_from_address_s2_of_the_table():
    # 6-11 FNC 93: DTRDP <table> K0 D1000 K100, X20 OFF -> ON: 100 words from address 0 into
    # D1000-D1099; here a 7-word table read from address 1, 5 words, and again from 0
    run(TABLE + "LD X20\nDTRDP RECIPE K1 D1000 K5\nLD X21\nDTRDP Q3 K0 D2000 K7\n",
        "0ms D1005=9\n10ms X20=1\n"
        "10ms expect D1000=20 D1001=30 D1002:h=H8000 D1003=-1 D1004=-1 D1005=9\n"
        "20ms D1000=0\n30ms expect D1000=0\n"                       # P: once per rising edge
        "40ms X21=1\n40ms expect D2000=10 D2003=-32768 D2006=7\n")


def test_table_pointer_indexed_with_v_and_destinations_of_other_kinds():
    # 2-10: Q0-Q31 can be V/Z-indexed (names cannot): Q0V0 with V0 = 3 is Q3; K4M0 and T take
    # the words too
    run(TABLE + "LD X0\nDTRD Q0V0 K2 K4M0 K1\nDTRD Q0 D10 T0 K1\n",
        "0ms V0=3 D10=1 X0=1\n0ms expect K4M0=30 M1=1 T0:w=200\n")


@pytest.mark.parametrize("line, stim", [
    ("DTRD Q5 K0 D0 K1", ""),           # no rows for Q5
    ("DTRD Q0 K1 D0 K2", ""),           # addresses 1-2 of a 2-word table
    ("DTRD Q0 D10 D0 K1", "0ms D10=-1"),
    ("DTRD Q0 K0 D0 D11", "0ms D11=0"),  # n below 1
    ("DTRD Q0V0 K0 D0 K1", "0ms V0=29"),  # Q29: no rows
])
def test_operation_errors_read_nothing(line, stim):
    run(TABLE + f"LD X0\n{line}\n",
        f"{stim}\n0ms D0=5 X0=1\n0ms expect alarm OPERATION_ERROR\n0ms expect M9067=1 D0=5\n",
        alarms=True)


@pytest.mark.parametrize("row, code", [
    (".table Q0 DTRD", "E105"),            # at least one word
    (".table Q32 DTRD K1", "E105"),        # tables are Q0-Q31
    (".table Q0 DTRD K1 D0", "E204"),      # words are constants
    (".table Q0 DTRD K1 K65536", "E206"),  # a 16-bit word
    (".table Q0 DTRD K-32769", "E206"),
])
def test_rows_are_checked(row, code):
    assert code in codes(f"{row}\nLD X0\nDTRD Q0 K0 D0 K1\nEND\n")


def test_legal_rows_and_index():
    assert codes(TABLE + "LD X0\nDTRDP RECIPE K0 D0 K7\nDTRD Q0Z1 D0 R0 D1\nEND\n") == []


def test_page_example_with_its_chinese_table_name():
    # 6-11 FNC 93 as printed: DTRDP 成分配方表 K0 D1000 K100 (a table name of Chinese
    # characters, 2-10); 100 words from address 0 into D1000-D1099
    words = " ".join(f"K{k * 3}" for k in range(100))
    run(f".define 成分配方表 Q7\n.table 成分配方表 DTRD {words}\nLD X20\n"
        "DTRDP 成分配方表 K0 D1000 K100\n",
        "0ms D1100=-4\n10ms X20=1\n10ms expect D1000=0 D1001=3 D1050=150 D1099=297 D1100=-4\n")
