"""Argument helpers shared by the command-line modules (no heavy imports here)."""
import argparse
import os
import sys


class _UsageError(Exception):
    """Bad input: reported as one line and exit status 2."""


class _Parser(argparse.ArgumentParser):
    """An ArgumentParser whose errors are one line on stderr (exit status 2)."""

    def error(self, message):
        """Print ``vibimpact: error: MESSAGE`` and exit with status 2."""
        message = " ".join(str(message).split())
        self.exit(2, f"vibimpact: error: {message} (see '{self.prog} --help')\n")


def _positive_int(minimum):
    def convert(text):
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"invalid integer {text!r}") from None
        if value < minimum:
            raise argparse.ArgumentTypeError(f"must be >= {minimum}, got {value}")
        return value
    convert.__name__ = "integer"
    return convert


def _float(text):
    try:
        return float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"invalid number {text!r}") from None


def _parse_sets(items):
    """``["k=v", ...]`` -> ``{k: float(v)}``; raises _UsageError naming the bad item."""
    out = {}
    for item in items or ():
        key, sep, text = item.partition("=")
        key = key.strip()
        if not sep or not key:
            raise _UsageError(f"--set expects NAME=VALUE, got {item!r}")
        if key == "eta":
            raise _UsageError("set eta with --eta, not --set")
        try:
            out[key] = float(text)
        except ValueError:
            raise _UsageError(f"--set {key}: value {text.strip()!r} is not a number") from None
    return out


def _check_output(path, overwrite, what):
    """Fail early (before computing) if ``path`` cannot be created."""

    if os.path.isdir(path):
        raise _UsageError(f"{what} {path!r} is a directory")
    if os.path.exists(path) and not overwrite:
        raise _UsageError(f"{what} {path!r} exists; pass --overwrite to replace it")
    directory = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(directory):
        raise _UsageError(f"cannot write {what} {path!r}: directory {directory!r} "
                          "does not exist")
    if not os.access(directory, os.W_OK | os.X_OK):
        raise _UsageError(f"cannot write {what} {path!r}: directory {directory!r} "
                          "is not writable")
    import tempfile

    try:  # os.access says yes to root and knows nothing of read-only mounts: try it
        fd, probe = tempfile.mkstemp(prefix=".vibimpact-probe-", dir=directory)
    except OSError as exc:
        raise _UsageError(f"cannot write {what} {path!r}: directory {directory!r} "
                          f"is not writable ({exc.strerror or exc})") from None
    os.close(fd)
    os.unlink(probe)


def _parse_analyses(text):
    from .sweeps.point import ANALYSES

    names = [a.strip() for a in str(text).split(",") if a.strip()]
    if not names:
        raise _UsageError("--analyses: give a comma-separated list of "
                          f"{', '.join(ANALYSES)} (or all)")
    if names == ["all"]:
        return tuple(ANALYSES)
    bad = [a for a in names if a not in ANALYSES]
    if bad:
        raise _UsageError(f"--analyses: unknown {', '.join(map(repr, bad))}; choose from "
                          f"{', '.join(ANALYSES)} (or all)")
    return tuple(a for a in ANALYSES if a in names or a == "period")


def _image_ext_ok(path, what):
    from matplotlib.backend_bases import FigureCanvasBase

    ext = os.path.splitext(path)[1].lstrip(".").lower()
    if ext == "nc" or ext not in FigureCanvasBase.get_supported_filetypes():
        raise _UsageError(f"{what} {path!r}: unknown image extension (use .png, .pdf or "
                          ".svg)")


class _Interrupted(KeyboardInterrupt):
    """SIGINT or SIGTERM during a sweep; ``signum`` decides the exit status 128 + signum."""

    def __init__(self, signum):
        super().__init__(signum)
        self.signum = signum


class _StopWorkersOnSignal:
    """While a sweep runs: SIGINT and SIGTERM raise :class:`_Interrupted` in the main
    thread, so both end with the saved-points message and exit status 128 + signum;
    :func:`vibimpact.sweep` kills its workers on the way out (finished points are already
    saved atomically, the points in flight are lost).
    """

    def __enter__(self):
        import signal

        self._old = {}
        try:
            for sig in (signal.SIGINT, signal.SIGTERM):
                self._old[sig] = signal.signal(sig, self._handle)
        except ValueError:  # not the main thread: leave the signals alone
            self.__exit__(None, None, None)
        return self

    def _handle(self, signum, frame):
        self.__exit__(None, None, None)  # a second Ctrl-C acts at once
        raise _Interrupted(signum)  # vi.sweep stops its workers on the way out

    def __exit__(self, *exc):
        import signal

        for sig, old in self._old.items():
            signal.signal(sig, old)
        self._old = {}
        return False


def _interrupt_status(exc):
    import signal

    return 128 + int(getattr(exc, "signum", signal.SIGINT))


def _finish_checkpointed(ds, out, ckpt, write, *, resuming, loaded, keep, overwrite, unit,
                         damaged=None):
    """Write the result of a checkpointed run and tidy its checkpoint.

    Warns about damaged checkpoint files that were recomputed, writes ``ds`` to ``out``
    with ``write(ds, out, overwrite=...)`` (a failure is a usage error that keeps the
    checkpoint), removes the checkpoint unless ``keep``, and says what a resumed run
    loaded.  ``unit`` names what a checkpoint file holds ("points", "rows").  Returns the
    number of ``unit`` loaded from the checkpoint and not recomputed.  ``damaged``: how
    many ``unit`` the checkpoint found damaged and recomputed, for a checkpoint that
    counts them itself (a map's); by default its ``*.corrupt`` files are listed.
    """
    import shutil

    from .sweeps.checkpoint import corrupt_files

    if damaged is None:
        bad = corrupt_files(ckpt) if resuming else []
        what = f"{unit[:-1]} files"
        names = f" ({', '.join(bad[:3])}{', ...' if len(bad) > 3 else ''})"
        damaged = len(bad)
    else:
        what, names, damaged = unit, "", damaged if resuming else 0
    if damaged:
        loaded = max(0, loaded - damaged)
        print(f"vibimpact: warning: {damaged} damaged {what} in {ckpt} were "
              f"recomputed{names}", file=sys.stderr)
    try:
        write(ds, out, overwrite=overwrite or resuming)
    except (ValueError, OSError) as exc:
        raise _UsageError(f"{exc} (the computed {unit} stay in {ckpt}; fix the problem "
                          "and rerun with --resume)") from None
    if not keep:
        shutil.rmtree(ckpt, ignore_errors=True)
    if resuming:
        print(f"vibimpact: resumed from {ckpt}: {loaded} {unit} loaded, not recomputed",
              file=sys.stderr)
    return loaded
