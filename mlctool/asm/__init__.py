"""Assembler, object files, linker and listings.

Belongs here: checked modules -> step addresses, object files, linked images, listings, map
files, project builds. Does not belong here: checking rules (check/), running programs (sim/).
"""

from __future__ import annotations

from mlctool.config import Config
from mlctool.diagnostics import Diagnostic, Span, diag
from mlctool.program import Image
from mlctool.targetapi import Target


def program_from_paths(paths: list[str], target: Target, config: Config | None = None
                       ) -> tuple[Image | None, list[Diagnostic], dict[str, list[str]]]:
    """Sources (.il), object modules (.mlo) or one linked program (.mlx) -> one linked Image.

    Returns (image or None when errors prevent it, diagnostics, source lines for rendering).
    Source paths stay as given (diagnostics point at the files); objects keep their names.
    """
    from mlctool.asm.build import is_object, load_inputs, with_capacity
    from mlctool.asm.encode import image_from_object
    from mlctool.asm.link import link

    target = with_capacity(target, config)
    # with objects among the inputs, calls into them are resolved by the linker (E505)
    inputs = load_inputs(list(paths), target, config, separate=any(is_object(p) for p in paths))
    diags = list(inputs.diagnostics)
    if inputs.errors:
        return None, diags, inputs.lines
    if inputs.programs:
        if len(paths) == 1:
            return image_from_object(inputs.programs[0][1]), diags, inputs.lines
        where = inputs.programs[0][0]
        diags.append(diag(where, Span.at(1), "E509", "a linked program (.mlx) runs alone; "
                          "it cannot be linked with other inputs"))
        return None, diags, inputs.lines
    program, found = link(inputs.objects, target, inputs.checked_together)
    diags += found
    if program is None:
        return None, diags, inputs.lines
    return image_from_object(program), diags, inputs.lines
