"""Assembler, object files, linker and listings."""

from __future__ import annotations

from mlctool.check import check_files
from mlctool.config import Config
from mlctool.diagnostics import Diagnostic
from mlctool.program import Image
from mlctool.targets import Target


def program_from_paths(paths: list[str], target: Target, config: Config | None = None
                       ) -> tuple[Image | None, list[Diagnostic], dict[str, list[str]]]:
    """Sources (.il), object modules (.mlo) or a linked image (.mlx) -> one linked Image.

    Returns (image or None when errors prevent it, diagnostics, source lines for rendering).
    """
    from mlctool.asm.link import link_modules

    result = check_files(paths, target, config)
    if result.errors:
        return None, result.diagnostics, result.lines
    image, diags = link_modules(result.modules, target)
    diags = result.diagnostics + diags
    if any(d.severity == "error" for d in diags):
        return None, diags, result.lines
    return image, diags, result.lines
