"""Shared CLI plumbing: target selection, diagnostics on stderr, no tracebacks."""

from __future__ import annotations

import _thread
import contextlib
import dataclasses
import fnmatch
import gc
import os
import signal
import sys
import threading

import click

from mlctool.config import Config, load_config
from mlctool.diagnostics import Diagnostic, MlcError, Span, diag
from mlctool.fileio import Outputs, begin_command
from mlctool.limits import integer
from mlctool.report import render_text
from mlctool.targetapi import Target, available_targets, load_target
from mlctool.targetapi.model import UnknownModel

# --max-wall: the timer that stops the command, and whether it did
_WALL: dict = {"timer": None, "hit": False, "text": ""}
WALL_EXIT = 1  # a run stopped by --max-wall did not pass (docs/reliability.md, Exit codes)


def max_wall_option(fn):
    return click.option("--max-wall", "max_wall", default=None, metavar="TIME", callback=_start_wall_limit,
                        expose_value=False, is_eager=True,
                        help="stop after TIME of wall-clock time (e.g. 30s, 5min): E607, exit 1 (for CI)")(fn)


def positive_time(value: str | None, flag: str, zero: bool = False) -> int | None:
    """A duration option (`500ms`, `2s`, the stimulus's units) -> microseconds, None when not
    given; a bad or non-positive one (negative, with `zero`) is the option's usage error."""
    if value is None:
        return None
    from mlctool.sim.stimulus.quantities import StimError, parse_time

    try:
        us = parse_time(value)
    except StimError as e:
        raise click.BadParameter(e.message, param_hint=flag) from None
    if us < 0 or (us == 0 and not zero):
        raise click.BadParameter("must be positive", param_hint=flag)
    return us


def _start_wall_limit(_ctx, _param, text: str | None) -> None:
    """Start the wall-clock limit: a timer that interrupts the command as Ctrl-C would, so every
    output being written is discarded (mlctool/fileio.py); run_guarded says why."""
    if text is None:
        return
    us = positive_time(text, "--max-wall")
    timer = threading.Timer(us / 1e6, _wall_reached)
    timer.daemon = True
    _WALL.update(timer=timer, text=text)
    timer.start()


def _wall_reached() -> None:
    _WALL["hit"] = True
    if hasattr(signal, "pthread_kill"):  # a real SIGINT: held while outputs are renamed (fileio.py)
        signal.pthread_kill(threading.main_thread().ident, signal.SIGINT)
    else:
        _thread.interrupt_main()


def _interrupted() -> int:
    if _WALL["hit"]:
        render_text([diag("<command line>", Span.at(1), "E607",
                          f"--max-wall {_WALL['text']}: the wall-clock limit was reached; stopped, "
                          "nothing written")], {})
        return WALL_EXIT
    click.echo("mlc: interrupted", err=True)
    return 130  # 128 + SIGINT


def run_guarded(group: click.Group, argv: list[str] | None) -> int:
    """Run the click group; turn every failure into a message and an exit code."""
    _WALL.update(timer=None, hit=False, text="")
    begin_command()  # no input read, no output planned (mlctool/fileio.py)
    try:
        return _run_guarded(group, argv)
    finally:
        if _WALL["timer"] is not None:
            _WALL["timer"].cancel()
        _WALL["timer"] = None


