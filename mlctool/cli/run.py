"""`mlc run`: the simulated PLC in real time, reachable by HMIs and SCADA (docs/commissioning.md).

Exit 0: stopped (Ctrl-C, SIGTERM, --duration, the stimulus's end) with every expectation
held; 1: an expectation failed, an alarm no expectation names was raised (E604) or the
program faulted; 2: usage errors, unreadable input, a
server that cannot be opened.
"""

from __future__ import annotations

import json
import re
import signal
import sys

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
    positive_time,
    show,
    target_option,
)
from mlctool.diagnostics import MlcError, Span, diag
from mlctool.sim.decode import unsimulated
from mlctool.sim.engines.engine import ENGINE_ENV, ENGINES
from mlctool.sim.run.output import run_diagnostics
from mlctool.sim.run.run import DEFAULT_SCAN_US, RunResult, Simulation, build_models
from mlctool.sim.scan import DEFAULT_WATCHDOG
from mlctool.sim.state import NameError_, parse_device_name
from mlctool.sim.stimulus.stimulus import MAX_SCANS, Stimulus, load_stimulus

MAX_SPEED = 1000.0


def _fail(message: str, code: str = "E750") -> MlcError:
    return MlcError(diag("<command line>", Span.at(1), code, message), 2)


def parse_speed(text: str) -> float:
    mt = re.fullmatch(r"([0-9]{1,4}(?:\.[0-9]{1,4})?)x?", text.strip().lower())
    speed = float(mt[1]) if mt else 0.0
    if not 0 < speed <= MAX_SPEED:
        raise _fail(f"--speed {text[:40]!r}: expected a factor above 0 and at most {MAX_SPEED:g}, e.g. 10x or 0.5x")
    return speed


def parse_allow(items: tuple[str, ...], target) -> list[tuple[str, int, int]] | None:
    """`--allow M0-M99,D100` -> [(device, lo, hi)]; a letter alone is the whole device."""
    if not items:
        return None
    out = []
    for item in items:
        for part in filter(None, (p.strip() for p in item.split(","))):
            dev = target.devices.get(part.upper())
            if dev is not None:
                out.append((dev.name, dev.lo, dev.hi))
                continue
            first, _, last = part.partition("-")
            try:
                a = parse_device_name(first, target)
                b = parse_device_name(last, target) if last else a
            except NameError_ as e:
                raise _fail(f"--allow {part[:40]!r}: {e}") from None
            if a.kind != b.kind or a.view not in ("bit", "w") or b.number < a.number:
                raise _fail(f"--allow {part[:40]!r}: expected a device, a letter (M) or a range of one "
                            "device (M0-M99, D100-D199)")
            out.append((a.kind, a.number, b.number))
    return out


@main_group.command("run", epilog=examples(
    "mlc run samples/nc5/conveyor.il --serve modbus-tcp://127.0.0.1:5502",
    "mlc run prog.il --stimulus plant.stim --speed 10x --duration 10min",
    "mlc run prog.il --serve rtu+tcp://127.0.0.1:5503 --station 2 --map fx --allow M0-M99",
))
@target_option
@encoding_option
@config_option
@click.option("--stimulus", "stim_path", default=None, type=click.Path(dir_okay=False),
              help="stimulus file: device models, inputs over time, expectations (docs/stimulus.md)")
@click.option("--scan-time", default=None, metavar="TIME", help="scan period (default: the stimulus's, else 10ms)")
@click.option("--duration", default=None, metavar="TIME",
              help="stop after TIME of PLC time (default: the stimulus's `run`, else until Ctrl-C)")
@click.option("--speed", default="1x", show_default=True, metavar="FACTOR",
              help="PLC time per wall-clock time: 10x runs a long process ten times faster")
@click.option("--serve", "serves", multiple=True, metavar="URL",
              help="serve the PLC's memory: modbus-tcp://127.0.0.1:5502, rtu+tcp://HOST:PORT, "
                   "ascii+tcp://HOST:PORT, rtu:/dev/ttyUSB0?baud=19200, ascii:DEVICE, opc.tcp://127.0.0.1:4840")
