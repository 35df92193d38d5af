"""Generated code compiled in parts (mlctool/sim/engines/pycompile.py): the same functions, and the
line numbers a traceback shows are those of the whole source."""

from __future__ import annotations

import traceback

from mlctool.sim.engines.pycompile import compile_parts, global_names, run_parts


def _source(n: int) -> list[str]:
    lines = ["K = 3"]
    for j in range(n):
        lines += [f"def f{j}(x):", f"    y = x + {j}", "    if y == 2 * K * 7:", "        raise ValueError(y)",
                  f"    return y * K + G{j % 5}"]
    return lines


def test_parts_define_what_the_whole_source_defines():
    lines = _source(50)
    parts = compile_parts(lines, "<gen>", part_lines=40)
    assert len(parts) > 5
    whole, cut = {f"G{k}": k for k in range(5)}, {f"G{k}": k for k in range(5)}
    exec(compile("\n".join(lines) + "\n", "<gen>", "exec"), whole)
    run_parts(parts, cut)
    calls = [j for j in range(50) if j != 21]  # f21(21) raises
    assert [cut[f"f{j}"](j) for j in calls] == [whole[f"f{j}"](j) for j in calls]
    assert {f"G{k}" for k in range(5)} <= global_names(parts) and "K" in global_names(parts)

    def line_of_failure(ns):
        try:
            ns["f21"](21)
        except ValueError as e:
            return traceback.extract_tb(e.__traceback__)[-1].lineno
        raise AssertionError("no fault")

    line = line_of_failure(cut)
    assert line == line_of_failure(whole) and lines[line - 1] == "        raise ValueError(y)"
