"""`mlc sim`: run a program on virtual time against a stimulus file.

Exit 0: every expectation held; 1: an expectation failed, the program faulted or raised an
alarm no expectation names; 2: usage errors or unreadable input.
"""

from __future__ import annotations

import sys
import time

import click

from mlctool.asm import program_from_paths
from mlctool.cli import main_group
from mlctool.cli.common import (
    Integer,
    collector_paused,
    command_scope,
    config_option,
    encoding_option,
    examples,
    get_config,
    get_target,
    load_tables,
    max_wall_option,
    output_format,
    positive_time,
    quiet_option,
    show,
    target_option,
    write_outputs,
)
from mlctool.cli.sim_batch import batch_cmd, expand, is_batch
from mlctool.diagnostics import Diagnostic, MlcError, Span, diag
from mlctool.fileio import Outputs, note_input
from mlctool.sim.decode import unsimulated
from mlctool.sim.engines.engine import ENGINE_ENV, ENGINES
from mlctool.sim.hardware.pin_window import EDGE_LIMIT, parse_window
from mlctool.sim.run.output import json_value, run_diagnostics, summary, to_json
from mlctool.sim.run.run import (
    DEFAULT_SCAN_US,
    RunResult,
    RunTooLong,
    Simulation,
    build_models,
    plan_scans,
)
from mlctool.sim.run.unmodelled import unmodelled_writes
from mlctool.sim.scan import DEFAULT_WATCHDOG
from mlctool.sim.state import NameError_, parse_device_name
from mlctool.sim.stimulus.stimulus import MAX_SCANS, StimError, Stimulus, load_stimulus, parse_time
from mlctool.targetapi.registry import simulation_of
from mlctool.targetapi.signals import device_signal

PROGRESS_MIN_SCANS = 5000


def _check_formats(vcd_path, junit_path, report_path) -> None:
    """E120 for an output named as another format. Called once the inputs are read, so that
    an output onto an input is E606 (which says more), and before the run."""
    for path, what, formats in ((vcd_path, "--vcd", {".vcd": "VCD"}), (junit_path, "--junit", {".xml": "XML"}),
                                (report_path, "--report", {".html": "HTML", ".htm": "HTML"})):
        if path:
            output_format(path, what, formats, formats[next(iter(formats))])


def _errors(diags: list[Diagnostic]) -> bool:
    return any(d.severity == "error" for d in diags)


@main_group.command("sim", epilog=examples(
    "mlc sim build/program.mlx --stimulus tests/start.stim --vcd out.vcd",
    "mlc sim prog.il --stimulus s.stim --report run.html   # the ladder lit scan by scan",
    "mlc sim src/main.il src/lib.il --stimulus 'tests/*.stim' -j 2 --junit junit.xml",
))
@target_option
@encoding_option
@config_option
@max_wall_option
@click.option("--stimulus", "stim_path", default=None, type=click.Path(dir_okay=False),
              help="stimulus file (docs/stimulus.md)")
@click.option("--scan-time", default=None, metavar="TIME", help="scan period (default 10ms)")
@click.option("--until", default=None, metavar="TIME", help="run the scans that start before TIME")
@click.option("--scans", type=Integer(0, MAX_SCANS), default=None, help="run N scans")
@click.option("--vcd", "vcd_path", default=None, type=click.Path(dir_okay=False),
              help="write a VCD waveform (and a .gtkw save file beside it)")
@click.option("--watch", multiple=True, metavar="DEV,...", help="devices to report and show")
@click.option("--json", "as_json", is_flag=True, help="print the result as JSON on stdout")
@click.option("--junit", "junit_path", default=None, type=click.Path(dir_okay=False),
              help="write JUnit XML, one test case per expectation line")
@click.option("--watchdog", type=Integer(1), default=DEFAULT_WATCHDOG, show_default=True,
              help="steps one scan may execute before it is stopped as a runaway")
@click.option("--report", "report_path", default=None, type=click.Path(dir_okay=False),
              help="write an HTML page: every expectation, the ladder lit by scan, waveforms (docs/ladder.md)")
