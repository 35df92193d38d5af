"""`mlc test`: run a project's stimulus files against its program; JUnit and coverage."""

from __future__ import annotations

import fnmatch
import json
import os
import sys
from pathlib import Path

import click

from mlctool.asm import program_from_paths
from mlctool.asm.project import project_tables
from mlctool.cli import main_group
from mlctool.cli.common import (
    Integer,
    collector_paused,
    encoding_option,
    examples,
    get_target,
    load_tables,
    max_wall_option,
    quiet_option,
    said_written,
    show,
    target_option,
    with_cli_encoding,
)
from mlctool.config import load_config
from mlctool.diagnostics import MlcError, Span, diag
from mlctool.fileio import Outputs, note_input
from mlctool.sim.campaign import coverage as cov
from mlctool.sim.campaign.cluster import ClusterError, cluster_diagnostic
from mlctool.sim.campaign.junit import to_junit
from mlctool.sim.campaign.suite import (
    ARTIFACT_DIR,
    artifact_paths,
    discover,
    failure_artifacts,
    merged_probe,
    run_all,
)
from mlctool.sim.run.output import ms, to_json
from mlctool.sim.run.unmodelled import unmodelled_writes
from mlctool.sim.run.vcd import gtkw_path

COVERAGE_FILES = ("coverage.txt", "coverage.json", "coverage.xml")


def _enter_project(path: str | None):
    """cd into the project folder (the one holding mlc.toml: PATH's, else the nearest one at or
    above the current folder) and load its configuration. PATH is the project's folder, its
    mlc.toml, or a file inside it (a module, a scenario): then the nearest mlc.toml above it.
    Returns (configuration, PATH relative to the project folder when PATH is a file in it)."""
    if path is None:
        start = Path.cwd()
    else:
        p = Path(path)
        if not p.exists():
            raise MlcError(diag(path, Span.at(1), "E100", f"{path}: no such file or folder"))
        start = p if p.is_dir() else p.parent
    start = start.resolve()
    folder = next((d for d in (start, *start.parents) if (d / "mlc.toml").is_file()), None)
    if folder is None:
        where = "here or above" if path is None else f"in {start} or above"
        raise MlcError(diag(str(start / "mlc.toml"), Span.at(1), "E100",
                            f"no mlc.toml {where} (mlc test runs a project's tests)"))
    inside = None
    if path is not None and Path(path).is_file() and Path(path).name != "mlc.toml":
        inside = os.path.relpath(Path(path).resolve(), folder)
    os.chdir(folder)
    return with_cli_encoding(load_config(explicit="mlc.toml")), inside


@main_group.command("test", epilog=examples(
    "mlc test                              # the project of the nearest mlc.toml",
    "mlc test --coverage --junit junit.xml -j 2",
    "mlc test tests/pick_cycle.stim        # one scenario of the project",
))
@target_option
@encoding_option
@max_wall_option
@click.option("--jobs", "-j", type=Integer(1, 64), default=1, show_default=True,
              help="run scenarios in N worker processes")
@click.option("--cluster", default=None, metavar="tcp://HOST:PORT",
              help="run the scenarios on this Dask scheduler's workers (docs/scale.md)")
@click.option("--junit", "junit_path", default=None, metavar="FILE", help="write JUnit XML")
@click.option("--coverage", "with_coverage", is_flag=True,
              help="record coverage; writes coverage.txt, coverage.json and coverage.xml (Cobertura)")
@click.option("--coverage-dir", default=None, metavar="DIR",
              help="folder for the coverage reports (default: the project's folder)")
@click.option("-k", "keywords", multiple=True, metavar="PATTERN",
              help="run only the scenarios whose path contains PATTERN, or matches it as a glob "
                   "(tests/pick*); repeatable: any of them")
@click.option("--json", "as_json", is_flag=True, help="print the results as JSON on stdout")
@click.option("--out", "out_dir", default=None, metavar="DIR",
              help=f"folder for a failing scenario's waveform and report page "
                   f"(default: beside --junit, else {ARTIFACT_DIR} in the project's folder)")
