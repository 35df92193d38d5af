"""`mlc import`: a vendor export (GX Works2 / GX Developer / WPLSoft / Delta CSV, plain IL), a
GX Works2 project (.gxw), a GX Developer program body (.wpg) or a FATEK WinProladder project /
ladder resource (.pdw / .ldr) -> IL."""

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
from mlctool.diagnostics import Span, diag, unreadable
from mlctool.fileio import Outputs, read_input
from mlctool.imports import (
    DIALECT_TARGET,
    FORMATS,
    detect,
    gx_developer_project,
    import_project,
    import_text,
    import_winproladder,
    import_wpg,
    is_gx_developer_project,
    is_gx_project,
    is_winproladder,
    is_wpg,
    project_file,
    read_comments,
    read_export,
)
from mlctool.syntax.source import source_encoding


@main_group.command("import", epilog=examples(
    "mlc import --target vs export.csv -o prog.il      # the format is recognised",
    "mlc import PROJECT -o prog.il   # a GX Developer project folder: its program body and COMMENT.wcd",
    "mlc import --target fbs project.pdw -o fatek.il   # FATEK WinProladder (.pdw / .ldr)",
))
@target_option
@encoding_option
@config_option
@click.option("--from", "fmt", type=click.Choice(FORMATS), default=None,
              help="the export's format (default: recognised from its content)")
@click.option("-o", "--output", default=None, type=click.Path(dir_okay=False),
              help="write the IL here (default: standard output)")
@click.option("--comments", "comments_file", default=None, type=click.Path(dir_okay=False),
              help="a GX device-comment CSV or GX Developer COMMENT.wcd: each device's comment on the lines "
              "using it")
@quiet_option
@click.option("--program", default=None, metavar="NAME",
              help="a GX Works2 project's program POU or a GX Developer project's program body to read "
              "(default: its only one)")
@click.argument("file", type=click.Path())
def import_cmd(target_name, config_path, fmt, output, comments_file, program, file):
    """Convert an editor's export or a GX Works2 / GX Developer / WinProladder project to plain IL (docs/formats.md).

    Without --target, a GX Works2, GX Developer, WPLSoft or Delta export, a GX Works2 project or
    a GX Developer program body or project folder (FX dialect) is imported for target vs, a
    WinProladder .pdw / .ldr for fbs; plain IL for the target of mlc.toml, else nc5.

    Exit 0: converted; 1: rows that cannot be placed; 2: unreadable input or not an export.
    """
    config = get_config(config_path)
    plan = Outputs()
    if output:
        plan.add(output, "-o")
        plan.validate()
    if is_gx_developer_project(file):
        body, found, diags = gx_developer_project(file, program)
        show(diags, {})
        if body is None:
            sys.exit(2)
        _import_wpg(body, target_name, config, output, comments_file, plan, None if comments_file else found)
        return
    head = _head(file)
    project = project_file(file, head)
    if project is not None:
        show([project], {})
        sys.exit(2)
    if is_wpg(file):
        if program is not None:
            raise click.UsageError("--program names a program POU of a GX Works2 project (.gxw); a GX Developer "
                                   f".wpg holds one program: {file}")
        _import_wpg(file, target_name, config, output, comments_file, plan)
        return
    if is_gx_project(file, head):
        _import_project(file, target_name, config, output, comments_file, program, plan)
        return
    if is_winproladder(file, head):
        _import_winproladder(file, target_name, config, output, comments_file, program, plan)
        return
    if program is not None:
        raise click.UsageError("--program names a program POU of a GX Works2 project (.gxw); "
                               f"{file} is none")
    text, diags = read_export(file, source_encoding(config)[0])
    found_fmt = fmt or (detect(text) if text is not None else "")
    # an FX-dialect export is a VS program unless the command line says otherwise
    dialect = DIALECT_TARGET.get(found_fmt) if not target_name else None
    target = get_target(target_name or dialect, config)
    comments = _comments(comments_file, target, config) if text is not None else None
    if text is not None:
        text, found_fmt, converted = import_text(file, text, target, fmt, comments)
        diags = diags + converted
    show(diags, {})
    if text is None:
        sys.exit(_exit_code(diags))
    _write(file, text, found_fmt, target, dialect, output, plan)


def _import_project(file, target_name, config, output, comments_file, program, plan):
    """A GX Works2 project: exit 2 for a file it cannot read (E915-E922), 1 for instructions
    the target cannot place, as the CSV's rows."""
    from mlctool.gxw import MAX_FILE

    dialect = DIALECT_TARGET["gxw"] if not target_name else None
    target = get_target(target_name or dialect, config)
    data = _read(file, MAX_FILE + 1)
    comments = _comments(comments_file, target, config)
    text, _, diags = import_project(file, data, target, comments, program)
    show(diags, {})
    if text is None:
        sys.exit(_exit_code(diags))
    _write(file, text, "gxw", target, dialect, output, plan)


