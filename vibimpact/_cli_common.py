"""Argument helpers shared by the command-line modules (no heavy imports here)."""
import argparse
import math
import os
import sys

from ._text import count, one_line


class UsageError(Exception):
    """Bad input: reported as one line and exit status 2."""


class Parser(argparse.ArgumentParser):
    """An ArgumentParser whose errors are one line on stderr (exit status 2).

    Every parser (the main one and each command's) takes ``-v/--verbose``, so that it can
    stand before or after the command name; repeated, it counts (see :func:`set_verbosity`).

    Parameters
    ----------
    verbose_dest : str
        The attribute the count goes to.  argparse gives a command's parser a namespace
        of its own and copies it over the main one, so the main parser counts in another
        attribute (``verbose_before``) and :func:`verbosity` adds the two.
    """

    def __init__(self, *args, verbose_dest="verbose", **kwargs):
        super().__init__(*args, **kwargs)
        # SUPPRESS: a command's parser must not reset a count the main parser has set
        self.add_argument("-v", "--verbose", action="count", default=argparse.SUPPRESS,
                          dest=verbose_dest,
                          help="report what the run does on stderr (-v: its steps, "
                               "-vv: debugging detail), through Python's logging")

    def error(self, message):
        """Print ``vibimpact: error: MESSAGE`` and exit with status 2."""
        message = " ".join(str(message).split())
        self.exit(2, f"vibimpact: error: {message} (see '{self.prog} --help')\n")


def verbosity(args):
    """The number of ``-v`` in parsed arguments: before and after the command name."""
    return getattr(args, "verbose", 0) + getattr(args, "verbose_before", 0)


def set_verbosity(count):
    """Send the package's log records (logger ``vibimpact``) to stderr.

    Parameters
    ----------
    count : int
        0: nothing is configured (warnings go to Python's last-resort handler), and the
        handler and level an earlier call in this process set are taken back; 1: INFO;
        2 or more: DEBUG.  The records go to ``sys.stderr`` as it is when each is
        written (a redirected stderr included).
    """
    import logging

    class _Stderr(logging.StreamHandler):
        _vibimpact_cli = True

        def __init__(self):
            logging.Handler.__init__(self)

        @property
        def stream(self):  # looked up at each record, never a stale stream
            return sys.stderr

    log = logging.getLogger("vibimpact")
    ours = [h for h in log.handlers if getattr(h, "_vibimpact_cli", False)]
    if not count:
        for handler in ours:
            log.removeHandler(handler)
        if ours:
            log.setLevel(logging.NOTSET)
        return
    if not ours:
        handler = _Stderr()
        handler.setFormatter(logging.Formatter("vibimpact: %(levelname)s: %(message)s"))
        log.addHandler(handler)
    log.setLevel(logging.INFO if count == 1 else logging.DEBUG)


def positive_int(minimum, maximum=None):
    """The argparse type of an integer option in ``[minimum, maximum]``: a value out of
    range is refused as ``argument --NAME: must be >= 1, got 0``, in the option's name
    (not as the API's argument would be, later)."""
    def convert(text):
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"invalid integer {text!r}") from None
        if value < minimum:
            raise argparse.ArgumentTypeError(f"must be >= {minimum}, got {value}")
        if maximum is not None and value > maximum:
            raise argparse.ArgumentTypeError(f"must be <= {maximum}, got {value}")
        return value
    convert.__name__ = "integer"
    return convert


