"""`mlc mcp`: the library's tools for AI agents over the Model Context Protocol (docs/agents.md)."""

from __future__ import annotations

import click

from mlctool.cli import main_group
from mlctool.cli.common import examples
from mlctool.diagnostics import MlcError, Span, diag


@main_group.command("mcp", epilog=examples(
    "mlc mcp                               # started by the agent's host (docs/agents.md)",
    "mlc mcp --list                        # the tools it offers",
))
@click.option("--list", "list_tools", is_flag=True, help="print the tools and exit")
def mcp_cmd(list_tools):
    """Serve check, explain, build, sim, ladder and a debugger to AI agents over MCP (stdio).

    Exit 0 when the client closes the connection; 2 when the `mcp` package is missing (E752).
    """
    try:
        from mlctool.agents.mcp_server import make_server
    except ImportError:
        raise MlcError(diag("<command line>", Span.at(1), "E752",
                            "mlc mcp needs the mcp package: pip install 'mlctool[agents]'"), 2) from None
    server = make_server()
    if list_tools:
        import asyncio

        for tool in asyncio.run(server.list_tools()):
            click.echo(f"{tool.name:12} {(tool.description or '').splitlines()[0]}")
        return
    server.run("stdio")
