"""`mlc export`: IL -> a vendor tool's form (GX Works2 CSV, WPLSoft CSV, a WinProladder project)."""

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
    quiet_option,
    show,
    target_option,
    write_outputs,
)
from mlctool.diagnostics import unreadable
from mlctool.exports import FORMATS, export_text
from mlctool.fileio import Outputs
from mlctool.imports import read_export
from mlctool.syntax.source import source_encoding


@main_group.command("export", epilog=examples(
    "mlc export --target vs --to gxworks2 prog.il -o MAIN.csv   # GX Works2: Read from CSV File",
    "mlc export --target vs --to wplsoft prog.il -o prog.csv",
    "mlc export --target fbs --to winproladder rungs.il --template project.pdw -o out.pdw",
))
@target_option
@encoding_option
@config_option
@click.option("--to", "fmt", type=click.Choice(FORMATS), required=True, help="the vendor tool's form")
@click.option("-o", "--output", default=None, type=click.Path(dir_okay=False),
              help="write the export here, in the tool's encoding (default: its text on standard output)")
@click.option("--template", default=None, type=click.Path(dir_okay=False),
              help="winproladder: a project WinProladder saved, holding a short program; the program is "
                   "written into it, the rest kept")
@quiet_option
@click.argument("file", type=click.Path())
def export_cmd(target_name, config_path, fmt, output, template, file):
    """Write an IL program in a vendor tool's form, for that tool to read (docs/formats.md).

    The step column is the address the target's step convention computes; `mlc import` of the
    output gives the IL back. --to winproladder writes the program into a project WinProladder
    saved (--template), keeping the rest of it. Exit 0: written; 1: the program has errors
    or instructions the form cannot hold; 2: unreadable input or an unusable template.
    """
    config = get_config(config_path)
    if fmt == "winproladder" and not (template and output):
        raise click.UsageError("--to winproladder writes a project file: give --template (a project WinProladder "
                               "saved) and -o")
    if template and fmt != "winproladder":
        raise click.UsageError("--template is for --to winproladder")
    plan = Outputs()
    if output:
        plan.add(output, "-o")
        plan.validate()
    target = get_target(target_name, config)
    text, diags = read_export(file, source_encoding(config)[0])
    data = None
    if text is not None and fmt == "winproladder":
        data, found = _winproladder(file, text, target, template)
        diags = diags + found
    elif text is not None:
        data, found = export_text(file, text, target, fmt)
        diags = diags + found
    show(diags, {})
    if data is None:
        sys.exit(2 if unreadable(diags) or any(d.code == "E931" for d in diags) else 1)
    if output:
        write_outputs(plan, {output: data})
    else:
        # the text on the terminal; the file GX Works2 reads (UTF-16) is written with -o
        sys.stdout.write(data.decode("utf-16") if data.startswith(b"\xff\xfe") else data.decode("utf-8"))


def _winproladder(file, text, target, template):
    from mlctool.diagnostics import Span, diag
    from mlctool.exports import export_winproladder
    from mlctool.fileio import read_input
    from mlctool.winproladder import MAX_FILE

    try:
        data = read_input(template, MAX_FILE + 1)
    except OSError as e:
        return None, [diag(template, Span.at(1), "E100", f"cannot read: {e.strerror or e}")]
    return export_winproladder(file, text, target, data)
