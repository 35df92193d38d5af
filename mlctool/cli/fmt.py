"""`mlc fmt`: canonical IL layout."""

from __future__ import annotations

import difflib
import sys

import click

from mlctool.cli import main_group
from mlctool.cli.common import (
    command_scope,
    config_option,
    encoding_option,
    examples,
    get_config,
    get_target,
    quiet,
    quiet_option,
    show,
    target_option,
)
from mlctool.diagnostics import unreadable
from mlctool.fileio import distinct, rewrite
from mlctool.fmt import FormatOptions, format_source
from mlctool.syntax.source import GUESSED, read_source, source_encoding


@main_group.command("fmt", epilog=examples(
    "mlc fmt src/*.il",
    "mlc fmt --check                       # a project's modules; CI: a diff and exit 1, nothing changed",
    "mlc fmt --steps renumber src/main.il  # leading step numbers, recomputed",
))
@target_option
@encoding_option
@config_option
@click.option("--check", "check_only", is_flag=True, help="change nothing; exit 1 and show a diff if a file would change")
@click.option("--steps", type=click.Choice(["drop", "keep", "renumber"]), default="drop", show_default=True,
              help="leading step numbers: drop them, keep them, or write the computed addresses")
@quiet_option
@click.argument("files", nargs=-1, type=click.Path(), metavar="[FILE]...")
def fmt_cmd(target_name, config_path, check_only, steps, files):
    """Rewrite IL files in the canonical layout (idempotent; code unchanged).

    With no FILE, the modules of the project of mlc.toml (docs/project.md). Each rewritten
    file is named on stderr (`formatted FILE`; -q: silent).

    Exit 0: nothing to change (or rewritten); 1: --check found changes or a file has syntax
    errors; 2: unreadable input.
    """
    config = get_config(config_path)
    files = files or command_scope((), config, "files to format").files
    target = get_target(target_name, config)
    encoding, _ = source_encoding(config)
    if not check_only:  # each file is rewritten in place: two names for one file are refused (E606)
        distinct(files, "the file")
    worst = 0
    for path in files:
        src, diags = read_source(path, encoding)
        show([d for d in diags if d.code == GUESSED], {})
        if src is None:
            show(diags, {})
            worst = max(worst, 2 if unreadable(diags) else 1)
            continue
        new, diags = format_source(src, target, FormatOptions(steps))
        if new is None:
            show(diags, {path: src.text.split("\n")})
            click.echo(f"{path}: not formatted (syntax errors)", err=True)
            worst = max(worst, 1)
            continue
        if new == src.text:
            continue
        if check_only:
            diff = difflib.unified_diff(src.text.splitlines(True), new.splitlines(True),
                                        f"{path} (current)", f"{path} (formatted)")
            sys.stdout.writelines(diff)
            worst = max(worst, 1)
        else:
            # the file's own encoding, BOM and line ending; through a symlink; mode and hard links kept
            rewrite(path, src.encode(new))
            if not quiet():
                click.echo(f"formatted {path}", err=True)
    sys.exit(worst)