@click.option("--map", "map_name", default=None, metavar="NAME",
              help="Modbus address map: vs, fx, dvp, nc5 (default: the target's, else vs; docs/commissioning.md)")
@click.option("--station", type=Integer(1, 247), default=1, show_default=True,
              help="Modbus station number (unit id)")
@click.option("--read-only", is_flag=True, help="clients may read, not write")
@click.option("--allow", "allows", multiple=True, metavar="DEV[-DEV],...",
              help="only these devices are writable (M, M0-M99, D100-D199; X too if listed)")
@click.option("--listen", default=None, metavar="ADDRESS",
              help="serve on this address too, beyond 127.0.0.1 (warns: W750)")
@click.option("--max-clients", type=Integer(1, 4096), default=256, show_default=True,
              help="connections per server; one more is closed at once")
@click.option("--engine", type=click.Choice(ENGINES), default=None, envvar=ENGINE_ENV,
              help="compiled (default), native or interp (docs/simulator.md)")
@click.option("--watchdog", type=Integer(1), default=DEFAULT_WATCHDOG, show_default=True,
              help="steps one scan may execute before it is stopped as a runaway")
@click.option("--json", "as_json", is_flag=True, help="print the run's figures as JSON on stdout at the end")
@click.argument("program", nargs=-1, type=click.Path(), metavar="[FILE]...")
def run_cmd(target_name, config_path, stim_path, scan_time, duration, speed, serves, map_name, station,
            read_only, allows, listen, max_clients, engine, watchdog, as_json, program):
    """Run the program of FILE... in real time, scans paced to the wall clock, optionally
    serving its memory over Modbus or OPC UA (docs/commissioning.md).

    A status line (scans, jitter, overruns) shows on a terminal; Ctrl-C stops after the scan
    in progress. Exit 0: stopped with every expectation held; 1: an expectation failed, an
    alarm no expectation names was raised or the program faulted; 2: usage error, unreadable input, a server that cannot be opened.
    """
    factor = parse_speed(speed)
    scan_us = positive_time(scan_time, "--scan-time")
    duration_us = positive_time(duration, "--duration")
    if read_only and allows:
        raise _fail("give --read-only or --allow, not both")
    from mlctool.commission.net import EndpointError, parse_endpoint

    try:
        endpoints = [parse_endpoint(u, listen) for u in serves]
    except EndpointError as e:
        raise _fail(str(e)) from None
    config = get_config(config_path)
    scope = command_scope(program, config, "program to run")
    target = get_target(target_name, config)
    with collector_paused():
        image, diags, lines = program_from_paths(list(scope.files), target, config)
    if image is None:
        show([d for d in diags if d.severity == "error"], lines)
        sys.exit(2)
    refused = unsimulated(image, target)
    if refused:
        show(refused, lines)
        sys.exit(2)
    st, stim_diags = load_stimulus(stim_path, target) if stim_path else (Stimulus("<none>", []), [])
    models, model_diags = build_models(st, target) if st is not None else ([], [])
    bad = [d for d in stim_diags + model_diags if d.severity == "error"]
    if st is None or bad:
        show(bad or stim_diags, {stim_path: st.lines} if st is not None else {})
        sys.exit(2)
    period = st.scan_us or scan_us or DEFAULT_SCAN_US
    n_scans = _scan_count(duration_us, st, period)
    from mlctool.commission.modbus_map import Permissions, default_map, load_map, map_names

    map_name = map_name or default_map(target)
    if map_name not in map_names():
        raise _fail(f"--map {map_name[:40]!r}: maps are {', '.join(map_names())}")
    perms = Permissions(target, read_only, parse_allow(allows, target))
    with collector_paused():
        sim = Simulation(image, target, st, models, period, [], trace=False, watchdog=watchdog, engine=engine)
    from mlctool.commission.realtime import LiveRun

    live = LiveRun(sim, factor)
    net = _start_servers(endpoints, live, target, image, load_map(map_name, target), perms, station, max_clients)
    previous = {sig: signal.signal(sig, lambda *_: (live.stop.set(), live.exchange.wake()))
                for sig in (signal.SIGINT, signal.SIGTERM)}
    servers = list(net.servers) if net is not None else []
    try:
        stats = live.run(n_scans, _status_line if sys.stderr.isatty() else None)
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)
        if net is not None:
            net.stop()
    if sys.stderr.isatty():
        click.echo("", err=True)
    result = RunResult(period, stats.scans, {}, [], live.outcomes, live.reports.alarms(), live.fault, [],
                       warnings=live.reports.warnings())
    show(run_diagnostics(result, st.path), {st.path: st.lines, **lines})
    click.echo(f"stopped: {stats.line()}" + "".join(f"; {_server_line(s)}" for s in servers), err=True)
    if as_json:
        sys.stdout.write(json.dumps({"stats": stats.as_dict(), "ok": result.ok,
                                     "failed": len(result.failed), "servers": [_server_json(s) for s in servers]},
                                    indent=2) + "\n")
    sys.exit(0 if result.ok else 1)


