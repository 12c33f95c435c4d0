"""Opening regular files only, and without blocking.  Standard library only.

A FIFO opened for reading blocks until a writer comes, a character device such as
``/dev/zero`` never ends, a socket cannot be opened at all: a file the toolkit reads (an
input file, a checkpoint's ``request.json`` or entries) must be a regular file, and is
refused in words ("is a FIFO, not a regular file") before anything waits on it.

:func:`open_regular` checks ``lstat`` (or ``stat``) before it opens (a device is never
opened), opens with ``O_NONBLOCK`` (a FIFO swapped in meanwhile does not block the open)
and checks ``fstat`` of what it opened (nothing swapped in between is read).  With
``follow=False`` a symbolic link is refused too (``O_NOFOLLOW``): a checkpoint's files
are read without following a link out of the checkpoint.
"""
from __future__ import annotations

import errno
import os
import stat

__all__ = ["NotRegular", "kind", "open_regular", "read_regular", "why_not_a_file"]

_KINDS = {stat.S_IFIFO: "a FIFO", stat.S_IFSOCK: "a socket",
          stat.S_IFCHR: "a character device", stat.S_IFBLK: "a block device",
          stat.S_IFDIR: "a directory", stat.S_IFLNK: "a symbolic link"}


class NotRegular(ValueError):
    """A path that is not a regular file (a FIFO, a device, a socket, a directory or,
    where links are not followed, a symbolic link); the message names it and what it
    is."""


def kind(mode: int) -> str:
    """What a ``st_mode`` is, in words: ``"a FIFO"``, ``"a directory"``, ...,
    ``"a regular file"``."""
    if stat.S_ISREG(mode):
        return "a regular file"
    return _KINDS.get(stat.S_IFMT(mode), "not a regular file")


def _refuse(what, mode):
    return NotRegular(f"{what} is {kind(mode)}, not a regular file")


def open_regular(name, what: str, *, dir_fd: int | None = None,
                 follow: bool = True) -> int:
    """A read-only file descriptor of the regular file ``name``.

    Parameters
    ----------
    name : str or os.PathLike
        The file (relative to ``dir_fd`` when given).
    what : str
        How the messages name it.
    dir_fd : int, optional
        A directory's descriptor ``name`` is relative to.
    follow : bool
        False: a symbolic link is refused, not followed.

    Raises
    ------
    NotRegular
        ``name`` is a FIFO, a device, a socket, a directory, or (``follow`` false) a
        symbolic link.
    OSError
        It cannot be opened (missing, no permission).
    """
    st = os.stat(name, dir_fd=dir_fd, follow_symlinks=follow)
    if not stat.S_ISREG(st.st_mode):
        raise _refuse(what, st.st_mode)
    flags = os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0) | \
        (0 if follow else getattr(os, "O_NOFOLLOW", 0))
    try:
        fd = os.open(name, flags, dir_fd=dir_fd)
    except OSError as exc:
        if exc.errno in (errno.ELOOP, errno.ENXIO):  # a link or a socket swapped in
            found = "a symbolic link" if exc.errno == errno.ELOOP else "a socket"
            raise NotRegular(f"{what} is {found}, not a regular file") from None
        raise
    mode = os.fstat(fd).st_mode
    if not stat.S_ISREG(mode):  # swapped between the stat and the open
        os.close(fd)
        raise _refuse(what, mode)
    return fd


def read_regular(name, what: str, max_bytes: int, *, dir_fd: int | None = None,
                 follow: bool = True) -> bytes:
    """The bytes of the regular file ``name`` (:func:`open_regular`), at most
    ``max_bytes`` of them.

    Raises
    ------
    NotRegular
        Not a regular file.
    ValueError
        Larger than ``max_bytes``.
    OSError
        It cannot be opened or read.
    """
    fd = open_regular(name, what, dir_fd=dir_fd, follow=follow)
    with os.fdopen(fd, "rb") as fh:
        size = os.fstat(fd).st_size
        data = fh.read(max_bytes + 1) if size <= max_bytes else b""
    if size > max_bytes or len(data) > max_bytes:
        raise ValueError(f"{what} is larger than {max_bytes} bytes (no file vibimpact "
                         "writes there is)")
    return data


def why_not_a_file(path) -> str:
    """Why the path ``path`` that is not a regular file cannot be read, to follow its
    name: ``": no such file"``, ``" is a FIFO, not a regular file"``, ``" is a broken
    symbolic link (to 'x')"``."""
    try:
        mode = os.stat(path).st_mode
    except OSError:
        if os.path.islink(path):
            try:
                return f" is a broken symbolic link (to {os.readlink(path)!r})"
            except OSError:
                return " is a broken symbolic link"
        return ": no such file"
    return ": no such file" if stat.S_ISREG(mode) else f" is {kind(mode)}, not a " \
        "regular file"
