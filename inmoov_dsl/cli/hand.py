"""The hand on the desk: its boards' links, the pose they hold, and the guard that
always leaves it safe.

Every gestplay command that moves the hand goes through ``opened``: it opens a link
per board (``wire.link``, where ``--port`` is read), waits for each board and asks
its pose, and whatever happens in the body (Ctrl-C, SIGTERM, a pulled cable) no board
is left with half a command: it sends a rig CANCEL (a kind whose commands go whole
needs nothing more), says what each board was sent, and leaves with the right exit
status.
"""

from __future__ import annotations

import sys
from collections.abc import Collection, Iterator
from contextlib import contextmanager
from dataclasses import dataclass

from .. import clock
from ..boards import Controller, controller
from ..errors import Diagnostic, GestError
from ..hardware import Profile
from ..wire.link import close, connect, parse_ports
from ..wire.player import BoardTrouble, Link, cancel_all, relax_all
from ..wire.ready import ask_dump, wait_ready
from . import typeahead
from .common import EXIT_INTERRUPTED, Exit, Stopped, note, status_of, warn, why

RELAX_WINDOW = 1.5  #: s after a Ctrl-C at a terminal in which a second one relaxes the hand
REST_POSE = "starting from the profile's rest pose"


@dataclass
class Hand:
    """The open links to a profile's boards, and the pose the boards said they hold."""

    profile: Profile
    links: list[Link]
    pose: dict[str, int]  #: servo name -> value, for the servos whose board answered


def board_pose(links: list[Link], profile: Profile, blind: bool = False,
               going_on: str = REST_POSE) -> dict[str, int]:
    """Each board's pose (``reach``), by servo name; a board that did not say it is
    planned from the profile's rest pose."""
    names = {s.id: s.name for s in profile.servos}
    pose: dict[str, int] = {}
    for link in links:
        values = reach(link, profile, blind, going_on)
        pose.update({names[sid]: v for sid, v in (values or {}).items() if sid in names})
    return pose


def reach(link: Link, profile: Profile, blind: bool, going_on: str) -> dict[int, int] | None:
    """Wait for the board to boot, sync it with CANCEL and ask its pose with DUMP: its
    values (servo ID -> value), or None. Nothing answering (no WAIT and no DUMP reply)
    is an error before any gesture byte goes out, unless ``blind`` (a link that cannot
    answer); a board that answered only in part is a warning ending in ``going_on``."""
    c = link.controller
    heard = bytearray()
    ready = wait_ready(link.port, controller=c, heard=heard, patient=not blind,
                       say=lambda text: note(f"board {link.board} on {link.name}: {text}",
                                             "gestplay"))
    if ready and c is not None and (refused := c.refusal(bytes(heard))):
        raise GestError(Diagnostic("error", f"{refused} (on {link.name})",
                                   hint="flash the MrlComm of that release, or ours: "
                                   "docs/controllers.md"))
    if ready and c is not None and (said := c.greeting(bytes(heard))):
        warn(said, "gestplay")
    values = ask_dump(link.port, link.board, controller=c)
    if ready and c is not None and (setup := c.setup(bytes(heard), values)):
        link.port.write(setup)
    where = f"board {link.board} on {link.name}"
    if values is None and not ready:
        if not blind:
            raise GestError(no_answer(link, profile))
        warn(f"{where} did not answer (--blind): {going_on}", "gestplay")
    elif values is None:
        warn(f"{where}: no {kind_of(link, profile).pose_reply}: {going_on}", "gestplay")
    elif not ready:
        warn(f"{where} {kind_of(link, profile).answered_late()}", "gestplay")
    return values


def kind_of(link: Link, profile: Profile) -> Controller:
    """The board on ``link`` as its kind drives it (a rig's too: its link's is None)."""
    board = next(b for b in profile.boards if b.id == link.board)
    return link.controller or controller(profile, board)


