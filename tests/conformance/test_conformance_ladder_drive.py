"""ito-soft-design/ladder_drive test/plc/emulator/test_cycle_run.rb (the Ruby PLC emulator of
the "Escalator" mnemonic language, commit 06e50dd404add931ddbd468d55e6360b9ec870c3): each
check with an FX/VS meaning, rewritten as IL and stimulus for the vs target with the value the
Ruby test states, run on every engine (native: tests/conformance/test_conformance_native.py). The suite reads the rung result itself (`@plc.bool`);
here the rung ends in OUT Y0 (or the coil the case names) so the result is a device.
tests/conformance/README.md lists the cases left out and why."""

from __future__ import annotations

import pytest
from conformance_kit import engine_params

import vskit


def rows(*table: tuple[dict[str, int], dict[str, int]]) -> str:
    """One scan per row: its inputs, then what the row expects after the scan."""
    out = []
    for k, (inputs, want) in enumerate(table):
        out.append(f"{10 * k}ms " + " ".join(f"{n}={v}" for n, v in inputs.items()))
        out.append(f"{10 * k}ms expect " + " ".join(f"{n}={v}" for n, v in want.items()))
    return "\n".join(out)


def truth(*values: int) -> str:
    """The four rows X0, X1 = 00, 01, 10, 11 and the Y0 each gives."""
    ins = ({"X0": 0, "X1": 0}, {"X0": 0, "X1": 1}, {"X0": 1, "X1": 0}, {"X0": 1, "X1": 1})
    return rows(*((i, {"Y0": v}) for i, v in zip(ins, values, strict=True)))


CASES = [
    pytest.param("LD X0\nOUT Y0", rows(({"X0": 0}, {"Y0": 0}), ({"X0": 1}, {"Y0": 1})), id="test_ld_x0"),
    pytest.param("LDI X0\nOUT Y0", rows(({"X0": 0}, {"Y0": 1}), ({"X0": 1}, {"Y0": 0})), id="test_ldi_x0"),
    pytest.param("LD X0\nINV\nOUT Y0", rows(({"X0": 1}, {"Y0": 0})), id="test_inv"),
    pytest.param("NOP\nLD X0\nOUT Y0", rows(({"X0": 1}, {"Y0": 1})), id="test_nop"),
    # the same after a rung: the load after `OUT Y1 / NOP` starts a rung (it was taken for a
    # second block of the rung before: E313, found when the cases were put into one program)
    pytest.param("LD X1\nOUT Y1\nNOP\nLD X0\nOUT Y0", rows(({"X0": 1, "X1": 0}, {"Y0": 1, "Y1": 0})),
                 id="test_nop-after-a-rung"),
    pytest.param("LD X0\nAND X1\nOUT Y0", truth(0, 0, 0, 1), id="test_and_x0_x1"),
    pytest.param("LD X0\nANI X1\nOUT Y0", truth(0, 0, 1, 0), id="test_ani_x0_x1"),
    pytest.param("LD X0\nOR X1\nOUT Y0", truth(0, 1, 1, 1), id="test_or_x0_x1"),
    pytest.param("LD X0\nORI X1\nOUT Y0", truth(1, 0, 1, 1), id="test_ori_x0_x1"),
    pytest.param("LD X0\nOUT Y0", rows(({"X0": 0}, {"Y0": 0})), id="test_out"),
    # test_anb: the suite writes its ANB before the second block (its own assembler's order).
    # DECISION: written as FX and VS 3-4 write it, after both blocks; the truth rows carry over
    pytest.param("LD X0\nOR X1\nLD X2\nOR X3\nANB\nOUT Y0",
                 rows(({"X0": 0, "X1": 0, "X2": 0, "X3": 0}, {"Y0": 0}), ({"X0": 1}, {"Y0": 0}),
                      ({"X0": 0, "X2": 1}, {"Y0": 0}), ({"X0": 1, "X2": 1}, {"Y0": 1})), id="test_anb"),
    pytest.param("LD X0\nLD X1\nORB\nOUT Y0", rows(({"X0": 0, "X1": 0}, {"Y0": 0}), ({"X0": 1}, {"Y0": 1})),
                 id="test_orb"),
    pytest.param("LD X0\nMPS\nOUT Y0\nMRD\nINV\nOUT Y1\nMPP\nAND X1\nOUT Y2",
                 rows(({"X0": 1, "X1": 1}, {"Y0": 1, "Y1": 0, "Y2": 1})), id="test_mrd_and_mpp"),
    pytest.param("LD X0\nSET M0", rows(({"X0": 0}, {"M0": 0}), ({"X0": 1}, {"M0": 1})), id="test_set"),
    pytest.param("LD X0\nRST M0", rows(({"M0": 1, "X0": 0}, {"M0": 1}), ({"X0": 1}, {"M0": 0})), id="test_rst"),
]


@pytest.mark.parametrize("il, stim, engine", engine_params(CASES))
def test_ladder_drive_case(il, stim, engine):
    vskit.run(il, stim, engine=engine)


@pytest.mark.parametrize("il, code", [
    # test_end: nothing after END runs. DECISION: the vs target refuses code after END (E302,
    # VS 3-2), so the program cannot be written; the suite's fact holds by construction
    pytest.param("END\nLD X0\nOUT Y0", "E302", id="test_end"),
    # test_out_is_no_effected_to_input_device, test_should_not_set/rst_if_device_is_input:
    # DECISION: an input is no coil operand of OUT/SET/RST (VS 3-1's operand table): refused,
    # so no program can write X
    pytest.param("LD X0\nOUT X1", "E210", id="test_out_is_no_effected_to_input_device"),
    pytest.param("LD X0\nSET X1", "E210", id="test_should_not_set_if_device_is_input"),
    pytest.param("LD X0\nRST X1", "E210", id="test_should_not_rst_if_device_is_input"),
])
def test_ladder_drive_case_refused_by_the_checker(il, code):
    assert code in [c for c, _ in vskit.check_codes(il + "\nEND", severities=("error",))]
