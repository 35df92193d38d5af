"""The `mlc` group itself (mlctool/cli/__init__.py)."""

from __future__ import annotations


def test_mistyped_command_names_the_nearest(mlc):
    """Issue 14 §3: `mlc chek` said only "No such command"."""
    r = mlc("chek", "a.il")
    assert r.code == 2 and "No such command 'chek'. Did you mean 'check'?" in r.err
    r = mlc("objdmp", "x.mlx")
    assert r.code == 2 and "Did you mean 'objdump'?" in r.err
    r = mlc("zzz")
    assert r.code == 2 and "Did you mean" not in r.err and "Commands: build, check," in r.err


def test_suggest_is_case_insensitive_and_quiet_when_nothing_is_near():
    from mlctool.suggest import closest, did_you_mean

    assert closest("otu", ["OUT", "LD"]) == "OUT"
    assert closest("sorces", ["target", "sources"]) == "sources"
    assert did_you_mean("qqqq", ["OUT", "LD"]) == ""


def test_mistyped_target_and_code_name_the_nearest(mlc, tmp_path):
    p = tmp_path / "a.il"
    p.write_text("LD X0\nOUT Y0\nEND\n")
    r = mlc("check", "--target", "vz", str(p))
    assert r.code == 2 and "error[E110]: unknown target 'vz' (available: fbs, nc5, vs); did you mean 'vs'?" in r.err
    r = mlc("explain", "W4O1")
    assert r.code == 2 and r.err.rstrip().endswith("did you mean W401?")
