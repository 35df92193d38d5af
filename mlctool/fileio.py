"""Output files: planned, checked against the inputs, then written all or none, atomically.

A command that writes files goes through an `Outputs` plan (docs/reliability.md); a missing
folder on the way to an output is created (`-o build/x.mlx`, `--junit out/j.xml`):

    plan = Outputs(inputs=[source, stimulus])      # the files the command reads
    plan.add(vcd_path, "--vcd")                    # E606 (exit 2): an input or another output
    plan.validate()                                # E605 (exit 2): a folder that cannot take it
    ...work...
    plan.write({vcd_path: data, ...})              # every file staged, then all renamed

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
    real = os.path.realpath(path)
    try:
        st = os.stat(path)
    except OSError:
        return real, None
    return real, (st.st_dev, st.st_ino)


def same_file(a: str, b: str) -> bool:
    ra, ia = _identity(a)
    rb, ib = _identity(b)
    return ra == rb or (ia is not None and ia == ib)


class Outputs:
    """The output files of one command run (see the module doc)."""

    def __init__(self, inputs: Iterable[str] = (), make_dirs: bool = True):
        self.inputs: list[tuple[str, tuple]] = []
        self.outputs: list[tuple[str, str, tuple]] = []  # (path, what, identity)
        self.make_dirs = make_dirs
        self._staged: list[tuple[str, str]] = []  # (temporary file, target)
        for p in inputs:
            self.add_input(p)

    def add_input(self, path: str) -> None:
        """An input (found late, such as the files a glob matched); E606 if it is an output."""
        ident = _identity(path)
        for p, what, other in self.outputs:
            if _same(ident, other):
                raise _clash(p, f"{what} {p} is the input {path}: refusing to overwrite it")
        self.inputs.append((path, ident))

    def add(self, path: str, what: str = "output") -> str:
        """Plan `path` as an output; E606 if it is an input or another output."""
        ident = _identity(path)
        for p, other in self.inputs:
            if _same(ident, other):
                raise _clash(path, f"{what} {path} is the input {p}: refusing to overwrite it")
        for p, w, other in self.outputs:
            if _same(ident, other):
                raise _clash(path, f"{what} {path} is also {w} {p}: one file cannot be both")
        self.outputs.append((path, what, ident))
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
        items = files.items() if isinstance(files, dict) else files
        try:
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
        """Remove every staged temporary file (a failed run leaves nothing behind)."""
        for tmp, _ in self._staged:
            try:
                os.unlink(tmp)
            except OSError:
                pass
        self._staged.clear()

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


def _open_regular(path: str) -> tuple[int, os.stat_result]:
    """A file descriptor of `path` and its fstat; OSError for anything but a regular file (a
    FIFO or a device would block the command forever or never end; a folder cannot be read).
    The descriptor is still non-blocking (without effect on a regular file's reads)."""
    fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))  # a FIFO opens at once
    try:
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode):
            raise OSError(errno.EISDIR if stat.S_ISDIR(st.st_mode) else errno.EINVAL,
                          "Is a directory" if stat.S_ISDIR(st.st_mode) else
                          "not a regular file (a pipe, FIFO, socket or device)")
    except BaseException:
        os.close(fd)
        raise
    return fd, st


def open_input(path: str, mode: str = "rb", encoding: str | None = None) -> IO:
    """An input file opened for reading; OSError for anything but a regular file."""
    fd, _ = _open_regular(path)
    try:
        os.set_blocking(fd, True)
        return os.fdopen(fd, mode, encoding=encoding)
    except BaseException:
        os.close(fd)
        raise


def read_input(path: str, limit: int) -> bytes:
    """At most `limit` bytes of an input file (OSError for anything but a regular file), by
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


def write_atomic(path: str, data: bytes | str) -> None:
    """Write all of `data` to `path` or nothing; an existing file is replaced only on success."""
    Outputs().write({path: data})


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
    _fill(fd, old, path)
    try:
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
