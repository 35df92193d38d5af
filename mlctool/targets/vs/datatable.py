"""Data tables (VS 6-11 FNC 93 DTRD).

The VS series has no file registers; the editor (Ladder Master S) stores data tables with
the project instead, each named by a table pointer Q0-Q31 or a name, and DTRD copies n words
of table S1 from its address S2 into D on. In IL source a table is `.table Qn DTRD WORD ...`
rows (target.toml `[tables.DTRD]`, checked by `mlc check`, kept in objects): the rows' words
in order, addresses from 0. Nothing outside the PLC takes part, so nothing else is modelled.
"""

from __future__ import annotations

from mlctool.sim import semantics as base
from mlctool.sim.state import Machine, s16
from mlctool.targets.vs.common import count, op_error, write_block
from mlctool.targets.vs.serial import mbus

KIND = "DTRD"


def words(m: Machine, q: int) -> list[int] | None:
    """The words of data table Qq (None: the program has no such table)."""
    cache = m.ext.setdefault("data_tables", {})
    if q not in cache:
        rows = mbus.tables(m, KIND).get(q)
        cache[q] = None if not rows else [s16(int(op.value)) for row in rows for op in row.repeats]
    return cache[q]


@base._on
def dtrd(m: Machine, s) -> None:
    """DTRD S1 S2 D n (6-11 FNC 93): n words of table S1 (Q0-Q31, indexable, or a name) from
    its address S2 into D on. DECISIONS (the page gives no limits): a table the program lacks,
    n below 1, or S2 .. S2+n-1 outside the table: operation error, nothing read."""
    q = s.ins.operands[0].number + s.ops[0].index_value(m)
    table = words(m, q)
    if table is None:
        return op_error(m, s, f"table Q{q} has no rows (.table Q{q} DTRD WORD ...)")
    first, n = s.ops[1].get(m), count(m, s.ops[3])
    if n < 1:
        return op_error(m, s, f"n = {n}: at least 1 word")
    if first < 0 or first + n > len(table):
        return op_error(m, s, f"addresses {first} .. {first + n - 1} are outside table Q{q} "
                              f"(0-{len(table) - 1})")
    write_block(m, s.ops[2], table[first:first + n], 16)


DATA_TABLE_ACTIONS = {"dtrd": dtrd}