def number(text):
    """The argparse type of a number option: a finite float (no option of the command
    line takes NaN or infinity; refused here, in the option's name)."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"invalid number {text!r}") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"must be a finite number, got {text!r}")
    return value


def positive_number(text):
    """The argparse type of a finite number > 0 (a tolerance)."""
    value = number(text)
    if value <= 0.0:
        raise argparse.ArgumentTypeError(f"must be a finite number > 0, got {text!r}")
    return value


def with_sets(base, sets, eta=None):
    """The parameter set ``base`` with the ``--set`` values ``sets`` (and ``--eta``)
    replaced; UsageError naming the option whose value lies outside its parameter's
    domain (:meth:`vibimpact.Params.domain`), or saying what else is wrong."""
    given = ([("--eta", "eta", eta)] if eta is not None else []) + \
        [(f"--set {k}", k, v) for k, v in sets.items()]
    known = base.as_dict()
    for option, name, value in given:
        if name in known and math.isfinite(value) and value not in base.domain(name):
            raise UsageError(f"{option}: {base.domain(name).rule(name)}, got {value!r}")
    try:
        return base.replace(**({} if eta is None else {"eta": eta}), **sets)
    except ValueError as exc:
        raise UsageError(error_text(exc)) from None


def parse_sets(items):
    """``["k=v", ...]`` -> ``{k: float(v)}``; raises UsageError naming the bad item."""
    out = {}
    for item in items or ():
        key, sep, text = item.partition("=")
        key = key.strip()
        if not sep or not key:
            raise UsageError(f"--set expects NAME=VALUE, got {item!r}")
        if key == "eta":
            raise UsageError("set eta with --eta, not --set")
        if key in out:
            raise UsageError(f"--set {key} given twice ({key}={out[key]:g} and "
                             f"{item.strip()}); give each parameter once")
        try:
            out[key] = float(text)
        except ValueError:
            raise UsageError(f"--set {key}: value {text.strip()!r} is not a number") from None
    return out


def check_output(path, overwrite, what, store=False, size=0):
    """Fail early (before computing) if ``path`` cannot be created: the one check of an
    output path (:func:`vibimpact.io.check_output_path`) as a :class:`UsageError`;
    ``size`` (bytes, an estimate of the file) must be free on its file system, and at
    least :data:`vibimpact.io.MIN_FREE`.

    Returns
    -------
    str
        The path (a store's trailing ``/`` removed).
    """
    from .io import MIN_FREE, check_output_path

    try:
        return check_output_path(path, overwrite, what=what, store=store,
                                 free=max(MIN_FREE, size))
    except ValueError as exc:
        raise UsageError(error_text(exc)) from None


def sweep_file_bytes(params, points, direction="up"):
    """An estimate of the file of a sweep or map of ``points`` grid points per
    direction (``"both"``: twice as many), for :func:`check_output`'s ``size``."""
    from ._limits import points_bytes
    from .points.point import SweepSettings
    from .system import to_system

    points *= 2 if direction == "both" else 1
    return points_bytes(points, SweepSettings().n_samples, to_system(params).n_state)


#: the option of the command line that sets each flag of the API a refusal names
#: (:class:`vibimpact.io.NeedsFlag`: an existing output, an existing checkpoint)
OPTION_OF_FLAG = {"overwrite": "--overwrite", "resume": "--resume"}


def reason(exc):
    """Why ``exc`` happened, in the command line's words, for one line.

    A refusal that a flag of the API lifts (:class:`vibimpact.io.NeedsFlag`, known by
    its ``flag`` and ``say``) names the option that sets it (``--overwrite``, not
    ``overwrite=True``); an ``OSError`` is its reason without the ``[Errno N]`` prefix;
    a ``KeyError`` names the missing key; anything else is its message.  Python's class
    names are left out (the message says what happened); only an exception without a
    message is named by its class.
    """
    flag, say = getattr(exc, "flag", None), getattr(exc, "say", None)
    if isinstance(flag, str) and callable(say):
        return say(OPTION_OF_FLAG.get(flag, "--" + flag.replace("_", "-")))
    if isinstance(exc, OSError) and exc.strerror:
        return str(exc.strerror)
    if isinstance(exc, KeyError) and exc.args:
        return f"{exc.args[0]!r} is missing"
    return one_line(exc)


def error_text(exc):
    """The message of a failure for one line: :func:`reason`, and the file name of an
    ``OSError`` that has one."""
    if isinstance(exc, OSError) and exc.strerror and exc.filename:
        return f"{reason(exc)}: {exc.filename!r}"
    return reason(exc)


def is_store(path):
    """A Zarr store (a directory with its ``zarr.json``), as ``map`` writes."""
    return os.path.isdir(path) and os.path.isfile(os.path.join(path, "zarr.json"))


def read_input(path, what="", stores=False):
    """The dataset of an input file a command reads, or one line saying why not.

    Parameters
    ----------
    path : str
    what : str
        The option or role that names the file in the messages (``"--from"``).
    stores : bool
        Also read a Zarr store (a map).

    Raises
    ------
    UsageError
        A directory, a missing file or one that cannot be read.
    """
    from . import io

    label = f"{what} {path!r}".strip()
    if stores and is_store(path):
        from .maps.store import open_map

        reader, kind = open_map, "a Zarr store"
    elif os.path.isdir(path):
        raise UsageError(f"{label} is a directory, not a NetCDF file"
                         + (" or a Zarr store" if stores else ""))
    elif not os.path.isfile(path):
        raise UsageError(f"{label}: no such file")
    else:
        reader, kind = io.read_netcdf, "NetCDF"
    try:
        return reader(path)
    except Exception as exc:  # netCDF4 raises OSError, xarray ValueError, ...
        raise UsageError(f"{what + ': ' if what else ''}cannot read {path!r} as {kind}: "
                         f"{reason(exc)}") from None


def write_outputs(*writes):
    """Write a command's outputs so that they succeed or fail together.

    Parameters
    ----------
    *writes : (str, callable)
        ``(path, write)`` in order; ``write()`` writes ``path``.  When one fails, or a
        signal (Ctrl-C, SIGTERM) stops the command before the last is written, the
        outputs written before it are removed again.

    Raises
    ------
    UsageError
        The failure in one line (ValueError, OSError, a NetCDF RuntimeError).
    """
    done = []

    def undo():
        for path in done:
            try:
                os.unlink(path)
            except OSError:
                pass

    try:
        for path, write in writes:
            write()
            done.append(path)
    except (ValueError, OSError, RuntimeError) as exc:
        undo()
        written = f" ({', '.join(map(repr, done))} removed again)" if done else ""
        raise UsageError(f"{error_text(exc)}{written}") from None
    except BaseException:
        # Ctrl-C or SIGTERM between two outputs: none of them stays (the signal's own
        # line and exit status follow)
        undo()
        raise


def parse_analyses(text):
    from .points.point import ANALYSES

    names = [a.strip() for a in str(text).split(",") if a.strip()]
    if not names:
        raise UsageError("--analyses: give a comma-separated list of "
                          f"{', '.join(ANALYSES)} (or all)")
    if names == ["all"]:
        return tuple(ANALYSES)
    bad = [a for a in names if a not in ANALYSES]
    if bad:
        raise UsageError(f"--analyses: unknown {', '.join(map(repr, bad))}; choose from "
                          f"{', '.join(ANALYSES)} (or all)")
    return tuple(a for a in ANALYSES if a in names or a == "period")


def _figsize(text):
    from .plotting.style import check_figsize

    w, sep, h = str(text).lower().partition("x")
    try:
        if sep:
            return check_figsize((float(w), float(h)))
    except ValueError:
        pass
    raise argparse.ArgumentTypeError(f"must be WIDTHxHEIGHT in inches, two numbers > 0 "
                                     f"(e.g. 3.5x2.8), got {text!r}")


def _dpi(text):
    from .plotting.style import check_dpi

    try:
        return check_dpi(float(text))
    except ValueError:
        pass
    raise argparse.ArgumentTypeError(f"must be a number > 0 (dots per inch), got {text!r}")


def _style(text):
    from .plotting.style import STYLES, check_style

    try:
        return check_style(text)
    except ValueError:
        pass
    raise argparse.ArgumentTypeError(f"must be one of {', '.join(map(repr, STYLES))}, "
                                     f"got {text!r}")


def add_figure_options(parser, what="the figure"):
    """``--figsize``, ``--dpi`` and ``--style`` of a command that draws ``what``; checked
    by :mod:`vibimpact.plotting.style`, as the plotting functions check their arguments."""
    parser.add_argument("--figsize", type=_figsize, default=None, metavar="WxH",
                        help=f"size of {what} in inches, e.g. 3.5x2.8 (default: the "
                             "kind's own; one journal column, 3.5 wide, with --style "
                             "paper)")
    parser.add_argument("--dpi", type=_dpi, default=None, metavar="N",
                        help=f"resolution of {what} in dots per inch (default: 150; 300 "
                             "with --style paper)")
    parser.add_argument("--style", type=_style, default=None, metavar="{default,paper}",
                        help="paper: a journal's look (serif fonts sized for one column, "
                             "thin lines, no title)")


def figure_options(args, drawing=True):
    """``{"figsize", "dpi", "style"}`` of the parsed arguments, for the plotting function;
    UsageError when one is given and ``drawing`` is false (no --plot to apply it to)."""
    opts = {k: getattr(args, k, None) for k in ("figsize", "dpi", "style")}
    if not drawing:
        given = [f"--{k}" for k, v in opts.items() if v is not None]
        if given:
            raise UsageError(f"{', '.join(given)}: for the image of --plot; give --plot "
                             "too")
    return opts


def image_ext_ok(path, what):
    from matplotlib.backend_bases import FigureCanvasBase

    ext = os.path.splitext(path)[1].lstrip(".").lower()
    if ext == "nc" or ext not in FigureCanvasBase.get_supported_filetypes():
        raise UsageError(f"{what} {path!r}: unknown image extension (use .png, .pdf or "
                          ".svg)")


class Interrupted(KeyboardInterrupt):
    """SIGINT or SIGTERM; ``signum`` decides the exit status 128 + signum."""

    def __init__(self, signum):
        super().__init__(signum)
        self.signum = signum


class StopWorkersOnSignal:
    """While it is entered: SIGINT and SIGTERM (what ``timeout`` and batch systems send)
    raise :class:`Interrupted` in the main thread, so that both unwind alike: temporary
    files are removed on the way out, workers are killed (finished points are already
    saved atomically, the points in flight are lost) and the command ends with one line
    and exit status 128 + signum.  The first signal restores the handlers found on
    entry, so a second one acts at once.  :func:`vibimpact.cli.main` enters it for the
    whole command; a sweep or map enters it again around its computation.
    """

    #: the signal that stopped this command, once one has (see :func:`signal_decides`)
    received = None

    def __enter__(self):
        import signal

        self._old = {}
        self._pid = os.getpid()
        try:
            for sig in (signal.SIGINT, signal.SIGTERM):
                self._old[sig] = signal.signal(sig, self._handle)
        except ValueError:  # not the main thread: leave the signals alone
            self.__exit__(None, None, None)
        return self

    def _handle(self, signum, frame):
        import signal

        if os.getpid() != self._pid:  # a worker forked before its own set-up (the pool
            # ends its workers with SIGTERM): die as by default, no Interrupted traceback
            signal.signal(signum, signal.SIG_DFL)
            os.kill(os.getpid(), signum)
            return
        self.__exit__(None, None, None)  # a second Ctrl-C acts at once
        StopWorkersOnSignal.received = signum  # for every guard of this command
        raise Interrupted(signum)  # vi.sweep stops its workers on the way out

    def __exit__(self, *exc):
        import signal

        for sig, old in self._old.items():
            signal.signal(sig, old)
        self._old = {}
        return False


def signal_decides(exc):
    """The interrupt to report instead of the error ``exc``, or None.

    A signal that unwinds a command can surface as another error: Python's ``zipfile``
    (a checkpoint entry being compressed) turns it into "Can't close the ZIP file while
    there is an open writing handle", a write cut short reports its own failure.  When a
    signal has stopped the command (:class:`StopWorkersOnSignal`), that signal decides
    the line and the exit status, not the error it caused."""
    signum = StopWorkersOnSignal.received
    if signum is None or isinstance(exc, KeyboardInterrupt):
        return None
    return Interrupted(signum)


def interrupt_status(exc):
    """128 + the signal number of an interrupt (130 for a plain KeyboardInterrupt)."""
    import signal

    return 128 + int(getattr(exc, "signum", signal.SIGINT))


def report_interrupt(exc, line):
    """Print ``line`` for the interrupt ``exc`` (once: :func:`vibimpact.cli.main` prints
    nothing more for it) and return its exit status."""
    if not getattr(exc, "reported", False):
        print(line, file=sys.stderr)
        exc.reported = True
    return interrupt_status(exc)


def checkpoint_of(out):
    """The checkpoint ``OUT.partial`` of the output ``out``, a
    :class:`vibimpact.engine.store.Checkpoint` (nothing is checked or created)."""
    from .engine.store import Checkpoint

    return Checkpoint(out + ".partial")


#: in a checkpoint: the stamp of the output written from it (see :func:`wrote_output`)
OUTPUT_STAMP = "output.json"


def _stamp(out):
    """``[size, mtime_ns, inode]`` of the file ``out`` (of a Zarr store's zarr.json)."""
    target = os.path.join(out, "zarr.json") if os.path.isdir(out) else out
    st = os.stat(target)
    return [st.st_size, st.st_mtime_ns, st.st_ino]


def wrote_output(ckpt, out):
    """Record in ``ckpt`` that ``out`` was written from it, before the checkpoint is
    removed or kept (--keep-checkpoint): a later --resume may replace that file, and
    only that file, without --overwrite (:func:`output_of`)."""
    import json

    try:
        (ckpt.path / OUTPUT_STAMP).write_text(json.dumps(_stamp(out)))
    except OSError:  # no stamp: a resume then asks for --overwrite
        pass


def output_of(ckpt, out):
    """True when the existing ``out`` is the file written from the checkpoint ``ckpt``
    (:func:`wrote_output`), which --resume may replace; an unrelated file needs
    --overwrite."""
    import json

    try:
        return json.loads((ckpt.path / OUTPUT_STAMP).read_text()) == _stamp(out)
    except (OSError, ValueError):
        return False


def remove_stale_temporaries(out):
    """Remove what an earlier run killed while writing ``out`` left beside it: the
    temporary files and stores of :func:`vibimpact.io.write_netcdf` and
    :func:`vibimpact.maps.write_map` (``.OUT.*.tmp``, ``.OUT.*.old``) and the temporary
    entries of its checkpoint (``OUT.partial/.tmp-*``).  Returns their number."""
    import glob

    directory, name = os.path.split(os.path.abspath(out))
    pattern = glob.escape(os.path.join(directory, "." + name + "."))
    stale = glob.glob(pattern + "*.tmp") + glob.glob(pattern + "*.old") + \
        glob.glob(os.path.join(glob.escape(out + ".partial"), ".tmp-*"))
    remove_paths(stale)
    return len(stale)


def remove_paths(paths):
    """Remove each file, link or directory tree of ``paths`` that exists; errors are
    ignored (what cannot be removed stays)."""
    import shutil

    for path in paths:
        if os.path.isdir(path) and not os.path.islink(path):
            shutil.rmtree(path, ignore_errors=True)
        elif os.path.lexists(path):
            try:
                os.unlink(path)
            except OSError:
                pass


def check_checkpoint(ckpt, resume):
    """UsageError unless a run may go ahead with ``ckpt``: it exists and is not a
    directory, or exists without ``resume``.  With ``resume``, the temporary files an
    earlier run killed while writing left are removed (:func:`remove_stale_temporaries`
    of the output ``ckpt`` belongs to)."""
    try:
        ckpt.check_reusable(resume)
    except ValueError as exc:
        raise UsageError(error_text(exc)) from None
    if ckpt.exists():  # a resume writes into it: try that before computing
        import tempfile

        try:
            fd, probe = tempfile.mkstemp(prefix=".tmp-probe-", dir=ckpt.path)
        except OSError as exc:
            raise UsageError(f"checkpoint {os.fspath(ckpt.path)!r} is not writable "
                             f"({exc.strerror or exc})") from None
        os.close(fd)
        os.unlink(probe)
    path = os.fspath(ckpt.path)
    if resume and path.endswith(".partial"):
        remove_stale_temporaries(path[:-len(".partial")])


def _saved_line(ckpt, unit, resumable):
    """What a stopped run kept: ``: 3 points saved in OUT.partial; rerun with --resume``
    (``resumable``, a checkpoint with something in it), `` before any point was saved``
    or ``; nothing written`` (no checkpoint, or a command without --resume)."""
    if ckpt is None or not resumable:
        return "; nothing written"
    if not ckpt.exists():
        return f" before any {unit[:-1]} was saved"
    points, rows = ckpt.saved()
    n = points if unit == "points" else rows
    return (f": {count(n, unit[:-1])} saved in {os.fspath(ckpt.path)}; rerun with "
            "--resume")


def run_checkpointed(ckpt, unit, compute, *, resumable=True):
    """``(compute(), None)``, or ``(None, exit status)`` after an interrupt or a lost
    worker.

    SIGINT and SIGTERM interrupt ``compute`` (:class:`StopWorkersOnSignal`; exit status
    128 + signum); a worker process that dies (:class:`vibimpact.engine.executors.
    WorkerLost`) ends it with exit status 2.  Either way one line says how many ``unit``
    ("points" or "rows") the checkpoint ``ckpt`` holds and how to resume, unless
    ``resumable`` is false or ``ckpt`` is None (a command without --resume: "nothing
    written").  A ValueError (a checkpoint of another request, a lost scheduler) is a
    UsageError.
    """
    from .engine.executors import WorkerLost

    try:
        with StopWorkersOnSignal():
            return compute(), None
    except KeyboardInterrupt as exc:
        return None, report_interrupt(
            exc, "vibimpact: interrupted" + _saved_line(ckpt, unit, resumable))
    except WorkerLost as exc:
        # one_line: Dask's KilledWorker spans lines
        print(f"vibimpact: error: {one_line(exc)}{_saved_line(ckpt, unit, resumable)}",
              file=sys.stderr)
        return None, 2
    except ValueError as exc:
        raise UsageError(error_text(exc)) from None
    except OSError as exc:  # a checkpoint that cannot be written: disk full, read-only
        raise UsageError(f"{error_text(exc)}{_saved_line(ckpt, unit, resumable)}") \
            from None


def finish_checkpointed(ds, out, ckpt, write, *, resuming, keep, overwrite, unit,
                        resumable=True):
    """Write the result of a checkpointed run and tidy its checkpoint.

    Warns about the damaged checkpoint entries the resume recomputed, writes ``ds`` to
    ``out`` with ``write(ds, out, overwrite=...)`` (a failure is a usage error that keeps
    the checkpoint), removes the checkpoint unless ``keep``, and says what a resumed run
    loaded.  ``unit`` names what the run counts ("points", "rows").  SIGINT or SIGTERM
    while writing removes the temporary file, keeps the checkpoint and says so (with
    --resume advice if ``resumable``), then propagates.  Returns the number of points
    loaded from the checkpoint and not recomputed.
    """
    from .engine.store import set_aside_line

    last = ckpt.last_resume() if resuming else {"points": 0, "streams": 0, "damaged": []}
    where = os.fspath(ckpt.path)
    warning = set_aside_line(last, where, unit)
    if warning:
        print(warning, file=sys.stderr)
    try:
        try:
            write(ds, out, overwrite=overwrite or (resuming and output_of(ckpt, out)))
        except (ValueError, OSError, RuntimeError) as exc:
            raise UsageError(f"{error_text(exc)} (the computed {unit} stay in {where}; "
                             "fix the problem and rerun with --resume)") from None
        wrote_output(ckpt, out)
        if not keep:
            ckpt.remove()
    except KeyboardInterrupt as exc:  # the write's temporary file is gone already
        report_interrupt(exc, "vibimpact: interrupted" + _saved_line(ckpt, unit,
                                                                      resumable))
        raise
    if resuming:
        loaded = last["points"] if unit == "points" else last["streams"]
        print(f"vibimpact: resumed from {where}: {count(loaded, unit[:-1])} loaded, not "
              "recomputed", file=sys.stderr)
    return last["points"]
