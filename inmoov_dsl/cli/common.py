"""What the command-line tools share: error printing, exit codes, signals, and the
arguments several commands take."""

from __future__ import annotations

import argparse
import contextlib
import gc
import math
import os
import re
import signal
import sys
from collections.abc import Callable, Iterable
from pathlib import Path

from .. import model  # noqa: F401  (gives the compiler its solver of places)
from ..errors import Diagnostic, GestError

EXIT_OK, EXIT_ERROR, EXIT_INTERRUPTED = 0, 1, 130


class Exit(Exception):  # noqa: N818 (not an error: the way out, everything said)
    """Leave the tool now with ``status``; what happened has been said."""

    def __init__(self, status: int):
        super().__init__(status)
        self.status = status


def report(diagnostics: Iterable[Diagnostic], prog: str) -> None:
    """Print diagnostics to stderr, those without a place in a file after ``prog:``."""
    for d in diagnostics:
        text = d.format()
        if d.pos is None:
            text = f"{prog}: {text}"
        print(text, file=sys.stderr)


def warn(message: str, prog: str) -> None:
    """Print a warning that has no place in a file: ``PROG: warning: message``."""
    report([Diagnostic("warning", message)], prog)


def note(message: str, prog: str) -> None:
    """Say what is going on, neither a result nor a warning (a wait that would
    otherwise be silent): ``PROG: message`` on standard error."""
    print(f"{prog}: {message}", file=sys.stderr, flush=True)


class Stopped(KeyboardInterrupt):
    """A signal that stops a tool as Ctrl-C does (SIGTERM from a service manager or
    kill, SIGHUP from a closed terminal): every path that leaves the hand safe on
    Ctrl-C runs for it too; the exit status is 128 + its number."""

    def __init__(self, signum: int):
        super().__init__(signum)
        self.name = signal.Signals(signum).name
        self.status = 128 + signum


def _stop(signum: int, frame: object) -> None:
    raise Stopped(signum)


def stop_on_signals() -> None:
    """SIGTERM and SIGHUP (where there is one) raise Stopped in the main thread."""
    for name in ("SIGTERM", "SIGHUP", "SIGBREAK"):
        if hasattr(signal, name):
            with contextlib.suppress(ValueError, OSError):  # not the main thread
                signal.signal(getattr(signal, name), _stop)


def why(exc: KeyboardInterrupt) -> str:
    """What stopped us, for a message: 'interrupted' or 'stopped by SIGTERM'."""
    return f"stopped by {exc.name}" if isinstance(exc, Stopped) else "interrupted"


def status_of(exc: KeyboardInterrupt) -> int:
    """The exit status for what stopped us: 130 for Ctrl-C, 128 + N for signal N."""
    return exc.status if isinstance(exc, Stopped) else EXIT_INTERRUPTED


def run(prog: str, body: Callable[[], int]) -> int:
    """Run a command: people get messages and exit codes, never a traceback. SIGTERM
    and SIGHUP stop it as Ctrl-C does. In a tool's own process, started with garbage
    collection off (``cli._start``), what start-up made is frozen (never looked at
    again) and collection goes on for the command. (What the command makes is not
    frozen: ruckig's objects must be collected before the interpreter ends, or nanobind
    reports them as leaked.)"""
    if not gc.isenabled():
        gc.freeze()
        gc.enable()
    stop_on_signals()
    try:
        return body()
    except GestError as exc:
        report(exc.diagnostics, prog)
        return EXIT_ERROR
    except Exit as exc:
        return exc.status
    except KeyboardInterrupt as exc:
        print(f"{prog}: {why(exc)}", file=sys.stderr)
        return status_of(exc)
    except BrokenPipeError:
        sys.stderr.close()  # the reader went away (| head): nothing more to say
        return EXIT_OK
    except IsADirectoryError as exc:  # a folder given for a file, to read or to write
        print(f"{prog}: error: '{exc.filename}' is a folder, not a file\n"
              "  hint: give a file's path (one in the folder: FOLDER/NAME)", file=sys.stderr)
        return EXIT_ERROR
    except OSError as exc:
        where = f" '{exc.filename}'" if exc.filename else ""
        print(f"{prog}: error: cannot use{where}: {exc.strerror or exc}", file=sys.stderr)
        return EXIT_ERROR


def add_lib(p: argparse.ArgumentParser) -> None:
    """``--lib DIR``: one more place to look for gestures."""
    p.add_argument("--lib", action="append", default=[], metavar="DIR",
                   help="also look for gestures in DIR (before GEST_PATH, ./gestures and "
                   "the built-in library); may be repeated")


COLOR_CHOICES = ("auto", "always", "never")


def add_color(p: argparse.ArgumentParser) -> None:
    """``--color auto|always|never``: colour the gesture code a command prints."""
    p.add_argument("--color", choices=COLOR_CHOICES, default="auto",
                   help="colour the gesture's code: auto (the default: when standard output "
                   "is a terminal and NO_COLOR is not set), always or never; colours need "
                   "pygments (pip install 'inmoov-dsl[highlight]')")


def wants_color(choice: str, stream=None, environ=None) -> bool:
    """Colour what goes to ``stream`` (standard output)? ``--color always`` and ``never``
    say so; ``auto`` colours a terminal unless NO_COLOR is set and not empty
    (no-color.org: an option on the command line wins over it)."""
    if choice != "auto":
        return choice == "always"
    if (os.environ if environ is None else environ).get("NO_COLOR"):
        return False
    stream = sys.stdout if stream is None else stream
    try:
        return bool(stream.isatty())
    except (AttributeError, ValueError):  # no isatty, or closed
        return False


