"""The virtual NC's addresses (targets/nc5/nc/addresses.py) against the signal table
(signals.tsv, from the manual): every address the model reads is an MLC -> NC (or HMI -> MLC)
row, every address it writes an NC -> MLC (or MLC -> HMI) row the MLC may only read (the
HMI's counters excepted: R/W, 5.3.15), of the width the model gives it. A disagreement here is
one of the two reading the manual wrong."""

from __future__ import annotations

import pytest

from mlctool.targets.nc5 import signals
from mlctool.targets.nc5.nc import addresses as A

READS = {2: "MLC->NC", 59: "HMI->MLC"}
WRITES = {3: "NC->MLC", 49: "MLC->HMI"}


def _patterns():
    """(address name, pattern as the manual prints it, entry) of every address the model uses,
    per-axis rows for each of the 9 lettered axes, runs for each of their rows."""
    for key, entry in sorted(A.entries().items()):
        kind, group, function = entry
        count = 9 if entry in A.PER_AXIS + A.PER_AXIS_PAIRS else A.RUNS.get(entry, 1)
        step = 2 if entry in A.PER_AXIS_PAIRS else 1
        for k in range(count):
            yield key, A.name((kind, group, function + step * k)), entry


@pytest.mark.parametrize("key,pattern,entry", list(_patterns()), ids=lambda v: v if isinstance(v, str) else "")
def test_each_address_is_a_row_of_its_direction_and_width(key, pattern, entry):
    row = signals.row(pattern)  # KeyError: no such row
    kind, group, _ = entry
    assert group in READS or group in WRITES, key
    if group in READS:
        assert row.direction == READS[group], (key, row)
    else:
        assert row.direction == WRITES[group], (key, row)
        assert row.read_only or group == 49, (key, row)
    if kind == "M":
        assert row.type == "bit", (key, row)
    else:
        assert (row.type.startswith("32-bit")) == (entry in A.WIDE), (key, row.type)


def test_the_system_time_is_the_systems_to_write():
    """D49000-D49002 (5.3.15): no channel; R, so the model (the system) writes them."""
    for k in range(3):
        row = signals.row(f"D{A.SYSTEM_TIME + k}")
        assert row.direction == "MLC->HMI" and row.read_only and row.type == "word"


def test_the_model_reads_and_writes_only_these_rows():
    """The addresses the model holds (NcModel a_* attributes) are exactly addresses.py's."""
    from mlctool.targetapi import load_target
    from mlctool.targets.nc5.nc.model import NcModel

    model = NcModel({}, load_target("nc5"))
    held = {k[2:].upper() for k in vars(model) if k.startswith("a_")}
    assert held == set(A.entries())


def test_decision_the_s_code_register_is_32_bit():
    """DECISION (signals.tsv D3x050): S codes above 32767 reach the MLC whole, in D3x050/D3x051."""
    from nc5kit import run

    run("LD M31065\nOUT M21016\n", "model nc5 program=part.nc\n0ms M21000=1\n"
        "100ms expect D31050:d=40000 D31024:d=40000\n", "S40000\nM30\n")
