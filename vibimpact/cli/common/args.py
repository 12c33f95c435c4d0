"""Argument parsing shared by the commands: the parser, verbosity, number options,
``--set``, ``--analyses`` (standard library only at import)."""
import argparse
import math
import sys

from ...base._text import parse_integer, parse_real
from .errors import UsageError, error_text


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

    def parse_known_args(self, args=None, namespace=None):
        """argparse's, then every option left at a :class:`ModelDefault` given the value
        the model of the parsed ``--preset`` declares for it."""
        namespace, extras = super().parse_known_args(args, namespace)
        ModelDefault.resolve_all(namespace)
        return namespace, extras

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


#: the most processes a ``--workers`` option takes (the API's limit too)
# MAX_WORKERS: imported from here by the commands that take --workers
from ...base._limits import ETA_RANGE, MAX_WORKERS  # noqa: E402, F401
#: the largest integer any option takes (a 64-bit signed integer: counts, seeds)
MAX_INT = 2**63 - 1


#: ``--preset``'s default: the preset the first registered model declares its default
#: (:data:`vibimpact.models.presets.DEFAULT`), looked up by :func:`preset_name` when the
#: arguments are parsed (``--help`` loads no model)
DEFAULT_PRESET = "<the default preset>"
#: how the help of ``--preset`` says what its default is
DEFAULT_PRESET_HELP = "the one 'vibimpact presets' marks as the default"


class ModelDefault:
    """An option's default that the model declares
    (:func:`vibimpact.models.presets.command_default`): the model of the command's
    ``--preset`` (parsed first; the preset a ``census_preset`` default names), looked up
    once the arguments are parsed, so that ``--help`` loads no model.

    Parameters
    ----------
    key : str
        One of :data:`vibimpact.models.presets.DEFAULT_KEYS`.
    text : str
        How ``--help`` says what the default is.
    """

    def __init__(self, key, text):
        self.key, self.text = key, text

    def __str__(self):
        return self.text

    @staticmethod
    def resolve_all(namespace):
        """Replace every :class:`ModelDefault` in ``namespace``, the preset first."""
        from ...models.presets import command_default

        found = sorted((v.key != "census_preset", k) for k, v in vars(namespace).items()
                       if isinstance(v, ModelDefault))
        for _, name in found:
            key = getattr(namespace, name).key
            setattr(namespace, name, command_default(key, getattr(namespace, "preset",
                                                                  None)))


#: ``--eta``'s default in a sweep: the frequencies the preset's model declares
SWEEP_FREQUENCIES = ModelDefault(
    "frequencies", "the range the preset's model declares; 'vibimpact presets' lists it")
#: ``--eta``'s default in a two-parameter map: the model's coarser grid
MAP_FREQUENCIES = ModelDefault(
    "map_frequencies", "the grid the preset's model declares for a map; 'vibimpact "
                       "presets' lists it")
#: ``--preset`` and ``--eta`` of a census or a basin image: where the model says its
#: attractors coexist
CENSUS_PRESET = ModelDefault(
    "census_preset", "the census preset the first model declares; 'vibimpact presets' "
                     "lists it")
CENSUS_FREQUENCY = ModelDefault(
    "census_frequency", "the frequency the preset's model declares for a census, else "
                        "the preset's own; 'vibimpact presets' lists it")


def swept(args):
    """The ``--eta`` text of a sweep; UsageError when neither given nor declared by the
    model of ``--preset``."""
    if args.eta is None:
        raise UsageError(f"--eta: the model of preset {args.preset!r} declares no "
                         "frequencies to sweep by default; give --eta START:STOP:STEP")
    return args.eta


def preset_name(text):
    """``--preset``'s value (its ``type``): the name as given, the default preset's
    name for :data:`DEFAULT_PRESET`."""
    if text == DEFAULT_PRESET:
        from ...models import presets

        return presets.DEFAULT
    return text


def positive_int(minimum, maximum=None):
    """The argparse type of an integer option in ``[minimum, maximum]`` (``maximum``
    defaults to :data:`MAX_INT`): written as a user writes an integer
    (:func:`vibimpact.base._text.parse_integer`); a value out of range is refused as
    ``argument --NAME: must be >= 1, got 0``, in the option's name (not as the API's
    argument would be, later)."""
    maximum = MAX_INT if maximum is None else maximum

    def convert(text):
        try:
            value = parse_integer(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"invalid integer {text!r} (digits 0-9 with "
                                             f"an optional sign)") from None
        if value < minimum:
            raise argparse.ArgumentTypeError(f"must be >= {minimum}, got {value}")
        if value > maximum:
            raise argparse.ArgumentTypeError(f"must be <= {maximum}, got {text.strip()}")
        return value
    convert.__name__ = "integer"
    return convert


def number(text):
    """The argparse type of a number option: a finite float written as a user writes a
    number (:func:`vibimpact.base._text.parse_real`: no digit separators, no non-ASCII
    digits, no NaN or infinity; refused here, in the option's name)."""
    try:
        return parse_real(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(f"invalid number: {exc}") from None


def positive_number(text):
    """The argparse type of a finite number > 0 (a tolerance)."""
    value = number(text)
    if value <= 0.0:
        raise argparse.ArgumentTypeError(f"must be a finite number > 0, got {text!r}")
    return value


def unit_fraction(text):
    """The argparse type of a number strictly between 0 and 1 (a share of a basin)."""
    value = number(text)
    if not 0.0 < value < 1.0:
        raise argparse.ArgumentTypeError(f"must be a number in (0, 1), got {text!r}")
    return value


def with_sets(base, sets, eta=None):
    """The parameter set ``base`` with the ``--set`` values ``sets`` (and ``--eta``, the
    model's forcing frequency whatever its name) replaced; UsageError naming the option
    whose value lies outside its parameter's domain (:meth:`vibimpact.Params.domain`),
    or saying what else is wrong."""
    from ... import models

    model = models.of_params(base)
    freq = model.frequency_name if model is not None else "eta"
    if freq in sets:
        raise UsageError(f"set {freq} with --eta, not --set")
    given = ([("--eta", freq, eta)] if eta is not None else []) + \
        [(f"--set {k}", k, v) for k, v in sets.items()]
    known = base.as_dict()
    for option, name, value in given:
        if name in known and math.isfinite(value) and value not in base.domain(name):
            raise UsageError(f"{option}: {base.domain(name).rule(name)}, got {value!r}")
        if name == freq and not ETA_RANGE[0] <= value <= ETA_RANGE[1]:
            raise UsageError(f"{option}: {freq} must lie in [{ETA_RANGE[0]:g}, "
                             f"{ETA_RANGE[1]:g}] (a forcing period the solver can "
                             f"resolve), got {value!r}")
    try:
        return base.replace(**({} if eta is None else {freq: eta}), **sets)
    except ValueError as exc:
        raise UsageError(error_text(exc)) from None


def parse_sets(items):
    """``["k=v", ...]`` -> ``{k: float(v)}``; raises UsageError naming the bad item."""
    out: dict[str, float] = {}
    for item in items or ():
        key, sep, text = item.partition("=")
        key = key.strip()
        if not sep or not key:
            raise UsageError(f"--set expects NAME=VALUE, got {item!r}")
        if key in out:
            raise UsageError(f"--set {key} given twice ({key}={out[key]:g} and "
                             f"{item.strip()}); give each parameter once")
        try:
            out[key] = parse_real(text)
        except ValueError as exc:
            raise UsageError(f"--set {key}: value {exc}") from None
    return out


def parse_analyses(text):
    from ...points.point import ANALYSES

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