def _run_guarded(group: click.Group, argv: list[str] | None) -> int:
    try:
        group.main(args=argv, prog_name="mlc", standalone_mode=False)
        return 0
    except MlcError as e:
        render_text(e.diagnostics, e.lines)
        return e.exit_code
    except click.exceptions.Exit as e:
        return e.exit_code
    except click.ClickException as e:
        e.show()
        return 2
    except click.exceptions.Abort as e:
        if isinstance(e.__cause__, KeyboardInterrupt):  # Ctrl-C or --max-wall (click wraps it)
            return _interrupted()
        click.echo("aborted", err=True)
        return 2
    except SystemExit as e:
        return e.code if isinstance(e.code, int) else 1
    except KeyboardInterrupt:
        return _interrupted()
    except RecursionError:
        click.echo("mlc: error: input nests too deeply to process", err=True)
        return 2
    except MemoryError:
        click.echo("mlc: error: out of memory on this input", err=True)
        return 2
    except Exception as e:  # a bug: say so plainly, trace only on request
        if os.environ.get("MLC_DEBUG"):
            import traceback  # here: only a bug reported on request needs it (start-up, issue 19)

            traceback.print_exc()
        click.echo(f"mlc: internal error: {type(e).__name__}: {e} (set MLC_DEBUG=1 for details)", err=True)
        return 3


def examples(*lines: str) -> str:
    """A command's help epilog: "Examples:" and command lines kept as written (the `\\b` line
    stops click from rewrapping them). tests/cli/test_docs_commands.py runs them."""
    return "\b\nExamples:\n" + "\n".join("  " + line for line in lines)


def get_config(explicit: str | None = None) -> Config:
    return with_cli_encoding(load_config(explicit=explicit))


def with_cli_encoding(config: Config) -> Config:
    """`--encoding` stands in for mlc.toml `encoding` (read by mlctool/syntax/source.py)."""
    ctx = click.get_current_context(silent=True)
    name = ctx.meta.get(_ENCODING_KEY) if ctx else None
    if name:
        config.data = {**config.data, "encoding": name}
    from mlctool.syntax.source import source_encoding

    _, problems = source_encoding(config)  # an unknown name in mlc.toml: E110 at its line, exit 2
    if problems:
        raise MlcError(problems[0], 2)
    return config


_ENCODING_KEY = "mlc.encoding"


def _remember_encoding(ctx: click.Context, _param, value: str | None) -> None:
    if value:
        from mlctool.syntax.source import encoding_refusal, known_encoding

        if known_encoding(value) is None:
            raise click.BadParameter(encoding_refusal(value))
        ctx.meta[_ENCODING_KEY] = value


def encoding_option(fn):
    """`--encoding NAME` for commands that read IL sources (read by get_config)."""
    return click.option("--encoding", default=None, metavar="NAME", expose_value=False, callback=_remember_encoding,
                        help="encoding of sources that are not UTF-8 (cp950, gb18030, cp932...; default: "
                             "mlc.toml `encoding`, else UTF-8, with a guess for other bytes)")(fn)


# An output's extension names its format (docs/reliability.md, "Outputs"); these are the
# formats mlc writes or reads, so that `--report x.svg` is known to be another format's name
_FORMATS = {".svg": "SVG", ".html": "HTML", ".htm": "HTML", ".vcd": "VCD", ".gtkw": "GTKWave save file",
            ".xml": "XML", ".json": "JSON", ".csv": "CSV", ".txt": "text", ".il": "IL source",
            ".stim": "stimulus", ".mlo": "object module", ".mlx": "linked program", ".lst": "listing",
            ".map": "link map", ".pos": "positioning program", ".mpos": "positioning program",
            ".toml": "TOML", ".png": "PNG", ".pdf": "PDF"}


def output_format(path: str, flag: str, formats: dict[str, str], default: str | None = None) -> str:
    """The format an output is written in, from its extension: one of `formats` (suffix ->
    format). A name with another format's extension (`--report run.svg`) is E120, exit 2;
    so is any other name when there is no `default` (the option chooses by extension)."""
    suffix = os.path.splitext(path)[1].lower()
    if suffix in formats:
        return formats[suffix]
    if default is not None and suffix not in _FORMATS:
        return default
    if suffix in _FORMATS:
        why = f"{suffix} is the extension of {_FORMATS[suffix]} files"
    else:
        why = "no extension" if not suffix else f"unknown extension {suffix}"
    raise MlcError(diag("<command line>", Span.at(1), "E120",
                        f"{flag} {path}: {why}; {flag} writes {' or '.join(dict.fromkeys(formats.values()))} "
                        f"({' or '.join(formats)})"), 2)