def _scan_count(duration_us: int | None, st: Stimulus, period: int) -> int | None:
    """--duration, else the stimulus's `run`, else None (until stopped)."""
    if duration_us is not None:
        n = -(-duration_us // period)
    elif st.run_scans is not None:
        n = st.run_scans
    elif st.run_time_us is not None:
        n = -(-st.run_time_us // period)
    else:
        return None
    if n > MAX_SCANS:
        raise _fail(f"--duration asks for {n:,} scans of {period} us; a run is at most {MAX_SCANS:,} scans "
                    "(leave --duration out to run until Ctrl-C)")
    return n


def _start_servers(endpoints, live, target, image, mapping, perms, station, max_clients):
    if not endpoints:
        return None
    from mlctool.commission.net import ModbusServer, NetThread, Slave

    servers = []
    for ep in endpoints:
        if ep.public:
            show([diag("<command line>", Span.at(1), "W750",
                       f"{ep.url}: serving beyond this machine; anyone who reaches {ep.host} can read"
                       + ("" if perms.read_only else " and write") + " the PLC's memory, unauthenticated")], {})
        if ep.framing is None:
            servers.append(_opcua_server(ep, live, target, image, perms))
        else:
            servers.append(ModbusServer(ep, Slave(mapping, perms, station), live.exchange, max_clients))
    net = NetThread()
    try:
        net.start(servers)
    except (OSError, RuntimeError) as e:
        failed = servers[len(net.servers)].endpoint  # the first one not started
        raise _fail(f"cannot open {failed.url}: {e}", "E751") from None
    for s in servers:
        where = f" on port {s.bound_port}" if s.endpoint.port == 0 else ""
        click.echo(f"serving {s.endpoint.url}{where} ({_what(s)})", err=True)
    return net


def _opcua_server(ep, live, target, image, perms):
    try:
        from mlctool.commission.opcua import OpcUaServer
    except ImportError:
        raise _fail("OPC UA needs the asyncua package: pip install 'mlctool[opcua]'", "E752") from None
    return OpcUaServer(ep, live, target, image, perms)


def _what(server) -> str:
    if server.endpoint.framing is None:
        return f"OPC UA, {len(server.nodes)} nodes"
    slave = server.slave
    return (f"Modbus {server.endpoint.framing.upper()}, station {slave.station}, map {slave.mapping.name}, "
            + ("read only" if slave.perms.read_only else "writes as allowed" if slave.perms.allow else "writes"))


def _server_line(server) -> str:
    s = server.stats
    return f"{server.endpoint.url}: {s.requests} requests, {s.accepted} connections"


def _server_json(server) -> dict:
    s = server.stats
    return {"url": server.endpoint.url, "requests": s.requests, "connections": s.accepted,
            "refused": s.refused, "busy": s.busy, "dropped": s.dropped}


def _status_line(stats) -> None:
    click.echo(f"\r{stats.line()}   ", nl=False, err=True)
