"""`mlc import`: a vendor export (GX Works2 / GX Developer / WPLSoft CSV, plain IL) -> IL."""

from __future__ import annotations

import sys

import click

from mlctool.cli import main_group
from mlctool.cli.common import (
    config_option,
    get_config,
    get_target,
    output_plan,
    show,
    target_option,
)
from mlctool.diagnostics import unreadable
from mlctool.imports import FORMATS, import_file


@main_group.command("import")
@target_option
@config_option
@click.option("--from", "fmt", type=click.Choice(FORMATS), default=None,
              help="the export's format (default: recognised from its content)")
@click.option("-o", "--output", default=None, type=click.Path(dir_okay=False),
              help="write the IL here (default: standard output)")
@click.argument("file", type=click.Path())
def import_cmd(target_name, config_path, fmt, output, file):
    """Convert an editor's export to plain IL for the target (docs/vs.md, Imports).

    Exit 0: converted; 1: rows that cannot be read; 2: unreadable input.
    """
    config = get_config(config_path)
    plan = output_plan([file], config)
    if output:
        plan.add(output, "-o")
        plan.validate()
    target = get_target(target_name, config)
    text, found_fmt, diags = import_file(file, target, fmt)
    show(diags, {})
    if text is None:
        sys.exit(2 if unreadable(diags) else 1)
    if output:
        plan.write({output: text})
        click.echo(f"{file}: {found_fmt} -> {output}", err=True)
    else:
        sys.stdout.write(text)
