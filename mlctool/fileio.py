"""Output files: planned, checked against the inputs, then written all or none, atomically.

A command that writes files goes through an `Outputs` plan (docs/reliability.md); a missing
folder on the way to an output is created (`-o build/x.mlx`, `--junit out/j.xml`):

    plan = Outputs()
    plan.add(vcd_path, "--vcd")                    # E606 (exit 2): an input or another output
    plan.validate()                                # E605 (exit 2): a folder that cannot take it
    ...work...
    plan.write({vcd_path: data, ...})              # every file staged, then all renamed

The inputs are not listed by the command: every input file is opened here (`read_input`,
`open_input`), and opening one notes it in the command's register of inputs. An output is
compared with that register when it is planned, an input with the planned outputs when it is
opened, and every output once more when it is written; whichever comes second is E606. So a
file the command reads is never one it writes, whatever the order and whoever reads it (the
sources, --config and mlc.toml, stimulus files, --table files, --comments of an import, a
reader added later). `note_input` notes a file the command will have read elsewhere (the
stimulus files a batch hands to its worker processes). The CLI starts each command with an
empty register (`begin_command`).

Nothing is written before every output is known to be distinct from every input and from the
other outputs (the same resolved path, a symlink to one, or a hard link: the same device and
inode) and every output folder is known to be writable. Each file is first written to a
temporary file in its own folder and only renamed over the target when all of them were
written, so a failure leaves every earlier file as it was. `stream()` hands out such a
temporary file to write during a long run (the VCD), renamed with the others.
"""

from __future__ import annotations

import contextlib
import errno
import os
import signal
import stat
import threading
import weakref
from collections.abc import Iterable
from typing import IO

from mlctool.diagnostics import MlcError, Span, diag

TEMP_PREFIX = ".mlc-"
OUTPUT_CLASH = "E606"
CANNOT_WRITE = "E605"
_CAN_HOLD = hasattr(signal, "pthread_sigmask")


def _cannot_write(path: str, why: object) -> MlcError:
    return MlcError(diag(path, Span.at(1), CANNOT_WRITE, f"cannot write {path}: {why}"))


def _identity(path: str) -> tuple[str, tuple[int, int] | None]:
    """(resolved path, (device, inode) if the file exists): two names for one file share one."""
    try:
        real = os.path.realpath(path)
        st = os.stat(path)
    except ValueError:  # a name no file can have (NUL): writing it is E605
        return path, None
    except OSError:
        return real, None
    return real, (st.st_dev, st.st_ino)


# The command's register of inputs: (device, inode) -> the path as given, which names it
# however it is spelt (a symlink or hard link to it, `./x`); and by resolved path, for an
# output whose folder is still missing (`-o sub/../x` names x, though no `sub` exists yet).
# Paths are resolved only when an output is checked, each once (a batch reads thousands).
_INPUTS: dict[tuple[int, int], str] = {}
_UNRESOLVED: list[tuple[str, str]] = []  # (absolute path, the path as given)
_RESOLVED: dict[str, str] = {}  # resolved path -> the path as given
# The plans with outputs not written yet: an input opened now is checked against them.
_PLANS: weakref.WeakSet[Outputs] = weakref.WeakSet()
_LOCK = threading.Lock()


def begin_command() -> None:
    """A new command: no input read yet, no output planned (run_guarded calls it)."""
    with _LOCK:
        _INPUTS.clear()
        _UNRESOLVED.clear()
        _RESOLVED.clear()
        _PLANS.clear()


def note_input(path: str) -> None:
    """`path` is an input of this command (read here or by a worker): E606 if an output
    planned and not written yet is that file. A missing file is no input of the command."""
    try:
        st = os.stat(path)
    except (OSError, ValueError):
        return
    _noted(path, st)


def _noted(path: str, st: os.stat_result) -> None:
    key = (st.st_dev, st.st_ino)
    with _LOCK:
        if key in _INPUTS:
            return
        _INPUTS[key] = path
        _UNRESOLVED.append((os.path.abspath(path), path))
        outputs = [out for plan in _PLANS for out in plan.outputs]
    if outputs:
        real = os.path.realpath(path)
        for out, what, ident in outputs:
            if ident[1] == key or ident[0] == real:
                raise _clash(out, f"{what} {out} is the input {path}: refusing to overwrite it")


