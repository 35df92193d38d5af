"""`mlc build`, `mlc link`, `mlc objdump`.

Exit codes: 0 ok; 1 source or link errors; 2 usage, unreadable input or a bad object file.
Nothing is written unless everything succeeded; every output is replaced atomically.
"""

from __future__ import annotations

import os
import sys

import click

from mlctool.asm.build import (
    Inputs,
    is_object,
    load_inputs,
    object_target,
    read_object,
    with_capacity,
)
from mlctool.asm.encode import source_name
from mlctool.asm.link import link
from mlctool.asm.listing import listing, objdump_json, objdump_text, unit_il
from mlctool.asm.mapfile import link_map
from mlctool.asm.objfile import ObjectFile, encode
from mlctool.asm.project import project_build, project_scope
from mlctool.cli import main_group
from mlctool.cli.common import (
    collector_paused,
    config_option,
    encoding_option,
    examples,
    get_config,
    get_target,
    quiet_option,
    require_project,
    show,
    target_option,
    write_outputs,
)
from mlctool.diagnostics import Diagnostic, MlcError, Span, diag, unreadable
from mlctool.fileio import Outputs
from mlctool.report import summary_line
from mlctool.targetapi import load_target
from mlctool.targets.fbs.files import (
    build_image,
    check_positioning,
    dump_json,
    dump_text,
    is_image,
    load_image,
)
from mlctool.targets.fbs.image import ImageError
from mlctool.targets.fbs.model import is_positioning_source

OBJECT_CODES = frozenset({"E501", "E502", "E503"})


def _usage(message: str, where: str = "<command line>") -> MlcError:
    return MlcError(diag(where, Span.at(1), "E510", message), 2)


def _report(diags: list[Diagnostic], lines: dict[str, list[str]]) -> None:
    show(diags, lines)
    errors = sum(d.severity == "error" for d in diags)
    warnings = sum(d.severity == "warning" for d in diags)
    if diags:
        click.echo(summary_line(errors, warnings), err=True)


def _exit_for(diags: list[Diagnostic]) -> None:
    errors = [d for d in diags if d.severity == "error"]
    if any(d.code in OBJECT_CODES for d in errors) or unreadable(errors):
        sys.exit(2)
    if errors:
        sys.exit(1)


def _plan(outputs: dict[str, str | None]) -> Outputs:
    """The outputs (what -> path) checked against the inputs read and each other, and their
    folders (E606, E605: exit 2), before any work (mlctool/fileio.py)."""
    plan = Outputs()
    for what, path in outputs.items():
        if path:
            plan.add(path, what)
    plan.validate()
    return plan


def _write_program(plan: Outputs, program: ObjectFile, target, out: str, listing_path: str | None,
                   map_path: str | None, lines) -> None:
    # everything is rendered before the first write, and written all or none
    files = [(out, encode(program))]
    if map_path:
        files.append((map_path, link_map(program, target, os.path.basename(out))))
    if listing_path:
        files.append((listing_path, listing(program, lines)))
    write_outputs(plan, files)


@main_group.command("build", epilog=examples(
    "mlc build                             # the project of mlc.toml",
    "mlc build src/main.il src/lib.il -o build/program.mlx --map build/program.map",
    "mlc build -c src/main.il src/lib.il -o objs/   # one object module per source",
))
@target_option
@encoding_option
@config_option
@click.option("-o", "--output", default=None, metavar="FILE|DIR",
              help="program.mlx (link), module.mlo, or a folder with -c")
@click.option("-c", "compile_only", is_flag=True, help="write one object module (.mlo) per source")
@click.option("--listing", "listing_path", default=None, metavar="FILE", help="write a listing")
@click.option("--map", "map_path", default=None, metavar="FILE", help="write a link map (linking only)")
@click.option("--sr", "sr", default=None, metavar="REG",
              help="FBs positioning table (.pos/.mpos): its start register SR (default R0)")
