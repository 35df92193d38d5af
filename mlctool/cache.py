"""The on-disk cache of derived data (docs/simulator.md "Compiled-code cache").

What is kept: data that mlctool derives from an input by a deterministic computation and that
is costly to derive again (the compiled engine's code of a linked program: ~0.8 s for a
64k-step program, a few milliseconds to load). An entry is found by a key that names
everything the data depends on: the caller's own parts (the object's SHA-256, the target,
the engine) plus `fingerprint()`: this mlctool's version and files and this Python's
version (marshal and bytecode formats differ between Pythons).

Where (DECISION): the user's cache folder, `$MLC_CACHE_DIR`, else `$XDG_CACHE_HOME/mlctool`,
else `~/.cache/mlctool` (`%LOCALAPPDATA%\\mlctool\\cache` on Windows); never beside the
project: entries hold code that is run, and a project folder comes from others (a cloned
repository could ship a crafted `.mlc-cache/`). So a relative `$MLC_CACHE_DIR` is refused (it
names a folder inside whatever folder a command runs in: a project's): the cache is off and
it says so (W612) where it would have been used. `MLC_CACHE=off` (or 0, no, false) disables it.

Trust model: the cache trusts its folder, not its entries' seals. An entry's SHA-256 is an
unkeyed hash: it finds truncation and corruption, but anyone who can write the folder can
write an entry with a matching hash, whose code mlc then runs. What keeps others out is the
folder rule below (private, ours, written by no one else), as for ~/.bashrc.

Safety:
- the folder is created private (0700) and used only if it belongs to this user and no one
  else can write it (POSIX); otherwise nothing is read or written;
- an entry is written to a temporary file beside it and renamed over it (atomic: a reader
  sees the old entry, the new one or none, never half of one);
- an entry holds its own key and a SHA-256 of its payload: one that is truncated, corrupt,
  written for another key or by another format, or whose payload does not decode is ignored
  (and rebuilt by the caller); one that decodes is still checked by the caller's `accept`;
- every failure to read or write is silent: the cache only ever saves time.
"""

from __future__ import annotations

import hashlib
import marshal
import os
import stat
import sys
import tempfile

ENV_DIR = "MLC_CACHE_DIR"
ENV_SWITCH = "MLC_CACHE"
MAGIC = b"MLCCACHE"
FORMAT = 1
_HEAD = len(MAGIC) + 1 + 32 + 32  # magic, format, key digest, payload digest

_fingerprint: str | None = None


_said: set[str] = set()  # the refusals already shown (once per process)


def enabled() -> bool:
    if os.environ.get(ENV_SWITCH, "").strip().lower() in ("off", "0", "no", "false"):
        return False
    why = refusal()
    if why is not None:
        if why not in _said:  # W612 where the cache would have been used, once
            from mlctool.diagnostics import Span, diag
            from mlctool.report import render_text

            _said.add(why)
            render_text([diag("<environment>", Span.at(1), "W612", why)], {}, sys.stderr)
        return False
    return True


def refusal() -> str | None:
    """Why the cache folder named by the environment is refused (a relative MLC_CACHE_DIR),
    or None."""
    explicit = os.environ.get(ENV_DIR)
    if explicit and not os.path.isabs(explicit):
        return (f"{ENV_DIR}={explicit!r} is not an absolute path: the on-disk cache is off (a relative "
                "folder lies in whatever folder a command runs in, such as a project's; give an absolute one)")
    return None


def folder() -> str:
    """Where entries live (the folder may not exist yet)."""
    explicit = os.environ.get(ENV_DIR)
    if explicit:
        return explicit
    if os.name == "nt":
        base = os.environ.get("LOCALAPPDATA") or os.path.expanduser("~\\AppData\\Local")
        return os.path.join(base, "mlctool", "cache")
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return os.path.join(base, "mlctool")


def fingerprint() -> str:
    """This mlctool and this Python: Python's version, and the name, size and modification
    time of every file of the package (an edited or upgraded mlctool never reads an older
    entry)."""
    global _fingerprint
    if _fingerprint is None:
        import mlctool

        h = hashlib.sha256(f"{sys.version}\0{sys.implementation.cache_tag}\0".encode())
        h.update(_files_digest(_package_root(mlctool)).encode())
        _fingerprint = h.hexdigest()
    return _fingerprint


def key(*parts: str | bytes) -> bytes:
    """The digest naming an entry: the caller's parts and fingerprint()."""
    h = hashlib.sha256(fingerprint().encode())
    for p in parts:
        b = p if isinstance(p, bytes) else p.encode()
        h.update(len(b).to_bytes(8, "little"))
        h.update(b)
    return h.digest()


