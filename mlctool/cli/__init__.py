"""The `mlc` command: click wiring only; every command calls plain functions of a stage."""

from __future__ import annotations

import os
import sys

import click

from mlctool import __version__
from mlctool.cli.common import run_guarded


@click.group(context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, prog_name="mlc")
def main_group() -> None:
    """mlctool: check, build and simulate PLC instruction-list programs."""


from mlctool.cli import asm as _asm  # noqa: E402,F401
from mlctool.cli import check as _check  # noqa: E402,F401  (registers commands)
from mlctool.cli import device as _device  # noqa: E402,F401
from mlctool.cli import fmt as _fmt  # noqa: E402,F401
from mlctool.cli import ladder as _ladder  # noqa: E402,F401
from mlctool.cli import sim as _sim  # noqa: E402,F401
from mlctool.cli import test as _test  # noqa: E402,F401


def main(argv: list[str] | None = None) -> None:
    sys.exit(run_guarded(main_group, argv))


if __name__ == "__main__":  # pragma: no cover
    main()

__all__ = ["main", "main_group", "os"]
