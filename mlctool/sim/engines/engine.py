"""Running compiled code (compile.py) on a Machine: the Scanner binds a program's generated
functions to the machine's containers and calls them (each runs a run of blocks and returns
the next block: compile_layout._Layout), with the reference interpreter (scan.py) for the
watchdog's last block and for programs the compiler leaves to it; `Writers` gives the machine the interpreter's writer records from the stamps the code
keeps; the helpers the generated code calls on its fault paths.
"""

from __future__ import annotations

import array
import math
import operator
import os
from collections.abc import Callable
from types import FunctionType

from mlctool.sim import scan as _scan
from mlctool.sim.decode import Program, Step
from mlctool.sim.engines import native
from mlctool.sim.engines.codecache import compiled as compiled_code
from mlctool.sim.engines.codegen import K8_MOD
from mlctool.sim.engines.pycompile import global_names, run_parts
from mlctool.sim.scan import DEFAULT_WATCHDOG, Fault, end_of_scan, run_scan, run_steps
from mlctool.sim.state import Machine, SimFault

ENGINES = ("compiled", "interp", "native")
DEFAULT_ENGINE = "compiled"
ENGINE_ENV = "MLC_SIM_ENGINE"

_T01 = bytes.maketrans(b"\x00\x01", b"01")  # device bits -> binary digits (Kn groups)

# Single-precision conversions without struct calls: one 4-byte buffer seen as a float (FF)
# and as an unsigned 32-bit word (FI). `FI[0] = raw; FF[0]` is bits_f32(raw) and
# `FF[0] = x; FI[0]` is f32_bits(x) (both round through a C float cast, as struct's "<f" does;
# overflow gives the signed infinity f32_bits returns; NaN payloads are kept the same way).
_FF = array.array("f", [0.0])
_FI = memoryview(_FF).cast("B").cast("I")

# The same buffer as two 16-bit halves (FH): a D pair goes in and comes out word by word,
# without building the 32-bit pattern (compile._FL/_FHI: the halves of the low and high word).
_FH = memoryview(_FF).cast("B").cast("H")

# Kn groups of 8 aligned bits (compile.value): the unsigned 64-bit word of 8 device bytes, each
# 0 or 1 (every bit store writes 0/1), little-endian; its remainder modulo K8_MOD (the 256
# patterns leave 256 different ones) indexes the lists K0-K3 of the 8-bit value moved to byte c
# of the group (a list index of a small remainder is cheaper than a dict lookup of the 64-bit word)
_KN = [[0] * K8_MOD for _ in range(4)]
for _b in range(256):
    for _c in range(4):
        _KN[_c][sum((_b >> _k & 1) << 8 * _k for _k in range(8)) % K8_MOD] = _b << 8 * _c
del _b, _c

# The float buffer as a float seen through a memoryview (FM): its item store casts the value as
# the array's does, without parsing the argument (cheaper)
_FM = memoryview(_FF).cast("B").cast("f")


class _InfRow(float):
    """FS of the infinity rows (high word 7F80H/FF80H): a pair with any low word but 0 is a NaN."""

    def __mul__(self, lo):
        return 0.0 if lo == 0 else math.nan


_F32_TABLES: dict = {}


def _f32_tables() -> dict:
    """FB, FS: the single-precision value of a D pair from its words without the buffer,
    FB[hi] + FS[hi] * lo (compile_ops.fvalue): FB[hi] is the value with low word 0, FS[hi] the
    step of one unit of the low word (the sum is exact: 24 significant bits fit a double; -0.0
    and subnormals too; a NaN row gives a NaN whatever the low word; the infinity rows _InfRow)."""
    if not _F32_TABLES:
        base = memoryview(array.array("I", range(0, 1 << 32, 1 << 16))).cast("B").cast("f").tolist()
        one = memoryview(array.array("I", range(1, 1 << 32, 1 << 16))).cast("B").cast("f").tolist()
        steps: dict = {}  # one object per distinct step (~512 and the NaN rows')
        fs = [steps.setdefault(step, step) for step in map(operator.sub, one, base)]
        for hi in (0x7F80, 0xFF80):  # +inf, -inf
            fs[hi] = _InfRow(0.0)
        _F32_TABLES.update(G_FB=base, G_FS=fs)
    return _F32_TABLES


