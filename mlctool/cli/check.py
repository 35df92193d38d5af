"""`mlc check`, `mlc explain`, `mlc targets`."""

from __future__ import annotations

import re
import sys

import click

from mlctool.check import check_files
from mlctool.check.other_target import likely_targets, wrong_target_note
from mlctool.cli import main_group
from mlctool.cli.common import (
    collector_paused,
    config_option,
    encoding_option,
    examples,
    expand_sources,
    get_config,
    get_target,
    require_project,
    target_option,
)
from mlctool.config import rules_dropped
from mlctool.diagnostics import Diagnostic, unreadable
from mlctool.report import SHOW_PER_CODE, render_text, summary_line, to_json
from mlctool.targetapi import available_targets, load_target


@main_group.command("check", epilog=examples(
    "mlc check                             # the project of the nearest mlc.toml",
    "mlc check src/main.il src/lib.il      # these files, as one program",
    "mlc check --format sarif src > mlc.sarif",
))
@target_option
@encoding_option
@config_option
@click.option("--format", "fmt", type=click.Choice(["text", "json", "sarif"]), default="text", show_default=True)
@click.option("--werror", is_flag=True, help="treat warnings as errors (exit 1)")
@click.option("--ignore", multiple=True, metavar="CODE",
              help="drop this warning code (repeatable; errors cannot be dropped)")
@click.option("--no-lint", is_flag=True, help="drop the lint warnings (W4xx)")
@click.option("--select", "select", multiple=True, metavar="CODE[,CODE]",
              help="run only these lint rules (W4xx); legality and structure checks always run")
@click.option("--show-all", is_flag=True,
              help=f"text output: show every diagnostic (default: the first {SHOW_PER_CODE} of each code, then a count)")
@click.argument("files", nargs=-1, type=click.Path(), metavar="[FILE|DIR]...")
def check_cmd(target_name, config_path, fmt, werror, ignore, no_lint, select, show_all, files):
    """Check instruction-list sources against the target's manual.

    With no FILE, checks the project of the nearest mlc.toml above the current folder: its
    `sources`, together, with its settings (and its positioning `tables`). A FILE that is a
    module of the project is checked with the whole project, and only its diagnostics are
    shown. A DIR stands for the *.il files below it.

    Exit 0: no errors; 1: errors (or warnings with --werror); 2: usage or unreadable input.
    """
    config = get_config(config_path)
    if not files:
        require_project(config, "files or folders to check")
    files = expand_sources(files)
    focus: list[str] = []
    if config.root is not None:  # (outside a project the linter does not load the assembler)
        from mlctool.asm.project import project_scope, table_file

        scope = project_scope(files, config)
        # the project's positioning tables are checked with its sources (a .pos in `tables`)
        files = scope.files + [p for p in map(table_file, scope.tables) if _positioning_source(p)]
        focus = scope.focus
    target = get_target(target_name, config)
    ignored = rules_dropped(ignore, select, no_lint)
    # FBs positioning programs (.pos/.mpos) have their own language: mlctool/targets/fbs
    positioning = [f for f in files if _positioning_source(f)]
    il_files = [f for f in files if f not in positioning]
    with collector_paused():
        result = check_files(il_files, target, config, ignored)
    diags, lines = result.diagnostics, result.lines
    if positioning:
        from mlctool.targets.fbs.files import check_positioning

        pos = check_positioning(positioning, config, ignored)
        diags = sorted(diags + pos.diagnostics, key=Diagnostic.sort_key)
        lines = {**lines, **pos.lines}
    if focus:  # modules of the project: checked with the others; the others' diagnostics not shown
        others = set(files) - set(focus)
        diags = [d for d in diags if d.file not in others]
    errors = sum(d.severity == "error" for d in diags)
    warnings = sum(d.severity == "warning" for d in diags)
    code = 2 if unreadable(diags) else 1 if errors or (werror and warnings) else 0
    if fmt == "json":
        _write_utf8(to_json(diags))
    elif fmt == "sarif":
        from mlctool.sarif import to_sarif

        _write_utf8(to_sarif(diags, code))
    else:
        render_text(diags, lines, sys.stderr, per_code=None if show_all else SHOW_PER_CODE)
        if diags:
            click.echo(summary_line(errors, warnings), err=True)
    guesses, their_errors = likely_targets(result.sources, target.name, config, result.diagnostics)
    if guesses:  # many errors of the instruction/device kinds that another target has not
        click.echo(wrong_target_note(guesses, their_errors, target.name, result.errors), err=True)
    sys.exit(code)


