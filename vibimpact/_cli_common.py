"""Argument helpers shared by the command-line modules (no heavy imports here)."""
import argparse


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
    import os

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
