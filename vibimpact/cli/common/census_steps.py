"""The steps the census commands (``attractors``, ``basins``) share: check the outputs
and the checkpoint, run checkpointed, write, and draw.

Like :mod:`vibimpact.cli`, only the standard library is imported at module level.
"""
import os
import shlex
import sys
import time

from .checkpoints import check_checkpoint, finish_checkpointed, run_checkpointed
from .errors import error_text, UsageError
from .figures import figure_options, image_ext_ok
from .files import check_output
from .inputs import check_distinct


def check_outputs(args, out, ckpt, inputs=()):
    """Refuse existing outputs (unless --overwrite, or a resume that wrote ``out``), a
    checkpoint a resume cannot use and two of the command's files that are one (``-o``,
    ``--plot``, the checkpoint and the ``(option, path)`` of the files it reads,
    ``inputs``), before any work; ``(resuming, figure options)``."""
    from ...engine.leftovers import output_of

    resuming = args.resume and ckpt.exists()
    check_output(out, args.overwrite or (resuming and output_of(ckpt, out)),
                 "output file")
    fig_kw = figure_options(args, drawing=args.plot is not None)
    if args.plot is not None:
        image_ext_ok(args.plot, "--plot")
        check_output(args.plot, args.overwrite, "plot file")
    check_distinct(("-o", out), ("--plot", args.plot), ("the checkpoint", ckpt.path),
                   inputs=inputs)
    check_checkpoint(ckpt, args.resume)
    return resuming, fig_kw


def run_and_write(args, out, ckpt, resuming, name, compute, write):
    """``compute(execution)`` with the command's workers, checkpoint and progress bar,
    then ``write(ds, out, overwrite=...)``; ``(ds, None, seconds)``, or ``(None, exit
    status, seconds)`` after an interrupt or a lost worker (checkpoint kept)."""
    from ...engine.execution import Execution

    t0 = time.perf_counter()
    run = Execution(workers=args.workers, checkpoint=ckpt.path, resume=args.resume,
                    progress=not args.no_progress and name)
    ds, status = run_checkpointed(ckpt, "points", lambda: compute(run))
    elapsed = time.perf_counter() - t0
    if ds is None:
        return None, status, elapsed
    ds.attrs.update(command=shlex.join(["vibimpact"] + list(args.argv)),
                    preset=args.preset, wall_time_s=round(elapsed, 3))
    finish_checkpointed(ds, out, ckpt, write, resuming=resuming,
                        keep=args.keep_checkpoint, overwrite=args.overwrite,
                        unit="points")
    from ...census.dataset import failed_note

    note = failed_note(ds)  # starts whose integration failed: written, said, exit 0
    if note is not None:
        print(f"vibimpact: warning: {note}", file=sys.stderr)
    return ds, None, elapsed


def draw(args, ds, out, plot, fig_kw):
    """``plot(ds, path=--plot)`` when asked; a failure is one line (``out`` stays)."""
    if args.plot is None:
        return
    try:
        plot(ds, path=args.plot, **fig_kw)
    except (ValueError, OSError) as exc:
        raise UsageError(f"--plot: {error_text(exc)} ({os.fspath(out)!r} is "
                         "written)") from None
    print(f"wrote {args.plot}")


__all__ = ["check_outputs", "run_and_write", "draw"]