@main_group.command("explain", epilog=examples(
    "mlc explain W401",
    "mlc explain M21000                    # a special M/D of the target: the manual's row",
    "mlc explain                           # every code, one line each",
))
@click.argument("code", metavar="[CODE|DEVICE]", required=False)
@target_option
def explain_cmd(code, target_name):
    """Print the documentation of a diagnostic code, or the manual's row of a special device.

    A device (M21000, D31024) is looked up in the target's signal table (NC5: the MLC <-> NC
    special M/D of manual ch. 5); the target is --target, else mlc.toml's, else nc5. With no
    CODE, list every code with its severity and summary.

    Exit 0: printed; 2: no such code or signal.
    """
    # imported here: `mlc check` of a clean program never reads the codes
    from mlctool.codes import CODES

    if code is None:
        for c in sorted(CODES.values(), key=lambda c: (c.code[1:], c.code)):
            click.echo(f"{c.code}  {c.severity:7}  {c.summary}")
        click.echo("mlc explain CODE prints one code's documentation (docs/check.md lists them too)")
        return
    c = CODES.get(code.upper())
    if c is not None:
        click.echo(f"{c.code} ({c.severity}): {c.summary}\n\n{c.doc.strip()}")
        return
    if _explain_device(code, target_name):
        return
    from mlctool.suggest import did_you_mean

    click.echo(f"mlc: unknown code {code!r} (codes: {', '.join(CODES)}){did_you_mean(code, CODES)}", err=True)
    sys.exit(2)


def _explain_device(text: str, target_name: str | None) -> bool:
    """Print the signal row of a device; False when `text` is no device. A device that is no
    signal is said so, exit 2."""
    from mlctool.syntax.operands import OperandSyntaxError, parse_operand
    from mlctool.targetapi.signals import signals_of

    if not re.fullmatch(r"[A-Za-z]+[0-9]+", text.strip()):
        return False
    target = get_target(target_name, get_config())
    try:
        op = parse_operand(text.strip(), target.operand_syntax)
    except OperandSyntaxError:
        return False
    if op.is_const or op.device not in target.devices:
        return False
    table = signals_of(target)
    found = table.at(op.kind, op.number) if table else None
    if found is None:
        r = table.range_of(op.kind, op.number) if table else None
        where = (f"an undefined number of the {r.direction} range {op.kind}{r.lo}-{op.kind}{r.hi} (W251)" if r
                 else f"not a special M/D of target {target.name}" if table else f"target {target.name} has no signal table")
        click.echo(f"mlc: {text.upper()} is no signal: {where}", err=True)
        sys.exit(2)
    click.echo(found.describe() + "\n")
    width = max(len(k) for k, _ in found.rows())
    for key, value in found.rows():
        click.echo(f"  {key:<{width}}  {value}")
    return True


@main_group.command("targets", epilog=examples(
    "mlc targets",
    "mlc check --target vs --model VS1 prog.il   # then check for one of them",
))
def targets_cmd():
    """List the targets and the manual each one follows.

    A manual is named by its title and edition; its file (the text the tables were read from)
    is named too when it is beside this checkout (../shared/manuals/), which a clone is not.
    """
    from pathlib import Path

    manuals = Path(__file__).resolve().parents[3] / "shared" / "manuals"
    for name in available_targets():
        t = load_target(name)
        line = f"{t.name:6} {t.title:22} manual: {t.settings.get('manual_title') or t.manual}"
        if t.manual and (manuals / t.manual).is_file():
            line += f" (file {manuals / t.manual})"
        click.echo(line)


def _positioning_source(path: str) -> bool:
    """An FBs positioning program (.pos/.mpos); an .il file is never one, and is told without
    loading the FBs tables (about 5 ms of a linter's start-up)."""
    if path.lower().endswith(".il"):
        return False
    from mlctool.targets.fbs.model import is_positioning_source

    return is_positioning_source(path)


def _write_utf8(text: str) -> None:
    """JSON and SARIF are UTF-8 whatever the locale's encoding (names may be Chinese, VS 2-10)."""
    buf = getattr(sys.stdout, "buffer", None)
    if buf is None:  # an in-memory text stream
        sys.stdout.write(text)
        return
    sys.stdout.flush()
    buf.write(text.encode("utf-8"))
    buf.flush()
