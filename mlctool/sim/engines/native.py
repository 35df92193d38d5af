"""The native engine: the compiled engine's generated functions (compile.py) built into a C
extension by Cython and the system's C compiler, run on the same Machine (issue 19).

Same code, same semantics: the source compiled to Python is the input, line for line; what
changes is who runs it. Before the build, the machine keeps its word registers, counter
values and timer bookkeeping in 64-bit arrays (Machine.use_arrays), and the containers a
function names become typed module variables (`cdef long long[::1] wD`), so a device read or
write is a bounds-checked C access instead of a list item; the functions' other names stay
Python objects. Where the generated code relies on something C types would change, the name
stays a Python object: a container the code slices or uses whole, any container of another
kind. The single-precision table FS, whose infinity rows are objects computing their product
(engine._InfRow), is typed only where every use of it is the float-pair read, which is then
written out with the infinity rows' rule (_float_pairs).

Locals get C types where Cython can infer them from typed operands (infer_types): the values
involved are raw 16-bit words, 32-bit pairs and their sums and products, all far inside 64
bits; `//` and `%` keep Python's rounding (cdivision off), indexes keep bounds checks and
negative wrap-around (the code tests a negative index before it uses it, as in Python).

Cost: building a program takes seconds (Cython, then cc; ~7 s for a small one, ~17 s for
bench/sim_speed.py's mixed) and is done once per program: the extension is kept in the user
cache (mlctool/cache.py, sealed like the compiled code) under the hash of what was built.
Programs whose generated code is longer than max_lines() run on the compiled engine instead.
Without Cython (`pip install mlctool[native]`) or a C compiler the engine is unavailable and
the Scanner runs the compiled engine, saying why (Scanner.native_error).
"""

from __future__ import annotations

import ast
import contextlib
import hashlib
import importlib.util
import io
import os
import re
import shutil
import subprocess
import sys
import sysconfig
import tempfile
from array import array

from mlctool import cache

KIND = "sim-native"
# generated lines above which a program runs on the compiled engine: the build grows with the
# code (~16 s for bench/sim_speed.py's mixed, 963 lines; 7 minutes for bench/gen.py's 64k-step
# program, 32k lines), so ~8,000 lines is a build of a minute or two; MLC_NATIVE_MAX_LINES
# raises it for whoever will wait once (the build is cached)
MAX_LINES = 8_000
MAX_LINES_ENV = "MLC_NATIVE_MAX_LINES"
_GLOBAL = "_c_"  # prefix of the module variables holding the containers
_DEF = re.compile(r"def (\w+)\((.*)\):$")
# A coil that keeps the rung result (compile.py, OUT: `bM[4] = a = <rung>`): Cython 3.3 turns a
# chained assignment to a typed container's item and a name, of an and/or of C values of two
# types (`e3 or k1 and k1`: an unsigned char and bints), into C code that takes a C value for
# an object pointer (a segmentation fault when it runs); assigned one target at a time, it is right
_KEPT_RESULT = re.compile(r"(\s*)(\w+\[[^\]]*\]) = a = (.+)$")
FALLBACKS: list[str] = []  # why NativeScanners of this process ran the compiled engine (once each)
on_build = None  # called before a build (the CLI says that one is under way: it takes seconds)
_LOADED: dict[str, object] = {}  # module name -> module (an extension loads once per process)
_C_TYPES = {"q": "long long", "d": "double", "B": "unsigned char", "H": "unsigned short", "I": "unsigned int",
            "Q": "unsigned long long", "f": "float"}
HEADER = ("# cython: language_level=3, infer_types=True, boundscheck=True, wraparound=True, "
          "initializedcheck=True, cdivision=False")


def max_lines() -> int:
    try:
        return int(os.environ.get(MAX_LINES_ENV, "")) or MAX_LINES
    except ValueError:
        return MAX_LINES


def fell_back(reason: str) -> None:
    if reason not in FALLBACKS:
        FALLBACKS.append(reason)


class NativeUnavailable(Exception):
    """The native engine cannot run here (no Cython, no C compiler, a build that failed)."""


def compiler() -> str | None:
    cc = os.environ.get("CC") or sysconfig.get_config_var("CC") or "cc"
    return shutil.which(cc.split()[0]) or shutil.which("cc") or shutil.which("gcc")


def unavailable() -> str | None:
    """Why the native engine cannot build here, or None."""
    try:
        import Cython  # noqa: F401
    except ImportError:
        return "Cython is not installed (pip install 'mlctool[native]')"
    if compiler() is None:
        return "no C compiler (cc) found"
    if not os.path.exists(os.path.join(sysconfig.get_paths()["include"], "Python.h")):
        return "the Python headers (Python.h) are not installed"
    return None