@click.option("--engine", type=click.Choice(ENGINES), default=None, envvar=ENGINE_ENV,
              help="compiled (default), native (compiled to C: needs Cython and a C compiler) or "
                   "interp, the reference interpreter (docs/simulator.md)")
@click.option("--jobs", "-j", type=Integer(1, 64), default=1, show_default=True,
              help="worker processes for a batch (--stimulus 'tests/*.stim')")
@click.option("--cluster", default=None, metavar="tcp://HOST:PORT",
              help="run a batch's scenarios on this Dask scheduler's workers (docs/scale.md)")
@click.option("--table", "tables", multiple=True, metavar="[SR=]FILE",
              help="load a register table with the program (target's own format; FBs: "
                   "R5000=home.pos or an image from mlc build)")
@click.option("--pulse-window", "pulse_window", default=None, metavar="FROM..TO",
              help="trace the pulse output pins as pulse trains between FROM and TO in the VCD "
                   f"(at most {EDGE_LIMIT} edges; FBs: docs/fbs.md)")
@quiet_option
@click.argument("program", nargs=-1, type=click.Path(), metavar="[FILE]...")
def sim_cmd(target_name, config_path, stim_path, scan_time, until, scans, vcd_path, watch,
            as_json, junit_path, watchdog, report_path, engine, jobs, cluster, tables, pulse_window, program):
    """Simulate the program of FILE... (sources, objects or a linked image) on virtual time.

    With no FILE, the project of mlc.toml (its sources and register tables); a FILE that is
    a module of the project runs the whole project (docs/project.md).

    Exit 0: every expectation held; 1: an expectation failed, the program faulted or raised
    an alarm no expectation names; 2: usage error or unreadable input.
    """
    if until is not None and scans is not None:
        raise click.UsageError("give --until or --scans, not both")
    if cluster and not is_batch(stim_path):
        raise click.UsageError("--cluster runs a batch: give --stimulus 'PATTERN' (e.g. 'tests/*.stim')")
    window = _window_option(pulse_window, vcd_path, stim_path)
    scan_us = positive_time(scan_time, "--scan-time")
    until_us = positive_time(until, "--until", zero=True)
    config = get_config(config_path)
    scope = command_scope(program, config, "program to simulate")
    program = scope.files
    # every output is checked against the inputs and the other outputs, and its folder, before
    # anything runs (mlctool/fileio.py); all are written at the end, or none
    plan = Outputs()
    keep_gtkw = None
    if vcd_path:
        from mlctool.sim.run.vcd import gtkw_is_ours, gtkw_path

        plan.add(vcd_path, "--vcd")
        if gtkw_is_ours(gtkw_path(vcd_path)):
            plan.add(gtkw_path(vcd_path), "the GTKWave save file of --vcd")
        else:
            keep_gtkw = gtkw_path(vcd_path)
    for path, what in ((junit_path, "--junit"), (report_path, "--report")):
        if path:
            plan.add(path, what)
    plan.validate()
    # however the command ends (an error, Ctrl-C, --max-wall), no staged output is left behind
    click.get_current_context().with_resource(plan)
    target = get_target(_object_target(list(program), target_name) or target_name, config)
    preload = load_tables(tables, scope.tables, target, config)
    with collector_paused():
        image, diags, lines = program_from_paths(list(program), target, config)
    if image is None:
        show([d for d in diags if d.severity == "error"], lines)
        sys.exit(2)
    refused = unsimulated(image, target)  # E905: never run an instruction as a silent no-op
    if refused:
        show(refused, lines)
        sys.exit(2)
    # W608: special devices the program writes whose function the run does not model; shown
    # with the run's diagnostics, once per device, and in --json's `warnings`
    unmodelled = unmodelled_writes(image, target)

    if engine == "native":
        _native_notes(ahead=True)
    if window is not None and simulation_of(target).pulse_pins is None:
        raise click.UsageError(f"--pulse-window: target {target.name} has no pulse outputs")
    if is_batch(stim_path):  # many scenarios: mlctool/cli/sim_batch.py
        if vcd_path or report_path:
            raise click.UsageError("--vcd and --report take one stimulus file, not a pattern")
        watch_views, watch_diags = _watch(watch, target)
        if watch_diags:
            show(watch_diags, {})
            sys.exit(2)
        from mlctool.sim.campaign.batch import Options  # (numpy: only batches need it)

        opts = Options(scan_us, until_us, scans, watch_views, watchdog, engine, preload)
        for path in expand(stim_path)[0]:  # the scenarios the batch reads are its inputs (E606 first)
            note_input(path)
        _check_formats(vcd_path, junit_path, report_path)
        sys.exit(batch_cmd(image, target, stim_path, opts, jobs, cluster, as_json, junit_path, program, lines, plan,
                           unmodelled))

    st, stim_diags = (load_stimulus(stim_path, target) if stim_path
                      else (Stimulus("<none>", []), []))
    watch_views, watch_diags = _watch(watch, target)
    models, model_diags = build_models(st, target, watch_views) if st is not None else ([], [])
    bad = stim_diags + watch_diags + model_diags
    if st is None or _errors(bad):
        show(bad, {stim_path: st.lines} if st is not None else {})
        sys.exit(2)

    _check_formats(vcd_path, junit_path, report_path)
    period = st.scan_us or scan_us or DEFAULT_SCAN_US
    try:
        n_scans = plan_scans(st, period, until_us, scans)
    except RunTooLong as e:
        raise MlcError(diag(stim_path or "<command line>", Span.at(1), "E601", str(e)), 2) from None
    with collector_paused():
        sim = Simulation(image, target, st, models, period, watch_views,
                         trace=vcd_path is not None or report_path is not None, watchdog=watchdog,
                         engine=engine, preload=preload, pulse_window=window)
    scan_lamps = None
    if report_path:
        from mlctool.ladder.report import ScanLamps

        scan_lamps = ScanLamps(sim, lines)
    vcd_stream = None
    if vcd_path and window is None and report_path is None:
        # streamed to a temporary file beside the VCD as the run goes (memory bounded by the
        # devices, not the changes); --pulse-window and --report need the whole trace kept
        from mlctool.sim.run.vcd import VcdStream

        vcd_file = plan.stream(vcd_path)
        vcd_stream = VcdStream(vcd_file, sim.views, image, target)
        sim.trace_sink = vcd_stream.add
    started = time.perf_counter()
    result = _run(sim, n_scans)
    seconds = time.perf_counter() - started
    if result.pin_window is not None and result.pin_window.overflow:
        raise click.UsageError(f"--pulse-window {pulse_window}: the pulse pins change more than "
                               f"{EDGE_LIMIT} times in the window; give a shorter one (no VCD written)")

    if engine == "native":
        _native_notes(ahead=False)
    _report(result, st, lines, as_json, watch_views, unmodelled, target)
    files = {}
    if vcd_path:
        from mlctool.sim.run.vcd import gtkw_path, to_gtkw, to_vcd

        if vcd_stream is not None:
            vcd_stream.close(result.time_us)
            vcd_file.close()
        else:
            files[vcd_path] = to_vcd(result, image, target)
        shown = watch_views or result.views
        if keep_gtkw is None:
            files[gtkw_path(vcd_path)] = to_gtkw(vcd_path, shown)
        else:
            click.echo(f"note: {keep_gtkw} was not written by mlc sim: kept as it is "
                       "(remove it to get mlc sim's view)", err=True)
    if junit_path:
        from mlctool.sim.campaign.junit import to_junit
        from mlctool.sim.campaign.suite import Scenario

        scenario = Scenario(st.path, result, run_diagnostics(result, st.path), st.lines, seconds=seconds)
        files[junit_path] = to_junit([scenario], " ".join(program))
    if report_path:
        from mlctool.ladder.report import report_html

        files[report_path] = report_html(sim, result, scan_lamps, watch_views, "")
    write_outputs(plan, files, [vcd_path] if vcd_stream is not None else [])
    sys.exit(0 if result.ok else 1)


