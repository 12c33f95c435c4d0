"""The ``--smoke DIR`` option of every analyses script (``tests/test_analyses_smoke.py``).

A smoke run is the script's whole path on a tiny problem (a few points, short runs, one
repeat) whose outputs -- reports, figures, data -- are written under ``DIR``, never over
``reports/`` or the README; its numbers mean nothing.  It exists so that a script whose
code has rotted (a renamed function, a moved module, a profile entry that matches
nothing) fails in the test suite instead of silently writing a stale report.
"""
from __future__ import annotations

import argparse
from pathlib import Path

HELP = ("tiny run (a few points, short runs) writing every output under DIR instead of "
        "reports/; its numbers mean nothing (tests/test_analyses_smoke.py)")


def add_option(ap):
    """Add ``--smoke DIR`` (a :class:`pathlib.Path`, default None) to the parser ``ap``."""
    ap.add_argument("--smoke", metavar="DIR", type=Path, default=None, help=HELP)
    return ap


def parser(doc):
    """An argument parser described by the first line of ``doc``, with ``--smoke``."""
    return add_option(argparse.ArgumentParser(description=doc.strip().splitlines()[0]))


def moved(path, smoke_dir):
    """``path`` itself, or the file of the same name under ``smoke_dir`` (created) in a
    smoke run."""
    if smoke_dir is None:
        return path
    Path(smoke_dir).mkdir(parents=True, exist_ok=True)
    return Path(smoke_dir) / Path(path).name


def shrink(namespace, smoke_dir, **tiny):
    """In a smoke run, replace the names of ``tiny`` in ``namespace`` (a script's
    ``globals()``) by their tiny values; outside one, do nothing."""
    if smoke_dir is None:
        return
    unknown = set(tiny) - set(namespace)
    if unknown:  # a renamed setting must not leave the smoke run at full size
        raise NameError(f"smoke run sets names the script does not have: {sorted(unknown)}")
    namespace.update(tiny)
