"""`mlc mcp`: an MCP server over stdio (the official Python SDK, `mcp` >= 2) whose tools are
agents/tools.py's functions, registered as they are: their docstrings are the tools'
descriptions, their parameters the input schemas, their dicts the structured results.

stdio only: the server's pipes are its caller's (the agent's host), as `mlc lsp`'s; it reads
the files the user can read and writes none (docs/reliability.md, "Threat model").
"""

from __future__ import annotations

from typing import Any

from mcp.server.mcpserver import MCPServer

from mlctool import __version__
from mlctool.agents import tools

INSTRUCTIONS = """mlctool checks, builds and simulates PLC instruction-list programs (Delta NC5 MLC,
Vigor VS, FATEK FBs). Give a program as `files` (paths from the server's folder) or `source`
(IL text). `check` lists diagnostics (codes: `explain`); `sim` runs a stimulus (docs/stimulus.md:
`scan 10ms`, `0ms X0=1`, `100ms expect Y0=1`, `run 1s`) and says which expectations held; the
debug_* tools step a program scan by scan or instruction by instruction, read and force
devices and go back in time."""


def make_server() -> MCPServer:
    server = MCPServer("mlctool", version=__version__, instructions=INSTRUCTIONS)
    sessions = tools.Sessions()

    @server.tool()
    def check(files: list[str] | None = None, source: str | None = None, target: str | None = None) -> dict[str, Any]:
        """Check IL sources against the target's manual (mlc check): errors, warnings and every
        diagnostic with file, line, column, code and message."""
        return tools.check(files, source, target)

    @server.tool()
    def explain(code: str) -> dict[str, Any]:
        """What a diagnostic code (E601, W401 ...) means (mlc explain)."""
        return tools.explain(code)

    @server.tool()
    def build(files: list[str] | None = None, source: str | None = None, target: str | None = None) -> dict[str, Any]:
        """Assemble and link the program without writing files (mlc build): ok, steps,
        modules, symbols, diagnostics."""
        return tools.build(files, source, target)

    @server.tool()
    def sim(files: list[str] | None = None, source: str | None = None, stimulus: str | None = None,
            stimulus_text: str | None = None, target: str | None = None, watch: list[str] | None = None,
            trace_from_ms: float | None = None, trace_to_ms: float | None = None) -> dict[str, Any]:
        """Simulate the program against a stimulus file or text (mlc sim --json): ok, scans,
        expectations passed/failed with each failure, alarms, fault; the `watch` devices'
        final values and, with trace_from_ms/trace_to_ms, their changes in that window."""
        return tools.sim(files, source, stimulus, stimulus_text, target, watch, trace_from_ms, trace_to_ms)

    @server.tool()
    def ladder(files: list[str] | None = None, source: str | None = None, target: str | None = None,
               comments: bool = False) -> dict[str, Any]:
        """The program drawn as ladder diagrams: one SVG document (mlc ladder -o x.svg)."""
        return tools.ladder(files, source, target, comments)

    @server.tool()
    def debug_start(files: list[str] | None = None, source: str | None = None, stimulus: str | None = None,
                    target: str | None = None) -> dict[str, Any]:
        """Open a debug session at scan 0 (mlc debug); returns its id for the other debug tools."""
        return sessions.start(files, source, stimulus, target)

    @server.tool()
    def debug_step(session: str, scans: bool = False, count: int = 1) -> dict[str, Any]:
        """Step `count` instructions (or whole scans with scans=true); where the session stands."""
        return sessions.step(session, scans, count)

    @server.tool()
    def debug_read(session: str, devices: list[str]) -> dict[str, Any]:
        """The values of devices (X0, D10, T0:w, a symbol) where the session stands."""
        return sessions.read(session, devices)

    @server.tool()
    def debug_force(session: str, device: str, value: str | None = None) -> dict[str, Any]:
        """Force a device to a value over the coming scans; without a value, release it."""
        return sessions.force(session, device, value)

    @server.tool()
    def debug_back(session: str, scans: bool = False) -> dict[str, Any]:
        """Go back one instruction (or one scan with scans=true): time travel."""
        return sessions.back(session, scans)

    @server.tool()
    def debug_stop(session: str) -> dict[str, Any]:
        """Close a debug session."""
        return sessions.stop(session)

    return server