def c_type(obj) -> str | None:
    """The typed-memoryview declaration for a container, or None: it stays a Python object."""
    if type(obj) is bytearray:
        return "unsigned char[::1]"
    fmt = obj.typecode if type(obj) is array else obj.format if type(obj) is memoryview else None
    base = _C_TYPES.get(fmt or "")
    return f"{base}[::1]" if base else None


def _heads(source: str):
    """(name, parameters) of each generated function's `def` line."""
    for line in source.splitlines():
        if line.startswith("def ") and (m := _DEF.match(line)):
            yield m.group(1), [p.strip() for p in m.group(2).split(",")]


def functions(source: str) -> frozenset[str]:
    """The names of the generated functions (the extension defines them: _bind keeps them)."""
    return frozenset(name for name, _ in _heads(source))


def containers(source: str) -> tuple[list[str], frozenset[str]]:
    """The containers the generated functions take as defaulted parameters (function_head),
    and those of them the code only indexes item by item (`wD[k]`): the ones a typed
    memoryview can stand for. A container also sliced or used whole (`bM[7:3:-1].translate`,
    a Kn group's bits) keeps its Python object."""
    names = {p.split("=")[0] for _, params in _heads(source) for p in params if "=" in p}
    whole: set[str] = set()
    itemwise: set[str] = set()
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Subscript) and isinstance(node.value, ast.Name) and not isinstance(node.slice, ast.Slice):
            itemwise.add(node.value.id)
            node.value.itemwise = True  # (marks the Name: seen through its subscript)
        elif isinstance(node, ast.Name) and node.id in names and not getattr(node, "itemwise", False):
            whole.add(node.id)
    return sorted(names), frozenset(n for n in names if n in itemwise and n not in whole)


def pyx_text(source: str, types: dict[str, str | None]) -> tuple[str, list[int]]:
    """The Cython module of the generated source and, for each of its lines, the source line
    (0-based; -1 for lines of its own). The containers become module variables bound by
    _bind(g); each function records the stamp it reached in LX when an exception leaves it
    (Scanner._stamp_reached reads the frames' locals, which compiled frames do not have)."""
    if types.get("FS"):
        source = _float_pairs(source)
    out = [HEADER, "from libc.math cimport NAN", "cdef long long WD  # the watchdog's step limit"]
    for name, ctype in types.items():
        if ctype is not None:
            out.append(f"cdef {ctype} {_GLOBAL}{name}")
    out += ["", "def _bind(dict g, dict names):",
            "    global WD" + "".join(", " + _GLOBAL + n for n in types),
            # (mlc sim --watchdog has no upper bound: a limit past 2^62 steps is never reached
            # either, and the C variable takes it)
            "    WD = min(names['WD'], 1 << 62)"]
    for name in types:
        out.append(f"    {_GLOBAL}{name} = g[{'G_' + name!r}]")
    out.append("    globals().update(names)")
    origin = [-1] * len(out)
    lines = source.splitlines()
    heads = [n for n, line in enumerate(lines) if line.startswith("def ")]
    if not lines or heads[:1] != [0] or any(line and not line.startswith((" ", "def ")) for line in lines):
        raise NativeUnavailable("the generated code is not a sequence of functions")
    for n, end in zip(heads, heads[1:] + [len(lines)], strict=True):
        m = _DEF.match(lines[n])
        if m is None:
            raise NativeUnavailable(f"unexpected function head at line {n + 1} of the generated code")
        params = [p.strip() for p in m.group(2).split(",") if "=" not in p]
        typed = [("long " + p) if p in ("ws", "ex", "jb") else p for p in params]
        guarded = "ws" in params
        out.append(f"def {m.group(1)}({', '.join(typed)}):")
        # the function's containers as locals, one reference taken per call (a module-level
        # memoryview used directly is acquired at every use)
        for p in m.group(2).split(","):
            if "=" in p:
                name = p.split("=")[0].strip()
                ctype = types.get(name)
                out.append(f"    cdef {ctype} {name} = {_GLOBAL}{name}" if ctype else f"    {name} = {_GLOBAL}{name}")
        origin += [n] * (len(out) - len(origin))
        if guarded:
            out.append("    try:")
            origin.append(n)
        for k in range(n + 1, end):
            pad = "    " if guarded else ""
            split = _KEPT_RESULT.match(lines[k])
            if split:  # `bY[0] = a = <rung>` as `a = <rung>` then `bY[0] = a` (_KEPT_RESULT)
                out += [f"{pad}{split[1]}a = {split[3]}", f"{pad}{split[1]}{split[2]} = a"]
                origin += [k, k]
            else:
                out.append(pad + lines[k])
                origin.append(k)
        if guarded:
            out += ["    except BaseException:", "        if ws > LX[0]: LX[0] = ws", "        raise"]
            origin += [end - 1] * 3
    return "\n".join(out) + "\n", origin


