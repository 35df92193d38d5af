"""`--help` of every command: examples at the end, consistent metavars, exit codes.

The examples themselves are run by tests/cli/test_docs_commands.py."""

from __future__ import annotations

import re

import click
import pytest

from mlctool.cli import all_commands, main_group


def _commands() -> dict[str, click.Command]:
    """Every command and group by its full name ("mlc", "mlc check", "mlc device serve")."""
    out: dict[str, click.Command] = {"mlc": main_group}

    def walk(prefix: str, cmd: click.Command) -> None:
        out[prefix] = cmd
        if isinstance(cmd, click.Group):
            ctx = click.Context(cmd)
            for name in cmd.list_commands(ctx):
                walk(f"{prefix} {name}", cmd.get_command(ctx, name))

    for name, cmd in all_commands().items():
        walk(f"mlc {name}", cmd)
    return out


COMMANDS = _commands()


def _examples(help_text: str) -> list[str]:
    tail = help_text.split("\n  Examples:\n", 1)
    assert len(tail) == 2, "no Examples section"
    lines = tail[1].rstrip("\n").split("\n")
    assert all(line.startswith("    mlc ") for line in lines), lines
    return [line.strip() for line in lines]


def test_every_command_is_covered():
    assert {"mlc check", "mlc build", "mlc sim", "mlc device serve", "mlc test"} <= set(COMMANDS)


@pytest.mark.parametrize("name", sorted(COMMANDS))
def test_help_ends_with_two_or_three_examples(mlc, name):
    r = mlc(*name.split()[1:], "--help")
    assert r.code == 0, r.err
    examples = _examples(r.out)
    assert 2 <= len(examples) <= 3
    if name != "mlc":  # each example of a command runs that command (or says what to run next)
        assert examples[0].startswith(name), examples


@pytest.mark.parametrize("name", ["mlc build", "mlc link", "mlc objdump", "mlc sim", "mlc check"])
def test_help_lists_exit_codes(mlc, name):
    r = mlc(*name.split()[1:], "--help")
    assert re.search(r"Exit 0: .*; 2: ", " ".join(r.out.split())), r.out


def test_file_metavars_are_consistent():
    """Files are FILE (FILE... for several, [FILE]... when none may be given), folders DIR."""
    allowed = {"FILE", "FILE...", "[FILE]", "[FILE]...", "[FILE|DIR]", "[FILE|DIR]...", "FILE|DIR", "DIR", "[DIR]",
               "[SR=]FILE"}
    seen = set()
    for name, cmd in COMMANDS.items():
        ctx = click.Context(cmd, info_name=name)
        for p in cmd.params:
            is_path = isinstance(p.type, click.Path) or any(k in (p.name or "") for k in ("path", "file", "dir", "output", "tables"))
            if isinstance(p, click.Argument) and p.name not in ("kind", "code") or (
                    isinstance(p, click.Option) and is_path and p.name != "serial"):
                metavar = p.make_metavar(ctx)
                seen.add(metavar)
                assert metavar in allowed, f"{name} {p.name}: {metavar}"
    assert {"FILE", "FILE...", "DIR"} <= seen
