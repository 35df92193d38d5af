"""The `mlc` command: click wiring only; every command calls plain functions of a stage.

Commands live in mlctool/cli/<area>.py and register themselves on `main_group` with
`@main_group.command(...)`. The modules are imported only when their command runs (or for
`mlc --help`), so `mlc check` does not pay for the simulator's or Modbus's imports. A new
command module is added to COMMAND_MODULES.

Belongs here: options, wiring, output and exit codes of the commands. Does not belong here:
logic a stage could hold (a command calls the stages' functions).
"""

from __future__ import annotations

import gc
import importlib
import sys

import click

from mlctool import __version__
from mlctool.cli.common import examples, run_guarded

COMMAND_MODULES = {
    "build": "mlctool.cli.asm", "link": "mlctool.cli.asm", "objdump": "mlctool.cli.asm",
    "check": "mlctool.cli.check", "debug": "mlctool.cli.debug", "explain": "mlctool.cli.check", "targets": "mlctool.cli.check",
    "device": "mlctool.cli.device",
    "export": "mlctool.cli.exports",
    "fmt": "mlctool.cli.fmt",
    "import": "mlctool.cli.imports",
    "init": "mlctool.cli.init",
    "ladder": "mlctool.cli.ladder",
    "lsp": "mlctool.cli.lsp",
    "mcp": "mlctool.cli.mcp",
    "run": "mlctool.cli.run",
    "sim": "mlctool.cli.sim",
    "test": "mlctool.cli.test",
    "verify": "mlctool.cli.verify",
}

# The first paragraph of each command's help, for the list in `mlc --help` without importing
# the command modules (tests/cli/test_cli_startup.py checks it against the commands' own help).
COMMAND_SUMMARIES = {
    "build": "Assemble sources into object modules (.mlo) or a linked program (.mlx).",
    "check": "Check instruction-list sources against the target's manual.",
    "debug": "Debug a program on the simulator: breakpoints, stepping, time travel (console or DAP).",
    "device": "Device models as real devices on a Modbus link.",
    "export": "Write an IL program in a vendor tool's form, for that tool to read (docs/formats.md).",
    "explain": "Print the documentation of a diagnostic code, or the manual's row of a special device.",
    "fmt": "Rewrite IL files in the canonical layout (idempotent; code unchanged).",
    "import": "Convert an editor's export or a GX Works2 / GX Developer / WinProladder project to plain IL (docs/formats.md).",
    "init": "Write a new project into DIR (default: here): mlc.toml, src/main.il, a passing scenario "
            "in tests/, a CI workflow and a pre-commit configuration.",
    "ladder": "Draw the FILEs as ladder diagrams, one rung per IL rung, in program order.",
    "lsp": "Serve the Language Server Protocol over stdio for editors (docs/editor.md).",
    "link": "Link object modules (.mlo): one main module and its subroutine libraries.",
    "mcp": "Serve check, explain, build, sim, ladder and a debugger to AI agents over MCP (stdio).",
    "objdump": "Show an object module (.mlo) or linked program (.mlx), or an FBs positioning "
               "register image (.json/.csv) as program text.",
    "run": "Run the program of FILE... in real time, scans paced to the wall clock, optionally "
           "serving its memory over Modbus or OPC UA (docs/commissioning.md).",
    "sim": "Simulate the program of FILE... (sources, objects or a linked image) on virtual time.",
    "targets": "List the targets and the manual each one follows.",
    "test": "Run the stimulus files of the project in DIR (default: the nearest mlc.toml at or above "
            "the current folder).",
    "verify": "Prove the properties of a property file on the program of FILE... (sources, objects or a "
              "linked image), or show the scan sequence that breaks them.",
}


class LazyGroup(click.Group):
    """A group whose commands are imported on first use (`mlc --help` imports none of them:
    the simulator's numpy and the device models cost about 250 ms)."""

    def list_commands(self, ctx):
        return sorted(set(super().list_commands(ctx)) | set(COMMAND_MODULES))

    def get_command(self, ctx, name):
        if name not in self.commands and name in COMMAND_MODULES:
            # the collector paused meanwhile: a command's imports create thousands of objects
            # that live to the end (classes, functions, tables), and walking them again and
            # again is a few ms of every start
            collecting = gc.isenabled()
            gc.disable()
            try:
                importlib.import_module(COMMAND_MODULES[name])
            finally:
                if collecting:
                    gc.enable()
        return self.commands.get(name)

    def resolve_command(self, ctx, args):
        name = args[0] if args else ""
        if name and not name.startswith("-") and self.get_command(ctx, name) is None:
            from mlctool.suggest import closest

            near = closest(name, self.list_commands(ctx))
            ctx.fail(f"No such command {name!r}." + (f" Did you mean {near!r}?" if near else "")
                     + f" Commands: {', '.join(self.list_commands(ctx))}.")
        return super().resolve_command(ctx, args)

    def format_commands(self, ctx, formatter):
        """click's command list, with the summaries of commands not imported yet taken from
        COMMAND_SUMMARIES (a command missing there is imported for its help)."""
        rows = []
        names = self.list_commands(ctx)
        limit = formatter.width - 6 - max(map(len, names), default=0)
        for name in names:
            cmd = self.commands.get(name)
            if cmd is None and name in COMMAND_SUMMARIES:
                rows.append((name, click.Command(name, help=COMMAND_SUMMARIES[name]).get_short_help_str(limit)))
                continue
            cmd = self.get_command(ctx, name)
            if cmd is not None and not cmd.hidden:
                rows.append((name, cmd.get_short_help_str(limit)))
        if rows:
            with formatter.section("Commands"):
                formatter.write_dl(rows)


@click.group(cls=LazyGroup, context_settings={"help_option_names": ["-h", "--help"]}, epilog=examples(
    "mlc check && mlc build && mlc test    # in a project folder (mlc.toml)",
    "mlc sim prog.il --stimulus s.stim     # one program, one scenario",
    "mlc explain W401                      # what a diagnostic means",
))
@click.version_option(__version__, prog_name="mlc")
def main_group() -> None:
    """mlctool: check, build and simulate PLC instruction-list programs."""


def all_commands() -> dict[str, click.Command]:
    """Every command, imported (for tests and documentation)."""
    ctx = click.Context(main_group)
    return {name: main_group.get_command(ctx, name) for name in main_group.list_commands(ctx)}


def main(argv: list[str] | None = None) -> None:
    sys.exit(run_guarded(main_group, argv))


if __name__ == "__main__":  # pragma: no cover
    main()

__all__ = ["all_commands", "main", "main_group"]