def inputs_read() -> list[str]:
    """The input files of this command so far, as they were named (tests/test_inputs_are_never_outputs.py)."""
    with _LOCK:
        return list(_INPUTS.values())


def _read_as(ident: tuple) -> str | None:
    """The input that `ident` (an output's identity) is, if the command read it."""
    with _LOCK:
        if ident[1] is not None and ident[1] in _INPUTS:
            return _INPUTS[ident[1]]
        for absolute, path in _UNRESOLVED:
            _RESOLVED.setdefault(os.path.realpath(absolute), path)
        _UNRESOLVED.clear()
        return _RESOLVED.get(ident[0])


def same_file(a: str, b: str) -> bool:
    ra, ia = _identity(a)
    rb, ib = _identity(b)
    return ra == rb or (ia is not None and ia == ib)


class Outputs:
    """The output files of one command run (see the module doc)."""

    def __init__(self, make_dirs: bool = True):
        self.outputs: list[tuple[str, str, tuple]] = []  # (path, what, identity)
        self.make_dirs = make_dirs
        self._staged: list[tuple[str, str]] = []  # (temporary file, target)

    def add(self, path: str, what: str = "output") -> str:
        """Plan `path` as an output; E606 if the command read it or it is another output."""
        ident = _identity(path)
        _refuse_input(path, what, ident)
        for p, w, other in self.outputs:
            if _same(ident, other):
                raise _clash(path, f"{what} {path} is also {w} {p}: one file cannot be both")
        self.outputs.append((path, what, ident))
        with _LOCK:
            _PLANS.add(self)
        return path

    def validate(self) -> None:
        """E605 for an output that cannot be written: it is a folder, or its folder is missing
        (unless the plan makes folders) or not writable. Checked before any work."""
        for path, _, _ in self.outputs:
            if os.path.isdir(path):
                raise _cannot_write(path, "it is a folder")
            folder = os.path.dirname(os.path.abspath(path))
            existing = folder
            while not os.path.isdir(existing):
                if os.path.lexists(existing) or not self.make_dirs:
                    what = "is not a folder" if os.path.lexists(existing) else "does not exist"
                    raise _cannot_write(path, f"the folder {_shown(existing, path)} {what}")
                existing = os.path.dirname(existing)
            if not os.access(existing, os.W_OK | os.X_OK):
                raise _cannot_write(path, f"the folder {_shown(existing, path)} is not writable")

    def stream(self, path: str, encoding: str = "utf-8") -> IO[str]:
        """A text file to write `path`'s content into; it becomes `path` on `write()`."""
        tmp, fd = self._temp(path)
        return os.fdopen(fd, "w", encoding=encoding, newline="")

    def write(self, files: dict[str, bytes | str] | Iterable[tuple[str, bytes | str]]) -> None:
        """Stage every file (and the streams), then rename them all over their targets."""
        items = list(files.items() if isinstance(files, dict) else files)
        try:
            # inputs opened since the outputs were planned, and files written without a plan
            for path in [p for _, p in self._staged] + [p for p, _ in items]:
                _refuse_input(path, self._what(path), _identity(path))
            for path, data in items:
                tmp, fd = self._temp(path)
                _fill(fd, data.encode("utf-8") if isinstance(data, str) else data, path)
            for tmp, path in self._staged:
                _settle(tmp, path)
            with held_interrupts():  # Ctrl-C or --max-wall waits until the set is in place
                for tmp, path in self._staged:
                    try:
                        os.replace(tmp, path)
                    except (OSError, ValueError) as e:  # ValueError: a name the OS cannot take (NUL)
                        raise _cannot_write(path, getattr(e, "strerror", None) or e) from e
                self._staged.clear()
        finally:
            self.discard()

    def discard(self) -> None:
        """Remove every staged temporary file (a failed run leaves nothing behind); the plan
        is over (its outputs no longer refuse an input)."""
        for tmp, _ in self._staged:
            try:
                os.unlink(tmp)
            except OSError:
                pass
        self._staged.clear()
        with _LOCK:
            _PLANS.discard(self)

    def _what(self, path: str) -> str:
        return next((w for p, w, _ in self.outputs if p == path), "output")

    def __enter__(self) -> Outputs:
        return self

    def __exit__(self, *exc) -> None:
        self.discard()

    def _temp(self, path: str) -> tuple[str, int]:
        folder = os.path.dirname(os.path.abspath(path))
        if self.make_dirs:
            try:
                os.makedirs(folder, exist_ok=True)
            except OSError as e:
                raise _cannot_write(path, e.strerror or e) from e
        # Ctrl-C between creating the file and noting it would leave it behind: held meanwhile
        with held_interrupts():
            try:
                import tempfile  # here: reading commands (`mlc check`) never write (a few ms of every start)

                fd, tmp = tempfile.mkstemp(prefix=TEMP_PREFIX, suffix=".tmp", dir=folder)
            except OSError as e:
                raise _cannot_write(path, e.strerror or e) from e
            self._staged.append((tmp, path))
        return tmp, fd


