"""The compiled engine's code of a linked program, kept on disk between runs (mlctool/cache.py).

`mlc sim prog.mlx` of a 64k-step program spends ~0.8 s generating and compiling its code; the
next run of the same object loads it in milliseconds. The entry's key: the object's SHA-256
(Image.digest), the target as the run sees it (name, model, capacity, settings, device
table), and cache.fingerprint() (this mlctool's files, this Python). Programs built from
sources have no digest and are compiled as before (compile.py keeps their code in memory).
What is stored is what compile_program() produced, attribute by attribute (or that it gave
None: the program runs on the interpreter); the code generator is not involved.
"""

from __future__ import annotations

from collections import OrderedDict
from types import CodeType

from mlctool import cache
from mlctool.sim.decode import Program
from mlctool.sim.engines.compile import Code, compile_program

KIND = "sim-code"
_MEMO: OrderedDict[bytes, Code | None] = OrderedDict()  # this process's loads, newest last
_MEMO_SIZE = 8
_NEEDED = {"code": (CodeType, tuple), "starts": list, "block_steps": list, "linemap": list, "funcs": list}


def _sound(value) -> bool:
    if value == ("none",):
        return True
    if not (isinstance(value, tuple) and len(value) == 2 and value[0] == "code" and isinstance(value[1], dict)):
        return False
    attrs = value[1]
    return all(isinstance(attrs.get(name), kind) for name, kind in _NEEDED.items())


def _as_code(value) -> Code | None:
    if value == ("none",):
        return None
    code = Code.__new__(Code)
    code.__dict__.update(value[1])  # (TypeError if Code ever gets __slots__: compiled() recompiles)
    return code


def _as_value(code: Code | None):
    if code is None:
        return ("none",)
    return ("code", dict(vars(code)))


def compiled(prog: Program) -> Code | None:
    """compile_program(prog), from the disk cache when the program is a linked object's."""
    digest = getattr(prog.image, "digest", "")
    if not digest or not cache.enabled():
        return compile_program(prog)
    key = cache.key(KIND, digest, cache.target_identity(prog.target))
    if key in _MEMO:
        _MEMO.move_to_end(key)
        return _MEMO[key]
    value = cache.load(KIND, key, _sound)
    code = None
    try:
        if value is not None:
            code = _as_code(value)
    except (TypeError, AttributeError):  # an entry Code can no longer take: compiled again
        value = None
    if value is None:
        code = compile_program(prog)
        try:
            cache.store(KIND, key, _as_value(code))
        except TypeError:  # a Code without a __dict__: not kept
            pass
    _MEMO[key] = code
    while len(_MEMO) > _MEMO_SIZE:
        _MEMO.popitem(last=False)
    return code