def _import_wpg(file, target_name, config, output, comments_file, plan, project_comments=None):
    """A GX Developer program body: exit 2 for a file it cannot read (E918-E921, E932, E933), 1
    for instructions the target cannot place, as a .gxw's. `project_comments`: the comment file
    of the body's project folder, which the user did not name: one it cannot read is W917 and
    the program is imported without comments."""
    from mlctool.wpg import MAX_FILE

    dialect = DIALECT_TARGET["wpg"] if not target_name else None
    target = get_target(target_name or dialect, config)
    data = _read(file, MAX_FILE + 1)
    comments = _comments(comments_file, target, config)
    said = []
    if project_comments is not None:
        comments, found = read_comments(project_comments, target, source_encoding(config)[0])
        said = [diag(project_comments, Span.at(1), "W917", f"the project's comments are not read: {d.code}: "
                     f"{d.message}", *d.notes, "the program is imported without them; --comments FILE "
                     "gives a comment file (with --encoding for its code page)")
                for d in found if d.severity == "error"]
    text, fmt, diags = import_wpg(file, data, target, comments)
    diags = said + diags
    show(diags, {})
    if text is None:
        sys.exit(_exit_code(diags))
    _write(file, text, fmt, target, dialect, output, plan)


def _import_winproladder(file, target_name, config, output, comments_file, program, plan):
    """A FATEK WinProladder .pdw / .ldr: exit 2 for a file it cannot read or forms the target
    cannot place (E923-E929), as the issue asks of vendor project files."""
    from mlctool.imports import WINPROLADDER_TARGET
    from mlctool.winproladder import MAX_FILE

    if comments_file or program is not None:
        raise click.UsageError("--comments and --program are for GX projects and exports; a WinProladder file "
                               "takes neither")
    dialect = WINPROLADDER_TARGET if not target_name else None
    target = get_target(target_name or dialect, config)
    text, fmt, diags = import_winproladder(file, _read(file, MAX_FILE + 1), target)
    show(diags, {})
    if text is None:
        sys.exit(_exit_code(diags))
    _write(file, text, fmt, target, dialect, output, plan)


# What says the file is no input the importer can read (exit 2, as for a file that cannot be
# read at all): not an export (E909, E912), a CPU of another series (E910), a GX Works2 project
# (E915-E922), a WinProladder file (E923-E929), a GX Developer body or project folder (E918-E921,
# E932-E934), a comment file (E936-E939). Anything else is a row or instruction the target
# cannot place: exit 1.
UNUSABLE = frozenset({"E909", "E910", "E912", *(f"E{n}" for n in range(915, 930)), "E932", "E933", "E934",
                      "E936", "E937", "E938", "E939"})


def _exit_code(diags) -> int:
    return 2 if unreadable(diags) or any(d.code in UNUSABLE for d in diags) else 1


def _read(file: str, limit: int) -> bytes:
    """A project file's bytes (at most `limit`: the reader refuses a larger one); exits 2
    (E100) when it cannot be read."""
    try:
        return read_input(file, limit)
    except OSError as e:
        show([diag(file, Span.at(1), "E100", f"cannot read: {e.strerror or e}")], {})
        sys.exit(2)


def _comments(comments_file, target, config) -> dict[str, str] | None:
    """The device comments of --comments (None without it); exits on an unusable file."""
    if not comments_file:
        return None
    comments, found = read_comments(comments_file, target, source_encoding(config)[0])
    if comments is None:
        show(found, {})
        sys.exit(_exit_code(found))
    return comments


def _write(file, text, found_fmt, target, dialect, output, plan):
    how = (f"target {target.name}, the dialect of a {found_fmt} export; --target chooses another"
           if dialect else f"target {target.name}")
    if output:
        write_outputs(plan, {output: text})
        click.echo(f"{file}: {found_fmt} -> {output} ({how}); check it with "
                   f"`mlc check --target {target.name} {output}`", err=True)
    else:
        sys.stdout.write(text)
        if dialect:
            click.echo(f"{file}: {found_fmt} ({how}); check it with `mlc check --target {target.name}`", err=True)


def _head(path: str) -> bytes:
    """The first bytes of the file (b"" if it cannot be read: read_export reports why)."""
    try:
        return read_input(path, 16)
    except OSError:
        return b""
