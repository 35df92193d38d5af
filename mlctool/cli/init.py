"""`mlc init`: a new project (mlctool/starter.py) written into a folder, never over a file."""

from __future__ import annotations

import os

import click

from mlctool.cli import main_group
from mlctool.cli.common import examples, get_target, quiet, quiet_option, write_outputs
from mlctool.config import Config
from mlctool.diagnostics import MlcError, Span, diag
from mlctool.fileio import Outputs
from mlctool.starter import project_files
from mlctool.targetapi import available_targets


@main_group.command("init", epilog=examples(
    "mlc init motor                        # a new NC5 project in motor/; then: cd motor && mlc test",
    "mlc init --target fbs axis            # FATEK FBs: with a positioning table (mlc.toml `tables`)",
))
@click.option("--target", "target_name", default="nc5", show_default=True, metavar="NAME",
              help=f"target PLC of the project ({', '.join(available_targets())})")
@quiet_option
@click.argument("folder", default=".", type=click.Path(file_okay=False), metavar="[DIR]")
def init_cmd(target_name, folder):
    """Write a new project into DIR (default: here): mlc.toml, src/main.il, a passing scenario
    in tests/, a CI workflow and a pre-commit configuration.

    The project passes `mlc check`, `mlc fmt --check` and `mlc test` as written
    (docs/getting-started.md). No file is ever overwritten: a folder that already holds one
    of them is refused (E122), nothing written. Exit 0: written; 2: usage error or a file in
    the way.
    """
    target = get_target(target_name, Config())  # an unknown --target: E110 with the names
    files = project_files(target.name)
    if not files:
        raise click.UsageError(f"target {target.name} has no starter project")
    paths = {os.path.join(folder, *rel.split("/")): data for rel, data in files.items()}
    taken = [p for p in paths if os.path.lexists(p)]
    if taken:
        raise MlcError(diag(taken[0], Span.at(1), "E122", f"mlc init: {taken[0]} exists; nothing written "
                            f"({len(taken)} of the {len(paths)} files of a new project are there already: "
                            "run it in an empty folder or name a new one)"))
    plan = Outputs()
    for path in paths:
        plan.add(path, "a file of the new project")
    plan.validate()
    write_outputs(plan, paths)
    if not quiet():
        where = "" if os.path.normpath(folder) == "." else f"cd {folder} && "
        click.echo(f"a new {target.name} project: next, {where}mlc test (docs/getting-started.md)", err=True)
