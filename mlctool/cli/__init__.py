"""The `mlc` command: click wiring only; every command calls plain functions of a stage.

Commands live in mlctool/cli/<area>.py and register themselves on `main_group` with
`@main_group.command(...)`. The modules are imported only when their command runs (or for
`mlc --help`), so `mlc check` does not pay for the simulator's or Modbus's imports. A new
command module is added to COMMAND_MODULES.
"""

from __future__ import annotations

import importlib
import sys

import click

from mlctool import __version__
from mlctool.cli.common import run_guarded

COMMAND_MODULES = {
    "build": "mlctool.cli.asm", "link": "mlctool.cli.asm", "objdump": "mlctool.cli.asm",
    "check": "mlctool.cli.check", "explain": "mlctool.cli.check", "targets": "mlctool.cli.check",
    "device": "mlctool.cli.device",
    "fmt": "mlctool.cli.fmt",
    "import": "mlctool.cli.imports",
    "ladder": "mlctool.cli.ladder",
    "sim": "mlctool.cli.sim",
    "test": "mlctool.cli.test",
}


class LazyGroup(click.Group):
    """A group whose commands are imported on first use."""

    def list_commands(self, ctx):
        return sorted(set(super().list_commands(ctx)) | set(COMMAND_MODULES))

    def get_command(self, ctx, name):
        if name not in self.commands and name in COMMAND_MODULES:
            importlib.import_module(COMMAND_MODULES[name])
        return self.commands.get(name)

    def resolve_command(self, ctx, args):
        name = args[0] if args else ""
        if name and not name.startswith("-") and self.get_command(ctx, name) is None:
            from mlctool.suggest import closest

            near = closest(name, self.list_commands(ctx))
            ctx.fail(f"No such command {name!r}." + (f" Did you mean {near!r}?" if near else "")
                     + f" Commands: {', '.join(self.list_commands(ctx))}.")
        return super().resolve_command(ctx, args)


@click.group(cls=LazyGroup, context_settings={"help_option_names": ["-h", "--help"]})
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
