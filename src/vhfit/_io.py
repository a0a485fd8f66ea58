"""File output: atomic writes and JSON encoding, each written once for the whole package."""

from __future__ import annotations

import contextlib
import functools
import json
import os
import tempfile
from pathlib import PurePath
from typing import Any

import numpy as np

__all__ = ["atomic_write", "json_default", "dumps"]


def atomic_write(path, text: str | bytes) -> None:
    """Write ``text`` (or bytes) to ``path`` via a temporary file and a rename: never a
    torn file.

    The data and then the directory entry are flushed to disk, so after a crash or a
    power cut the file holds either the old or the new text. Temporary files left by
    writers that were killed (``.<name>.<pid>.tmp-*.part``, their process gone) are
    removed. A new file gets the usual permissions (umask), a replaced one keeps its own.
    """
    path = os.fspath(path)
    d = os.path.dirname(os.path.abspath(path))
    base = os.path.basename(path)
    _remove_orphans(d, base)
    fd, tmp = tempfile.mkstemp(dir=d, prefix=f".{base}.{os.getpid()}.tmp-", suffix=".part")
    try:
        try:
            mode = os.stat(path).st_mode & 0o7777
        except OSError:
            mode = 0o666 & ~_umask()
        os.chmod(tmp, mode)
        with os.fdopen(fd, "wb" if isinstance(text, bytes) else "w") as f:
            f.write(text)
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise
    _fsync_dir(d)


@functools.cache
def _umask() -> int:
    old = os.umask(0o022)  # reading it means setting it: do it once
    os.umask(old)
    return old


def _fsync_dir(d: str) -> None:
    try:
        fd = os.open(d, os.O_RDONLY)
    except OSError:  # e.g. Windows: directories cannot be opened
        return
    try:
        os.fsync(fd)
    except OSError:
        pass
    finally:
        os.close(fd)


def _remove_orphans(d: str, base: str) -> None:
    """Delete ``.<base>.<pid>.tmp-*.part`` files whose writing process no longer exists."""
    prefix = f".{base}."
    try:
        names = [n for n in os.listdir(d) if n.startswith(prefix) and n.endswith(".part")]
    except OSError:
        return
    for name in names:
        pid = name[len(prefix):].split(".", 1)[0]
        if pid.isdigit() and not _alive(int(pid)):
            with contextlib.suppress(OSError):
                os.unlink(os.path.join(d, name))


def _alive(pid: int) -> bool:
    if pid == os.getpid() or os.name == "nt":  # Windows' os.kill would terminate it
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except (PermissionError, OSError):
        return True  # exists (another user's) or cannot tell: leave its file alone
    return True


def json_default(o: Any) -> Any:
    """JSON encoding of what ``json`` cannot encode: numpy scalars and arrays, paths, else str."""
    if isinstance(o, np.generic):
        return o.item()
    if isinstance(o, np.ndarray):
        return o.tolist()
    if isinstance(o, PurePath):
        return str(o)
    return str(o)


def dumps(obj: Any, **kw: Any) -> str:
    """``json.dumps`` with :func:`json_default`."""
    return json.dumps(obj, default=json_default, **kw)
