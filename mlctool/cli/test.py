"""`mlc test`: run a project's stimulus files against its program; JUnit and coverage."""

from __future__ import annotations

import fnmatch
import json
import os
import sys
from pathlib import Path

import click

from mlctool.asm import program_from_paths
from mlctool.cli import main_group
from mlctool.cli.common import (
    encoding_option,
    examples,
    get_target,
    max_wall_option,
    output_plan,
    show,
    target_option,
    with_cli_encoding,
)
from mlctool.config import load_config
from mlctool.diagnostics import MlcError, Span, diag
from mlctool.sim import coverage as cov
from mlctool.sim.cluster import ClusterError, cluster_diagnostic
from mlctool.sim.junit import to_junit
from mlctool.sim.output import ms, to_json
from mlctool.sim.suite import (
    ARTIFACT_DIR,
    artifact_paths,
    discover,
    failure_artifacts,
    merged_probe,
    run_all,
)
from mlctool.sim.unmodelled import unmodelled_writes
from mlctool.sim.vcd import gtkw_path

COVERAGE_FILES = ("coverage.txt", "coverage.json", "coverage.xml")


def _enter_project(path: str | None):
    """cd into the project folder (the one holding mlc.toml: PATH's, else the nearest one at or
    above the current folder) and load its configuration."""
    if path is None:
        here = Path.cwd()
        folder = next((d for d in (here, *here.parents) if (d / "mlc.toml").is_file()), here)
    else:
        p = Path(path)
        folder = p.parent if p.is_file() else p
    if not (folder / "mlc.toml").is_file():
        where = "here or above" if path is None else f"in {folder}"
        raise MlcError(diag(str(folder / "mlc.toml"), Span.at(1), "E100",
                            f"no mlc.toml {where} (mlc test runs a project's tests)"))
    os.chdir(folder)
    return with_cli_encoding(load_config(explicit="mlc.toml"))


@main_group.command("test", epilog=examples(
    "mlc test                              # the project of the nearest mlc.toml",
    "mlc test --coverage --junit junit.xml -j 2",
    "mlc test samples/project",
))
@target_option
@encoding_option
@max_wall_option
@click.option("--jobs", "-j", type=click.IntRange(1, 64), default=1, show_default=True,
              help="run scenarios in N worker processes")
@click.option("--cluster", default=None, metavar="tcp://HOST:PORT",
              help="run the scenarios on this Dask scheduler's workers (docs/scale.md)")
@click.option("--junit", "junit_path", default=None, metavar="FILE", help="write JUnit XML (path relative to the project)")
@click.option("--coverage", "with_coverage", is_flag=True,
              help="record coverage; writes coverage.txt, coverage.json and coverage.xml (Cobertura)")
@click.option("--coverage-dir", default=".", show_default=True, metavar="DIR", help="folder for the coverage reports")
@click.option("-k", "keywords", multiple=True, metavar="PATTERN",
              help="run only the scenarios whose path contains PATTERN, or matches it as a glob "
                   "(tests/pick*); repeatable: any of them")
@click.option("--json", "as_json", is_flag=True, help="print the results as JSON on stdout")
@click.option("--out", "out_dir", default=None, metavar="DIR",
              help=f"folder for a failing scenario's waveform and report page "
                   f"(default: beside --junit, else {ARTIFACT_DIR})")
@click.argument("path", required=False, type=click.Path(), metavar="[DIR]")
def test_cmd(target_name, jobs, cluster, junit_path, with_coverage, coverage_dir, keywords, as_json, out_dir, path):
    """Run the stimulus files of the project in DIR (default: the nearest mlc.toml at or above
    the current folder).

    mlc.toml names the program (`sources`) and the scenarios (`tests`, globs). Exit 0 when
    every expectation held, 1 on any failure or fault, 2 on usage errors or unreadable input.
    """
    config = _enter_project(path)
    target = get_target(target_name, config)
    sources, stims, problems = discover(config)
    if problems:
        show(problems, {})
        sys.exit(2)
    stims = _selected(stims, keywords)
    plan = output_plan([*sources, *stims], config)
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
    image, diags, lines = program_from_paths(sources, target, config)
    if image is None:
        show([d for d in diags if d.severity == "error"], lines)
        sys.exit(2)
    try:
        if with_coverage:
            scenarios = run_all(image, target, stims, sources, jobs, with_coverage, cluster)
        else:  # a batch: bit-sliced or numpy lanes where the program and stimuli allow (same results)
            from mlctool.sim.batch import Options, run_batch

            scenarios = run_batch(image, target, stims, Options(), jobs, cluster=cluster)[0]
    except ClusterError as e:
        show([cluster_diagnostic(e)], {})
        sys.exit(2)

    all_lines = dict(lines)
    unmodelled = unmodelled_writes(image, target)  # W608: once per device for the whole suite
    show(unmodelled, lines)
    for sc in scenarios:
        all_lines[sc.stim] = sc.stim_lines
        show(sc.diagnostics, all_lines)
    for sc in scenarios:  # the files its models read (an NC part program) are inputs too
        for p in sc.inputs:
            plan.add_input(p)
    files = {}
    for sc in scenarios:
        if sc.result is not None and not sc.ok:
            found = failure_artifacts(image, target, sc, lines, out_dir)
            files.update(found)
            sc.artifacts = tuple(p for p in found if not p.endswith(".gtkw"))
    if as_json:
        sys.stdout.write(_json(scenarios, unmodelled))
    else:
        _table(scenarios)
    if junit_path:
        files[junit_path] = to_junit(scenarios, config.data.get("name", "mlc test"))
    if with_coverage:
        rep = cov.report(image, merged_probe(len(image.instrs), scenarios))
        for name, render in zip(COVERAGE_FILES, (cov.to_text, cov.to_json, cov.to_cobertura), strict=True):
            files[os.path.join(coverage_dir, name)] = render(rep)
    plan.write(files)
    for sc in scenarios:
        if sc.artifacts:
            click.echo(f"{sc.stim}: failed; waveform {sc.artifacts[0]}, report {sc.artifacts[1]}", err=True)
    if with_coverage and not as_json:
        click.echo(cov.to_text(rep), nl=False)
    sys.exit(0 if all(sc.ok for sc in scenarios) else 1)


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


def _json(scenarios, unmodelled) -> str:
    """{"scenarios": {path: the `mlc sim --json` document, or null when the stimulus could not
    be read}, "passed", "failed", "artifacts": {path: [waveform, report]}}."""
    docs = {sc.stim: json.loads(to_json(sc.result, unmodelled)) if sc.result is not None else None
            for sc in scenarios}
    passed = sum(sc.ok for sc in scenarios)
    return json.dumps({"scenarios": docs, "passed": passed, "failed": len(scenarios) - passed,
                       "artifacts": {sc.stim: list(sc.artifacts) for sc in scenarios if sc.artifacts}},
                      indent=2, ensure_ascii=False) + "\n"


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
