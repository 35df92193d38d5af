"""What the conformance tests share: the engines each case runs on, and the one program the
native engine runs all the cases of a suite in (a native build takes seconds: one program,
built once, each case selected by a latched relay of its own)."""

from __future__ import annotations

import pytest

# the native engine runs a step-ladder case on its own (such a program runs the reference
# routines, so nothing is built) and every other case in combined()'s program
ENGINES = ("interp", "compiled")
SELECT = 3000  # M3000 + k selects case k (M2000-M3999 are latched: kept over a power-cycle)


def engine_params(cases: list) -> list:
    """(il, stim, engine) per case and engine: interp and compiled, and native for a
    step-ladder case."""
    out = []
    for case in cases:
        il, stim = case.values
        for engine in ENGINES + (("native",) if "STL" in il else ()):
            out.append(pytest.param(il, stim, engine, id=f"{case.id}-{engine}"))
    return out


def combined(cases: list) -> tuple[str, list[tuple[str, str]]]:
    """One program holding every case that has no step ladder, each behind `LDI M<3000+k> /
    CJ P<100+k>` (a skipped case runs nothing), its subroutines after one FEND; and (id,
    stimulus) per case, the stimulus turning its selector On first."""
    main, subs, stims = [], [], []
    for k, case in enumerate(c for c in cases if "STL" not in c.values[0]):
        il, stim = case.values
        body, _, sub = il.partition("FEND")
        main += [f"LDI M{SELECT + k}", f"CJ P{100 + k}", body.strip(), f"P{100 + k}"]
        subs += [sub.strip()] if sub.strip() else []
        stims.append((case.id, f"0ms M{SELECT + k}=1\n{stim}"))
    return "\n".join([*main, "FEND", *subs]), stims