def _native_notes(ahead: bool) -> None:
    """Say on stderr when --engine native cannot run here (before: no Cython, no compiler)
    or did not run a program (after: too long, a failed build); the compiled engine ran."""
    from mlctool.sim.engines import native

    missing = native.unavailable()
    if ahead:
        native.on_build = lambda: click.echo("note: building the native engine for this program (seconds; "
                                             "the user cache keeps it)", err=True)
        reasons = [missing] if missing else []
    else:  # (the reason said ahead is among the fallbacks: said once)
        reasons = [r for r in native.FALLBACKS if r != missing]
    for reason in reasons:
        click.echo(f"note: the native engine did not run ({reason}); the compiled engine did", err=True)


def _object_target(paths: list[str], explicit: str | None) -> str | None:
    """The target the objects among PROGRAM were built for: it beats mlc.toml (the object is
    what runs); a --target naming another one is a usage error, not an E503 at load."""
    from mlctool.asm.build import is_object, object_target

    named = {p: object_target(p) for p in paths if is_object(p)}
    found = sorted({t for t in named.values() if t})
    if not found:
        return None
    if len(found) > 1:
        raise click.UsageError("the objects were built for different targets: "
                               + ", ".join(f"{p} ({t})" for p, t in named.items() if t))
    if explicit and explicit != found[0]:
        where = next(p for p, t in named.items() if t == found[0])
        raise click.UsageError(f"{where} was built for target {found[0]}, not {explicit}: "
                               f"drop --target or rebuild for {explicit}")
    return found[0]


