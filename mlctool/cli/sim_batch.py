"""`mlc sim PROGRAM --stimulus 'tests/*.stim'`: many scenarios against one program.

Per scenario, the diagnostics, JSON document and JUnit test suite are those of
`mlc sim PROGRAM --stimulus FILE` (mlctool/sim/campaign/batch.py runs them, as lanes or in processes).
"""

from __future__ import annotations

import glob
import json
import sys

import click

from mlctool.cli.common import show, write_outputs
from mlctool.diagnostics import Diagnostic, Span, diag
from mlctool.fileio import Outputs, note_input
from mlctool.sim.campaign.cluster import ClusterError, cluster_diagnostic
from mlctool.sim.run.output import summary, to_json

GLOB_CHARS = "*?["


def is_batch(stim_path: str | None) -> bool:
    return bool(stim_path) and any(c in stim_path for c in GLOB_CHARS)


def expand(pattern: str) -> tuple[list[str], list[Diagnostic]]:
    paths = sorted(glob.glob(pattern, recursive=True))
    if not paths:
        return [], [diag("<--stimulus>", Span.at(1), "E100", f"no stimulus file matches {pattern!r}")]
    return paths, []


def batch_cmd(image, target, pattern: str, opts, jobs: int, cluster: str | None, as_json: bool,
              junit_path: str | None, program: tuple[str, ...], lines: dict[str, list[str]],
              plan: Outputs, unmodelled: list[Diagnostic] = ()) -> int:
    """Run, report and return the exit status (0 all passed, 1 a scenario failed, 2 bad input).
    `unmodelled`: the program's W608 (sim/run/unmodelled.py), shown once, in every JSON document."""
    paths, problems = expand(pattern)
    if problems:
        show(problems, {})
        return 2
    from mlctool.sim.campaign.batch import run_batch  # (numpy: imported by batches only)

    try:
        scenarios, stats = run_batch(image, target, paths, opts, jobs, cluster=cluster)
    except ClusterError as e:
        show([cluster_diagnostic(e)], {})
        return 2
    for sc in scenarios:  # the files its models read (an NC part program) are inputs too
        for p in sc.inputs:
            note_input(p)
    show(list(unmodelled), lines)
    bad_input = False
    docs = {}
    for sc in scenarios:
        all_lines = dict(lines)
        all_lines[sc.stim] = sc.stim_lines
        show(sc.diagnostics, all_lines)
        if sc.result is None:
            bad_input = True
            docs[sc.stim] = None
            continue
        if as_json:  # (only then: a JSON document per scenario is most of a large batch's output cost)
            docs[sc.stim] = json.loads(to_json(sc.result, unmodelled))
        else:
            click.echo(f"{sc.stim}: {summary(sc.result)}")
    passed = sum(sc.ok for sc in scenarios)
    if as_json:
        sys.stdout.write(json.dumps({"scenarios": docs}, indent=2, ensure_ascii=False) + "\n")
    else:
        click.echo(f"batch: {len(scenarios)} scenarios, {passed} passed, {len(scenarios) - passed} "
                   f"failed ({stats.lanes} run as lanes, {stats.single + stats.reruns} one by one)")
    if junit_path:
        from mlctool.sim.campaign.junit import to_junit

        write_outputs(plan, {junit_path: to_junit(scenarios, " ".join(program))})
    if bad_input:
        return 2
    return 0 if passed == len(scenarios) else 1
