"""Generated Python compiled in parts: the memory of compile() grows with the source it is
given (its syntax tree), ~1 GB for the ~190 k lines of a 256k-instruction program, so a long
source is compiled a few thousand lines at a time, cut where a top-level `def` begins, each
part's line numbers moved to where its lines stand in the whole source (so a traceback line
still indexes the generated source and its line map). Executing the parts in order into one
namespace defines what executing the whole source would (issue 19, peak memory)."""

from __future__ import annotations

from types import CodeType

PART_LINES = 4000


def _moved(code: CodeType, by: int) -> CodeType:
    """`code` and the code objects nested in it, numbered `by` lines further down."""
    consts = tuple(_moved(c, by) if isinstance(c, CodeType) else c for c in code.co_consts)
    return code.replace(co_firstlineno=code.co_firstlineno + by, co_consts=consts)


def compile_parts(lines: list[str], filename: str, part_lines: int = PART_LINES) -> tuple[CodeType, ...]:
    """The source `lines` (joined by newlines) as code objects to execute in order."""
    parts: list[CodeType] = []
    start = 0
    while start < len(lines):
        end = min(start + part_lines, len(lines))
        while end < len(lines) and not lines[end].startswith("def "):  # a top-level statement begins
            end += 1
        code = compile("\n".join(lines[start:end]) + "\n", filename, "exec")
        parts.append(_moved(code, start) if start else code)
        start = end
    return tuple(parts)


def run_parts(code: CodeType | tuple[CodeType, ...], namespace: dict) -> None:
    """Execute compiled code (one code object, or compile_parts' parts) into `namespace`."""
    for part in code if isinstance(code, tuple) else (code,):
        exec(part, namespace)  # noqa: S102 - our own generated code


def global_names(code: CodeType | tuple[CodeType, ...]) -> frozenset[str]:
    """Every name the code (its parts and the functions in them) can look up as a global."""
    out: set[str] = set()
    todo = list(code) if isinstance(code, tuple) else [code]
    while todo:
        c = todo.pop()
        out.update(c.co_names)
        todo += [k for k in c.co_consts if isinstance(k, CodeType)]
    return frozenset(out)
