"""The link edge: what a command's ``--port`` says, opened for a profile's boards.

Every command that talks to a board or a glove opens it here. ``board_ports`` is the one
reading of ``--port`` (``PORT`` when one board is needed, ``BOARD=PORT`` for each of
several); ``open_board`` opens one board's port at its baud, ``connect`` a link to each
board, and ``open_listener`` the port a glove (or a board mirroring it) sends the
protocol stream on. A ``sim://`` that names no profile is completed here with the
profile and board the port is for (the virtual board of what is being played), as
pyserial's URL handlers intend: callers pass a port spec and a profile, never the
``sim://`` handler's parts.
"""

from __future__ import annotations

from collections.abc import Collection, Mapping, Sequence
from dataclasses import dataclass

import serial

from ..boards import controller
from ..errors import Diagnostic, GestError
from ..hardware import Board, Glove, Profile
from .player import Link
from .ports import open_port
from .urlhandler import protocol_sim

LISTEN_POLL = 0.05  #: s; the longest a read of a listened port blocks


def every_board(spec: str) -> bool:
    """Is ``spec`` a port for every board: a ``sim://`` that names no profile (each
    board its own virtual board)?"""
    return protocol_sim.bare(spec)


def named_boards(specs: Sequence[str]) -> set[int]:
    """The board IDs ``--port ID=PORT`` arguments name (known to the profile or not)."""
    keys = (spec.partition("=") for spec in specs)
    return {int(key) for key, sep, _ in keys if sep and key.isdigit()}


def board_ports(specs: Sequence[str], profile: Profile, needed: Collection[int] | None = None,
                names: Mapping[int, str] | None = None) -> dict[int, str]:
    """Board ID -> its port, as ``--port`` says: ``--port COM3`` when one board is
    needed, ``--port BOARD=PORT`` for each of several (BOARD: its ID or its name, or its
    name in ``names``), or several in one: ``left=COM3,right=COM4``; a bare ``sim://``
    alone is the virtual board of every needed board.
    ``names``: what may take a port, by ID (default: the profile's boards, named by
    their IDs); ``needed``: those that must have one (default all); one given a port
    without being needed has it too. The ports as given (``parse_ports`` completes
    ``sim://``)."""
    label = dict(names) if names else {b.id: str(b.id) for b in profile.boards}
    keys = {**{str(i): i for i in label}, **{n: i for i, n in label.items()}}
    keys.update({b.name: b.id for b in profile.boards if b.name not in keys and b.id in label})
    specs = [part for spec in specs for part in _split(spec, keys)]
    needed = [i for i in label if needed is None or i in needed] or list(label)
    ports: dict[int, str] = {}
    for spec in specs:
        key, sep, port = spec.partition("=")
        if sep and key in keys:
            ports[keys[key]] = port
        elif sep and key.isdigit():
            raise GestError(Diagnostic("error", f"--port {spec}: profile '{profile.name}' "
                                       f"has no board {key} (boards: "
                                       f"{', '.join(label.values())})"))
        elif len(needed) == 1 or (len(specs) == 1 and every_board(spec)):
            ports.update(dict.fromkeys(needed, spec))
        else:
            what = f"profile '{profile.name}' has" if len(needed) == len(label) else \
                "this needs"
            raise GestError(Diagnostic(
                "error", f"{what} {len(needed)} boards: give a port for each",
                hint=" ".join(f"--port {label[i]}=PORT" for i in needed)))
    missing = [label[i] for i in needed if i not in ports]
    if missing:
        what = "" if names else "board "
        raise GestError(Diagnostic("error", f"no port for {what}{', '.join(missing)}",
                                   hint=f"add --port {missing[0]}=PORT"))
    return ports


def _split(spec: str, keys: Collection[str]) -> list[str]:
    """``left=COM3,right=COM4`` as two ports, when each part names a board."""
    parts = spec.split(",")
    named = len(parts) > 1 and all(p.partition("=")[0] in keys for p in parts)
    return parts if named else [spec]


def parse_ports(specs: Sequence[str], profile: Profile,
                needed: Collection[int] | None = None) -> dict[int, str]:
    """Board ID -> the port to open for it (``board_ports``), a bare ``sim://``
    completed as the virtual board of that board of ``profile``."""
    return {board: protocol_sim.complete(port, profile, board)
            for board, port in board_ports(specs, profile, needed).items()}


def open_board(spec: str, profile: Profile, board: Board | None = None,
               timeout: float = 0) -> serial.SerialBase:
    """The port ``spec`` of ``board`` (default the profile's first), open at its baud;
    ``timeout``: as ``ports.open_port``."""
    board = board or profile.boards[0]
    spec = protocol_sim.complete(spec, profile, board.id)
    port = controller(profile, board).open(spec)  # a bus, which its kind opens
    return port if port is not None else open_port(spec, board.baud, timeout)


def connect(ports: Mapping[int, str], profile: Profile) -> list[Link]:
    """Open a link to each board of the profile that has a port (as ``parse_ports``
    gives them), each as its kind needs (a serial port at the board's baud, an I2C
    bus): all or none."""
    links: list[Link] = []
    try:
        for board in (b for b in profile.boards if b.id in ports):
            links.append(Link(board.id, open_board(ports[board.id], profile, board),
                              ports[board.id], controller(profile, board)))
    except GestError:
        close(links)
        raise
    return links


def close(links: Sequence[Link]) -> None:
    """Close every link."""
    for link in links:
        link.port.close()


@dataclass
class Listener:
    """A port that sends the protocol stream: a glove's (or a board's that mirrors it).
    Nothing is ever written to it."""

    port: serial.SerialBase
    glove: Glove | None  #: the profile's glove, whose stream it is (None: it has none)
    baud: int

    def read(self) -> bytes:
        """What has come, waiting at most ``LISTEN_POLL`` for a first byte."""
        return self.port.read(max(1, self.port.in_waiting))

    def close(self) -> None:
        """Close the port."""
        self.port.close()


def open_listener(spec: str, profile: Profile, baud: int | None = None) -> Listener:
    """Open ``spec`` to read what the profile's glove sends, at ``baud`` (default the
    glove's; a profile without a glove: its first board's)."""
    glove = profile.gloves[0] if profile.gloves else None
    baud = baud or (glove.baud if glove else profile.boards[0].baud)
    name = protocol_sim.complete(spec, profile, profile.boards[0].id)
    return Listener(open_port(name, baud, timeout=LISTEN_POLL), glove, baud)