# compile_ops.fvalue's single-precision read of a D pair, FB[hi] + FS[hi] * lo: FS is an
# object whose infinity rows (high word 7F80H/FF80H) compute their product (engine._InfRow:
# 0.0 for a zero low word, else NaN). With FS typed, those rows hold 0.0 and the test is
# written out: the same values, in C.
_FLOAT_PAIR = re.compile(r"\(FB\[(\w+)\] \+ FS\[\1\] \* ([\w\[\] +]+)\)")
INF_ROWS = (0x7F80, 0xFF80)


def _float_pairs(source: str) -> str:
    def pair(m: re.Match) -> str:
        hi, lo = m.group(1), m.group(2)
        return (f"(FB[{hi}] + FS[{hi}] * {lo} if {hi} != {INF_ROWS[0]} and {hi} != {INF_ROWS[1]} "
                f"else (FB[{hi}] if {lo} == 0 else NAN))")
    return _FLOAT_PAIR.sub(pair, source)


def float_pairs_only(source: str) -> bool:
    """FS appears only in the float-pair reads _float_pairs writes out (else it stays an object)."""
    return "FS[" not in _FLOAT_PAIR.sub("", source)


def build(source: str, types: dict[str, str | None]) -> tuple[object, list[int], str]:
    """The extension module of `source` (from the cache or built now), the line origins of its
    .pyx and the file name its traceback entries carry."""
    text, origin = pyx_text(source, types)
    digest = hashlib.sha256(f"{sys.version}\0{_cython_version()}\0".encode() + text.encode()).digest()
    mod_name = f"mlc_native_{digest.hex()[:24]}"
    filename = f"{mod_name}.pyx"
    if mod_name in _LOADED:
        return _LOADED[mod_name], origin, filename
    suffix = sysconfig.get_config_var("EXT_SUFFIX") or ".so"
    key = cache.key(KIND, digest)
    blob = cache.load(KIND, key, lambda v: isinstance(v, bytes)) if cache.enabled() else None
    with tempfile.TemporaryDirectory(prefix="mlc-native-", ignore_cleanup_errors=True) as tmp:  # (a loaded DLL stays on Windows)
        so = os.path.join(tmp, mod_name + suffix)
        if blob is None:
            if on_build is not None:
                on_build()
            blob = _compile(text, tmp, mod_name, so)
            cache.store(KIND, key, blob)
        else:
            with open(so, "wb") as f:
                f.write(blob)
        spec = importlib.util.spec_from_file_location(mod_name, so)
        if spec is None or spec.loader is None:
            raise NativeUnavailable("the built extension cannot be loaded")
        mod = importlib.util.module_from_spec(spec)
        try:
            spec.loader.exec_module(mod)
        except (ImportError, OSError) as e:
            raise NativeUnavailable(f"the built extension does not load: {e}") from None
    _LOADED[mod_name] = mod
    return mod, origin, filename


def _cython_version() -> str:
    try:
        import Cython
    except ImportError:
        return ""
    return Cython.__version__


def _compile(text: str, tmp: str, mod_name: str, so: str) -> bytes:
    reason = unavailable()
    if reason:
        raise NativeUnavailable(reason)
    from Cython.Compiler import Options
    from Cython.Compiler.Main import CompilationOptions
    from Cython.Compiler.Main import compile as cython_compile

    pyx = os.path.join(tmp, mod_name + ".pyx")
    c_file = os.path.join(tmp, mod_name + ".c")
    with open(pyx, "w", encoding="utf-8") as f:
        f.write(text)
    Options.error_on_unknown_names = False  # the generated code's globals are bound at run time
    chatter = io.StringIO()  # Cython's warnings (the globals it cannot see) and hints
    with contextlib.redirect_stderr(chatter), contextlib.redirect_stdout(chatter):
        # (traceback entries name the .pyx by its bare name, wherever it was built)
        try:
            result = cython_compile(pyx, CompilationOptions(language_level=3, output_file=c_file, quiet=True))
        except Exception as e:  # noqa: BLE001 - any Cython failure: the compiled engine runs
            raise NativeUnavailable(f"Cython failed: {type(e).__name__}: {e}") from None
    if result.num_errors:
        raise NativeUnavailable("Cython could not translate the generated code")
    cmd = [compiler(), "-O2", "-fno-strict-aliasing", "-shared", "-fPIC", "-w",
           "-I", sysconfig.get_paths()["include"], c_file, "-o", so]
    done = subprocess.run(cmd, capture_output=True, text=True)  # noqa: S603 - our own build
    if done.returncode != 0:
        raise NativeUnavailable(f"the C compiler failed: {done.stderr.strip()[-300:]}")
    with open(so, "rb") as f:
        return f.read()