def number(low: float, high: float, above: bool = False, whole: bool = False
           ) -> Callable[[str], float]:
    """An argparse type: a finite number from ``low`` (excluded if ``above``) to ``high``,
    a whole one if ``whole``; anything else is a usage error saying what to give."""
    kind = "a whole number" if whole else "a number"
    top = f"{int(high):,}" if float(high).is_integer() else f"{high:g}"
    span = f"above {low:g} and at most {top}" if above else f"from {low:g} to {top}"

    def parse(text: str) -> float:
        try:
            value = int(text) if whole else float(text)
        except ValueError:
            value = math.nan
        if not (low < value if above else low <= value) or not value <= high:
            raise argparse.ArgumentTypeError(f"'{text}' is not {kind} {span}")
        return value

    parse.__name__ = kind  # argparse names the type in some messages
    return parse


def parse_args(ap: argparse.ArgumentParser, argv: list[str] | None) -> argparse.Namespace:
    """``ap.parse_args``, refusing what no shell can pass (a NUL in an argument)."""
    argv = sys.argv[1:] if argv is None else argv
    if any("\x00" in a for a in argv):
        ap.error("an argument contains a NUL character")
    return ap.parse_args(argv)


def add_ports(p: argparse.ArgumentParser, what: str = "the board's port", more: str = "") -> None:
    """``--port PORT`` (required; for a profile with several boards, a port per board:
    ``right=COM3,left=COM4``): ``what`` a port is, ``more`` said after."""
    from .options import PORT_FORMS

    p.add_argument("--port", action="append", required=True, metavar="PORT",
                   help=f"{what}; {PORT_FORMS}{more}")


def add_blind(p: argparse.ArgumentParser) -> None:
    """``--blind``: play on a link where no board answers."""
    p.add_argument("--blind", action="store_true",
                   help="go on when no board answers (a link that cannot answer); the plan "
                   "then starts from the profile's rest pose")


def add_version(p: argparse.ArgumentParser) -> None:
    """``--version``: the package's version."""
    from .. import __version__

    p.add_argument("--version", action="version", version=f"%(prog)s {__version__}")


def status_line(text: str) -> None:
    """One line that redraws itself on a terminal (each one on its own line otherwise)."""
    if sys.stdout.isatty():
        sys.stdout.write(f"\r\x1b[2K{text}")
    else:
        sys.stdout.write(f"{text}\n")
    sys.stdout.flush()


def send_value(port, servo_id: int, value: int, controller=None) -> None:
    """Move one servo now: on a rig, CANCEL (the board may be mid-command), then the
    pair; another kind, its ``controller``'s command. What the board sent is read off,
    so a pulled cable raises here."""
    from ..protocol import frame
    from ..wire.ready import drain

    port.write(controller.set_values({servo_id: value}) if controller else
               frame([(servo_id, value)]))
    drain(port)


def gesture_name(name: str | None, file: str | None = None) -> str:
    """``name`` (``--name``) if it can name a gesture, a GestError saying why not
    otherwise; with no name, the file's name made one (``wave-back.gest``: ``wave_back``)."""
    if name is None and file is not None:
        name = re.sub(r"\W", "_", Path(file).stem, flags=re.ASCII)
        name = name if name[:1].isalpha() or name[:1] == "_" else f"g_{name}"
    from ..language.syntax import KEYWORDS

    if not name.isidentifier() or not name.isascii():
        raise GestError(Diagnostic("error", f"'{name}' cannot name a gesture",
                                   hint="--name takes a word: letters, digits and _"))
    if name in KEYWORDS:
        raise GestError(Diagnostic("error", f"'{name}' is a keyword of the language, not a "
                                   "name", hint=f"--name my_{name}"))
    return name


def write_out(path: str | None, text: str, about: str = "") -> None:
    """``text`` to the file ``path``, saying so on stderr (``wrote PATH``, then
    ``about``), or to standard output when ``path`` is None or ``-``."""
    if path in (None, "-"):
        sys.stdout.write(text)
        sys.stdout.flush()
        return
    Path(path).write_text(text, encoding="utf-8")
    print(f"wrote {path}{about}", file=sys.stderr)


def stdin_bytes() -> bytes:
    """All of standard input, as bytes (a text stream put in its place, as tests do, is
    encoded back to UTF-8)."""
    buffer = getattr(sys.stdin, "buffer", None)
    return buffer.read() if buffer is not None else \
        sys.stdin.read().encode("utf-8", "surrogatepass")


def add_allow_contact(p: argparse.ArgumentParser) -> None:
    """``--allow-contact``: play what drives the robot's parts into each other."""
    p.add_argument("--allow-contact", action="store_true",
                   help="play a motion that drives the robot's parts into each other "
                   "(a warning instead of a refusal), for a robot whose parts are padded")


def guard_for(profile, allow_contact: bool, prog: str):
    """The players' self-collision guard for ``profile`` (``model.guard.Guard``); its
    warning that nothing is checked, said once now if python-fcl is missing."""
    from ..model.guard import Guard

    guard = Guard(profile, allow_contact)
    if guard.missing is not None:
        report([guard.missing], prog)
    return guard