def _fault(m: Machine, writers: dict | None, ref, extent: int, q: int = 0, pos: float = 0) -> None:
    """An index-modified operand outside its device: the writer records deferred so far are
    applied (the interpreter had made them), then Ref.addr raises the interpreter's fault."""
    if writers:
        w = m.writer
        if isinstance(w, Writers):
            for k, v in writers.items():
                w.spill[k] = (q, pos, v)
        else:  # pragma: no cover - the engine always runs with Writers
            w.update(writers)
    ref.addr(m, extent)
    raise SimFault(f"{ref.text}: address out of range")  # pragma: no cover - addr raised


def _drop_loops(m: Machine, target: int) -> None:
    """scan._jump_to: a CJ out of FOR bodies drops those loops (4.1 API-08 item 3)."""
    fors = m.fors
    while fors and not (fors[-1][0] < target <= fors[-1][1]):
        fors.pop()


_INF = float("inf")


class Writers(dict):
    """`Machine.writer` while a compiled Scanner runs the machine: the interpreter's records
    (device -> index of its last writing instruction, or -line of a stimulus line), made lazy.

    The generated code stores, per group of writes whose devices it knows, the stamp of the
    block execution that ran it (`marks[g] = ws`; groups are numbered in code order, so
    (stamp, group) orders them); other writes (index-modified destinations, reference routines,
    the stimulus, the interpreter fallback) go through `__setitem__` into `spill` with the
    position `at` (the generated code sets it before a reference routine; between scans it is
    after the last block). Reading the dict applies what happened since the last read, in
    order, so it holds exactly what the interpreter's dict holds."""

    __hash__ = None  # type: ignore[assignment]

    def __init__(self, base: dict, groups: list[dict], dyn: list[tuple] = ()):
        if isinstance(base, Writers):
            base.resolve()
        super().__init__(base)
        self.groups = groups  # record group -> {device: instruction index}
        self.marks = [0] * len(groups)  # stamp of each group's last execution (0: never)
        self.dyn_specs = dyn  # index-modified store -> (position, ((kind, offset), ...), writer)
        self.dyn = [{} for _ in dyn]  # index-modified store -> {address: stamp}
        self.spill: dict = {}  # device -> (stamp, position, writer)
        self.k = 0  # last stamp given to a block execution
        self.mat = 0  # stamps <= mat are applied
        self.at = [0, _INF]  # (stamp, position) of writes made through __setitem__

    def resolve(self) -> None:
        spill = self.spill
        if self.k == self.mat and not spill:
            return
        mat, groups = self.mat, self.groups
        ev = [(s, g, None) for g, s in enumerate(self.marks) if s > mat]
        ev += [(s, p, (key, v)) for key, (s, p, v) in spill.items()]
        for (p, parts, v), d in zip(self.dyn_specs, self.dyn):
            for addr, s in d.items():
                ev += [(s, p, ((kind, addr + off), v)) for kind, off in parts]
            d.clear()
        ev.sort(key=lambda e: (e[0], e[1]))
        put, update = dict.__setitem__, dict.update
        for _, g, kv in ev:
            if kv is None:
                update(self, groups[g])
            else:
                put(self, kv[0], kv[1])
        spill.clear()
        self.mat = self.k

    def __setitem__(self, key, value) -> None:
        at = self.at
        self.spill[key] = (at[0], at[1], value)

    def update(self, *args, **kw) -> None:
        for key, value in dict(*args, **kw).items():
            self[key] = value

    def _read(name: str):  # noqa: N805 - builds the read methods
        base = getattr(dict, name)

        def method(self, *args, **kw):
            self.resolve()
            return base(self, *args, **kw)
        method.__name__ = name
        return method

    for _name in ("__getitem__", "__contains__", "__iter__", "__len__", "__eq__", "__ne__", "__repr__",
                  "get", "keys", "values", "items", "copy", "pop", "setdefault", "popitem"):
        locals()[_name] = _read(_name)
    del _name, _read

    def __delitem__(self, key) -> None:
        self.resolve()
        dict.__delitem__(self, key)

    def clear(self) -> None:
        self.resolve()
        dict.clear(self)


# ---------------------------------------------------------------------------- running

# generated-code names of Machine containers other than the device dicts (bX, wD ...)
_CONTAINERS = {"cv": "cval", "bE": "edge", "ts": "t_seen", "tr": "t_running", "tl": "t_last",
               "tf": "t_frac", "tp": "t_preset"}


