"""The ``softcath`` command line.

Each subcommand lives in its own module ``softcath.cli.<name>`` (``cli/<name>.py``) exposing
``HELP`` (one line), ``add_arguments(parser)`` and ``run(args) -> int``.
A module is imported only when its command is parsed (:func:`build_parser`), so it imports
the library at its top and ``softcath --help`` still imports none of it; the heavy optional
dependencies (CadQuery, OpenCV, Panel, ...) stay inside the functions that use them.

Every way a command can fail ends here, in :func:`main`: an input error
(:class:`~softcath.design.errors.SoftcathError`) or any other exception becomes one
line ``softcath CMD: error: ...`` on stderr and exit status 2; ``--debug``
adds the traceback. SIGTERM ends a command like Ctrl-C (its clean-up runs,
e.g. the recorder writes its summary); a failure to write stdout (a closed
pipe, a full disk) is reported the same way.
"""

from __future__ import annotations

import argparse
import importlib
import logging
import os
import re
import signal
import sys
import traceback
import warnings

from softcath import __version__
from softcath.cli.help_text import PlainFormatter
from softcath.cli.options import check_option_effects, in_command_terms, option_terms
from softcath.core.atomic import forget_created_dirs, remove_created_dirs
from softcath.core.errors import SoftcathError
from softcath.core.interrupts import clear_stop, request_stop
from softcath.core.output_ledger import forget_inputs, protect_inputs

#: (subcommand, module): a command's module is imported when that command is parsed, so
#: ``softcath --help`` imports none of them; :func:`build_parser` without a command imports
#: every one (a broken install must not lose a subcommand silently).
SUBCOMMANDS: tuple[tuple[str, str], ...] = (
    ("demo", "softcath.cli.demo"),
    ("design", "softcath.cli.design"),
    ("analytic", "softcath.cli.analytic"),
    ("calibrate", "softcath.cli.calibrate"),
    ("fem", "softcath.cli.fem"),
    ("section", "softcath.cli.section"),
    ("sweep", "softcath.cli.sweep"),
    ("report", "softcath.cli.report"),
    ("select", "softcath.cli.select"),
    ("measure", "softcath.cli.measure"),
    ("record", "softcath.cli.record"),
    ("bench", "softcath.cli.bench"),
    ("discrepancy", "softcath.cli.discrepancy"),
    ("coil", "softcath.cli.coil"),
    ("predict", "softcath.cli.predict"),
    ("optimise", "softcath.cli.optimise"),
    ("app", "softcath.cli.app"),
)

#: Each command's one-line help, as its module's ``HELP`` says (a test keeps them equal): the
#: top-level ``--help`` lists the commands without importing their modules.
HELP: dict[str, str] = {
    "demo": "run the whole story on the paper's design and write DIR/index.html",
    "design": "show / validate / export (STEP, STL) a design",
    "analytic": "curvature, elongation, tip pose over a pressure range",
    "calibrate": "the paper's ellipse shape optimisation against a measurement CSV",
    "fem": (
        "one FEM bending check (mesh, solve, compare with the analytic model); --nonlinear for finite strain"
    ),
    "section": "2-D section model: FEM-grade curvature per MPa in milliseconds",
    "sweep": "run a design sweep (local processes or Dask), resumable",
    "report": "write a static HTML report of a sweep directory",
    "select": "rank a sweep's designs by constraints and objectives (Pareto front)",
    "measure": "measure the tip in a video / image folder / camera into a CSV and an overlay video",
    "record": "record serial sensors (and a camera) into the measurement CSV at 200 Hz",
    "bench": "virtual bench: simulated devices and camera recorded through the real pipeline",
    "discrepancy": "name the effect the model is missing (hysteresis, lag, ...) and show the gap shrink",
    "coil": (
        "resolved-wire coil stiffness (tension, compression, bending with contact) vs homogenised models"
    ),
    "predict": "prediction bands of the bending gain under parameter uncertainty, vs a measurement",
    "optimise": "optimise a design (DE or NSGA-II) under select-style objectives and constraints",
    "app": "the interactive design app in the browser (local web server; Ctrl-C stops it)",
}

