"""Checks of a command's inputs that several commands share, made before any work: the
files it reads and writes are all different files, and a ``--state0`` has one value per
state of the model.

Only the standard library is imported here (``vibimpact --help`` stays instant).
"""
import math
import os

from .errors import UsageError


def same_file(a, b):
    """Whether the paths ``a`` and ``b`` name one file, however they are spelled.

    ``x.png``, ``./x.png``, ``sub/../x.png``, an absolute path and a symbolic link to
    the file are one file: their :func:`os.path.realpath` agree, or, when both exist,
    :func:`os.path.samefile` says so (a hard link, a bind mount).

    Parameters
    ----------
    a, b : str or os.PathLike

    Returns
    -------
    bool
    """
    a, b = os.fspath(a), os.fspath(b)
    try:
        if os.path.realpath(a) == os.path.realpath(b):
            return True
    except (OSError, ValueError):  # a link loop, a NUL in the name: vetted elsewhere
        return False
    try:
        return os.path.samefile(a, b)
    except (OSError, ValueError):  # one does not exist (yet)
        return False


def check_distinct(*outputs, inputs=()):
    """Refuse, before any work, an output of a command that is one file with another of
    its outputs or with a file it reads (two inputs may be one file).

    Parameters
    ----------
    *outputs : (str, path or None)
        ``(option, path)`` of every file or directory the command writes (``("-o",
        "x.nc")``, ``("--plot", "x.png")``); a ``None`` path (an option not given) is
        left out.
    inputs : sequence of (str, path or None)
        ``(option, path)`` of the files it reads (``("--sweep", "s.nc")``).

    Raises
    ------
    UsageError
        Naming both options and paths: ``-o 'x.png' and --plot './x.png' name the same
        file``.
    """
    outs = [(o, os.fspath(p)) for o, p in outputs if p is not None]
    ins = [(o, os.fspath(p)) for o, p in inputs if p is not None]
    pairs = [(outs[i], b) for i in range(len(outs)) for b in outs[i + 1:] + ins]
    for (first, a), (second, b) in pairs:
        if same_file(a, b):
            same = "" if a == b else f" {b!r}"
            raise UsageError(f"{first} {a!r} and {second}{same} name the same file; give "
                             "different files")


def check_state0(values, system, option="--state0"):
    """Refuse a start state that does not fit the model: one finite number per state
    variable (``system.model.state_names``).

    Parameters
    ----------
    values : sequence of float or None
        The parsed numbers (None: not given, nothing to check).
    system : vibimpact.core.system.System
    option : str
        The option named in the message.

    Raises
    ------
    UsageError
    """
    if values is None:
        return
    names = tuple(system.model.state_names)
    if len(values) != len(names):
        raise UsageError(f"{option} expects {len(names)} numbers for the "
                         f"{system.model.name} model ({', '.join(names)}), got "
                         f"{len(values)}")
    if not all(math.isfinite(v) for v in values):
        raise UsageError(f"{option} must be finite numbers, got "
                         f"{' '.join(f'{v:g}' for v in values)}")


__all__ = ["check_distinct", "check_state0", "same_file"]
