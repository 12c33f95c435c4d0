"""``vibimpact rerun``: redo the command recorded in an output file and compare the data.

Every file written by ``simulate``, ``classify``, ``bifurcation`` (its ``.nc``),
``continue`` and ``map`` (a Zarr store or a NetCDF file) stores the command line in the
global attribute ``command``.  ``rerun`` parses it with today's
parser, runs it in this process with the output redirected to a new file, and compares
every data variable and coordinate of the two files bit for bit (NaN equal to NaN, string
variables as text), and their attributes (:func:`vibimpact.io.attribute_differences`):
every global attribute but the time stamps, versions, platform and command line
(:data:`vibimpact.base.provenance.NOT_COMPARED`), and every attribute of every variable and
coordinate, so that a file whose attributes contradict its data or its command (units,
flag meanings, parameters, counters changed after the run) is reported.  Only the standard library
is imported at module level.
"""
import contextlib
import io as _stdio
import os
import shlex
import sys

from .common.errors import UsageError
from .common.files import check_output, is_store, read_input
from ..engine.leftovers import remove_paths
from ..base._text import count

RERUNNABLE = ("simulate", "classify", "bifurcation", "map", "continue")

_RERUN_EPILOG = """\
examples:
  vibimpact rerun fig8.nc                 # recompute into a temporary file, compare
  vibimpact rerun run.nc -o again.nc      # keep the recomputed file
  vibimpact rerun map.zarr                # a map (Zarr store or .nc) as well

The recorded command runs again exactly (same parameters, grid, solver settings, blocks),
its output redirected: simulate's --plot image is not redrawn (its dense samples are
kept), classify writes no interval table, bifurcation draws no image, map draws no
--plot image and runs on local processes even when it was run on a --scheduler (the
results do not depend on where they were computed).  A 'simulate --from SWEEP.nc' run
starts again from the state and parameters its file records (state0, start_*), without
reading the sweep's file: that may have moved, changed or gone since.

The attributes are compared too: every global attribute but the time stamps, versions,
platform and command line (date_created, history, wall_time_s, source, *_version,
vibimpact_git_*, platform, cpu_model, command), and every attribute of every variable
and coordinate (units, flag_meanings, ...): a file whose attributes were changed after
the run, or that otherwise contradicts its recorded command, is reported as different,
naming them (VARIABLE:ATTRIBUTE for a variable's).

Before it starts, rerun says on stderr what it runs and how big it is ('vibimpact:
rerunning 'vibimpact classify ...': 301 sweep points, 2 worker processes, about N s
of computing on one core').  A file may come from anyone: a recorded command larger
than {limits} is refused (exit status 2, nothing computed) unless --yes is given.

exit status: 0 identical ('identical: N variables and M attributes of the run'), 1
different (the differing variables and attributes are listed), 2 bad input (missing,
foreign or damaged file, no recorded command, a recorded command over the limits above
without --yes).
"""


def _recorded_args(path, command, build_parser):
    """Parse the recorded command line with today's parser (``build_parser()``, handed
    down by :mod:`vibimpact.cli` so that no command imports the registration table); the
    argparse Namespace."""
    if not isinstance(command, str) or not command.strip():
        raise UsageError(f"{path!r} has no 'command' attribute: not written by vibimpact "
                          f"{', '.join(RERUNNABLE)}")
    try:
        argv = shlex.split(command)
    except ValueError as exc:
        raise UsageError(f"{path!r}: cannot parse the recorded command {command!r}: "
                          f"{exc}") from None
    # the command is the first word after the options of the main parser (-v, -vv)
    name = next((a for a in argv[1:] if not a.startswith("-")), None)
    if not argv or os.path.basename(argv[0]) != "vibimpact" or name not in RERUNNABLE:
        raise UsageError(f"{path!r}: the recorded command {command!r} is not a vibimpact "
                          f"{', '.join(RERUNNABLE)} command")
    err = _stdio.StringIO()
    try:
        with contextlib.redirect_stderr(err), contextlib.redirect_stdout(_stdio.StringIO()):
            args = build_parser().parse_args(argv[1:])
    except SystemExit:
        why = " ".join(err.getvalue().split()) or "not accepted"
        raise UsageError(f"{path!r}: the recorded command {command!r} is not valid for "
                          f"this version ({why})") from None
    args.argv = argv[1:]
    return args


def _redirect(args, new, overwrite):
    """Point the parsed command at ``new`` and switch off side outputs."""
    args.overwrite = overwrite
    if args.command == "simulate":
        if args.plot is not None and args.dense is None:
            args.dense = 64  # what --plot implied for the recorded file
        args.plot = None
        args.output = new
    elif args.command == "continue":
        args.output = new
    elif args.command in ("classify", "map"):
        args.output = new
        args.resume = False
        args.keep_checkpoint = False
        args.no_progress = True
        if args.command == "map":
            args.plot = None
            args.scheduler = None
    else:  # bifurcation: the data file only, no image
        args.data_only = new
        args.no_progress = True
    return args


def _remove_dead_reruns(path):
    """Remove the hidden output, checkpoint and temporary files (``.FILE.rerun-PID-*``,
    ``..FILE.rerun-PID-*.tmp``) that a rerun of ``path`` killed with SIGKILL left, when
    process PID no longer runs; the files of a rerun still running are left alone."""
    import re

    directory, name = os.path.split(os.path.abspath(path))
    ours = re.compile(r"\.\.?" + re.escape(name) + r"\.rerun-(\d+)-")
    try:
        names = os.listdir(directory)
    except OSError:
        return
    remove_paths(os.path.join(directory, base) for base in names
                 if (m := ours.match(base)) and not _running(int(m.group(1))))


