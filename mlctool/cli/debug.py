"""`mlc debug`: the debugger console, or its Debug Adapter Protocol server (docs/debug.md)."""

from __future__ import annotations

import sys
from typing import NoReturn

import click

from mlctool.cli import main_group
from mlctool.cli.common import (
    Integer,
    command_scope,
    config_option,
    encoding_option,
    examples,
    get_config,
    get_target,
    load_tables,
    positive_time,
    show,
    target_option,
)
from mlctool.diagnostics import Span, diag
from mlctool.sim.engines.engine import ENGINE_ENV, ENGINES


@main_group.command("debug", epilog=examples(
    "mlc debug --stimulus tests/start.stim      # a project's program: step, break, back, rung ...",
    "mlc debug --dap                            # a DAP server on stdio (VS Code: docs/debug.md)",
    "mlc debug prog.il --web --port 8080        # the live ladder monitor: http://127.0.0.1:8080/",
))
@target_option
@encoding_option
@config_option
@click.option("--stimulus", "stim_path", default=None, type=click.Path(dir_okay=False),
              help="stimulus file (docs/stimulus.md): inputs, models, forces")
@click.option("--scan-time", default=None, metavar="TIME", help="scan period (default 10ms)")
@click.option("--engine", type=click.Choice(ENGINES), default=None, envvar=ENGINE_ENV,
              help="engine of whole scans: compiled (default), native or interp (docs/simulator.md)")
@click.option("--checkpoint-every", type=Integer(1), default=100, show_default=True,
              help="scans between time-travel checkpoints (at most 64 kept)")
@click.option("--table", "tables", multiple=True, metavar="[SR=]FILE",
              help="load a register table with the program, as mlc sim --table (FBs: R5000=home.pos); "
                   "in a project, its mlc.toml `tables` are loaded too")
@click.option("--dap", is_flag=True, help="serve the Debug Adapter Protocol on stdin/stdout")
@click.option("--dap-port", type=Integer(1, 65535), default=None, metavar="N",
              help="serve the Debug Adapter Protocol on 127.0.0.1:N (one client, which gives the printed "
                   "token in its launch request)")
@click.option("--web", is_flag=True,
              help="serve the live ladder monitor on 127.0.0.1: contacts and coils lit by their devices' "
                   "values (docs/ladder.md \"Lighting\"), a device table to watch, set and force values, "
                   "force by clicking")
@click.option("--port", type=Integer(0, 65535), default=None, metavar="N",
              help="the --web monitor's port (default: a free one; the URL is printed)")
@click.argument("program", nargs=-1, type=click.Path(), metavar="[FILE]...")
def debug_cmd(target_name, config_path, stim_path, scan_time, engine, checkpoint_every, tables, dap, dap_port, web,
              port, program):
    """Debug a program on the simulator: breakpoints, stepping, time travel (console or DAP).

    With no FILE, the program of the project of mlc.toml; a FILE that is a module of the
    project runs the whole project (docs/project.md). The console reads commands (`help` lists them) from the terminal, or from a pipe for
    scripts. With --dap or --dap-port the program comes in the client's launch request.
    With --web the ladder is served as a live monitor page until Ctrl-C.
    Exit 0: the session ended; 2: usage error, unreadable input or a port in use (E609).
    """
    scan_us = positive_time(scan_time, "--scan-time")
    if web and (dap or dap_port is not None):
        raise click.UsageError("--web and --dap/--dap-port are different front ends: give one")
    if port is not None and not web:
        raise click.UsageError("--port is the --web monitor's port (the DAP server's is --dap-port)")
    if tables and (dap or dap_port is not None):
        raise click.UsageError("--table is for the console and --web (a DAP session does not load register tables)")
    config = get_config(config_path)
    if dap or dap_port is not None:
        from mlctool.debug.dap import listen, serve_port, serve_stdio, session_token

        model = click.get_current_context().meta.get("mlc.model")  # --model (cli/common.py)
        defaults = {"target": target_name, "model": model, "config": config, "engine": engine, "scanTime": scan_us,
                    "checkpointEvery": checkpoint_every}
        if dap_port is None:
            serve_stdio(defaults)
            return
        try:
            token = session_token()
        except ValueError as e:
            raise click.UsageError(str(e)) from None
        try:
            srv = listen(dap_port)
        except OSError as e:
            _cannot_serve("--dap-port", dap_port, e)
        serve_port(srv, token, defaults)
        return
    # no FILE: the project; a module of the project: the whole project runs
    scope = command_scope(program, config, "program FILE... (or --dap)")
    program = scope.files
    from mlctool.debug.console import Console, interactive
    from mlctool.debug.load import LoadError, load_session

    target = get_target(target_name, config)
    preload = load_tables(tables, scope.tables, target, config)
    try:
        session = load_session(list(program), stim_path, target, config, scan_us, engine, checkpoint_every,
                               preload=preload)
    except LoadError as e:
        show(e.diagnostics, e.lines)
        sys.exit(2)
    from mlctool.sim.run.unmodelled import unmodelled_writes

    show(unmodelled_writes(session.image, target), session.lines)  # W608, as mlc sim says it
    if web:
        from mlctool.debug.web import Monitor, WebServer, serve

        try:
            server = WebServer(Monitor(session), port or 0)
        except OSError as e:
            _cannot_serve("--port", port, e)
        serve(server, lambda text: click.echo(text))
        return
    interactive(Console(session, click.echo))


def _cannot_serve(option: str, port: int, e: OSError) -> NoReturn:
    """E609, exit 2: the port is taken (or not ours to take)."""
    show([diag(f"<{option}>", Span.at(1), "E609", f"cannot serve on 127.0.0.1:{port}: {e.strerror or e}")], {})
    sys.exit(2)