@quiet_option
@click.argument("path", required=False, type=click.Path(), metavar="[FILE|DIR]")
def test_cmd(target_name, jobs, cluster, junit_path, with_coverage, coverage_dir, keywords, as_json, out_dir, path):
    """Run the stimulus files of the project in DIR (default: the nearest mlc.toml at or above
    the current folder).

    mlc.toml names the program (`sources`), its register tables (`tables`) and the scenarios
    (`tests`, globs). PATH may also be a file of the project: a scenario runs alone, a module
    runs every scenario. Files named on the command line (--junit, --out, --coverage-dir) are
    relative to the current folder, as with every command; each file written is named on
    stderr (-q: silent). Exit 0 when every expectation held, 1 on any failure or fault, 2 on
    usage errors or unreadable input.
    """
    here = os.getcwd()
    config, inside = _enter_project(path)
    # named outputs: relative to where the command was run, now from the project's folder
    junit_path, out_dir, coverage_dir = (None if p is None else os.path.relpath(os.path.join(here, p))
                                         for p in (junit_path, out_dir, coverage_dir))
    coverage_dir = coverage_dir or "."
    target = get_target(target_name, config)
    sources, stims, problems = discover(config)
    if problems:
        show(problems, {})
        sys.exit(2)
    stims = _selected(_inside(inside, sources, stims), keywords)
    tables = project_tables(config)
    plan = Outputs()
    if junit_path:
        plan.add(junit_path, "--junit")
    out_dir = out_dir or (os.path.dirname(junit_path) or "." if junit_path else ARTIFACT_DIR)
    for stim in stims:  # a failure's files: planned for every scenario, written for failures
        vcd, html = artifact_paths(stim, out_dir)
        for p in (vcd, gtkw_path(vcd), html):
            plan.add(p, "a failure's file")
    if with_coverage:
        for name in COVERAGE_FILES:
            plan.add(os.path.join(coverage_dir, name), "--coverage")
    plan.validate()
    preload = load_tables((), tables, target, config)
    with collector_paused():
        image, diags, lines = program_from_paths(sources, target, config)
    if image is None:
        show([d for d in diags if d.severity == "error"], lines)
        sys.exit(2)
    try:
        if with_coverage:
            scenarios = run_all(image, target, stims, jobs, with_coverage, cluster, preload)
        else:  # a batch: bit-sliced or numpy lanes where the program and stimuli allow (same results)
            from mlctool.sim.campaign.batch import Options, run_batch

            scenarios = run_batch(image, target, stims, Options(preload=preload), jobs, cluster=cluster)[0]
    except ClusterError as e:
        show([cluster_diagnostic(e)], {})
        sys.exit(2)

    # the project's properties (mlc.toml [verify]), beside its scenarios: not when PATH or -k
    # picks scenarios
    verified = None
    if not inside and not keywords and config.data.get("verify"):
        from mlctool.cli.verify import plan_counterexamples
        from mlctool.verify.explicit import DEFAULT_MAX_STATES
        from mlctool.verify.report import project_checks, project_props, run_files

        props_paths, checks = project_props(config), project_checks(config)
        verified = run_files(image, target, props_paths, "auto", DEFAULT_MAX_STATES, None, out_dir, checks, lines)
        plan_counterexamples(verified, plan, lines)
    all_lines = dict(lines)
    unmodelled = unmodelled_writes(image, target)  # W608: once per device for the whole suite
    show(unmodelled, lines)
    for sc in scenarios:
        all_lines[sc.stim] = sc.stim_lines
        show(sc.diagnostics, all_lines)
    for sc in scenarios:  # the files its models read (an NC part program) are inputs too
        for p in sc.inputs:
            note_input(p)
    files = {}
    for sc in scenarios:
        if sc.result is not None and not sc.ok:
            found = failure_artifacts(image, target, sc, lines, out_dir, preload)
            files.update(found)
            sc.artifacts = tuple(p for p in found if not p.endswith(".gtkw"))
    if verified is not None:
        show(verified.findings, {**lines, **verified.lines})
        files.update(verified.files)
    if as_json:
        sys.stdout.write(_json(scenarios, unmodelled, verified))
    else:
        _table(scenarios)
        if verified is not None:
            click.echo(verified.text(), nl=False)
    if junit_path:
        files[junit_path] = to_junit(scenarios, config.data.get("name", "mlc test"))
        if verified is not None:
            files[junit_path] = _with_properties(files[junit_path], verified)
    if with_coverage:
        rep = cov.report(image, merged_probe(len(image.instrs), scenarios))
        for name, render in zip(COVERAGE_FILES, (cov.to_text, cov.to_json, cov.to_cobertura), strict=True):
            files[os.path.join(coverage_dir, name)] = render(rep)
    plan.write(files)

    def shown(p: str) -> str:  # a path as the user reaches it from where the command ran
        return os.path.relpath(os.path.abspath(p), here)

    said_written(map(shown, files))
    for sc in scenarios:
        if sc.artifacts:
            click.echo(f"{sc.stim}: failed; waveform {shown(sc.artifacts[0])}, report {shown(sc.artifacts[1])}",
                       err=True)
    if with_coverage and not as_json:
        click.echo(cov.to_text(rep), nl=False)
    sys.exit(0 if all(sc.ok for sc in scenarios) and (verified is None or verified.exit_code == 0) else 1)


