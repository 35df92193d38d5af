"""W250-W253: `mlc check` knows the NC5's special M/D (check/signals.py, the rows of
targets/nc5/signals.tsv). Expected codes and columns are written out from the manual's rows
(5.2.1/5.2.2), not taken from the checker's output."""

from __future__ import annotations

import pytest

from mlctool.check import check_texts
from mlctool.config import Config
from mlctool.syntax.source import decode
from mlctool.targetapi import load_target

NC5 = load_target("nc5")
SIGNAL_CODES = {"W250", "W251", "W252", "W253", "W212"}


def diags(body: str, config: Config | None = None, target=NC5):
    src = decode("t.il", f"LD X0\n{body}\nEND\n".encode())[0]
    return [d for d in check_texts([src], target, config).diagnostics if d.code in SIGNAL_CODES]


def codes(body: str, config: Config | None = None) -> list[tuple[str, int]]:
    return [(d.code, d.span.col) for d in diags(body, config)]


def test_out_to_an_nc_flag_names_the_signal_and_says_it_is_the_ncs():
    """The issue's acceptance: OUT M31064 (M 碼執行, 5.2.1 L3964, 5.3.10)."""
    [d] = diags("OUT M31064")
    assert (d.code, d.severity, d.span.line, d.span.col, d.span.end_col) == ("W250", "warning", 2, 5, 11)
    assert "M31064 is M 碼執行 (M code strobe, NC->MLC, manual 5.3.10)" in d.message
    assert "the NC writes it (R)" in d.message


@pytest.mark.parametrize("body, col", [
    ("SET M31016", 5), ("RST M31016", 5), ("PLS M31016", 5), ("PLF M31016", 5), ("ALT M31016", 5),
    ("MOV K1 D31048", 8),  # a destination operand: D3x048 M code data
    ("MOV K0 K2M31000", 8),  # a Kn group covering the mode feedback M31000-M31007
    ("ZRST M30990 M31005", 6),  # a ZRST range that covers M31000
    ("DECO D0 M30996 K3", 9),  # 2^3 = 8 bits M30996-M31003, the span of DECO D (only W251 before)
    ("DMOV K1 D31023", 9),  # a 32-bit destination whose high word is D3x024's low word
])
def test_every_kind_of_write_to_an_r_row_is_w250(body, col):
    assert codes(body) == [("W250", col)]


@pytest.mark.parametrize("body", [
    "LD M31064\nOUT Y0", "LDI M31016\nOUT Y0", "MOV D31048 D0", "MOV K2M31000 D0", "DMOV D31024 D0",
    "OUT M21000", "SET M21016", "MOV K3 D21000", "DMOV K100 D21014", "MOV K1 D21128",
])
def test_reads_and_writes_of_the_mlcs_own_rows_say_nothing(body):
    assert codes(body) == []


def test_the_message_of_a_range_names_the_first_signal_and_counts_the_rest():
    [d] = diags("ZRST M31000 M31010")
    assert d.message.startswith("ZRST M31000 M31010 writes M31000, 自動執行(AUTO) (AUTO mode")
    assert "and 7 more signals the NC writes" in d.message


def test_the_system_time_is_the_systems():
    """D49000-D49002 typed R although the range is MLC->HMI (DECISION in signals.tsv)."""
    [d] = diags("MOV K1 D49000")
    assert d.code == "W250" and "the system writes it" in d.message
    assert codes("DMOV K1 D49104") == []  # D49x04 total machining time: R/W as printed


@pytest.mark.parametrize("body, col", [
    ("OUT M20000", 5),  # channel 0 reuses the numbers: M20000 is no cycle start (5.1)
    ("LD M21002\nOUT Y0", 4),  # a gap of 5.2.1: read
    ("MOV D21001 D0", 5), ("OUT M59000", 5), ("MOV K1 D49950", 8), ("OUT M31999", 5),
    ("MOV K0 K4M21100", 8),  # a group entirely between rows (M2x075 .. M2x128)
])
def test_an_undefined_number_of_the_special_ranges_is_w251(body, col):
    assert codes(body) == [("W251", col)]


def test_w251_says_the_nc_writes_an_undefined_nc_to_mlc_number():
    [d] = diags("OUT M31999")
    assert "NC->MLC special range M30000-M38999, written by the NC" in d.message


def test_decision_a_group_over_signals_is_not_warned_for_its_spare_bits():
    """K4M31000 reads the 8 mode bits and 8 undefined ones (M31008-M31015): no W251."""
    assert codes("MOV K4M31000 D0") == []


def test_a_channel_above_the_configured_count_is_w252():
    assert codes("OUT M22000") == [("W252", 5)]
    [d] = diags("LD M38016\nOUT Y0")
    assert d.code == "W252" and "channel 8's" in d.message and "has 1 channel" in d.message
    two = Config(data={"channels": 2})
    assert codes("OUT M22000", two) == [] and codes("OUT M23000", two) == [("W252", 5)]
    assert codes("DMOV K1 D49200") == [("W252", 9)]  # HMI: channel 2 by the third digit (DECISION)
    assert codes("DMOV K1 D49200", two) == [] and codes("MOV K1 D49200", two) == [("W253", 8)]


@pytest.mark.parametrize("body, col, words", [
    ("MOV K1 D21014", 8, "lower word of the 32-bit signal D21014"),
    ("MOV D31025 D0", 5, "upper word of the 32-bit signal D31024"),
    ("DMOV D31025 D0", 6, "starts at the upper word of D31024"),
    ("DMOV K1 D21000", 9, "covers D21000 (NC 模式切換, NC mode select, a 16-bit signal)"),
])
def test_32_bit_signals_by_halves_are_w253(body, col, words):
    [d] = diags(body)
    assert (d.code, d.span.col) == ("W253", col) and words in d.message


def test_the_severity_is_a_warning_a_project_may_raise():
    [d] = diags("OUT M31064", Config(severity={"W250": "error"}))
    assert d.severity == "error"


def test_w212_is_still_the_area_rule_of_a_target_without_signals():
    vs = load_target("vs")
    assert [d.code for d in diags("OUT M9000", target=vs)] == ["W212"]


def test_symbols_and_index_registers():
    assert codes(".define MCODE M31064\nOUT MCODE") == [("W250", 5)]
    assert codes("MOV K1 D31048V0") == []  # index-modified: the number is not known before the run


def test_the_config_key_channels_is_checked(tmp_path):
    from mlctool.config import ConfigError, load_config

    (tmp_path / "mlc.toml").write_text("channels = 9\n")
    with pytest.raises(ConfigError) as e:
        load_config(tmp_path)
    [d] = e.value.diagnostics
    assert d.code == "E110" and d.span.line == 1 and "channels 1-8" in d.message
    (tmp_path / "mlc.toml").write_text("channels = 3\n")
    assert load_config(tmp_path).data["channels"] == 3
