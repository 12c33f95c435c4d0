"""The command line's standard output and error as they may be: full (``>/dev/full``),
closed (``>&-``) or a pipe whose reader has gone (``| head -1``); standard library only.

While a command runs, ``sys.stdout`` and ``sys.stderr`` are :class:`Guarded`: a write or
flush that fails is remembered and the stream is written no more, so the command runs to
its end and keeps its files (a failing ``print`` of the result table no longer ends the
command with a traceback after the file was written, or, worse, in the middle of its
work).  At the end :meth:`Streams.status` decides the exit status:

* the command's own non-zero status (bad input, an interrupt, a difference) is kept;
* a status 0 whose printed output (on stdout or stderr) was lost becomes
  :data:`LOST_OUTPUT` (74, ``EX_IOERR`` of ``sysexits.h``), with one line on stderr when
  only stdout failed;
* a status 0 whose output went to a pipe that was closed becomes :data:`BROKEN_PIPE`
  (141 = 128 + SIGPIPE, what a shell reports for a program ended by SIGPIPE), without a
  line: the reader stopped reading on purpose (``vibimpact presets | head -1``).

In the process's own command line a failed stream's file descriptor is then pointed at
the null device, so that the interpreter's last flush at exit finds nothing to fail on
("Exception ignored ... BrokenPipeError", exit status 120).
"""
import errno
import os
import sys
from typing import TextIO, cast

#: exit status of a command whose printed output was lost (EX_IOERR of sysexits.h)
LOST_OUTPUT = 74
#: exit status of a command whose printed output went to a closed pipe (128 + SIGPIPE)
BROKEN_PIPE = 141

#: the errors that mean a stream's reader has gone
_PIPE_GONE = (errno.EPIPE, errno.ECONNRESET)


class Guarded:
    """A text stream that remembers its first failure instead of raising it.

    Parameters
    ----------
    stream : text stream or None
        The stream written to; None for a stream the process was started without (its
        descriptor closed: Python leaves ``sys.stdout`` None then), whose first write
        fails with ``EBADF``.
    name : str
        ``"stdout"`` or ``"stderr"``, for the message.
    """

    def __init__(self, stream, name):
        self._stream = stream
        self.name = name
        #: the first OSError of a write or flush (None while every write succeeded)
        self.error: OSError | None = None

    def _fail(self, exc):
        if not isinstance(exc, OSError):  # ValueError: a closed file
            exc = OSError(errno.EBADF, "closed")
        self.error = exc

    def write(self, text):
        """Write ``text``; after a failure, nothing (the length is returned all the
        same, as the caller expects)."""
        if self.error is None:
            if self._stream is None:
                if text:
                    self._fail(OSError(errno.EBADF, "closed"))
            else:
                try:
                    return self._stream.write(text)
                except (OSError, ValueError) as exc:
                    self._fail(exc)
        return len(text)

    def writelines(self, lines):
        for line in lines:
            self.write(line)

    def flush(self):
        if self.error is None and self._stream is not None:
            try:
                self._stream.flush()
            except (OSError, ValueError) as exc:
                self._fail(exc)

    def isatty(self):
        if self.error is not None or self._stream is None:
            return False
        try:
            return self._stream.isatty()
        except (OSError, ValueError):
            return False

    def fileno(self):
        if self._stream is None:
            import io

            raise io.UnsupportedOperation(f"{self.name} is closed")
        return self._stream.fileno()

    @property
    def closed(self):
        return self._stream is None or getattr(self._stream, "closed", False)

    def __getattr__(self, name):  # encoding, errors, buffer, ...
        return getattr(self._stream, name)

    @property
    def broken_pipe(self):
        """Whether the failure was a pipe whose reader has gone."""
        return isinstance(self.error, OSError) and self.error.errno in _PIPE_GONE


class Streams:
    """``sys.stdout`` and ``sys.stderr`` guarded for one command (a context manager).

    Parameters
    ----------
    program : bool
        The process's own command line: after a failure the stream's file descriptor is
        pointed at the null device (never done for an in-process call, whose streams
        belong to the caller).
    """

    def __init__(self, program):
        self.program = program
        self.saved: tuple[TextIO, TextIO] | None = None
        self.out: Guarded | None = None
        self.err: Guarded | None = None

    def __enter__(self):
        self.saved = (sys.stdout, sys.stderr)
        self.out = Guarded(sys.stdout, "stdout")
        self.err = Guarded(sys.stderr, "stderr")
        # a Guarded stands in for the text stream it wraps (write, flush, fileno, ...)
        sys.stdout, sys.stderr = cast(TextIO, self.out), cast(TextIO, self.err)
        return self

    def __exit__(self, *exc_info):
        self.flush()
        assert self.saved is not None and self.out is not None and self.err is not None
        sys.stdout, sys.stderr = self.saved
        if self.program:
            for guarded, fd in ((self.out, 1), (self.err, 2)):
                if guarded.error is not None:
                    _discard(guarded._stream, fd)
        return False

    def flush(self):
        """Flush both streams (a failure is remembered, not raised)."""
        assert self.out is not None and self.err is not None  # inside the with block
        self.out.flush()
        self.err.flush()

    def status(self, status):
        """The exit status of a command that ended with ``status`` (see the module):
        ``status`` itself, or :data:`LOST_OUTPUT` / :data:`BROKEN_PIPE` for a command
        that succeeded but whose printed output was lost.  Says so in one line on
        stderr when stdout alone failed (not for a closed pipe)."""
        self.flush()
        assert self.out is not None and self.err is not None  # inside the with block
        if status not in (0, None):
            return status
        failed = [g for g in (self.out, self.err) if g.error is not None]
        if not failed:
            return status
        if all(g.broken_pipe for g in failed):
            return BROKEN_PIPE
        if self.err.error is None:
            assert self.out.error is not None  # stdout is the one that failed
            why = self.out.error.strerror or str(self.out.error)
            self.err.write(f"vibimpact: error: cannot write to stdout ({why}): the "
                           f"printed results are lost (the command ran to its end and "
                           f"kept its files)\n")
            self.err.flush()
        return LOST_OUTPUT


def _discard(stream, fd):
    """Point descriptor ``fd`` (of the failed ``stream``) at the null device and drop
    what the stream still holds, so that the interpreter's flush at exit succeeds."""
    try:
        null = os.open(os.devnull, os.O_WRONLY)
    except OSError:
        return
    try:
        os.dup2(null, fd)
    except OSError:
        pass
    finally:
        os.close(null)
    if stream is not None:
        try:
            stream.flush()  # what it buffered goes to the null device now
        except (OSError, ValueError):
            pass


def fill_closed_descriptors():
    """Open the null device on standard input, output and error where the process was
    started with them closed (``>&-``), so that no file the command opens takes
    descriptor 1 or 2 (a stray write to "stdout" would land in it, a worker would
    inherit it as its output).  ``sys.stdout`` stays None: the command's first write to
    it is then a lost output (:class:`Guarded`)."""
    while True:
        try:
            fd = os.open(os.devnull, os.O_RDWR)
        except OSError:
            return
        if fd > 2:
            os.close(fd)
            return


__all__ = ["BROKEN_PIPE", "Guarded", "LOST_OUTPUT", "Streams", "fill_closed_descriptors"]