_IDENTITIES: dict[int, tuple[object, str]] = {}  # id(target) -> (the target, kept alive; its identity)


def target_identity(target) -> str:
    """Everything of a target an entry derived for it can depend on: the tables as the command
    sees them (model, capacity, settings from mlc.toml, devices, every instruction with its op
    and operands) and the files of the package that declares it. fingerprint() covers only
    mlctool's own files: a third-party target's tables and routines are not among them (issue
    30.15: a toy target whose MOV changed ran the old cached code). Computed once per Target
    (some 20 ms for VS's tables)."""
    found = _IDENTITIES.get(id(target))
    if found is not None and found[0] is target:
        return found[1]
    from mlctool.targetapi.registry import target_package

    tables = (sorted(target.devices.items()), sorted(target.instructions.items()), sorted(target.variants.items()),
              sorted(target.unavailable))
    h = hashlib.sha256(repr((target.name, target.model, target.capacity, target.settings, tables)).encode())
    try:
        package = target_package(target.name)
    except (KeyError, TypeError):  # a Target built by hand (tests): its tables are all there is
        package = None
    if package is not None:  # a built-in target's files are fingerprint()'s already
        import mlctool

        folder = os.path.dirname(os.path.abspath(package.tables))
        if not folder.startswith(_package_root(mlctool) + os.sep):
            h.update(_files_digest(folder).encode())
    if len(_IDENTITIES) > 64:
        _IDENTITIES.clear()
    identity = h.hexdigest()
    _IDENTITIES[id(target)] = (target, identity)
    return identity


def _package_root(module) -> str:
    return os.path.dirname(os.path.abspath(module.__file__))


def _files_digest(root: str) -> str:
    """The name, size and modification time of every source or table file below `root`."""
    h = hashlib.sha256()
    for path, dirs, files in os.walk(root):
        dirs[:] = sorted(d for d in dirs if d != "__pycache__")
        for name in sorted(files):
            if name.endswith((".py", ".toml", ".json", ".lark")):
                try:
                    st = os.stat(os.path.join(path, name))
                except OSError:
                    continue
                h.update(f"{os.path.relpath(os.path.join(path, name), root)}\0{st.st_size}\0{st.st_mtime_ns}\n".encode())
    return h.hexdigest()


def _usable(path: str) -> bool:
    """The folder exists (made private if not), is ours, and only we can write it."""
    try:
        os.makedirs(path, mode=0o700, exist_ok=True)
        st = os.stat(path)
    except OSError:
        return False
    if os.name != "posix":
        return stat.S_ISDIR(st.st_mode)
    return stat.S_ISDIR(st.st_mode) and st.st_uid == os.getuid() and not st.st_mode & 0o022


def _entry_path(digest: bytes, kind: str) -> str:
    return os.path.join(folder(), f"{kind}-{digest.hex()}.bin")


def load(kind: str, digest: bytes, accept=None):
    """The value stored under (kind, digest), or None: no entry, the cache is off, or the
    entry is not sound (see the module's doc). `accept(value) -> bool` vets the decoded value."""
    if not enabled() or not _usable(folder()):
        return None
    path = _entry_path(digest, kind)
    try:
        with open(path, "rb") as f:
            data = f.read()
    except OSError:
        return None
    if len(data) < _HEAD or data[:len(MAGIC)] != MAGIC or data[len(MAGIC)] != FORMAT:
        return None
    at = len(MAGIC) + 1
    if data[at:at + 32] != digest:  # an entry of another key under this name
        return None
    payload = memoryview(data)[_HEAD:]  # (no copy: entries run to tens of MB)
    if hashlib.sha256(payload).digest() != data[at + 32:_HEAD]:
        return None
    try:
        value = marshal.loads(payload)
    except (ValueError, EOFError, TypeError):
        return None
    if accept is not None and not accept(value):
        return None
    return value


def store(kind: str, digest: bytes, value) -> bool:
    """Keep `value` (marshal-able: tuples, lists, dicts, strings, numbers, code objects) under
    (kind, digest). False when it was not stored (the cache is off or unusable, the value
    cannot be marshalled, the disk refused)."""
    if not enabled():
        return False
    where = folder()
    if not _usable(where):
        return False
    try:
        payload = marshal.dumps(value)
    except ValueError:
        return False
    data = MAGIC + bytes([FORMAT]) + digest + hashlib.sha256(payload).digest() + payload
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{kind}-", suffix=".tmp", dir=where)
    except OSError:
        return False
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(data)
        os.replace(tmp, _entry_path(digest, kind))
        return True
    except OSError:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        return False
