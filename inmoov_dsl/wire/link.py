"""The link edge: what a command's ``--port`` says, opened for a profile's boards.

Every command that talks to a board or a glove opens it here. ``board_ports`` is the one
reading of ``--port`` (``PORT`` when one board is needed, ``BOARD=PORT`` for each of
several, or a list of them: ``right=COM3,left=COM4``; each item checked, each board
given once); ``open_board`` opens one board's port at its baud, ``connect`` a link to each
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
from ..errors import Diagnostic, GestError, did_you_mean
from ..hardware import Board, Glove, Profile
from .player import Link
from .ports import not_of_another_kind, open_port, shipped
from .urlhandler import protocol_sim

LISTEN_POLL = 0.05  #: s; the longest a read of a listened port blocks


def every_board(spec: str) -> bool:
    """Is ``spec`` a port for every board: a ``sim://`` that names no profile (each
    board its own virtual board)?"""
    return protocol_sim.bare(spec)


def named_boards(specs: Sequence[str], profile: Profile) -> set[int]:
    """The board IDs ``--port BOARD=PORT`` arguments name (``board_ports``'s reading:
    a name or ID the profile does not have is an error)."""
    keys = _keys(profile, {b.id: str(b.id) for b in profile.boards})
    return {_board(item, key, keys, profile, None) for spec in specs
            for item in _items(spec, keys) if (key := _key(item)) is not None}


def board_ports(specs: Sequence[str], profile: Profile, needed: Collection[int] | None = None,
                names: Mapping[int, str] | None = None) -> dict[int, str]:
    """Board ID -> its port, as ``--port`` says: ``--port COM3`` when one board is
    needed, ``--port BOARD=PORT`` for each of several (BOARD: its ID or its name, or its
    name in ``names``), or several in one: ``left=COM3,right=COM4``; a bare ``sim://``
    alone is the virtual board of every needed board. Each board is given once, and an
    item that names no board of the profile, gives no port, or is empty is an error.
    ``names``: what may take a port, by ID (default: the profile's boards, named by
    their IDs); ``needed``: those that must have one (default all); one given a port
    without being needed has it too. The ports as given (``parse_ports`` completes
    ``sim://``)."""
    label = dict(names) if names else {b.id: str(b.id) for b in profile.boards}
    keys = _keys(profile, label)
    items = [item for spec in specs for item in _items(spec, keys)]
    needed = [i for i in label if needed is None or i in needed] or list(label)
    ports: dict[int, str] = {}
    given: dict[int, str] = {}  # each board's item, for the one that gives it again
    for item in items:
        key = _key(item)
        if key is not None:
            board = _board(item, key, keys, profile, names)
            _give(ports, given, [board], item, _port(item, key), key)
        elif len(needed) == 1 or (len(items) == 1 and every_board(item)):
            _give(ports, given, needed, item, item, label[needed[0]])
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


#: what a port may hold before an '=' (a URL's or a path's characters) and a board's
#: name does not: ``sim://?boot=0`` is a port, ``left=COM4`` a board's
NOT_A_NAME = frozenset(":/\\?&#%")


def _key(item: str) -> str | None:
    """The board ``item`` names when it is ``BOARD=PORT`` (None: it is a port)."""
    key, sep, _ = item.partition("=")
    return key.strip() if sep and not NOT_A_NAME & set(key) else None


def _port(item: str, key: str) -> str:
    """The port of ``BOARD=PORT``; none given is an error naming the board."""
    port = item.partition("=")[2].strip()
    if not port:
        raise GestError(Diagnostic("error", f"--port {item}: no port for board {_said(key)}",
                                   hint=f"give one after the '=': {key}=PORT, a device "
                                   "('gestplay ports' lists them), a pyserial URL or sim://"))
    return port


def _said(key: str) -> str:
    """A board as the user named it: an ID as it is, a name quoted."""
    return key if key.isdigit() else f"'{key}'"


def _keys(profile: Profile, label: Mapping[int, str]) -> dict[str, int]:
    """What names each board of ``label`` in ``--port``: its ID, its label, its name."""
    keys = {**{str(i): i for i in label}, **{n: i for i, n in label.items()}}
    keys.update({b.name: b.id for b in profile.boards if b.name not in keys and b.id in label})
    return keys


def _board(item: str, key: str, keys: Mapping[str, int], profile: Profile,
           names: Mapping[int, str] | None) -> int:
    """The board ``key`` names; one the profile does not have is an error that lists
    its boards (and the closest name)."""
    if key in keys:
        return keys[key]
    if not key:
        boards = ", ".join(names.values()) if names else _listed(profile)
        raise GestError(Diagnostic("error", f"--port {item}: no board before the '='",
                                   hint=f"BOARD=PORT, BOARD one of: {boards}"))
    raise GestError(no_board(f"--port {item}", key, keys, profile, names))


def board_named(key: str, profile: Profile, option: str = "--board") -> Board:
    """The board of ``profile`` that ``key`` names, its ID or its name, as ``--port
    BOARD=PORT`` names it (``option KEY``: what the error quotes)."""
    keys = _keys(profile, {b.id: str(b.id) for b in profile.boards})
    if key not in keys:
        raise GestError(no_board(f"{option} {key}", key, keys, profile))
    return next(b for b in profile.boards if b.id == keys[key])


def _listed(profile: Profile) -> str:
    """The profile's boards as a key names them: ``181 or 'right', 183 or 'left'``."""
    return ", ".join(str(b.id) if b.name == f"board {b.id}" else f"{b.id} or '{b.name}'"
                     for b in profile.boards)


def no_board(said: str, key: str, keys: Mapping[str, int], profile: Profile,
             names: Mapping[int, str] | None = None) -> Diagnostic:
    """``said`` names a board ``profile`` does not have: its boards, and the closest
    name or the shipped profiles that have that board (a profile not given, say)."""
    boards = ", ".join(names.values()) if names else _listed(profile)
    hint = None if key.isdigit() else did_you_mean(key, keys)
    if hint is None and not names:
        have = shipped(lambda p: any(key in (str(b.id), b.name) for b in p.boards))
        hint = (f"profile '{have[0]}' has board {_said(key)}: add --profile {have[0]}"
                if len(have) == 1 else f"profiles {', '.join(have[:-1])} and {have[-1]} "
                f"have board {_said(key)}: add --profile with one of them (--profile "
                f"{have[0]})" if have else None)
    return Diagnostic("error", f"{said}: profile '{profile.name}' has no board "
                      f"{_said(key)} (boards: {boards})", hint=hint)


def _give(ports: dict[int, str], given: dict[int, str], boards: Sequence[int], item: str,
          port: str, said: str) -> None:
    """Give ``boards`` the ``port`` of ``item``; a board given a port twice is an error."""
    again = next((b for b in boards if b in given), None)
    if again is not None:
        raise GestError(Diagnostic("error", f"--port {item}: board {_said(said)} is given "
                                   "twice", hint=f"first as {given[again]}; give each "
                                   "board one port"))
    for board in boards:
        ports[board], given[board] = port, item


def _items(spec: str, keys: Collection[str]) -> list[str]:
    """The items of one ``--port``: ``left=COM3,right=COM4`` is a list (its first item
    names a board, or one of them names a board of the profile, or one is empty); a port
    with a comma in it (``sim://a,b``) is one item. An empty item is an error."""
    parts = [part.strip() for part in spec.split(",")]
    listed = len(parts) > 1 and ("" in parts or _key(parts[0]) is not None
                                 or any(_key(p) in keys for p in parts))
    if not listed:
        return [spec.strip()]
    if "" in parts:
        at = parts.index("")
        where = "before the first comma" if at == 0 else "after the last comma" \
            if at == len(parts) - 1 else "between two commas"
        raise GestError(Diagnostic("error", f"--port {spec}: an empty item {where}",
                                   hint=f"--port {','.join(p for p in parts if p)}"))
    return parts


def parse_ports(specs: Sequence[str], profile: Profile,
                needed: Collection[int] | None = None) -> dict[int, str]:
    """Board ID -> the port to open for it (``board_ports``), a bare ``sim://``
    completed as the virtual board of that board of ``profile``."""
    return {board: protocol_sim.complete(port, profile, board)
            for board, port in board_ports(specs, profile, needed).items()}


def open_board(spec: str, profile: Profile, board: Board | None = None,
               timeout: float = 0) -> serial.SerialBase:
    """The port of ``board`` (default the profile's first) that ``spec`` gives, as
    ``--port`` gives it (``board_ports``: ``COM3``, ``left=COM3``, a list), open at its
    baud; ``timeout``: as ``ports.open_port``."""
    board = board or profile.boards[0]
    return _open(board_ports([spec], profile, [board.id])[board.id], profile, board, timeout)


def _open(spec: str, profile: Profile, board: Board, timeout: float = 0) -> serial.SerialBase:
    """The port ``spec`` of ``board``, open at its baud, as its kind opens it."""
    _virtual_twin(spec, profile, board)
    spec = protocol_sim.complete(spec, profile, board.id)
    port = controller(profile, board).open(spec)  # a bus, which its kind opens
    if port is None:
        not_of_another_kind(spec, profile, board)
    return port if port is not None else open_port(spec, board.baud, timeout)


def _virtual_twin(spec: str, profile: Profile, board: Board) -> None:
    """A ``sim://`` that names a profile is that profile's board, of its kind: one of
    another kind than ``board`` (``sim://rhand`` for a Maestro) could never answer,
    which is said at once rather than after waiting for it."""
    if protocol_sim.bare(spec):
        return
    try:
        other, twin = protocol_sim.named(spec)
    except protocol_sim.SimError:
        return  # not a sim:// URL, or opening it says what is wrong
    if twin.kind == board.kind:
        return
    own = protocol_sim.complete("sim://", profile, board.id)
    own = own.partition("?")[0] if board.id == profile.boards[0].id else own
    raise GestError(Diagnostic(
        "error", f"port {spec} is the virtual board of profile '{other.name}' (board "
        f"{twin.id}, kind {twin.kind}): it cannot answer as board {board.id} of profile "
        f"'{profile.name}' (kind {board.kind})",
        hint=f"a virtual board is of its own profile's kind: for profile '{profile.name}' "
        f"give --port sim:// (the virtual board of what is played) or {own}"))


def connect(ports: Mapping[int, str], profile: Profile) -> list[Link]:
    """Open a link to each board of the profile that has a port (as ``parse_ports``
    gives them), each as its kind needs (a serial port at the board's baud, an I2C
    bus): all or none."""
    links: list[Link] = []
    try:
        for board in (b for b in profile.boards if b.id in ports):
            links.append(Link(board.id, _open(ports[board.id], profile, board),
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
