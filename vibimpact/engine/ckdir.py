"""The files of a checkpoint directory, never through a symbolic link and never
blocking.  Standard library only.

Every file of a checkpoint is read and written through a descriptor of the directory
itself (:func:`dir_fd`: ``O_DIRECTORY | O_NOFOLLOW``), so a checkpoint path swapped for
a symbolic link, a file or another directory while a run goes on is noticed and named
(:class:`Found`), and nothing is read or written where a link points.  Files are read
only when regular (a FIFO named like an entry or ``request.json`` does not block,
:mod:`vibimpact.base._regular`), JSON bounded in size and depth (:mod:`vibimpact.base._json`),
and written to a temporary name and renamed (:func:`write_atomic`).  A new checkpoint
is made whole (:func:`create`): built under a temporary name beside it with its
``request.json``, then renamed into place, so an interrupt never leaves a checkpoint
without its request.
"""
from __future__ import annotations

import contextlib
import errno
import os
import secrets
import stat

from ..base._regular import kind

__all__ = ["Found", "found_at", "dir_fd", "opened", "write_atomic", "create",
           "remove_temporaries"]

_FLAGS = os.O_RDONLY | getattr(os, "O_DIRECTORY", 0) | getattr(os, "O_NOFOLLOW", 0) | \
    getattr(os, "O_CLOEXEC", 0)


class Found(ValueError):
    """The checkpoint path holds something else than a directory: ``found`` says what
    (``"a symbolic link (to '/tmp/x')"``, ``"a regular file"``, ...)."""

    def __init__(self, path, found):
        super().__init__(f"{os.fspath(path)!r} is {found}")
        self.found = found


def found_at(path) -> str | None:
    """What is at ``path`` now, in words (None: nothing)."""
    try:
        st = os.lstat(path)
    except FileNotFoundError:
        return None
    if stat.S_ISLNK(st.st_mode):
        try:
            return f"a symbolic link (to {os.readlink(path)!r})"
        except OSError:
            return "a symbolic link"
    return kind(st.st_mode)


def dir_fd(path) -> tuple[int, os.stat_result]:
    """``(descriptor, stat)`` of the directory ``path`` itself.

    Raises
    ------
    Found
        ``path`` is a symbolic link (never followed) or not a directory.
    FileNotFoundError
        Nothing is there.
    """
    try:
        fd = os.open(path, _FLAGS)
    except OSError as exc:
        if exc.errno in (errno.ELOOP, errno.ENOTDIR):
            raise Found(path, found_at(path) or "gone") from None
        raise
    return fd, os.fstat(fd)


@contextlib.contextmanager
def opened(path):
    """A block with the descriptor of the directory ``path`` (:func:`dir_fd`)."""
    fd, _ = dir_fd(path)
    try:
        yield fd
    finally:
        os.close(fd)


def write_atomic(dfd: int, name: str, data: bytes) -> None:
    """Write ``data`` as the file ``name`` of the directory ``dfd``: to a temporary
    ``.tmp-*`` name, flushed, synced and renamed, so that ``name`` is whole or absent;
    the temporary is removed on any failure."""
    tmp = f".tmp-{secrets.token_hex(6)}{os.path.splitext(name)[1]}"
    flags = os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_NOFOLLOW", 0) | \
        getattr(os, "O_CLOEXEC", 0)
    fd = os.open(tmp, flags, 0o600, dir_fd=dfd)
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, name, src_dir_fd=dfd, dst_dir_fd=dfd)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp, dir_fd=dfd)
        raise


def create(path, files: dict) -> os.stat_result:
    """Make the directory ``path`` holding ``files`` (``{name: bytes}``) at once: built
    under a temporary name beside it (:func:`vibimpact.base._writing.temp_prefix`, removed on
    any failure) and renamed into place.  Returns the new directory's stat.

    Raises
    ------
    FileExistsError
        Something appeared at ``path`` meanwhile.
    OSError
        It cannot be made.
    """
    import shutil

    from ..base._writing import temp_prefix

    path = os.fspath(path)
    parent = os.path.dirname(os.path.abspath(path))
    os.makedirs(parent, exist_ok=True)
    while True:  # mkdtemp's mode 0o700 would outlive the rename: the umask decides
        tmp = os.path.join(parent, f"{temp_prefix(path)}{secrets.token_hex(4)}.tmp")
        try:
            os.mkdir(tmp)
            break
        except FileExistsError:
            continue
    try:
        with opened(tmp) as fd:
            for name, data in files.items():
                write_atomic(fd, name, data)
        if os.path.lexists(path):
            raise FileExistsError(errno.EEXIST, "exists", path)
        os.rename(tmp, path)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    return os.lstat(path)


def remove_temporaries(path) -> int:
    """Remove the temporary files (``.tmp-*``) a run killed while saving left in the
    checkpoint directory ``path`` (nothing where ``path`` is a link or not a
    directory).  Returns their number."""
    try:
        fd, _ = dir_fd(path)
    except (OSError, ValueError):
        return 0
    removed = 0
    try:
        for name in os.listdir(fd):
            if name.startswith(".tmp-"):
                with contextlib.suppress(OSError):
                    os.unlink(name, dir_fd=fd)
                    removed += 1
    finally:
        os.close(fd)
    return removed