def _running(pid):
    """Whether process ``pid`` exists."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:  # exists, another user's
        return True
    return True


def _announce(path, command, parsed, yes):
    """Say on stderr what the rerun will run and how big it is; UsageError, before any
    work, when it is over a limit of :mod:`vibimpact.cli.common.rerun_size` and ``yes`` is
    false (a file from an unknown source must not start a long job on its own)."""
    from .common.rerun_size import size_of

    try:
        size = size_of(parsed)
    except UsageError as exc:  # a grid the command refuses, as it refuses it
        raise UsageError(f"rerunning {command!r}: {exc}") from None
    if size.over and not yes:
        cost = f" ({size.cost()})" if size.cost() else ""
        raise UsageError(f"{path!r} records {command!r}: {'; '.join(size.over)}{cost}; "
                          f"check the command and pass --yes to run it")
    print(f"vibimpact: rerunning {command!r}: {size.text()}", file=sys.stderr)


def _cmd_rerun(args):
    import tempfile

    from .. import __version__, io

    path = os.fspath(args.file)
    keep = args.output is not None
    if keep:
        new = os.fspath(args.output)
        from .common.inputs import same_file

        if same_file(new, path):
            raise UsageError(f"-o {new!r} is the file being rerun, {path!r}; give another")
        if not is_store(new):  # an existing store: the map command checks --overwrite
            check_output(new, args.overwrite, "output file")
    old = read_input(path, "file", stores=True)
    parsed = _recorded_args(path, old.attrs.get("command"), args.build_parser)
    if getattr(parsed, "from_sweep", None) is not None:  # simulate --from: start recorded
        from .common.start import recorded_start

        parsed.recorded_start = recorded_start(old, path)
    _announce(path, old.attrs["command"], parsed, args.yes)  # before any work or file
    if not keep:
        directory = os.path.dirname(os.path.abspath(path))
        _remove_dead_reruns(path)
        try:
            fd, new = tempfile.mkstemp(prefix=f".{os.path.basename(path)}.rerun-"
                                              f"{os.getpid()}-",
                                       suffix=".zarr" if is_store(path) else ".nc",
                                       dir=directory)
        except OSError as exc:
            raise UsageError(f"cannot create a temporary file next to {path!r} "
                              f"({exc.strerror or exc}); give -o NEW.nc") from None
        os.close(fd)
        os.unlink(new)
    _redirect(parsed, new, args.overwrite if keep else False)
    parsed.rerun_of = path  # no --resume advice: rerun has none
    # what the run may leave when stopped: its checkpoint (one that was there before is
    # refused by the command and kept) and, for the comparison only, its output
    leftovers = [] if keep else [new]
    if not os.path.lexists(new + ".partial"):
        leftovers.append(new + ".partial")

    recorded = old.attrs.get("vibimpact_version")
    if recorded and str(recorded) != __version__:
        print(f"vibimpact: warning: {path!r} was written by vibimpact {recorded}, this is "
              f"{__version__}", file=sys.stderr)
    try:
        with contextlib.redirect_stdout(_stdio.StringIO()):
            try:
                status = parsed.func(parsed)
            except UsageError as exc:
                raise UsageError(f"rerunning {old.attrs['command']!r}: {exc}") from None
        if status != 0:
            return status
        fresh = read_input(new, "rerun output", stores=True)
    finally:
        remove_paths(leftovers)

    diffs, total = io.differences(old, fresh, attributes=False)
    attr_diffs, attr_total = io.attribute_differences(old, fresh, files=True)
    if not diffs and not attr_diffs:
        print(f"identical: {count(total, 'variable')} and "
              f"{count(attr_total, 'attribute')} of the run"
              + (f"; wrote {new}" if keep else ""))
        return 0
    parts = [f"{len(diffs)} of {total} variables" if diffs else "",
             f"{len(attr_diffs)} of {count(attr_total, 'attribute')} of the run"
             if attr_diffs else ""]
    print(f"different: {' and '.join(p for p in parts if p)} differ"
          + (f"; wrote {new}" if keep else ""))
    for name, why in diffs:
        print(f"  {name}: {why}")
    for name, why in attr_diffs:
        print(f"  attribute {name}: {why}")
    return 1


def add_parser(sub, fmt):
    """Add ``rerun`` to the subparsers ``sub`` (the whole command line's parser, to read
    the recorded command with, comes as ``args.build_parser``: set by
    :func:`vibimpact.cli.build_parser` for every command)."""
    import textwrap

    from .common.rerun_size import limits_text

    head, sep, tail = _RERUN_EPILOG.partition("Before it starts")
    first, blank, rest = (sep + tail).partition("\n\n")
    epilog = head + textwrap.fill(" ".join(first.format(limits=limits_text()).split()),
                                  88) + "\n" + blank + rest
    r = sub.add_parser("rerun", help="redo the command recorded in an output file and "
                       "compare bit for bit", formatter_class=fmt, epilog=epilog,
                       description="Run the command recorded in a simulate, classify, "
                                   "bifurcation, continue or map output\nagain and "
                                   "compare every data variable and coordinate with it, "
                                   "bit for bit.")
    r.add_argument("file", metavar="OUT.nc|OUT.zarr",
                   help="NetCDF file or map Zarr store written by vibimpact")
    r.add_argument("-o", "--output", metavar="NEW.nc", default=None,
                   help="keep the recomputed file here (default: a temporary file next "
                        "to OUT.nc, removed afterwards)")
    r.add_argument("--overwrite", action="store_true", help="replace an existing NEW.nc")
    r.add_argument("--yes", action="store_true",
                   help="run the recorded command even when it is larger than a rerun "
                        "starts without asking (see below)")
    r.set_defaults(func=_cmd_rerun)


__all__ = ["add_parser", "RERUNNABLE"]
