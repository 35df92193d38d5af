"""Bad input to the virtual NC: the part program's mistakes are diagnostics with file, line,
column and code before the run (exit 2); a parameter out of range is E601 at its column; a
signal name that does not exist gets a did-you-mean; the part program is an input no output
may overwrite."""

from __future__ import annotations

import pytest
from nc5kit import model_diags

PROGRAM = "LDI M0\nOUT M21012\nMOV K100 D21004\nEND\n"


def sim(mlc, tmp_path, stim: str, part: str | None = "M30\n", *args):
    (tmp_path / "p.il").write_text(PROGRAM)
    (tmp_path / "s.stim").write_text(stim)
    if part is not None:
        (tmp_path / "part.nc").write_text(part)
    return mlc("sim", "p.il", "--stimulus", "s.stim", *args, cwd=tmp_path)


@pytest.mark.parametrize("line,col,code", [
    ("G02 X1. Y1. R5.", 1, "E261"),
    ("G01 X1. F100 I5.", 14, "E262"),
    ("G01 A5. F100", 5, "E262"),  # A is not one of axes=X,Y,Z
    ("M98 P100", 1, "E262"),
    ("X1.2.3", 1, "E260"),
    ("G01 X1. (no end", 9, "E260"),
    ("G00 X1 X2", 8, "E263"),
    ("G04", 1, "E263"),
    ("X1.2345", 1, "E264"),
    ("S-5", 1, "E264"),
    ("G01 Y5.", 1, "E265"),
])
def test_part_program_mistakes_are_located(line, col, code):
    assert model_diags("model nc5 program=part.nc\n", f"G90\n{line}\nM30\n") == [("part.nc", 2, col, code)]


def test_the_cli_refuses_to_run_a_wrong_part_program(mlc, tmp_path):
    r = sim(mlc, tmp_path, "model nc5 program=part.nc\nrun 100ms\n", "G01 X1. F100\nG03 X2.\n")
    assert r.code == 2 and "part.nc:2:1: error[E261]" in r.err and "Traceback" not in r.err, r.err


@pytest.mark.parametrize("param,code,words", [
    ("channel=9", "E601", "channel takes 1-8"),
    ("axes=X,Q", "E601", "axes takes"),
    ("axes=X,X", "E601", "axes takes"),
    ("rapid=0", "E601", "rapid takes 1-999999"),
    ("feedback=2min", "E601", "feedback takes 0s-60s"),
    ("start=1,2", "E601", "start takes one position"),
    ("soft1_x=5:1", "E601", "LO 5 is above HI 1"),
    ("standby_pot=20", "E601", "standby_pot takes 1-16"),
    ("mpg=X0", "E601", "mpg takes a data register"),
    ("bogus=1", "E601", "has no parameter"),
    ("program=missing.nc", "E100", "cannot read the part program"),
])
def test_parameters_are_checked_at_their_column(mlc, tmp_path, param, code, words):
    r = sim(mlc, tmp_path, f"model nc5 {param}\nrun 100ms\n")
    assert r.code == 2 and code in r.err and words in r.err, r.err
    if code == "E601":
        assert "s.stim:1:11:" in r.err, r.err  # the parameter's own column


def test_signal_names_get_a_did_you_mean(mlc, tmp_path):
    r = sim(mlc, tmp_path, "model nc5\n10ms expect NC1.X.poss=0\nrun 20ms\n")
    assert r.code == 2 and "E602" in r.err and "did you mean 'X.pos'" in r.err, r.err
    r = sim(mlc, tmp_path, "model nc5 axes=X,Z\n10ms expect NC1.spindel.rpm=0\nrun 20ms\n")
    assert r.code == 2 and "did you mean 'spindle.rpm'" in r.err, r.err
    r = sim(mlc, tmp_path, "model nc5\n10ms expect NC2.mode=0\nrun 20ms\n")
    assert r.code == 2 and "no model named NC2" in r.err, r.err
    r = sim(mlc, tmp_path, "model nc6\nrun 20ms\n")
    assert r.code == 2 and "did you mean 'nc5'" in r.err, r.err


def test_the_part_program_is_an_input(mlc, tmp_path):
    r = sim(mlc, tmp_path, "model nc5 program=part.nc\nrun 20ms\n", "M30\n", "--vcd", "part.nc")
    assert r.code == 2 and "E606" in r.err and (tmp_path / "part.nc").read_text() == "M30\n", r.err


