"""The one protocol reader: bytes in, events out (the sibling of encode.py).

A pure state machine fed one byte at a time, as mido's tokenizer is: ``Reader(policy)``,
then ``feed(byte)`` returns the events that byte completes: a ``Pair`` (servo ID,
value), a ``Signal`` (protocol.Signal itself), a ``Reply`` (a DUMP reply), or ``Noise``
(a byte that is none of these). No clock and no I/O.

What a byte means where it arrives is the reader's ``Policy``, named after who reads:

- ``BOARD``, a servo board (its firmware, the virtual board, the metrics, the repl's
  mirror): CANCEL, DUMP and RELAX are signals wherever they arrive and drop a half-read
  pair; any other byte is an ID where an ID is expected (a foreign one, above 180) and
  a value where a value is expected, clamped to 180.
- ``RECORDER``, gestc record listening to a glove (``StreamReader``, which keeps each
  pair with the time it came): nothing is a pair before the first CANCEL; the other
  signals (248..254) pass by and keep a half-read pair; a byte of 181..247 is noise and
  drops it.
- ``GLOVE``, a glove listening to the computer: MIN and MAX, nothing else.
- ``PLAYER``, the computer listening to a board: WAIT, and DUMP replies
  (``START BOARD_ID N (id value)*N END``) found among other bytes (``parse_dump``;
  ``Replies`` keeps those whose BOARD_ID is a board's, 181 and up).
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator
from dataclasses import dataclass, field

from .protocol import FIRST_BOARD_ID, LAST_BOARD_ID, MAX_VALUE, Signal, reply


@dataclass(frozen=True)
class Pair:
    """A servo command: servo ``id`` (above 180 on a board: a foreign one), ``value``."""

    id: int
    value: int


@dataclass(frozen=True)
class Reply:
    """A board's answer to DUMP: its ID and its (servo ID, value) pairs."""

    board: int
    pairs: tuple[tuple[int, int], ...]

    @property
    def size(self) -> int:
        """Its length in bytes, START to END (``protocol.reply``)."""
        return len(reply(self.board, self.pairs))


@dataclass(frozen=True)
class Noise:
    """A byte the policy reads as no part of a pair and no signal."""

    byte: int


Event = Pair | Signal | Reply | Noise


@dataclass(frozen=True)
class Policy:
    """What a reader makes of each byte."""

    breaking: frozenset[Signal]  #: signals that drop a half-read pair
    passing: frozenset[Signal] = frozenset()  #: signals that leave a half-read pair alone
    clamp: bool = False  #: a byte above 180 is an ID or a value clamped to 180 (else noise)
    sync: bool = False  #: nothing is a pair before the first CANCEL
    pairs: bool = True  #: reads (ID, value) pairs at all
    replies: bool = False  #: reads DUMP replies


BOARD = Policy(frozenset({Signal.CANCEL, Signal.DUMP, Signal.RELAX}), clamp=True)
RECORDER = Policy(frozenset({Signal.CANCEL}), frozenset(Signal) - {Signal.CANCEL}, sync=True)
GLOVE = Policy(frozenset(), frozenset({Signal.MIN, Signal.MAX}), pairs=False)
PLAYER = Policy(frozenset(), frozenset({Signal.WAIT}), pairs=False, replies=True)