def no_answer(link: Link, profile: Profile) -> Diagnostic:
    """What to say when nothing answers on a link (no WAIT, no DUMP reply)."""
    from ..firmware.sketches import sketch_names

    kind = kind_of(link, profile)
    board = kind.board
    if not kind.ours:
        return Diagnostic(
            "error", f"no board answered on {link.name} (board {link.board}, {board.kind} "
            f"at {board.baud} baud)", hint=kind.unanswered())
    sketch = next(n for n, i in sketch_names(profile).items() if i == board.id)
    return Diagnostic(
        "error", f"no board answered on {link.name} (board {link.board}, {board.baud} baud)",
        hint=f"try another port ('gestplay ports' lists them and marks the likely "
        f"Arduinos), check that the board's sketch uses {board.baud} baud, or flash it: "
        f"gestc upload {sketch} --port {link.name}; --blind plays anyway on a link "
        f"that cannot answer")


@contextmanager
def opened(prog: str, profile: Profile, ports: list[str], blind: bool = False,
           going_on: str = REST_POSE, boards: Collection[int] | None = None
           ) -> Iterator[Hand]:
    """The hand, its links open and its pose asked (``board_pose``); closed after.
    ``boards``: those that need a port (default all; ``link.board_ports``).

    Ctrl-C sends a rig CANCEL, so that no half command is pending (``cancel_all``),
    says so in each kind's words (``stopped``) and leaves (``Exit``) with status 130
    and the hand holding its pose; at a terminal, a second Ctrl-C soon after
    relaxes the hand (its servos go limp), and what is typed meanwhile is left for the
    shell (``typeahead``). SIGTERM and SIGHUP do as Ctrl-C (exit 143, 129). A lost link
    sends CANCEL where it still can and is one line of error."""
    modes = typeahead.modes()  # the terminal as found, before any line editor
    links = connect(parse_ports(ports, profile, boards), profile)
    try:
        yield Hand(profile, links, board_pose(links, profile, blind, going_on))
    except KeyboardInterrupt as exc:
        cancel_all(links)
        raise Exit(_interrupted(prog, links, exc, modes, stopped(links, profile))) from None
    except BoardTrouble as exc:  # a board that cannot go on said so
        cancel_all(links)
        raise GestError(exc.diagnostic) from None
    except OSError as exc:  # a serial port's SerialException, an I2C bus's error
        cancel_all(links)
        where = ", ".join(f"board {link.board} on {link.name}" for link in links)
        raise GestError(Diagnostic("error", f"lost the link ({where}): {exc}")) from None
    finally:
        close(links)


HELD = "each servo holds its last position"  #: after a stop, when the kinds say it apart


def stopped(links: list[Link], profile: Profile) -> str:
    """What a stop did, in one clause: what each kind was sent (``stop_sent``; by board
    when the kinds differ), then what the servos do (``stop_held``)."""
    kinds = [kind_of(link, profile) for link in links]
    sent: dict[str, list[int]] = {}
    for link, kind in zip(links, kinds, strict=True):
        sent.setdefault(kind.stop_sent(), []).append(link.board)
    held = {kind.stop_held() for kind in kinds}
    if len(sent) <= 1:
        return f"{next(iter(sent), 'nothing sent')}, {held.pop() if held else HELD}"
    said = ", ".join(f"{words} to board{'s' * (len(ids) > 1)} {', '.join(map(str, ids))}"
                     for words, ids in sent.items())
    return f"{said}; {held.pop() if len(held) == 1 else HELD}"


def _interrupted(prog: str, links: list[Link], exc: KeyboardInterrupt,
                 modes: typeahead.Modes | None, said: str) -> int:
    """Say what the stop did (``said``: ``stopped``); at a terminal, relax the hand on
    a second Ctrl-C. The terminal goes back to ``modes``, and what is typed from now
    on to the shell. The exit status."""
    at_terminal = sys.stdin.isatty()
    typeahead.release(modes)
    if isinstance(exc, Stopped) or not at_terminal:
        print(f"\n{prog}: {why(exc)}: {said}", file=sys.stderr)
        return status_of(exc)
    try:  # a second Ctrl-C may come as soon as the first one is answered
        print(f"\n{prog}: interrupted: {said} (Ctrl-C again to relax it)", file=sys.stderr,
              flush=True)
        clock.sleep(RELAX_WINDOW)
    except Stopped as again:
        return status_of(again)
    except KeyboardInterrupt:
        relax_all(links)
        print(f"{prog}: relaxed: the servos are limp until the next command",
              file=sys.stderr)
    return EXIT_INTERRUPTED