def _with_properties(junit: str, verified) -> str:
    """The scenarios' JUnit document with the properties' test suites after them."""
    import xml.etree.ElementTree as ET

    root = ET.fromstring(junit.split("\n", 1)[1])
    for suite in ET.fromstring(verified.junit("").split("\n", 1)[1]):
        root.append(suite)
    ET.indent(root)
    return '<?xml version="1.0" encoding="UTF-8"?>\n' + ET.tostring(root, encoding="unicode") + "\n"


def _inside(inside: str | None, sources: list[str], stims: list[str]) -> list[str]:
    """PATH a file of the project: a scenario runs alone, a module (or mlc.toml) runs them all."""
    if inside is None or any(os.path.normpath(inside) == os.path.normpath(s) for s in sources):
        return stims
    chosen = [s for s in stims if os.path.normpath(s) == os.path.normpath(inside)]
    if not chosen:
        raise click.UsageError(f"{inside} is neither a module of the project (`sources`) nor one of its "
                               f"scenarios (`tests`): " + ", ".join(stims))
    return chosen


def _selected(stims: list[str], keywords: tuple[str, ...]) -> list[str]:
    """-k: the scenarios whose path contains a PATTERN (as pytest -k matches names) or matches
    it as a glob (a PATTERN with * ? or [), either against the whole path or the file name."""
    if not keywords:
        return stims

    def hit(stim: str, k: str) -> bool:
        if any(c in k for c in "*?["):
            return fnmatch.fnmatchcase(stim, k) or fnmatch.fnmatchcase(os.path.basename(stim), k)
        return k in stim

    chosen = [s for s in stims if any(hit(s, k) for k in keywords)]
    if not chosen:
        raise click.UsageError(f"no scenario matches -k {' -k '.join(keywords)}; the scenarios: "
                               + ", ".join(stims))
    return chosen


def _json(scenarios, unmodelled, verified=None) -> str:
    """{"scenarios": {path: the `mlc sim --json` document, or null when the stimulus could not
    be read}, "passed", "failed", "artifacts": {path: [waveform, report]}}, and "properties"
    (the `mlc verify --json` results) when mlc.toml names property files."""
    docs = {sc.stim: json.loads(to_json(sc.result, unmodelled)) if sc.result is not None else None
            for sc in scenarios}
    passed = sum(sc.ok for sc in scenarios)
    body = {"scenarios": docs, "passed": passed, "failed": len(scenarios) - passed,
            "artifacts": {sc.stim: list(sc.artifacts) for sc in scenarios if sc.artifacts}}
    if verified is not None:
        body["properties"] = json.loads(verified.json())["results"]
    return json.dumps(body, indent=2, ensure_ascii=False) + "\n"


def _table(scenarios) -> None:
    from rich.console import Console
    from rich.table import Table

    from mlctool.report import use_color

    table = Table(title="mlc test", title_justify="left")
    for col in ("scenario", "expectations", "failed", "scans", "virtual time", "result"):
        table.add_column(col, justify="left" if col in ("scenario", "result") else "right")
    for sc in scenarios:
        r = sc.result
        if r is None:
            table.add_row(sc.stim, "-", "-", "-", "-", "[red]ERROR[/red] (stimulus)")
            continue
        failed = sum(not e.passed for e in r.expectations)
        status = "[green]PASS[/green]" if sc.ok else "[red]FAIL[/red]" + (" (fault)" if r.fault else "")
        table.add_row(sc.stim, str(len(r.expectations)), str(failed), str(r.scans), f"{ms(r.time_us)} ms", status)
    passed = sum(sc.ok for sc in scenarios)
    console = Console(file=sys.stdout, no_color=not use_color(sys.stdout), highlight=False, width=110)
    console.print(table)
    console.print(f"{passed} passed, {len(scenarios) - passed} failed")
