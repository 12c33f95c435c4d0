"""A checkpointed command in the command line's words: its checkpoint ``OUT.partial``
checked before computing, the run with its interrupt and lost-worker lines, the result
written and the checkpoint tidied.  The lifecycle itself (signals, checkpoint, leftovers)
is the engine's (:mod:`vibimpact.engine.signals`, :mod:`vibimpact.engine.store`,
:mod:`vibimpact.engine.leftovers`)."""
import os
import sys

from ...base._text import count, one_line
from .errors import UsageError, error_text, hold_signals, report_interrupt
from ...engine.leftovers import output_of, remove_stale_temporaries, wrote_output
from ...engine.signals import StopWorkersOnSignal, signal_decides


def checkpoint_of(out):
    """The checkpoint ``OUT.partial`` of the output ``out``, a
    :class:`vibimpact.engine.store.Checkpoint` (nothing is checked or created)."""
    from ...engine.store import Checkpoint

    return Checkpoint(out + ".partial")


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
    UsageError.  An error that a signal caused (a library that turned the interrupt into
    its own exception, a worker the signal killed; :func:`signal_decides`) is that
    signal, said with the same saved points, not left to :func:`vibimpact.cli.main`'s
    bare interrupted line.
    """
    from ...engine.executors import WorkerLost

    try:
        try:
            with StopWorkersOnSignal():
                return compute(), None
        except Exception as exc:
            interrupt = signal_decides(exc)
            if interrupt is None:
                raise
            raise interrupt from exc
    except KeyboardInterrupt as exc:
        return None, report_interrupt(
            exc, "vibimpact: interrupted" + _saved_line(ckpt, unit, resumable))
    except WorkerLost as exc:
        hold_signals()  # the last line: a signal now adds none
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
    from ...engine.store import set_aside_line

    last = ckpt.last_resume() if resuming else {"points": 0, "streams": 0, "damaged": []}
    where = os.fspath(ckpt.path)
    warning = set_aside_line(last, where, unit)
    if warning:
        print(warning, file=sys.stderr)
    try:
        try:
            try:
                write(ds, out, overwrite=overwrite or (resuming and output_of(ckpt, out)))
            except (ValueError, OSError, RuntimeError) as exc:
                if signal_decides(exc) is not None:
                    raise
                raise UsageError(f"{error_text(exc)} (the computed {unit} stay in "
                                 f"{where}; fix the problem and rerun with --resume)") \
                    from None
            wrote_output(ckpt, out)
            if not keep:
                ckpt.remove()
        except Exception as exc:  # an error the signal caused is the signal
            interrupt = signal_decides(exc)
            if interrupt is None:
                raise
            raise interrupt from exc
    except KeyboardInterrupt as exc:  # the write's temporary file is gone already
        report_interrupt(exc, "vibimpact: interrupted" + _saved_line(ckpt, unit,
                                                                      resumable))
        raise
    if resuming:
        loaded = last["points"] if unit == "points" else last["streams"]
        print(f"vibimpact: resumed from {where}: {count(loaded, unit[:-1])} loaded, not "
              "recomputed", file=sys.stderr)
    return last["points"]
