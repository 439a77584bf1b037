"""Requests with ids through the one drive loop (what the service sends): each is
started, finished or stopped; ``after`` queues, ``loop`` repeats, a stop holds the hand
where it is and a relax lets it go. No real time passes (the repl tests' timeline)."""

from test_repl import RHAND, ClockedPort, Timeline

from inmoov_dsl.live.drive import Drive, Note, library_program
from inmoov_dsl.live.orders import Control, Order
from inmoov_dsl.protocol import Signal
from inmoov_dsl.wire.board import BoardCore
from inmoov_dsl.wire.player import Link
from inmoov_dsl.wire.sim import VirtualBoard

INDEX = RHAND.servos[RHAND.index("index")].id
PROGRAM = library_program()


def drive(script):
    """Run timed requests [(seconds, request)] through a Drive: its notes (kind, id),
    the board, and what was sent to it."""
    timeline = Timeline(script)
    board = VirtualBoard(BoardCore.from_profile(RHAND, RHAND.boards[0]), 9600)
    port = ClockedPort(board, timeline)
    sent = []
    write = port.write
    port.write = lambda data: (sent.append((timeline.t, bytes(data))), write(data))[1]
    notes: list[Note] = []
    Drive([Link(181, port, "timeline")], RHAND, {}, PROGRAM, notes.append,
          now=timeline.now, sleep=timeline.sleep).run(timeline.next_line)
    board.advance(timeline.t + 1)
    told = [(n.kind, n.id) for n in notes if n.kind in ("started", "finished", "stopped",
                                                         "stop", "relax")]
    return told, board, sent


def index_values(board):
    return [w.value for _, w in board.log if w.id == INDEX]


def test_a_request_that_takes_over_stops_the_one_it_interrupts():
    told, board, _ = drive([(0.0, Order("index 180 over 1s", "a")),
                            (0.3, Order("index 0 over 0.5s", "b"))])
    assert told == [("started", "a"), ("stopped", "a"), ("started", "b"), ("finished", "b")]
    assert max(index_values(board)) < 180 and index_values(board)[-1] == 0


def test_a_request_after_waits_for_the_one_before():
    told, board, sent = drive([(0.0, Order("index 90 over 0.5s", "a")),
                               (0.1, Order("index 0 over 0.5s", "b", after=True))])
    assert told == [("started", "a"), ("finished", "a"), ("started", "b"), ("finished", "b")]
    values = index_values(board)
    assert values[values.index(90):].count(90) >= 1 and values[-1] == 0  # 90 reached first


def test_a_request_that_loops_plays_its_passes_and_finishes_once():
    told, _, sent = drive([(0.0, Order("wiggle", "w", loop=3))])
    assert told == [("started", "w"), ("finished", "w")]
    _, _, once = drive([(0.0, Order("wiggle", "w"))])
    assert 2.5 < sent[-1][0] / once[-1][0] < 3.5  # three passes, one after the other


def test_a_stop_holds_the_hand_where_it_is_and_empties_the_queue():
    told, board, sent = drive([(0.0, Order("index 180 over 1s", "a")),
                               (0.1, Order("index 0", "b", after=True)),
                               (0.5, Control("stop", "s"))])
    assert told == [("started", "a"), ("stopped", "a"), ("stopped", "b"), ("stop", "s")]
    stopped_at = next(t for t, data in sent if data == bytes([Signal.CANCEL]) and t >= 0.5)
    assert all(t <= stopped_at for t, _ in sent)  # nothing sent after the CANCEL
    held = index_values(board)[-1]
    assert 0 < held < 180  # where it was: neither the target nor back


def test_a_relax_lets_the_servos_go_until_the_next_request():
    told, board, _ = drive([(0.0, Order("index 90 over 0.5s", "a")),
                            (1.0, Control("relax", "r"))])
    assert told == [("started", "a"), ("finished", "a"), ("relax", "r")]
    assert board.core.relaxed
