"""The NC5 signal table (mlctool/targets/nc5/signals.tsv) against the manual's text, its
decisions, and the lookups every front end uses (targetapi/signals.py, targets/nc5/signals.py).

The manual's rows are counted here on their own, by line patterns, not by the generator's
parser; regenerating with tools/gen_nc5_signals.py must give the committed file."""

from __future__ import annotations

import re
import sys
from pathlib import Path

import pytest

from mlctool.targetapi import load_target
from mlctool.targetapi.signals import describe_device, signals_of
from mlctool.targets.nc5 import signals as nc5

ROOT = Path(__file__).resolve().parents[3]
TSV = ROOT / "mlctool" / "targets" / "nc5" / "signals.tsv"
MANUAL = next((p / "shared" / "manuals" / "000_a33d4a328dc57a96.txt" for p in ROOT.parents
               if (p / "shared" / "manuals" / "000_a33d4a328dc57a96.txt").is_file()), None)
needs_manual = pytest.mark.skipif(MANUAL is None, reason="the NC5 manual text is not beside the checkout")


def manual_lines() -> list[str]:
    return MANUAL.read_text("utf-8").split("\n")


def between(lines: list[str], start: str, end: str) -> list[str]:
    """The lines after the heading `start` (5.2.1: "## 5.2.1 ..." or "### 5.2.1 ...") up to the
    next heading that starts with `end`."""
    a = next(k for k, x in enumerate(lines) if k > 3000 and re.match(rf"#+ {re.escape(start)}\s", x))
    b = next(k for k, x in enumerate(lines) if k > a and re.match(rf"#+ {re.escape(end)}", x))
    return lines[a + 1:b]


ROW = re.compile(r"^[^\t]+\t[MD][0-9x]{5}\t[^\t]*\t(R|R/W|)$")  # 名稱 / 裝置 / 說明 / 類型


@needs_manual
@pytest.mark.parametrize("table, start, end", [
    ("5.2.1", "5.2.1", "5.2.2 "),
    ("5.2.2", "5.2.2", "5.3 "),
])
def test_every_row_of_the_summary_tables_is_a_row_of_the_file(table, start, end):
    printed = [x.split("\t")[1] for x in between(manual_lines(), start, end) if ROW.match(x)]
    ours = [s.device for s in nc5.rows() if s.table == table]
    assert len(printed) == len(ours) == {"5.2.1": 772, "5.2.2": 362}[table]
    assert printed == ours


@needs_manual
@pytest.mark.parametrize("section, first, variables", [
    ("5.3.16", "M2x128", (25000, 25127)), ("5.3.17", "M3x128", (25256, 25383)),
    ("5.3.18", "D2x128", (25128, 25255)), ("5.3.19", "D3x128", (25384, 25511)),
])
def test_the_hmi_tables_give_every_point_its_variable(section, first, variables):
    text = "\n".join(between(manual_lines(), section, "5.3."))
    pairs = re.findall(r"\t([MD][23]x\d{3})\t#(\d{5})", text)
    assert len(pairs) == 128
    ours = {s.device: s.variable for s in nc5.rows() if section in s.sections}
    assert ours == {d: f"#{v}" for d, v in pairs}
    assert sorted(int(v) for _, v in pairs) == list(range(variables[0], variables[1] + 1))
    assert nc5.row(first).variable == f"#{variables[0]}"


@needs_manual
def test_the_ethercat_rows_of_5_3_20():
    text = "\n".join(between(manual_lines(), "5.3.20", "6"))
    printed = re.findall(r"\b([MD][0-9x]{5})\b", text)
    assert printed == ["M30000", "D3x000", "D3x001"]
    assert sorted(s.device for s in nc5.rows() if "5.3.20" in s.sections) == sorted(printed)


@needs_manual
def test_regenerating_gives_the_committed_file():
    sys.path.insert(0, str(ROOT / "tools"))
    try:
        import gen_nc5_signals
    finally:
        sys.path.remove(str(ROOT / "tools"))
    assert gen_nc5_signals.generate(MANUAL) == TSV.read_text("utf-8"), \
        "signals.tsv is stale: python3 tools/gen_nc5_signals.py > mlctool/targets/nc5/signals.tsv"


def test_every_row_is_complete():
    rows = nc5.rows()
    assert len(rows) == 1134
    assert len({s.device for s in rows}) == len(rows)
    for s in rows:
        assert s.name and s.english and s.section.startswith("5."), s
        assert s.access in ("R", "R/W") and s.type in ("bit", "word", "32-bit", "32-bit float"), s
        assert s.direction == {"2": "MLC->NC", "3": "NC->MLC", "4": "MLC->HMI", "5": "HMI->MLC"}[s.device[1]]
        assert (s.type == "bit") == (s.kind == "M")
    # every NC->MLC row is the NC's; every MLC->NC row the MLC's (5.2: R / R/W)
    assert {s.access for s in rows if s.direction == "NC->MLC"} == {"R"}
    assert {s.access for s in rows if s.direction == "MLC->NC"} == {"R/W"}