EXIT_ERROR = 2
EXIT_INTERRUPTED = 130


class Terminated(KeyboardInterrupt):
    """SIGTERM, delivered like Ctrl-C so every command's clean-up runs."""


class StdoutError(OSError):
    """Writing the command's own output to stdout failed (closed pipe, full disk)."""


class _GuardedStdout:
    """``sys.stdout`` for the length of a command: its write failures become :class:`StdoutError`
    (an output file's failure stays what it is)."""

    def __init__(self, stream) -> None:
        self._stream = stream

    def write(self, text: str) -> int:
        try:
            return self._stream.write(text)
        except OSError as exc:
            raise StdoutError(exc.errno, exc.strerror) from exc

    def flush(self) -> None:
        try:
            self._stream.flush()
        except OSError as exc:
            raise StdoutError(exc.errno, exc.strerror) from exc

    def __getattr__(self, name):
        return getattr(self._stream, name)


class _Parser(argparse.ArgumentParser):
    """argparse with the CLI's one-line refusal: ``softcath CMD: error: OPTION = VALUE: BOUND``, exit 2.

    Its help is plain text (:class:`softcath.cli.help_text.PlainFormatter`), subcommands' too.
    """

    def __init__(self, *args, **kwargs) -> None:
        kwargs.setdefault("formatter_class", PlainFormatter)
        super().__init__(*args, **kwargs)

    def error(self, message: str):  # type: ignore[override]
        _say(f"{self.prog}: error: {parser_message(' '.join(message.split()))} (see {self.prog} --help)")
        raise SystemExit(EXIT_ERROR)

    def parse_known_args(self, args=None, namespace=None):  # type: ignore[override]
        # A subcommand's positionals may come after its options (``discrepancy paper --reference
        # prototype CURVE.csv``): argparse's intermixed parse, which calls back here, so guarded.
        if self._intermixing or not self._can_intermix():
            parsed, extra = super().parse_known_args(args, namespace)
        else:
            self._intermixing = True
            try:
                parsed, extra = self.parse_known_intermixed_args(args, namespace)
            finally:
                self._intermixing = False
        # A subcommand's parser reports its own leftovers, so the line names the command.
        if extra and self._subparsers is None and not self._intermixing:
            self.error(_unrecognized(extra))
        return parsed, extra

    _intermixing = False

    def _can_intermix(self) -> bool:
        """A leaf parser whose arguments argparse's intermixed parse takes."""
        if self._subparsers is not None:
            return False
        return all(a.nargs not in (argparse.REMAINDER, argparse.PARSER) for a in self._actions)


def _unrecognized(extra: list[str]) -> str:
    """argparse's message for arguments the command does not take, as ``OPTION = VALUE: bound``."""
    first = extra[0]
    if first.startswith("-") and len(first) > 1:
        option, eq, value = first.partition("=")
        if not eq and len(extra) > 1 and not extra[1].startswith("-"):
            value = extra[1]
        shown = repr(value) if value else "None"
        return f"{option} = {shown}: not an option of this command"
    return f"argument = {first!r}: not expected here (every positional is taken)"


_ARGPARSE_FORMS = (
    (re.compile(r"^argument (?P<opt>[^:]+): invalid (?P<type>\w+) value: (?P<val>.*)$"), "must be a {type}"),
    (
        re.compile(r"^argument (?P<opt>[^:]+): invalid choice: (?P<val>'.*?') \((?P<rest>.*)\)$"),
        "invalid choice; {rest}",
    ),
    (re.compile(r"^argument (?P<opt>[^:]+): (?P<val>)expected one argument$"), "needs a value"),
    (re.compile(r"^argument (?P<opt>[^:]+): (?P<val>)(?P<rest>.*)$"), "{rest}"),
)


def parser_message(message: str) -> str:
    """argparse's refusal said as ``OPTION = VALUE: BOUND`` where it names one argument."""
    if " = " in message.split(":", 1)[0]:
        return message
    if message.startswith("the following arguments are required: "):
        names = message.split(": ", 1)[1]
        return f"{names} = None: required"
    for pattern, bound in _ARGPARSE_FORMS:
        m = pattern.match(message)
        if m:
            opt = m.group("opt").split("/")[-1]
            val = m.group("val") or "None"
            return f"{opt} = {val}: {bound.format(**m.groupdict())}"
    return message