def _window_option(text: str | None, vcd_path: str | None, stim_path: str | None):
    """--pulse-window FROM..TO -> (from us, to us); it shapes the VCD, so it needs --vcd."""
    if text is None:
        return None
    if not vcd_path:
        raise click.UsageError("--pulse-window shapes the VCD: give --vcd too")
    if is_batch(stim_path):
        raise click.UsageError("--pulse-window takes one stimulus file, not a pattern")
    try:
        return parse_window(text, parse_time)
    except (ValueError, StimError) as e:
        raise click.BadParameter(getattr(e, "message", str(e)), param_hint="--pulse-window") from None


def _watch(items: tuple[str, ...], target):
    views, diags = [], []
    for item in items:
        for name in filter(None, (x.strip() for x in item.split(","))):
            try:
                view = parse_device_name(name, target)
            except NameError_ as e:
                diags.append(diag("<--watch>", Span.at(1), "E602", str(e)))
                continue
            if view not in views:
                views.append(view)
    return views, diags


def _run(sim: Simulation, n_scans: int) -> RunResult:
    if not (sys.stderr.isatty() and n_scans >= PROGRESS_MIN_SCANS):
        return sim.run(n_scans)
    from rich.console import Console
    from rich.progress import Progress

    progress = Progress(console=Console(stderr=True), transient=True)
    with progress:
        task = progress.add_task("simulating", total=n_scans)
        step = max(1, n_scans // 200)
        return sim.run(n_scans, lambda k: progress.update(task, completed=k) if k % step == 0 else None)


def _report(r: RunResult, st: Stimulus, lines: dict[str, list[str]], as_json: bool, watch,
            unmodelled: list[Diagnostic], target) -> None:
    diags = unmodelled + run_diagnostics(r, st.path)
    all_lines = dict(lines)
    all_lines[st.path] = st.lines
    show(diags, all_lines)
    if as_json:
        sys.stdout.write(to_json(r, unmodelled))
        return
    for v in watch:
        found = device_signal(target, v.kind, v.number) if v.view in ("bit", "w", "d") else None
        click.echo(f"{v.name} = {json_value(r.devices.get(v.name))}" + (f"  ; {found.text}" if found else ""))
    click.echo(summary(r))