class Scanner:
    """Runs scans of one program on one Machine; `engine` names the engine actually used."""

    def __init__(self, prog: Program, m: Machine, engine: str = DEFAULT_ENGINE):
        if engine not in ENGINES:
            raise ValueError(f"unknown engine {engine!r}; engines: {', '.join(ENGINES)}")
        self.prog = prog
        self.m = m
        self.code = compiled_code(prog) if engine == "compiled" else None  # disk-cached for objects
        self.engine = "compiled" if self.code is not None else "interp"
        self._zero_t = bytearray(len(m.t_seen))  # a bytearray: a bytes source is copied first
        self._checked = False
        self._ready = False  # compiled code checked: scans run it
        self._stale = None
        self._layout = m.layout
        self._before = _scan.before_scan_routine(m.target)  # what run_scan does before step 0
        if self.code is not None:
            self._runs = [s.run for s in prog.steps]
            self._bind()

    def _bind(self) -> None:
        code, prog = self.code, self.prog
        g: dict = {"__builtins__": __builtins__, "T01": _T01, "G_FF": _FF, "G_FI": _FI, "G_FH": _FH, "G_FM": _FM,
                   **{f"G_K{c}": _KN[c] for c in range(4)}, "LX": [0, 0],
                   "WD": DEFAULT_WATCHDOG,
                   "FLT": _fault, "JMP": _drop_loops, "NB": len(code.starts),
                   "BLK": {st: j for j, st in enumerate(code.starts)}, **code.consts}
        used = global_names(code.code)  # the steps and accessors the code names (not all of them:
        for s in prog.steps:            # a 256k-instruction program had ~550 k such globals)
            if f"S{s.index}" in used:
                g[f"S{s.index}"] = s
            for k, ref in enumerate(s.ops):
                if f"O{s.index}_{k}" in used:
                    g[f"O{s.index}_{k}"] = ref
        if "G_FB" in used:  # single-precision operands (built once, when a program needs them)
            g.update(_f32_tables())
        self.g = g
        self._lx, self._watchdog = g["LX"], g["WD"]
        self._defaulted: list[tuple[Callable, tuple[str, ...]]] = []
        self._rebind()
        run_parts(code.code, g)  # our own generated code (compile.py, in parts: pycompile.py)
        self.fns: list[Callable] = [g[name] for name in code.funcs] + [self._past_end]
        # the containers a function names are its parameters' defaults (compile_layout.function_head)
        for f in g.values():
            if type(f) is FunctionType and f.__code__.co_filename == code.filename and f.__defaults__:
                c = f.__code__
                params = c.co_varnames[c.co_argcount - len(f.__defaults__):c.co_argcount]
                self._defaulted.append((f, tuple("G_" + p for p in params)))

    def _past_end(self, m: Machine, ws: int, ex: int, jb: int) -> int:
        """The block after the last one: control ran off the program."""
        raise Fault("execution ran past the last instruction without END", self.prog.steps[-1])

    def _rebind(self) -> None:
        m, g = self.m, self.g
        for k, arr in m.bits.items():
            g["G_b" + k] = arr
            if "q" + k in self.code.used:  # Kn reads 8 aligned bits at a time (value())
                g["G_q" + k] = memoryview(arr)[:len(arr) // 8 * 8].cast("Q")
        for k, arr in m.words.items():
            g["G_w" + k] = arr
        for name, attr in _CONTAINERS.items():
            g["G_" + name] = getattr(m, attr)
        w = m.writer
        if not isinstance(w, Writers) or w.groups is not self.code.groups:
            w = m.writer = Writers(w, self.code.groups, self.code.dyn)
        g["W"], g["G_R"], g["SP"], g["AT"] = w, w.marks, w.spill, w.at
        self._writer = w
        for n, d in enumerate(w.dyn):
            g[f"DY{n}"] = d
        for f, names in self._defaulted:
            f.__defaults__ = tuple(g[n] for n in names)
        if self._stale is None:
            self._stale = self._stale_check()

    def _stale_check(self) -> Callable:
        """A function telling whether the machine replaced a container the code holds (a
        power cycle gives new lists): one identity test per container the code uses."""
        tests = ["m.writer is not W"]
        for name in sorted(self.code.used):
            if name in _CONTAINERS:
                tests.append(f"m.{_CONTAINERS[name]} is not G_{name}")
            elif name[0] == "b" and name[1:] in self.m.bits:
                tests.append(f"m.bits[{name[1:]!r}] is not G_{name}")
            elif name[0] == "q" and name[1:] in self.m.bits:  # the view of a replaced store
                tests.append(f"G_{name}.obj is not m.bits[{name[1:]!r}]")
            elif name[0] == "w" and name[1:] in self.m.words:
                tests.append(f"m.words[{name[1:]!r}] is not G_{name}")
        exec(f"def _stale(m):\n    return {' or '.join(tests)}\n", self.g)  # noqa: S102
        return self.g["_stale"]

    def __call__(self, watchdog: int = DEFAULT_WATCHDOG) -> None:
        self.scan(watchdog)

    def scan(self, watchdog: int = DEFAULT_WATCHDOG) -> None:
        if not self._ready:  # the interpreter, or the first scan (instrumentation check)
            if self.code is not None and not self._checked:
                self._check_instrumented()
            if self.code is None:
                run_scan(self.prog, self.m, watchdog)
                return
            self._ready = True
        m = self.m
        m.t_seen[:] = self._zero_t
        if m.layout != self._layout or m.writer is not self._writer:  # power cycle, another Scanner
            self._layout = m.layout
            if self._stale(m):
                self._rebind()
        m.acc = False
        if m.blocks or m.stack or m.calls or m.fors:  # (a scan that ran to its end left them empty)
            m.blocks.clear()
            m.stack.clear()
            m.calls = []
            m.fors = []
        if self._before is not None:
            self._before(m)
        fns = self.fns
        w = self._writer
        lx = self._lx
        if self._watchdog != watchdog:
            self._watchdog = self.g["WD"] = watchdog
        k = w.k  # the last stamp given to a block execution (Writers)
        try:
            j = fns[0](m, k, 0, 0)
            while j >= 0:  # the functions count the blocks they run (compile_layout._Layout)
                j = fns[j](m, lx[0], lx[1], j)
            k = lx[0]
            if j != -1:  # block -2-j would pass the watchdog: the interpreter stops at its step
                k += 1
                w.at[:] = k, _INF
                self._interp(self.code.starts[-2 - j], lx[1], watchdog)
        except SimFault as e:
            k = self._stamp_reached(e, k)
            raise Fault(e.message, self._fault_step(e)) from None
        except BaseException as e:
            k = self._stamp_reached(e, k)
            raise
        finally:
            w.k = k
            at = w.at  # writes between scans: after this scan's
            at[0] = k
            at[1] = _INF
        end_of_scan(m)

    def _check_instrumented(self) -> None:
        """Steps whose routine was wrapped after decoding (coverage) must run as wrapped: such
        a program runs on the interpreter."""
        self._checked = True
        if any(s.run is not r for s, r in zip(self.prog.steps, self._runs)):
            self.code = None
            self.engine = "interp"
        self._runs = []

    def _stamp_reached(self, e: BaseException, k: int) -> int:
        """The last stamp the generated code gave when `e` stopped it: `ws` of its frames in
        the traceback (a stamp is a local; LX holds it only where a function returned)."""
        tb = e.__traceback__
        while tb is not None:
            frame = tb.tb_frame
            if frame.f_code.co_filename == self.code.filename:
                k = max(k, frame.f_locals.get("ws", k))
            tb = tb.tb_next
        return max(k, self._lx[0])

    def _fault_step(self, e: BaseException) -> Step | None:
        tb = e.__traceback__
        line = None
        while tb is not None:  # the innermost frame of the generated code
            here = self._source_line(tb.tb_frame.f_code.co_filename, tb.tb_lineno)
            if here is not None:
                line = here
            tb = tb.tb_next
        if line is None:
            return None
        return self.prog.steps[self.code.linemap[line]]

    def _source_line(self, filename: str, lineno: int) -> int | None:
        """The generated source's line (0-based) of a traceback entry, None: not its code."""
        return lineno - 1 if filename == self.code.filename else None

    def _interp(self, pc: int, executed: int, watchdog: int) -> None:
        """The interpreter's loop (scan.run_steps) from step `pc` with `executed` steps done."""
        run_steps(self.prog, self.m, pc, executed, watchdog)


def default_engine() -> str:
    """MLC_SIM_ENGINE if it names an engine (the tests run everything on both), else compiled."""
    env = os.environ.get(ENGINE_ENV, "")
    return env if env in ENGINES else DEFAULT_ENGINE


def scanner(prog: Program, m: Machine, engine: str | None = None) -> Scanner:
    engine = engine or default_engine()
    if engine == "native":
        return NativeScanner(prog, m)
    return Scanner(prog, m, engine)


class NativeScanner(Scanner):
    """The native engine (native.py): the compiled engine's functions built into a C extension
    and run over the machine's containers as C arrays. Where it cannot be built (no Cython or
    C compiler, a program too long) this is the compiled engine, and `native_error` says why."""

    def __init__(self, prog: Program, m: Machine):
        self.native = None  # the extension module
        self.native_error: str | None = None
        self._origin: list[int] = []
        self._native_file = ""
        m.use_arrays()
        super().__init__(prog, m, "compiled")
        if self.code is None:
            return
        lines, limit = self.code.source.count("\n"), native.max_lines()
        if lines > limit:
            self.native_error = (f"the program's generated code ({lines:,} lines) is over the native engine's "
                                 f"{limit:,} (its build would take minutes; {native.MAX_LINES_ENV} raises the limit)")
            native.fell_back(self.native_error)
            return
        names, itemwise = native.containers(self.code.source)
        if not native.float_pairs_only(self.code.source):
            itemwise -= {"FS"}
        # the lookup tables as typed arrays (FS only where the extension writes out its rows)
        tables = {k: v for k, v in _native_tables().items() if k in self.g and (k != "G_FS" or "FS" in itemwise)}
        types = {name: native.c_type(tables.get("G_" + name, self.g.get("G_" + name))) if name in itemwise else None
                 for name in names}
        try:
            self.native, self._origin, self._native_file = native.build(self.code.source, types)
        except native.NativeUnavailable as e:
            self.native_error = str(e)
            native.fell_back(self.native_error)
            return
        self._tables = tables
        self._own = native.functions(self.code.source)
        self.engine = "native"
        self._bind_native()
        self.fns = [getattr(self.native, name) for name in self.code.funcs] + [self._past_end]

    def _rebind(self) -> None:
        """Bind the machine's containers as arrays (use_arrays: again after a power cycle or a
        restored checkpoint) and the writer stamps as one (both engines run on them)."""
        self.m.use_arrays()
        super()._rebind()
        w = self._writer
        if type(w.marks) is list:  # a new Writers: its stamps as an array, bound again
            w.marks = array.array("q", w.marks)
            super()._rebind()
        if self.native is not None:
            self._bind_native()

    def _bind_native(self) -> None:
        g = self.g
        g.update(self._tables)  # (the Python functions are not run once the extension is)
        own = self._own  # the extension's functions, not the Python ones of the same names
        self.native._bind(g, {k: v for k, v in g.items() if not k.startswith(("G_", "__")) and k not in own})
        self.native._mlc_owner = self
        self._bound_wd = g["WD"]

    def __call__(self, watchdog: int = DEFAULT_WATCHDOG) -> None:
        mod = self.native
        if mod is not None and (mod._mlc_owner is not self or watchdog != self._bound_wd):
            self._watchdog = self.g["WD"] = watchdog  # (another Scanner of the same program ran it)
            self._bind_native()
        self.scan(watchdog)

    def _source_line(self, filename: str, lineno: int) -> int | None:
        if filename == self._native_file and 0 < lineno <= len(self._origin):
            line = self._origin[lineno - 1]
            return line if line >= 0 else None
        return super()._source_line(filename, lineno)


_NATIVE_TABLES: dict = {}


def _native_tables() -> dict:
    """The compiled code's lookup tables as typed arrays (the Kn groups, the float bases)."""
    if not _NATIVE_TABLES:
        _NATIVE_TABLES.update({f"G_K{c}": array.array("q", _KN[c]) for c in range(4)})
        tables = _f32_tables()
        _NATIVE_TABLES["G_FB"] = array.array("d", tables["G_FB"])
        # the infinity rows' products are written out by native._float_pairs: 0.0 here
        _NATIVE_TABLES["G_FS"] = array.array("d", (0.0 if type(x) is _InfRow else x for x in tables["G_FS"]))
    return _NATIVE_TABLES