def build_parser(command: str | None = None) -> argparse.ArgumentParser:
    """Build the argument parser with the subcommands of :data:`SUBCOMMANDS`.

    Parameters
    ----------
    command
        ``None``: every subcommand's parser, each module imported. A name: that
        subcommand's parser only; the others are listed with their one-line :data:`HELP`
        and their modules are not imported (``""``: none is imported).

    Raises
    ------
    ImportError
        If a subcommand's module does not import.
    """
    parser = _Parser(
        prog="softcath",
        description="Design, check and measure a hydraulically actuated soft micro-catheter tip. "
        "Units: mm, N, MPa, s.",
    )
    parser.add_argument("--version", action="version", version=f"softcath {__version__}")
    parser.add_argument("-v", "--verbose", action="store_true", help="log progress details")
    parser.add_argument(
        "--debug", action="store_true", help="show the full traceback of an error (for bug reports)"
    )
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for name, module_name in SUBCOMMANDS:
        if command is not None and name != command:
            sub.add_parser(name, help=HELP.get(name))  # listed; its module loads when it is chosen
            continue
        module = importlib.import_module(module_name)
        p = sub.add_parser(name, help=module.HELP, description=module.__doc__)
        module.add_arguments(p)
        p.set_defaults(
            _run=module.run,
            _terms=option_terms(p),
            _defaults={a.dest: a.default for a in p._actions if a.option_strings},
        )
    return parser


def _chosen_command(argv: list[str] | None) -> str:
    """The subcommand ``argv`` names (its first positional; the global options are flags), or ``""``."""
    args = sys.argv[1:] if argv is None else argv
    first = next((a for a in args if not a.startswith("-")), "")
    return first if first in dict(SUBCOMMANDS) else ""


class _BriefFormatter(logging.Formatter):
    """Log records without tracebacks (those are for ``--debug``)."""

    def format(self, record: logging.LogRecord) -> str:
        if record.exc_info or record.exc_text:
            record = logging.makeLogRecord(record.__dict__)
            record.exc_info = record.exc_text = None
        return super().format(record)


def _configure_logging(*, verbose: bool, debug: bool) -> None:
    handler = logging.StreamHandler()
    fmt = "%(levelname)s %(name)s: %(message)s"
    handler.setFormatter(logging.Formatter(fmt) if debug else _BriefFormatter(fmt))
    root = logging.getLogger()
    for h in list(root.handlers):
        if getattr(h, "_softcath", False):
            root.removeHandler(h)
    handler._softcath = True  # type: ignore[attr-defined]
    root.addHandler(handler)
    root.setLevel(logging.DEBUG if debug else logging.INFO if verbose else logging.WARNING)
    logging.captureWarnings(True)  # Python warnings become one log line each


def _one_line_warning(message, category, filename, lineno, line=None) -> str:
    return f"{category.__name__}: {message} ({os.path.basename(filename)}:{lineno})"


def _on_sigterm(signum, frame) -> None:  # pragma: no cover - exercised by subprocess tests
    request_stop(Terminated)
    raise Terminated()


def _on_sigint(signum, frame) -> None:  # pragma: no cover - exercised by subprocess tests
    request_stop(KeyboardInterrupt)
    raise KeyboardInterrupt()


def _describe(exc: BaseException) -> str:
    """One line for an exception that is not an input error."""
    if isinstance(exc, MemoryError):
        return "out of memory; use a coarser mesh / fewer designs (rerun with --debug for details)"
    if type(exc).__name__ == "BrokenProcessPool":  # concurrent.futures: a worker was killed
        return (
            "a worker process died (killed, or out of memory); this run's outputs were not written: "
            "rerun it (with fewer --workers if memory is short)"
        )
    if isinstance(exc, OSError) and exc.strerror:
        where = f": {exc.filename}" if exc.filename else ""
        return f"{exc.strerror}{where}"
    text = " ".join(str(exc).split()) or "(no message)"
    return (
        f"unexpected {type(exc).__name__}: {text[:300]} "
        "(a bug in softcath: rerun with --debug and report the traceback)"
    )


