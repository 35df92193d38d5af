"""Atomic output: write to a temporary file beside the target, then rename over it.

Every output of every command goes through `write_atomic`, so the rules live here once: a
missing folder on the way to an output is created (`-o build/x.mlx`, `--junit out/j.xml`),
and a file is either replaced whole or left as it was.
"""

from __future__ import annotations

import os
import tempfile

from mlctool.diagnostics import MlcError, Span, diag


def write_atomic(path: str, data: bytes | str) -> None:
    """Write all of `data` to `path` or nothing; an existing file is replaced only on success."""
    if isinstance(data, str):
        data = data.encode("utf-8")
    folder = os.path.dirname(os.path.abspath(path))
    try:
        os.makedirs(folder, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=".mlc-", suffix=".tmp", dir=folder)
    except OSError as e:
        raise MlcError(diag(path, Span.at(1), "E605", f"cannot write {path}: {e.strerror or e}")) from e
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(data)
            f.flush()
            os.fsync(f.fileno())
        os.chmod(tmp, 0o644)
        os.replace(tmp, path)
    except OSError as e:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise MlcError(diag(path, Span.at(1), "E605", f"cannot write {path}: {e.strerror or e}")) from e