_QUIET_KEY = "mlc.quiet"


def _remember_quiet(ctx: click.Context, _param, value: bool) -> None:
    if value:
        ctx.meta[_QUIET_KEY] = True


def quiet_option(fn):
    """`-q/--quiet`: no `wrote FILE` lines (read by write_outputs and said_written)."""
    return click.option("-q", "--quiet", is_flag=True, expose_value=False, callback=_remember_quiet,
                        help="do not name the files written (one `wrote FILE` line each on stderr)")(fn)


def quiet() -> bool:
    """Whether -q was given: the files written are not named."""
    ctx = click.get_current_context(silent=True)
    return bool(ctx is not None and ctx.meta.get(_QUIET_KEY))


def said_written(paths) -> None:
    """One `wrote FILE` line per file written, on stderr (stdout carries the command's data:
    --json, a table, a ladder), unless -q (docs/project.md, "Outputs")."""
    if quiet():
        return
    for path in paths:
        click.echo(f"wrote {path}", err=True)


def write_outputs(plan: Outputs, files, streamed=()) -> None:
    """plan.write(files), then say each file written (the `streamed` ones too: plan.stream)."""
    items = list(files.items() if isinstance(files, dict) else files)
    plan.write(items)
    said_written([*streamed, *(path for path, _ in items)])


def require_project(config: Config, what: str) -> None:
    """A command given no FILE works on the project: outside one, a usage error naming `what`
    it needs instead."""
    if config.root is None:
        raise click.UsageError(f"no FILE given and no mlc.toml here or above: name the {what}, or run "
                               "inside a project (docs/project.md)")


def command_scope(files, config: Config, what: str):
    """What a command works on by the one rule of docs/project.md (mlctool/asm/project.py
    project_scope); no FILE outside a project is a usage error naming `what` it needs."""
    if not files:
        require_project(config, what)
    from mlctool.asm.project import (
        project_scope,  # (not for `mlc check` of a file outside a project)
    )

    return project_scope(files, config)


def expand_sources(args: list[str] | tuple[str, ...], pattern: str = "*.il") -> list[str]:
    """File arguments as given; a directory stands for the files matching `pattern` below it,
    sorted by path (deterministic whatever the file system's order), hidden folders skipped."""
    out: list[str] = []
    for arg in args:
        if not os.path.isdir(arg):
            out.append(arg)
            continue
        found = []
        for folder, dirs, files in os.walk(arg):
            dirs[:] = [d for d in dirs if not d.startswith(".")]
            found += [os.path.join(folder, f) for f in files if fnmatch.fnmatch(f, pattern)]
        if not found:
            raise click.UsageError(f"{arg}: no {pattern} files in this folder or below")
        out += sorted(found)
    return out


def get_target(name: str | None, config: Config, model: str | None = None) -> Target:
    """The target of `--target` (else mlc.toml, else nc5), cut to `--model` (else mlc.toml
    `model`, else the target's default model)."""
    name = name or config.target or "nc5"
    ctx = click.get_current_context(silent=True)
    model = model or (ctx.meta.get(_MODEL_KEY) if ctx else None) or config.data.get("model")
    try:
        return with_pulse_modes(load_target(name, str(model).upper() if model else None), config)
    except KeyError:
        from mlctool.suggest import did_you_mean

        names = available_targets()
        raise MlcError(diag("<command line>", Span.at(1), "E110", f"unknown target {name!r} (available: "
                            f"{', '.join(names)})" + did_you_mean(name, names, "'", 0.5))) from None
    except UnknownModel as e:
        raise MlcError(diag("<command line>", Span.at(1), "E110", str(e))) from None