def _stdout_failed() -> None:
    # Point stdout at /dev/null so the interpreter's final flush cannot raise again.
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
    except (OSError, ValueError, AttributeError):
        pass


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``softcath`` console script; returns the exit status."""
    parser = build_parser(_chosen_command(argv))
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # --help (0) or a refused argument (2, already said in one line)
        return exc.code if isinstance(exc.code, int) else EXIT_ERROR
    _configure_logging(verbose=args.verbose, debug=args.debug)
    old_term = old_int = None
    clear_stop()
    if hasattr(signal, "SIGTERM"):
        try:
            old_term = signal.signal(signal.SIGTERM, _on_sigterm)
            old_int = signal.signal(signal.SIGINT, _on_sigint)
        except ValueError:  # not the main thread (an embedding program)
            old_term = old_int = None
    name = args.command + (f" {args.action}" if getattr(args, "action", None) else "")
    _printable_streams()
    forget_created_dirs()
    forget_inputs()
    protect_inputs(_input_files(args))
    ok = False
    real_stdout, real_formatwarning = sys.stdout, warnings.formatwarning
    warnings.formatwarning = _one_line_warning
    sys.stdout = _GuardedStdout(real_stdout)
    try:
        check_option_effects(args, args.command, getattr(args, "_defaults", {}))
        status = int(args._run(args) or 0)
        sys.stdout.flush()
        ok = status == 0
        return status
    except KeyboardInterrupt as exc:
        what = "terminated" if isinstance(exc, Terminated) else "interrupted"
        _say(f"softcath {name}: {what}")
        return EXIT_INTERRUPTED
    except StdoutError as exc:
        _stdout_failed()
        _say(f"softcath {name}: error: cannot write the output to stdout ({exc.strerror or exc})")
        return EXIT_ERROR
    except Exception as exc:
        if args.debug:
            traceback.print_exc()
        if isinstance(exc, SoftcathError):
            said = in_command_terms(exc, getattr(args, "_terms", {}))
            _say(f"softcath {name}: error: {' '.join(str(said).split())}")
        else:
            _say(f"softcath {name}: error: {_describe(exc)}")
        return EXIT_ERROR
    finally:
        # A refused or failed command leaves no empty --out behind.
        if ok:
            forget_created_dirs()
        else:
            remove_created_dirs()
        forget_inputs()
        sys.stdout, warnings.formatwarning = real_stdout, real_formatwarning
        logging.captureWarnings(False)
        if old_term is not None:
            signal.signal(signal.SIGTERM, old_term)
        if old_int is not None:
            signal.signal(signal.SIGINT, old_int)


#: Options that name what a command writes, not what it reads.
_OUTPUT_OPTIONS = frozenset({"out", "step", "stl"})


def _input_files(args: argparse.Namespace) -> list[tuple[str, object]]:
    """``(option, path)`` of every argument that may name a file the command reads."""
    terms = getattr(args, "_terms", {})
    found = []
    for dest, value in vars(args).items():
        if dest.startswith("_") or dest in _OUTPUT_OPTIONS:
            continue
        for v in value if isinstance(value, list) else [value]:
            if isinstance(v, str | os.PathLike) and str(v):
                found.append((terms.get(dest, dest.upper()), v))
    return found


def _printable_streams() -> None:
    """Write characters the terminal's encoding lacks (a path's undecodable bytes) as escapes.

    A path read from the command line may hold bytes the locale cannot encode (Python keeps
    them as surrogates); printing it after the outputs were written must not fail the command.
    """
    for stream in (sys.stdout, sys.stderr):
        reconfigure = getattr(stream, "reconfigure", None)
        if reconfigure is not None:
            try:
                reconfigure(errors="backslashreplace")
            except (ValueError, OSError):  # a stream that is already closed or detached
                pass


def _say(line: str) -> None:
    try:
        print(line, file=sys.stderr, flush=True)
    except OSError:
        pass


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
