"""Unit words as word arrays: the VS UnG operand (U1G3 = BFM#3 of special module 1).

The buffer memory of the modules lives in `Machine.bfm` ((unit, register) -> raw 16-bit word),
which FROM/TO (targets/vs/bfm.py) and the stimulus (`BFM1#3=5`) use. An instruction with a U1G3
operand reads and writes the same registers through `m.words["U1G"]`, an array view of unit 1,
so every instruction that handles D registers handles UnG unchanged (slices included).
"""

from __future__ import annotations


class UnitWords:
    """Registers 0..size-1 of one unit, stored sparsely in the shared `store`."""

    __slots__ = ("store", "unit", "size")

    def __init__(self, store: dict[tuple[int, int], int], unit: int, size: int) -> None:
        self.store, self.unit, self.size = store, unit, size

    def __len__(self) -> int:
        return self.size

    def __getitem__(self, i):
        if isinstance(i, slice):
            return [self.store.get((self.unit, k), 0) for k in range(*i.indices(self.size))]
        return self.store.get((self.unit, self._at(i)), 0)

    def __setitem__(self, i, value) -> None:
        if isinstance(i, slice):
            places = range(*i.indices(self.size))
            values = list(value)
            if len(values) != len(places):  # a list would grow or shrink: memory cannot
                raise ValueError("unit words keep their size")
            for k, v in zip(places, values, strict=True):
                self.store[(self.unit, k)] = v
            return
        self.store[(self.unit, self._at(i))] = value

    def __iter__(self):
        return iter(self[:])

    def _at(self, i: int) -> int:
        j = i + self.size if i < 0 else i
        if not 0 <= j < self.size:
            raise IndexError(i)
        return j


def unit_word_arrays(devices, store: dict[tuple[int, int], int]) -> dict[str, UnitWords]:
    """`m.words` entries of the target's unit words: "U1G" ... for each unit of the model."""
    out = {}
    for name, dev in devices.items():
        if dev.unit_prefix:
            lo, hi = dev.units
            for unit in range(lo, hi + 1):
                out[f"{dev.unit_prefix}{unit}{name}"] = UnitWords(store, unit, dev.hi + 1)
    return out