def _refuse_input(path: str, what: str, ident: tuple) -> None:
    read = _read_as(ident)
    if read is not None:
        raise _clash(path, f"{what} {path} is the input {read}: refusing to overwrite it")


def distinct(paths: Iterable[str], what: str) -> None:
    """E606 when two of `paths` are one file (`mlc fmt a.il ./a.il`: rewritten in place, each
    is its own input and output, but one file is not rewritten twice)."""
    seen: list[tuple[str, tuple]] = []
    for path in paths:
        ident = _identity(path)
        for p, other in seen:
            if _same(ident, other):
                raise _clash(path, f"{what} {path} is also {what} {p}: one file cannot be both")
        seen.append((path, ident))


def _clash(path: str, message: str) -> MlcError:
    return MlcError(diag(path, Span.at(1), OUTPUT_CLASH, message))


def _same(a: tuple, b: tuple) -> bool:
    return a[0] == b[0] or (a[1] is not None and a[1] == b[1])


def _shown(folder: str, path: str) -> str:
    rel = os.path.relpath(folder)
    return rel if not rel.startswith("..") and not os.path.isabs(path) else folder


def _fill(fd: int, data: bytes, path: str) -> None:
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(data)
    except OSError as e:
        raise _cannot_write(path, e.strerror or e) from e


def _settle(tmp: str, path: str) -> None:
    """The staged file on disk, with the permissions of a new file."""
    try:
        with open(tmp, "rb+") as f:
            os.fsync(f.fileno())
        os.chmod(tmp, 0o644)
    except OSError as e:
        raise _cannot_write(path, e.strerror or e) from e


@contextlib.contextmanager
def held_interrupts():
    """SIGINT (Ctrl-C, and --max-wall, which sends it to the main thread) is held until the
    block ends, then delivered: for the few steps that must not be cut in two."""
    if not _CAN_HOLD or threading.current_thread() is not threading.main_thread():
        yield
        return
    held = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, held)


def _open_regular(path: str, note: bool = True) -> tuple[int, os.stat_result]:
    """A file descriptor of `path` and its fstat; OSError for anything but a regular file (a
    FIFO or a device would block the command forever or never end; a folder cannot be read).
    The descriptor is still non-blocking (without effect on a regular file's reads). The file
    is noted as an input of the command (E606 if it is a planned output) unless `note` is
    False: only for a peek at an output itself (is the .gtkw beside --vcd mlc sim's own?)."""
    fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))  # a FIFO opens at once
    try:
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode):
            raise OSError(errno.EISDIR if stat.S_ISDIR(st.st_mode) else errno.EINVAL,
                          "Is a directory" if stat.S_ISDIR(st.st_mode) else
                          "not a regular file (a pipe, FIFO, socket or device)")
        if note:
            _noted(path, st)
    except BaseException:
        os.close(fd)
        raise
    return fd, st