def test_signals_reach_json_watch_and_vcd(mlc, tmp_path):
    import json

    r = sim(mlc, tmp_path, "model nc5 program=part.nc\n0ms M21000=1\n100ms expect NC1.X.pos=10000\n"
                           "run 200ms\n", "G00 X10.\nM30\n", "--json", "--watch", "NC1.state",
            "--vcd", "o.vcd")
    assert r.code == 0, r.err
    data = json.loads(r.out)
    assert data["devices"]["NC1.X.pos"] == 10000 and data["devices"]["NC1.state"] == 6
    vcd = (tmp_path / "o.vcd").read_text()
    assert "NC1.X.pos" in vcd and "NC1.spindle.rpm" in vcd and "NC1.A.pos" not in vcd


def test_addresses_put_the_channel_where_5_1_says():
    """5.1: M2c000 channel c in the second digit; the HMI rows D49c00 in the third (notes #3)."""
    from mlctool.targets.nc5.nc import addresses as a

    assert a.number(a.CYCLE_START, 1) == 21000 and a.number(a.CYCLE_START, 8) == 28000
    assert a.number(a.JOG_PLUS, 2, axis=a.AXIS_ORDER.index("Z")) == 22386  # 6.4: Z +2
    assert a.number(a.PARTS_DONE, 3) == 49300 and a.name(a.PARTS_DONE) == "D49x00"
    assert a.name(a.MST_FINISH) == "M2x016" and a.name(a.T_CODE) == "D3x052"


def test_cycle_start_without_a_part_program_warns_w345_at_the_model_line(mlc, tmp_path):
    """A model nc5 line without program=: jogging, homing, modes need none (no warning); cycle
    start in AUTO runs an empty program, W345 at the model line, once, in --json's warnings."""
    import json

    quiet = sim(mlc, tmp_path, "scan 1ms\nmodel nc5\n0ms D21000=4\n20ms expect NC1.mode=4\nrun 50ms\n", None)
    assert quiet.code == 0 and "W345" not in quiet.err, quiet.err
    stim = ("scan 1ms\n# the virtual NC\nmodel nc5 axes=X\n10ms M21000=1\n20ms M21000=0\n30ms M21000=1\n"
            "40ms expect NC1.state=6\nrun 50ms\n")  # 6: program end (published.STATES)
    r = sim(mlc, tmp_path, stim, None)
    assert r.code == 0, r.err
    assert r.err.count("W345") == 1 and "s.stim:3:1: warning[W345]" in r.err, r.err
    assert "at 11 ms (scan 11): NC1: cycle start with no part program" in r.err  # read before the next scan
    warned = json.loads(sim(mlc, tmp_path, stim, None, "--json").out)["warnings"]
    assert [(w["code"], w["line"]) for w in warned] == [("W345", 3)]
    r = sim(mlc, tmp_path, stim.replace("model nc5 axes=X", "model nc5 axes=X program=part.nc"))
    assert r.code == 0 and "W345" not in r.err  # a part program (M30): no warning


def _project(tmp_path):
    (tmp_path / "mlc.toml").write_text('target = "nc5"\nsources = ["p.il"]\ntests = ["t/*.stim"]\n')
    (tmp_path / "p.il").write_text(PROGRAM)
    (tmp_path / "t").mkdir()
    (tmp_path / "t" / "a.stim").write_text("model nc5 program=part.nc\n0ms M21000=1\n100ms expect M31023=1\n")
    (tmp_path / "t" / "part.nc").write_text("M30\n")


def test_the_part_program_is_an_input_of_mlc_test_and_of_a_batch(mlc, tmp_path):
    """run.model_inputs: mlc test and a batch (`--stimulus 'GLOB'`) refuse an output that is a
    scenario's part program, as mlc sim does, and leave it whole."""
    _project(tmp_path)
    r = mlc("test", "--junit", "t/part.nc", cwd=tmp_path)
    assert r.code == 2 and "E606" in r.err and "t/part.nc" in r.err, r.err
    assert (tmp_path / "t" / "part.nc").read_text() == "M30\n"
    r = mlc("sim", "p.il", "--stimulus", "t/*.stim", "--junit", "t/part.nc", cwd=tmp_path)
    assert r.code == 2 and "E606" in r.err, r.err
    assert (tmp_path / "t" / "part.nc").read_text() == "M30\n"
    r = mlc("test", "--junit", "out.xml", cwd=tmp_path)
    assert r.code == 0 and (tmp_path / "out.xml").is_file(), r.err
