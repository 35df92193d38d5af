"""VS UnG buffer-memory operands (U1G3 = BFM#3 of special module 1; 2-9-2, 5-1, 6-9) and the
expansion-card mnemonics EC1X0 / EC1Y0 / EC1D0 (2-16): syntax, checker legality, object round
trip, simulation through the buffer memory the stimulus drives."""

from __future__ import annotations

import pytest
from test_vs_sim_fx import VS, run

from mlctool.asm.encode import directives_of, object_from_module
from mlctool.asm.listing import unit_il
from mlctool.asm.objfile import decode, encode
from mlctool.check import check_texts
from mlctool.syntax.operands import OperandSyntaxError, parse_operand
from mlctool.syntax.source import SourceText
from mlctool.targetapi import load_target


def errors(text: str, model: str = "VS3") -> list[str]:
    r = check_texts([SourceText("t.il", text)], load_target("vs", model))
    return [d.code for d in r.diagnostics if d.severity == "error"]


def test_syntax_is_the_targets():
    u = parse_operand("U1G0Z0", VS.operand_syntax)
    assert (u.kind, u.unit, u.number, u.index, str(u)) == ("G", "U1", 0, ("Z", 0), "U1G0Z0")
    ec = parse_operand("EC2D5", VS.operand_syntax)
    assert (ec.kind, ec.number) == ("D", 9285)  # 2-16-3: EC2D0-EC2D19 = D9280-D9299
    assert parse_operand("EC3Y7", VS.operand_syntax).number == 9317
    assert parse_operand("EC1X0", VS.operand_syntax).number == 9260
    with pytest.raises(OperandSyntaxError):
        parse_operand("EC1D20", VS.operand_syntax)
    # NC5 declares neither: U1G3 stays a symbol name there
    with pytest.raises(OperandSyntaxError):
        parse_operand("U1G3", load_target("nc5").operand_syntax)


@pytest.mark.parametrize("line, model, code", [
    ("MOV U1G3 D0", "VS3", None),
    ("MOV H1100 U2G0", "VS3", None),               # the 5-1 example
    ("MOV K55 U1G0Z0", "VS3", None),               # 2-9-2: G indexable
    ("DMOV K70000 U16G32766", "VS3", None),
    ("FMOV K20 EC1D6 K4", "VS3", None),            # 2-16 example
    ("MOV U8G0 D0", "VS2", None),
    ("MOV U9G0 D0", "VS2", "E205"),                # U1-U8 on VS2/VSM
    ("MOV U17G0 D0", "VS3", "E205"),
    ("MOV U1G0 D0", "VS1", "E205"),                # no special modules on VS1
    ("MOV G3 D0", "VS3", "E203"),                  # G needs its unit
    ("DMOV D0 U1G32767", "VS3", "E208"),           # the pair runs past BFM#32767
    ("SET U1G3", "VS3", "E204"),                   # basic instructions: no UnG
    ("MOV K1 EC1D20", "VS3", "E203"),
])
def test_legality(line, model, code):
    got = errors(f"LD M9000\n{line}\nEND\n", model)
    assert got == ([code] if code else []), got


def test_compare_contact_takes_ung_but_ld_does_not():
    assert errors("LD= U1G30 K201\nOUT M0\nEND\n") == []   # 5-1 example
    assert errors("LD U1G30\nOUT M0\nEND\n") == ["E204"]


def test_object_round_trip():
    text = ("LD M9000\nMOV U1G3 D0\nDMOV K70000 U2G10\nMOV K55 U16G0Z0\nLD= U1G30 K201\nOUT M0\n"
            "MOV EC1D0 D100\nEND\n")
    r = check_texts([SourceText("t.il", text)], VS)
    assert r.errors == 0
    data = encode(object_from_module(r.modules[0], directives_of("t.il", r.lines["t.il"])))
    obj = decode(data, VS)
    il = unit_il(obj, 0)
    assert "U16G0Z0" in il and "U2G10" in il
    again = check_texts([SourceText("t.il", il)], VS)
    assert again.errors == 0
    assert encode(object_from_module(again.modules[0], directives_of("t.il", again.lines["t.il"]))) == data


def test_simulation_reads_and_writes_the_stimulus_buffer_memory():
    il = ("LD M9000\nMOV U1G3 D0\nDMOV K70000 U2G10\nMOV K4 Z0\nMOV K55 U1G0Z0\n"
          "LD= U1G30 K201\nOUT M0\nLD X0\nFMOV K20 EC1D6 K4\nMOV EC1D0 D100\n"
          "LD X1\nTO K1 K40 U1G3 K1\n")  # FROM/TO and UnG are the same registers
    run(il, "0ms BFM1#3=77 BFM1#30=201 D9260=9\n"
            "20ms expect D0=77 M0=1 BFM2#10=4464 BFM2#11=1 BFM1#4=55 D100=0\n"
            "30ms X0=1 X1=1 BFM1#30=5 BFM1#3=-2\n"
            "60ms expect D0=-2 M0=0 D100=9 D9266=20 D9269=20 D9270=0 BFM1#40=-2\n")


def test_index_past_the_buffer_memory_is_a_fault_not_a_traceback():
    from vskit import image_of, simulate

    r = simulate(image_of("LD M9000\nMOV K32767 Z0\nMOV K1 U1G1Z0\nEND\n"), "10ms expect D0=0\n")
    assert r.fault is not None and "U1G" in str(r.fault)
