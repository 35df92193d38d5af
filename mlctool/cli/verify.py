"""`mlc verify`: prove a program's properties (a `.props` file, docs/verify.md) or show the
scan sequence that breaks them, written as a stimulus file `mlc sim` replays.

Exit 0: every property proven (a `reachable` one: a witness found); 1: a property violated
or undecided (UNKNOWN: the budget ran out); 2: usage errors or unusable input.
"""

from __future__ import annotations

import sys

import click

from mlctool.asm import program_from_paths
from mlctool.cli import main_group
from mlctool.cli.common import (
    collector_paused,
    command_scope,
    config_option,
    encoding_option,
    examples,
    get_config,
    get_target,
    output_format,
    positive_time,
    quiet_option,
    show,
    target_option,
    write_outputs,
)
from mlctool.fileio import Outputs, note_input
from mlctool.verify.builtin import CHECKS
from mlctool.verify.explicit import DEFAULT_MAX_STATES
from mlctool.verify.run import ENGINES

ARTIFACT_DIR = "mlc-verify-out"


@main_group.command("verify", epilog=examples(
    "mlc verify samples/nc5/conveyor.il --props samples/nc5/conveyor.props",
    "mlc verify samples/verify/press.il --props samples/verify/press.props --engine symbolic",
    "mlc verify samples/verify/press.il --props samples/verify/press.props --json --sarif v.sarif --junit v.xml",
))
@target_option
@encoding_option
@config_option
@click.option("--props", "props_paths", multiple=True, type=click.Path(dir_okay=False), metavar="FILE",
              help="property file (repeatable; default: mlc.toml [verify] properties)")
@click.option("--engine", type=click.Choice(ENGINES), default="auto", show_default=True,
              help="explicit (breadth-first over reachable states), symbolic (bounded model checking and "
                   "k-induction) or auto (explicit, then symbolic if its budget runs out)")
@click.option("--max-states", type=click.IntRange(1), default=DEFAULT_MAX_STATES, show_default=True,
              help="states the explicit search may visit per property before it answers UNKNOWN")
@click.option("--max-wall", default=None, metavar="TIME",
              help="wall-clock time for all properties (e.g. 30s): past it, UNKNOWN with statistics")
@click.option("--out", "out_dir", default=None, metavar="DIR",
              help=f"folder for counterexamples and witnesses (.stim and .vcd; default {ARTIFACT_DIR})")
@click.option("--json", "as_json", is_flag=True, help="print the results as JSON on stdout")
@click.option("--sarif", "sarif_path", default=None, type=click.Path(dir_okay=False),
              help="write SARIF 2.1.0: a violated or undecided property is a result at its line")
@click.option("--junit", "junit_path", default=None, type=click.Path(dir_okay=False),
              help="write JUnit XML, one test case per property")
@click.option("--check", "checks", multiple=True, type=click.Choice(CHECKS), metavar="NAME",
              help="a built-in check too (repeatable): " + ", ".join(CHECKS) + " (docs/verify.md; default: "
                   "mlc.toml [verify] checks)")
@quiet_option
@click.argument("program", nargs=-1, type=click.Path(), metavar="[FILE]...")
def verify_cmd(target_name, config_path, props_paths, engine, max_states, max_wall, out_dir, as_json,
               sarif_path, junit_path, checks, program):
    """Prove the properties of a property file on the program of FILE... (sources, objects or
    a linked image), or show the scan sequence that breaks them.

    With no FILE, the project of mlc.toml; with no --props, the files its [verify]
    `properties` name. A violated property's counterexample is a stimulus file (and VCD) in
    --out that `mlc sim` replays to the same failing expectation.

    Exit 0: every property proven; 1: one violated or undecided (UNKNOWN); 2: usage error or
    unusable input.
    """
    config = get_config(config_path)
    scope = command_scope(program, config, "program to verify")
    wall_us = positive_time(max_wall, "--max-wall")
    seconds = None if wall_us is None else wall_us / 1e6
    from mlctool.verify.report import project_checks, project_props, run_files

    paths = list(props_paths) or project_props(config)
    wanted = [(c, "<command line>", 1) for c in checks] or project_checks(config)
    if not paths and not wanted:
        raise click.UsageError("no property file: give --props FILE or --check NAME, or name them in mlc.toml "
                               "([verify] properties = [\"tests/*.props\"], checks = [...])")
    out_dir = out_dir or ARTIFACT_DIR
    for path in [*scope.files, *paths]:  # read below, after the outputs are planned: inputs now (E606)
        note_input(path)
    plan = Outputs()
    for path, what, formats in ((sarif_path, "--sarif", {".sarif": "SARIF", ".json": "SARIF"}),
                                (junit_path, "--junit", {".xml": "XML"})):
        if path:
            plan.add(path, what)
            output_format(path, what, formats, "SARIF" if what == "--sarif" else None)
    plan.validate()
    click.get_current_context().with_resource(plan)
    target = get_target(target_name, config)
    with collector_paused():
        image, diags, lines = program_from_paths(list(scope.files), target, config)
    if image is None:
        show([d for d in diags if d.severity == "error"], lines)
        sys.exit(2)
    outcome = run_files(image, target, paths, engine, max_states, seconds, out_dir, wanted, lines)
    plan_counterexamples(outcome, plan, lines)
    show(outcome.findings, {**lines, **outcome.lines})
    if as_json:
        sys.stdout.write(outcome.json())
    else:
        click.echo(outcome.text(), nl=False)
    files = dict(outcome.files)
    if sarif_path:
        from mlctool.sarif import to_sarif

        files[sarif_path] = to_sarif(outcome.findings, outcome.exit_code)
    if junit_path:
        files[junit_path] = outcome.junit(" ".join(paths))
    write_outputs(plan, files)
    sys.exit(outcome.exit_code)


def plan_counterexamples(outcome, plan: Outputs, lines: dict) -> None:
    """Exit 2 on the properties' errors (E110 ...); else plan each counterexample's file as an
    output (E606 where it is an input), before anything is written."""
    if outcome.errors:
        show(outcome.errors, {**lines, **outcome.lines})
        sys.exit(2)
    for path in outcome.files:
        plan.add(path, "a counterexample's file")
    plan.validate()
