"""`mlc lsp`: the language server (mlctool/lsp/)."""

from __future__ import annotations

import sys

import click

from mlctool.cli import main_group
from mlctool.cli.common import examples


@main_group.command("lsp", epilog=examples(
    "mlc lsp                               # an editor starts it: messages on stdin/stdout",
    "mlc lsp --stdio                       # the same (what vscode-languageclient passes)",
))
@click.option("--stdio", is_flag=True, help="talk over standard input and output (the default and only transport)")
def lsp_cmd(stdio):
    """Serve the Language Server Protocol over stdio for editors (docs/editor.md).

    Diagnostics as `mlc check` gives them (the project of the mlc.toml above each file),
    hover, completion, go to definition, references, rename, document symbols, formatting
    and quick fixes.

    Exit 0: the editor ended the session (shutdown and exit); 1: the editor went away without
    a shutdown; 2: usage error.
    """
    from mlctool.lsp.server import server

    server.start_io()  # returns on the editor's `exit` (pygls's own sys.exit is swallowed) or at EOF
    # 0 after a shutdown, else 1, as pygls means for `exit`; sys.exit, not ctx.exit: the guarded
    # runner calls click outside standalone mode, where ctx.exit's code was returned and lost
    sys.exit(0 if getattr(server.protocol, "_shutdown", False) else 1)