# -- the decisions beside the rows (DECISION in signals.tsv), each held here

def test_decision_mode_feedback_is_m3x000_not_m2x288():
    """6.1's table prints M2x288-M2x295 as the mode feedback; 5.2.1, 5.3.1 and 6.1's heading
    say M3x000-M3x007. M2x288.. are the synchronous followers (5.3.11)."""
    modes = [nc5.lookup(f"M3100{k}") for k in range(8)]
    assert [m.signal.english for m in modes] == ["AUTO mode", "EDIT mode", "MDI mode", "MPG mode", "JOG mode",
                                                "RAPID mode", "INC mode", "HOME mode"]
    assert all(m.signal.direction == "NC->MLC" and m.signal.read_only and m.signal.decision for m in modes)
    follower = nc5.lookup("M21288")
    assert follower.signal.name == "X 從動軸追隨主動軸" and follower.signal.section == "5.3.11"
    assert follower.signal.direction == "MLC->NC" and not follower.signal.read_only
    assert "misprint" not in follower.signal.decision and "mode feedback" in follower.signal.decision


def test_decision_program_running_is_read_only():
    s = nc5.row("M3x016")
    assert s.access == "R" and s.decision.startswith("DECISION: the 裝置類型 cell is empty")


def test_decision_m21000_is_cycle_start():
    assert nc5.lookup("M21000").signal.english == "cycle start"
    assert nc5.lookup("M31016").signal.english == "program running"


def test_decision_m3x357_is_the_c_axis():
    s = nc5.row("M3x357")
    assert s.name == "V 軸在原點位置" and s.english == "C axis at home position" and "C axis" in s.decision
    assert nc5.row("M3x359").english == "V axis at home position"


def test_decision_spindle_speeds_and_mlc_axis_commands_are_32_bit():
    assert nc5.row("D2x024").type == nc5.row("D2x030").type == "32-bit"
    assert nc5.row("D3x050").type == "32-bit" and nc5.row("D3x048").type == "word"
    assert nc5.lookup("D21025").high and nc5.lookup("D21025").signal.device == "D2x024"
    assert {nc5.row(f"D2x{n}").type for n in range(256, 320, 2)} == {"32-bit float"}
    assert nc5.lookup("D21319").signal.device == "D2x318"
    assert nc5.row("D2x014").type == "32-bit" and not nc5.row("D2x014").decision  # 5.2.2 says so itself


def test_decision_hmi_channel_is_the_third_digit():
    assert nc5.lookup("D49100").channel == 1 and nc5.lookup("D49100").signal.device == "D49x00"
    assert nc5.lookup("D49802").channel == 8 and nc5.lookup("D49802").signal.device == "D49x02"
    assert nc5.lookup("D49000").channel == 0 and nc5.lookup("D49000").signal.english == "system time: year, month"
    assert nc5.lookup("D49900") is None  # 49900-49999: no channel (target.toml [signals])


def test_decision_system_time_is_read_only_the_machining_time_not():
    assert [nc5.row(f"D4900{k}").access for k in range(3)] == ["R", "R", "R"]
    assert nc5.row("D49x04").access == nc5.row("D49x06").access == "R/W"
    assert nc5.row("D49x04").decision and nc5.row("D49x06").decision


def test_decision_m3x432_answers_the_mlc():
    assert nc5.row("M2x432").direction == "MLC->NC" and "M2x432" in nc5.row("M3x432").decision


# -- lookups

def test_channel_zero_numbers_are_the_systems_own():
    """M20000 is no 'channel 0 cycle start': channel 0 reuses the numbers (5.1)."""
    assert nc5.lookup("M20000") is None
    assert nc5.lookup("M30000").signal.english == "EtherCAT connected" and nc5.lookup("M30000").channel == 0
    assert nc5.lookup("M31000").signal.english == "AUTO mode"
    assert nc5.lookup("M29000") is None and nc5.lookup("M1000") is None and nc5.lookup("K5") is None


def test_device_of_a_pattern_on_a_channel():
    assert nc5.device("M2x000", 1) == "M21000" and nc5.device("M3x064", 8) == "M38064"
    assert nc5.device("D49x00", 2) == "D49200" and nc5.device("M30000", 0) == "M30000"
    with pytest.raises(ValueError):
        nc5.device("M2x000", 9)
    with pytest.raises(KeyError):
        nc5.row("M2x002")


def test_describe_device_is_the_line_front_ends_show():
    t = load_target("nc5")
    assert describe_device(t, "M", 21000) == "M21000 - 程式啟動 cycle start, MLC->NC, channel 1, 5.3.2"
    assert describe_device(t, "D", 31025) == ("D31025 - 第一主軸命令速度 spindle 1 commanded speed, NC->MLC, 32-bit, "
                                              "high word of D31024, channel 1, 5.3.13")
    assert describe_device(t, "M", 100) is None
    assert describe_device(load_target("vs"), "M", 21000) is None and signals_of(load_target("vs")) is None
