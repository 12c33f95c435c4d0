"""What a run leaves beside its output and in its checkpoint: the temporary files of a
run killed while writing, and the stamp of the output written from a checkpoint.
Standard library only."""
from __future__ import annotations

import os

#: in a checkpoint: the stamp of the output written from it (see :func:`wrote_output`)
OUTPUT_STAMP = "output.json"


def stamp(out):
    """``[size, mtime_ns, inode]`` of the file ``out`` (of a Zarr store's zarr.json)."""
    target = os.path.join(out, "zarr.json") if os.path.isdir(out) else out
    st = os.stat(target)
    return [st.st_size, st.st_mtime_ns, st.st_ino]


def wrote_output(ckpt, out):
    """Record in ``ckpt`` that ``out`` was written from it, before the checkpoint is
    removed or kept (--keep-checkpoint): a later resume may replace that file, and
    only that file, without overwriting (:func:`output_of`).  The stamp is written
    atomically and never through a symbolic link (nor into a FIFO)."""
    import json

    try:
        ckpt.write_file(OUTPUT_STAMP, json.dumps(stamp(out)).encode())
    except (OSError, ValueError):  # no stamp: a resume then asks for --overwrite
        pass


def output_of(ckpt, out):
    """True when the existing ``out`` is the file written from the checkpoint ``ckpt``
    (:func:`wrote_output`), which a resume may replace; an unrelated file needs
    overwriting.  The stamp is read only from a regular file, bounded."""
    try:
        return ckpt.read_json(OUTPUT_STAMP) == stamp(out)
    except (OSError, ValueError):
        return False


def remove_checkpoint_temporaries(checkpoint):
    """Remove the temporary entries (``.tmp-*``) a run killed while saving left in the
    checkpoint directory ``checkpoint`` (nothing where it is a symbolic link).  Returns
    their number."""
    from .ckdir import remove_temporaries

    return remove_temporaries(checkpoint)


def remove_stale_temporaries(out):
    """Remove what an earlier run killed while writing ``out`` left beside it: the
    temporary files and stores of :func:`vibimpact.io.write_netcdf` and
    :func:`vibimpact.maps.write_map` (``.OUT.*.tmp``, ``.OUT.*.old``) and the temporary
    entries of its checkpoint (``OUT.partial/.tmp-*``).  A temporary whose name carries
    the id of a process still running (:mod:`vibimpact.base._writing`) is left alone.
    Returns their number."""
    import glob

    from ..base._writing import running, temporary_pid

    directory, name = os.path.split(os.path.abspath(out))
    pattern = glob.escape(os.path.join(directory, "." + name + "."))
    # a checkpoint being made (.OUT.partial.PID-*.tmp) is its maker's while it runs
    stale = [p for p in glob.glob(pattern + "*.tmp") + glob.glob(pattern + "*.old")
             if (pid := temporary_pid(out, p) or temporary_pid(out + ".partial", p))
             is None or not running(pid)]
    remove_paths(stale)
    return len(stale) + remove_checkpoint_temporaries(out + ".partial")


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