@quiet_option
@click.argument("sources", nargs=-1, type=click.Path(), metavar="[FILE]...")
def build_cmd(target_name, config_path, output, compile_only, listing_path, map_path, sr, sources):
    """Assemble sources into object modules (.mlo) or a linked program (.mlx).

    With no FILE, builds the project described by mlc.toml (docs/project.md); so do FILEs
    that are modules of the project, without -o or -c. Each file written is named on stderr
    (`wrote FILE`; -q: silent).
    A positioning program (.pos/.mpos) builds into a register image (-o TABLE.json|.csv).

    Exit 0: built; 1: errors in the sources or at link (nothing written); 2: usage error,
    unreadable input or a bad object file.
    """
    config = get_config(config_path)
    if any(is_positioning_source(s) for s in sources):
        _build_positioning(sources, output, sr, config)
        return
    if sr is not None:
        raise _usage("--sr is for FBs positioning programs (.pos/.mpos)")
    target = with_capacity(get_target(target_name, config), config)
    where = ""
    if sources and output is None and not compile_only and project_scope(sources, config).project:
        sources = ()  # modules of the project, and no output named: the project's build
    if not sources:
        job = project_build(config)
        sources, where = job.sources, "mlc.toml "
        output = output or job.output
        listing_path = listing_path or job.listing
        map_path = map_path or job.map
    _check_request(sources, output, compile_only, listing_path, map_path)
    if compile_only:
        plan = _plan(_object_paths(sources, output))
    else:
        plan = _plan({f"{where}output" if where else "-o": output,
                                       f"{where}listing" if where else "--listing": listing_path,
                                       f"{where}map" if where else "--map": map_path})
    # objects name their sources relative to the project (else the current folder), never
    # absolutely: the same source gives the same bytes from any folder (asm/encode.py)
    root = str(config.root) if config.root else os.getcwd()
    # objects compile separately: a CALL into another module is the linker's to resolve
    separate = compile_only or output.lower().endswith(".mlo") or any(is_object(s) for s in sources)
    with collector_paused():
        inputs = load_inputs(list(sources), target, config, root, separate)
    _report(inputs.diagnostics, inputs.lines)
    _exit_for(inputs.diagnostics)
    if inputs.programs:
        raise _usage("a linked program (.mlx) cannot be an input of build or link", inputs.programs[0][0])
    if compile_only:
        write_outputs(plan, zip(_object_paths(sources, output).values(), map(encode, inputs.objects), strict=True))
        return
    if output.lower().endswith(".mlo"):
        obj = inputs.objects[0]
        files = [(output, encode(obj))] + ([(listing_path, listing(obj, inputs.lines))] if listing_path else [])
        write_outputs(plan, files)
        return
    _link_and_write(plan, inputs, target, output, listing_path, map_path)


def _check_request(sources, output, compile_only, listing_path, map_path) -> None:
    """Usage errors, found before any work (exit 2)."""
    if compile_only:
        if listing_path or map_path:
            raise _usage("-c writes objects only; --listing/--map need one output")
        if any(is_object(s) for s in sources):
            raise _usage("-c compiles sources; pass objects to mlc link")
        if os.path.exists(output or ".") and not os.path.isdir(output or "."):
            raise _usage(f"-c -o names a folder for the objects; {output!r} is a file")
        return
    if output is None:
        raise _usage("no output: give -o PROGRAM.mlx or -o MODULE.mlo (or -c)")
    if output.lower().endswith(".mlo"):
        if len(sources) != 1 or is_object(sources[0]):
            raise _usage("a .mlo output holds one module compiled from one source; use -c for several")
        if map_path:
            raise _usage("--map needs a linked output (.mlx)")
    elif not output.lower().endswith(".mlx"):
        raise _usage(f"output {output!r}: use .mlx for a linked program or .mlo for an object module")


def _build_positioning(sources, output, sr, config) -> None:
    """One FBs positioning source -> its SR register image (mlctool/targets/fbs)."""
    if len(sources) != 1:
        raise _usage("build one positioning program (.pos/.mpos) at a time")
    if output is None or not is_image(output):
        raise _usage("a positioning program builds a register image: give -o TABLE.json or -o TABLE.csv")
    plan = _plan({"-o": output})
    checked = check_positioning(list(sources), config)
    _report(checked.diagnostics, checked.lines)
    _exit_for(checked.diagnostics)
    try:
        data = build_image(checked.programs[sources[0]], output, sr)
    except ImageError as e:
        raise _usage(str(e)) from None
    write_outputs(plan, {output: data})


def _object_paths(sources, output) -> dict[str, str]:
    """-c: the object of each source (the label a clash names -> its path)."""
    folder = output or "."
    outs: dict[str, str] = {}
    for src in sources:
        path = os.path.join(folder, os.path.splitext(os.path.basename(src))[0] + ".mlo")
        if path in outs.values():
            raise _usage(f"{src} and another source would both write {path}")
        outs[f"the object of {src}"] = path
    return outs


def _link_and_write(plan: Outputs, inputs: Inputs, target, output, listing_path, map_path) -> None:
    program, diags = link(inputs.objects, target, inputs.checked_together)
    _report(diags, inputs.lines)
    if program is None:
        sys.exit(1)
    _write_program(plan, program, target, output, listing_path, map_path, inputs.lines)


def _object_target_name(path: str, explicit: str | None, config) -> str:
    return explicit or config.target or object_target(path) or "nc5"