def with_pulse_modes(target: Target, config: Config) -> Target:
    """The target with mlc.toml `pulse_modes` (FBs: the axes' pulse output mode, set in the
    programming tool on the real PLC) over its packaged default; axes not listed keep it.
    Targets without pulse outputs are unchanged."""
    modes = config.data.get("pulse_modes")
    packaged = target.settings.get("pulse_modes")
    if not modes or packaged is None:
        return target
    merged = [m.replace("/", "") for m in modes] + list(packaged)[len(modes):]
    return dataclasses.replace(target, settings={**target.settings, "pulse_modes": merged})


def load_tables(specs, project_specs: list[str], target: Target, config: Config) -> list:
    """The register tables to preload: mlc.toml `tables` (project_specs, paths relative to
    here: mlctool/asm/project.py project_tables), then each `--table` (specs), loaded by the
    target's extension (its Simulation.load_table). A bad --table is a usage error; a bad
    mlc.toml entry is E121 at its line; a table file's own problems are shown, exit 2."""
    if not specs and not project_specs:
        return []
    from mlctool.targetapi.registry import simulation_of

    load = simulation_of(target).load_table
    where = config.locate("tables")
    if load is None:
        if project_specs:
            raise MlcError(diag(*where, "E121", f"mlc.toml `tables`: target {target.name} has no register "
                                "tables (FBs positioning tables only)"))
        raise click.BadParameter(f"target {target.name} has no register tables", param_hint="--table")
    out = []
    for spec, ours in [*((s, True) for s in project_specs), *((s, False) for s in specs)]:
        try:
            table, problems = load(spec)
        except ValueError as e:
            if ours:
                raise MlcError(diag(*where, "E121", f"mlc.toml `tables`: {e}")) from None
            raise click.BadParameter(str(e), param_hint="--table") from None
        if table is None:
            show(problems, {})
            sys.exit(2)
        out.append(table)
    return out


def show(diags: list[Diagnostic], lines: dict[str, list[str]]) -> None:
    render_text(diags, lines, sys.stderr)


_MODEL_KEY = "mlc.model"


def _remember_model(ctx: click.Context, _param, value: str | None) -> None:
    if value:
        ctx.meta[_MODEL_KEY] = value


def target_option(fn):
    """`--target NAME` (passed as `target_name`) and `--model NAME` (read by get_target, so
    every command that takes a target takes a model without a parameter of its own)."""
    fn = click.option("--model", default=None, metavar="NAME", expose_value=False, callback=_remember_model,
                      help="model of the target family (e.g. VS1; default: from mlc.toml, else the target's default)")(fn)
    return click.option("--target", "target_name", default=None, metavar="NAME",
                        help="target PLC (default: from mlc.toml, else nc5)")(fn)
class Integer(click.IntRange):
    """An integer option (within a range), read as every number is: ASCII digits only
    (mlctool/limits.py; click's own reading, int(), takes "٣" as 3)."""

    name = "integer"

    def convert(self, value, param, ctx):
        if isinstance(value, str):
            try:
                integer(value.strip())
            except ValueError as e:
                self.fail(str(e), param, ctx)
        return super().convert(value, param, ctx)


config_option = click.option("--config", "config_path", default=None, type=click.Path(dir_okay=False),
                             help="configuration file (default: mlc.toml or pyproject.toml found upward)")


@contextlib.contextmanager
def collector_paused():
    """For loading a program in a command's process: the cyclic garbage collector paused while
    the block builds its objects (a 64k-step program: ~1 M instructions, operands, steps and
    accessors, which form no cycles and live to the end), then those objects frozen
    (gc.freeze: still freed by reference counting, skipped by the collector), so that its
    next collections do not walk them all again. About 0.4 s of the 64k-step program's start
    under load (issue 19). What an earlier block froze is thawed first, so in a process that
    runs many commands (the tests) frozen garbage does not pile up. Not for a long-lived
    process that loads again and again (mlc lsp): frozen objects' cycles are never collected."""
    paused = gc.isenabled()
    gc.disable()
    gc.unfreeze()
    try:
        yield
    finally:
        if paused:
            gc.freeze()
            gc.enable()