class Reader:
    """Reads the protocol a byte at a time, by the rules of ``policy``."""

    def __init__(self, policy: Policy):
        self.policy = policy
        self.pending: int | None = None  #: a servo ID waiting for its value
        self.synced = not policy.sync  #: pairs can be told apart (a CANCEL has come)
        self._open: list[list[int]] = []  #: replies begun: the bytes after each START

    def reset(self) -> None:
        """Forget everything read: nothing pending, no reply begun, not yet in step."""
        self.pending = None
        self.synced = not self.policy.sync
        self._open = []

    def feed(self, byte: int) -> tuple[Event, ...]:
        """Read one byte: the events it completes (mostly none or one)."""
        replies = self._replies(byte) if self.policy.replies else ()
        return replies + self._pairs(byte)

    def read(self, data: Iterable[int]) -> Iterator[Event]:
        """Read bytes: every event they complete, in order."""
        for byte in data:
            yield from self.feed(byte)

    def _pairs(self, byte: int) -> tuple[Event, ...]:
        policy = self.policy
        if byte in policy.breaking:
            self.pending = None
            self.synced = self.synced or byte == Signal.CANCEL
            return (Signal(byte),)
        if byte in policy.passing:
            return (Signal(byte),)
        if not policy.pairs:
            return ()
        if not self.synced:
            return (Noise(byte),)  # joined mid-command: wait for the next CANCEL
        if byte > MAX_VALUE and not policy.clamp:
            self.pending = None  # not a value: the pair is lost
            return (Noise(byte),)
        if self.pending is None:
            self.pending = byte
            return ()
        sid, self.pending = self.pending, None
        return (Pair(sid, min(byte, MAX_VALUE)),)

    def _replies(self, byte: int) -> tuple[Reply, ...]:
        """Every START begins a reply that may turn out to be noise (a value above 180,
        an ID twice, no END where it belongs); replies begun earlier go on meanwhile."""
        done: list[Reply] = []
        still: list[list[int]] = []
        for head in self._open:
            n = len(head)  # bytes after START: board, count, then the pairs
            if n >= 2 and n == 2 + 2 * head[1]:
                if byte == Signal.END:
                    done.append(Reply(head[0], tuple(zip(head[2::2], head[3::2],
                                                         strict=True))))
            # board and count: any byte; then a value up to 180, an ID not seen before
            elif n < 2 or (byte <= MAX_VALUE if n % 2 else byte not in head[2::2]):
                head.append(byte)
                still.append(head)
        if byte == Signal.START:
            still.append([])
        self._open = still
        return tuple(done)


@dataclass
class StreamReader:
    """Bytes in the protocol, as they arrive, to (time, servo ID, value) samples: the
    recorder's reading (``RECORDER``) of a glove, or of any stream in the protocol."""

    ids: frozenset[int]  #: the servo IDs to keep
    samples: list[tuple[float, int, int]] = field(default_factory=list)
    skipped: int = 0  #: bytes before the first CANCEL, signals, noise, other IDs' pairs
    reader: Reader = field(default_factory=lambda: Reader(RECORDER), repr=False)

    def feed(self, t: float, data: Iterable[int]) -> None:
        """Read bytes that arrived at ``t``: keep the pairs for ``ids``; count the rest
        (but CANCEL) as skipped, a pair for another ID as one."""
        for event in self.reader.read(data):
            match event:
                case Pair(id=sid, value=value) if sid in self.ids:
                    self.samples.append((t, sid, value))
                case Signal.CANCEL:
                    pass
                case _:
                    self.skipped += 1


def is_board(board_id: int) -> bool:
    """Is ``board_id`` a board's ID (FIRST_BOARD_ID..LAST_BOARD_ID)? A reply naming
    another (180: a servo's ID, a value) is no board's answer."""
    return FIRST_BOARD_ID <= board_id <= LAST_BOARD_ID


class Replies:
    """DUMP replies in a board's bytes as they come (``PLAYER``'s reading), from board
    ``board_id`` if given, else from any board ID (``is_board``): each byte read once,
    however the bytes are split."""

    def __init__(self, board_id: int | None = None):
        self.board_id = board_id
        self.reader = Reader(PLAYER)
        self.count = 0  #: bytes read so far

    def feed(self, data: bytes) -> tuple[int, dict[int, int]] | None:
        """The reply these bytes complete, as (board ID, servo ID -> value), or None; of
        two that overlap, the one that starts first."""
        found: tuple[int, Reply] | None = None
        for byte in data:
            self.count += 1
            for event in self.reader.feed(byte):
                if isinstance(event, Reply) and is_board(event.board) and \
                        self.board_id in (None, event.board):
                    start = self.count - event.size
                    if found is None or start < found[0]:
                        found = (start, event)
        return None if found is None else (found[1].board, dict(found[1].pairs))


def parse_dump(data: bytes, board_id: int | None = None
               ) -> tuple[int, dict[int, int]] | None:
    """Find a DUMP reply in bytes from a board (WAIT bytes, noise and replies naming
    no board's ID around it are skipped), from board ``board_id`` if given: (board ID,
    servo ID -> value), or None if no complete reply is there. Of two that overlap,
    the one that starts first."""
    return Replies(board_id).feed(data)