@main_group.command("link", epilog=examples(
    "mlc link objs/main.mlo objs/lib.mlo -o build/program.mlx",
    "mlc link objs/main.mlo objs/lib.mlo -o build/program.mlx --map build/program.map --listing build/program.lst",
))
@target_option
@config_option
@click.option("-o", "--output", required=True, metavar="FILE", help="the linked program (.mlx)")
@click.option("--listing", "listing_path", default=None, metavar="FILE", help="write a listing")
@click.option("--map", "map_path", default=None, metavar="FILE", help="write a link map")
@quiet_option
@click.argument("objects", nargs=-1, required=True, type=click.Path(), metavar="FILE...")
def link_cmd(target_name, config_path, output, listing_path, map_path, objects):
    """Link object modules (.mlo): one main module and its subroutine libraries.

    Exit 0: linked; 1: link errors (nothing written); 2: usage error, unreadable input or a
    bad object file.
    """
    config = get_config(config_path)
    target = with_capacity(get_target(target_name or _object_target_name(objects[0], None, config), config),
                           config)
    if not output.lower().endswith(".mlx"):
        raise _usage(f"output {output!r}: a linked program is written as .mlx")
    plan = _plan({"-o": output, "--listing": listing_path, "--map": map_path})
    inputs = Inputs()
    for p in objects:
        obj, problem = read_object(p, target)
        if problem is not None:
            inputs.diagnostics.append(problem)
        elif obj.kind == "program":
            inputs.diagnostics.append(diag(p, Span.at(1), "E509", "a linked program cannot be linked again"))
        else:
            inputs.objects.append(obj)
    names = {}
    for p, obj in zip(objects, inputs.objects, strict=False):
        if obj.units[0].path in names:
            inputs.diagnostics.append(diag(p, Span.at(1), "E508", f"{p} and {names[obj.units[0].path]} "
                                           f"are both module {obj.units[0].path!r}"))
        names.setdefault(obj.units[0].path, p)
    _report(inputs.diagnostics, {})
    if inputs.diagnostics:
        sys.exit(2)
    _link_and_write(plan, inputs, target, output, listing_path, map_path)


@main_group.command("objdump", epilog=examples(
    "mlc objdump                           # in a project: its program (mlc.toml `output`)",
    "mlc objdump --json build/program.mlx",
    "mlc objdump build/program.mlx --il-dir rebuilt/   # IL that rebuilds the same bytes",
))
@target_option
@click.option("--json", "as_json", is_flag=True, help="machine-readable JSON")
@click.option("--il", "as_il", is_flag=True, help="IL source that assembles back to the same bytes")
@click.option("--il-dir", default=None, metavar="DIR",
              help="write each module's IL to DIR/<module name> (to rebuild a linked program)")
@config_option
@quiet_option
@click.argument("file", required=False, type=click.Path(), metavar="[FILE]")
def objdump_cmd(target_name, as_json, as_il, il_dir, config_path, file):
    """Show an object module (.mlo) or linked program (.mlx), or an FBs positioning
    register image (.json/.csv) as program text.

    With no FILE, the program the project of mlc.toml builds (its `output`: run `mlc build`
    first).

    Exit 0: shown; 2: usage error, unreadable input or a bad object file.
    """
    if file is None:
        config = get_config(config_path)
        require_project(config, "object or program to show")
        file = project_build(config).output
        if not os.path.exists(file):
            raise _usage(f"{file} does not exist: build the project first (mlc build)")
    if is_image(file):
        program, sr, problem = load_image(file)
        if problem is not None:
            raise MlcError(problem, 2)
        click.echo(dump_json(program, sr) if as_json else dump_text(program, sr), nl=False)
        return
    name = target_name or object_target(file) or "nc5"
    try:
        target = load_target(name)
    except KeyError:
        raise MlcError(diag(file, Span.at(1), "E503", f"object is for target {name!r}, "
                            "which this mlctool does not know"), 2) from None
    obj, problem = read_object(file, target)
    if problem is not None:
        raise MlcError(problem, 2)
    if as_json:
        click.echo(objdump_json(obj), nl=False)
    elif il_dir:
        plan = Outputs()
        files = {}
        for k, u in enumerate(obj.units):
            path = os.path.join(il_dir, *u.path.split("/"))
            if source_name(path, il_dir) != u.path:
                raise _usage(f"module name {u.path!r} cannot be written under {il_dir}")
            files[plan.add(path, f"the IL of module {u.path}")] = unit_il(obj, k)
        plan.validate()
        write_outputs(plan, files)
    elif as_il:
        click.echo("".join(unit_il(obj, k) for k in range(len(obj.units))), nl=False)
    else:
        click.echo(objdump_text(obj), nl=False)
