"""`mlc check` and `mlc --help` start as a linter must: without the simulator, numpy, Modbus,
rich or lark (issue 14; bench/startup.py measures the time, this test only what is imported)."""

from __future__ import annotations

import subprocess

import click
import pytest

from mlctool.cli import COMMAND_MODULES, COMMAND_SUMMARIES, all_commands
from tests.conftest import MLC_COMMAND, SAMPLES

TINY = """; a latch, a timer, a jump (directives and a label: all on the regex fast path)
.define START X0
.define LAMP Y0
LD START
OR M0
ANI X1
OUT M0
LD M0
TMR T0 K10
LD T0
CJ P1
OUT LAMP
P1:
LD X3
OUT Y1
END
"""

HEAVY = ("numpy", "pymodbus", "serial", "mlctool.sim", "mlctool.devices", "mlctool.asm", "mlctool.ladder", "mlctool.targets.fbs",
         "rich", "lark", "websockets")


def imported(*args: str, cwd=None) -> tuple[set[str], subprocess.CompletedProcess]:
    """Modules the whole `python -m mlctool ARGS` process imports (from -X importtime)."""
    r = subprocess.run([MLC_COMMAND[0], "-X", "importtime", *MLC_COMMAND[1:], *args], capture_output=True,
                       text=True, cwd=cwd)
    names = {line.rsplit("|", 1)[1].strip() for line in r.stderr.splitlines() if line.startswith("import time:")}
    names.discard("package")  # the header line
    return names, r


def heavy(names: set[str]) -> list[str]:
    return sorted(n for n in names if any(n == h or n.startswith(h + ".") for h in HEAVY))


@pytest.mark.parametrize("args", [["--help"], [], ["check", "--help"], ["check", "tiny.il"], ["check", "bad.il"],
                                  ["check", "--format", "sarif", "bad.il"]])
def test_linting_imports_nothing_heavy(tmp_path, args):
    (tmp_path / "tiny.il").write_text(TINY)
    (tmp_path / "bad.il").write_text(TINY.replace("LD T0", "LD T0 X1\nFOO X9\nOUT Y99999"))
    names, r = imported(*args, cwd=tmp_path)
    assert "mlctool.cli" in names, r.stderr[-2000:]  # the command ran (and importtime worked)
    assert r.returncode in ((2,) if not args else (0, 1)), r.stderr[-2000:]  # `mlc` alone: usage, 2
    if args and args[-1] == "bad.il":
        assert "E205" in r.stderr + r.stdout and "E201" in r.stderr + r.stdout
    assert heavy(names) == []


def test_check_of_a_sample_with_a_syntax_error_still_works(tmp_path):
    # lark comes in for the line the regexes do not take, and reports it
    (tmp_path / "odd.il").write_text("LD X0\nOUT Y0 @\nEND\n")
    names, r = imported("check", "odd.il", cwd=tmp_path)
    assert r.returncode == 1 and "E103" in r.stderr and "lark" in names


def test_help_summaries_are_the_commands_own():
    commands = all_commands()
    assert set(COMMAND_SUMMARIES) == set(COMMAND_MODULES) == set(commands)
    for name, cmd in commands.items():
        for limit in (20, 45, 70, 200):
            assert click.Command(name, help=COMMAND_SUMMARIES[name]).get_short_help_str(limit) == \
                cmd.get_short_help_str(limit), (name, limit)


def test_samples_check_without_lark():
    sources = sorted(str(p) for p in SAMPLES.glob("nc5/*.il") if "bad" not in p.parts)
    names, r = imported("check", *sources[:12])
    assert r.returncode in (0, 1) and "lark" not in names, r.stderr[-2000:]
