"""`mlc ladder`: IL sources drawn as ladder diagrams (SVG, HTML, terminal)."""

from __future__ import annotations

import sys

import click

from mlctool.cli import main_group
from mlctool.cli.common import (
    Integer,
    command_scope,
    config_option,
    encoding_option,
    examples,
    get_config,
    get_target,
    output_format,
    quiet_option,
    show,
    target_option,
    write_outputs,
)
from mlctool.diagnostics import unreadable
from mlctool.fileio import Outputs
from mlctool.ladder import sheets_from_files
from mlctool.report import summary_line

WRITERS = {".svg": "SVG", ".html": "HTML", ".htm": "HTML"}


@main_group.command("ladder", epilog=examples(
    "mlc ladder prog.il                    # on the terminal",
    "mlc ladder                            # in a project: every module of mlc.toml",
    "mlc ladder src/main.il -o main.svg    # a module of the project, its CALLs resolved",
))
@target_option
@encoding_option
@config_option
@click.option("-o", "--output", "out_path", default=None, type=click.Path(dir_okay=False),
              help="write OUT.svg (rungs stacked) or OUT.html (self-contained page)")
@click.option("--term", is_flag=True, help="print the ladder on the terminal (default without -o)")
@click.option("--title", default="", help="title of the HTML page")
@click.option("--width", type=Integer(60, 1000), default=None, metavar="N",
              help="terminal ladder N characters wide (default: the terminal's; 100 when not a terminal)")
@click.option("--comments", is_flag=True, help="show device comments (line and .define comments) under contacts")
@quiet_option
@click.argument("files", nargs=-1, type=click.Path(), metavar="[FILE]...")
def ladder_cmd(target_name, config_path, out_path, term, title, width, comments, files):
    """Draw the FILEs as ladder diagrams, one rung per IL rung, in program order.

    With no FILE, the modules of the project of mlc.toml; a FILE that is a module of the
    project is drawn with the whole project loaded (its CALLs resolve), alone (docs/project.md).
    The sources must pass `mlc check` without errors. Exit 0: drawn; 1: the sources have
    errors (shown as by mlc check, nothing written); 2: usage error or unreadable input.
    """
    kind = output_format(out_path, "-o", WRITERS) if out_path is not None else None
    config = get_config(config_path)
    scope = command_scope(files, config, "sources to draw")
    plan = Outputs()
    if out_path is not None:
        plan.add(out_path, "-o")
        plan.validate()
    target = get_target(target_name, config)
    sheets, diags, lines = sheets_from_files(scope.files, target, config)
    errors = [d for d in diags if d.severity == "error"]
    if errors:
        show(errors, lines)
        click.echo(summary_line(len(errors), 0) + "; nothing drawn", err=True)
        sys.exit(2 if unreadable(errors) else 1)
    if scope.focus:
        sheets = [s for s in sheets if s.path in scope.focus]  # (the project's spelling of each, as loaded)
    if kind == "SVG":
        from mlctool.ladder.svg import sheets_svg

        write_outputs(plan, {out_path: sheets_svg(sheets, comments)})
    elif kind == "HTML":
        from mlctool.ladder.html import sheets_html

        write_outputs(plan, {out_path: sheets_html(sheets, title, comments)})
    if term or kind is None:
        from mlctool.ladder.term import print_sheets

        print_sheets(sheets, width, comments)
