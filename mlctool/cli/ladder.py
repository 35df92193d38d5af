"""`mlc ladder`: IL sources drawn as ladder diagrams (SVG, HTML, terminal)."""

from __future__ import annotations

import sys

import click

from mlctool.cli import main_group
from mlctool.cli.common import (
    config_option,
    encoding_option,
    examples,
    get_config,
    get_target,
    show,
    target_option,
)
from mlctool.diagnostics import unreadable
from mlctool.fileio import Outputs
from mlctool.ladder import sheets_from_files
from mlctool.report import summary_line

WRITERS = {".svg": "svg", ".html": "html", ".htm": "html"}


@main_group.command("ladder", epilog=examples(
    "mlc ladder prog.il                    # on the terminal",
    "mlc ladder src/main.il src/lib.il -o program.html   # a main program and its library",
    "mlc ladder prog.il -o prog.svg",
))
@target_option
@encoding_option
@config_option
@click.option("-o", "--output", "out_path", default=None, type=click.Path(dir_okay=False),
              help="write OUT.svg (rungs stacked) or OUT.html (self-contained page)")
@click.option("--term", is_flag=True, help="print the ladder on the terminal (default without -o)")
@click.option("--title", default="", help="title of the HTML page")
@click.argument("files", nargs=-1, required=True, type=click.Path(), metavar="FILE...")
def ladder_cmd(target_name, config_path, out_path, term, title, files):
    """Draw the FILEs as ladder diagrams, one rung per IL rung, in program order.

    The sources must pass `mlc check` without errors. Exit 0: drawn; 1: the sources have
    errors (shown as by mlc check, nothing written); 2: usage error or unreadable input.
    """
    kind = None
    if out_path is not None:
        suffix = "." + out_path.rsplit(".", 1)[-1].lower() if "." in out_path else ""
        kind = WRITERS.get(suffix)
        if kind is None:
            raise click.BadParameter("the output must end in .svg or .html", param_hint="-o")
    config = get_config(config_path)
    plan = Outputs()
    if out_path is not None:
        plan.add(out_path, "-o")
        plan.validate()
    target = get_target(target_name, config)
    sheets, diags, lines = sheets_from_files(list(files), target, config)
    errors = [d for d in diags if d.severity == "error"]
    if errors:
        show(errors, lines)
        click.echo(summary_line(len(errors), 0) + "; nothing drawn", err=True)
        sys.exit(2 if unreadable(errors) else 1)
    if kind == "svg":
        from mlctool.ladder.svg import sheets_svg

        plan.write({out_path: sheets_svg(sheets)})
    elif kind == "html":
        from mlctool.ladder.html import sheets_html

        plan.write({out_path: sheets_html(sheets, title)})
    if term or kind is None:
        from mlctool.ladder.term import print_sheets

        print_sheets(sheets)