def open_input(path: str, mode: str = "rb", encoding: str | None = None, note: bool = True) -> IO:
    """An input file opened for reading; OSError for anything but a regular file. Noted as
    an input of the command (see `_open_regular` for `note`)."""
    fd, _ = _open_regular(path, note)
    try:
        os.set_blocking(fd, True)
        return os.fdopen(fd, mode, encoding=encoding)
    except BaseException:
        os.close(fd)
        raise


def read_input(path: str, limit: int) -> bytes:
    """At most `limit` bytes of an input file (OSError for anything but a regular file; noted
    as an input of the command), by
    plain reads of the file descriptor: no file object, one fstat (a batch reads thousands of
    small stimulus files; open_input + read cost ~6 us a file more). The first read asks for
    the size fstat gave plus one byte, not `limit` (reading a 100-byte file with read(64 MB)
    allocates the 64 MB first); then it reads on to the end, up to `limit` (the file may
    have grown since)."""
    fd, st = _open_regular(path)
    try:
        want = min(st.st_size, limit - 1) + 1
        data = os.read(fd, want)
        if not data:
            return data
        parts = [data]
        got = len(data)
        while got < limit:
            more = os.read(fd, min(max(want, 1 << 16), limit - got))
            if not more:
                break
            parts.append(more)
            got += len(more)
        return data if len(parts) == 1 else b"".join(parts)
    finally:
        os.close(fd)


def rewrite(path: str, data: bytes) -> None:
    """New content for an existing file that stays the same file (`mlc fmt`): a symbolic link
    is written through (the link stays a link, its target gets the text), the permission bits
    are kept (0600 stays 0600), and a file with several hard links is rewritten in place so
    every name still shows the new text (docs/reliability.md).

    A file with one name is replaced atomically (temporary file beside it, renamed over it).
    A hard-linked file cannot be: a rename would give it a new inode and split the names. It
    is overwritten in place instead, after the new text is ready and a copy of the old bytes
    is saved beside it; if the write fails, the old bytes are put back (and if even that
    fails, the message names the saved copy)."""
    real = os.path.realpath(path)
    try:
        st = os.stat(real)
    except OSError as e:
        raise _cannot_write(path, e.strerror or e) from e
    if st.st_nlink > 1:
        _overwrite_in_place(real, data, path)
        return
    plan = Outputs(make_dirs=False)
    try:
        tmp, fd = plan._temp(real)
        _fill(fd, data, path)
        _settle(tmp, path)
        try:
            os.chmod(tmp, stat.S_IMODE(st.st_mode))
            if hasattr(os, "chown") and (st.st_uid, st.st_gid) != (os.getuid(), os.getgid()):
                try:  # the group can be kept by its member; the owner only by root
                    os.chown(tmp, -1 if os.getuid() else st.st_uid, st.st_gid)
                except OSError:
                    pass
            os.replace(tmp, real)
        except OSError as e:
            raise _cannot_write(path, e.strerror or e) from e
        plan._staged.clear()
    finally:
        plan.discard()


def _overwrite_in_place(real: str, data: bytes, path: str) -> None:
    try:
        with open(real, "rb") as f:
            old = f.read()
    except OSError as e:
        raise _cannot_write(path, e.strerror or e) from e
    plan = Outputs(make_dirs=False)
    tmp, fd = plan._temp(real)  # the saved copy of the old bytes
    try:  # (a full disk fails here already: the empty copy is removed below)
        _fill(fd, old, path)
        with open(real, "r+b") as f:
            try:
                f.write(data)
                f.truncate()
                f.flush()
                os.fsync(f.fileno())
            except OSError as e:
                try:
                    f.seek(0)
                    f.write(old)
                    f.truncate()
                    f.flush()
                except OSError:
                    plan._staged.clear()  # keep the copy: it is the only whole old text
                    raise _cannot_write(path, f"{e.strerror or e}; the old text is saved in {tmp}") from e
                raise _cannot_write(path, f"{e.strerror or e} (the file is unchanged)") from e
    except OSError as e:
        raise _cannot_write(path, e.strerror or e) from e
    finally:
        plan.discard()
