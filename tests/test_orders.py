"""Requests with ids through the one drive loop (what the service sends): each is
started, finished or stopped; ``after`` queues, ``loop`` repeats, a stop holds the hand
where it is and a relax lets it go. No real time passes (the repl tests' timeline)."""

import itertools
import random

import pytest
from test_repl import RHAND, ClockedPort, Timeline

from inmoov_dsl.boards.rig.core import BoardCore
from inmoov_dsl.live.drive import Drive, Note, library_program
from inmoov_dsl.live.orders import Control, Order
from inmoov_dsl.protocol import Signal
from inmoov_dsl.wire.pace import LIVE_HORIZON
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
    # the stop: CANCEL, then the values that may not have arrived, in one write
    stopped_at, stop = next((t, data) for t, data in sent if t >= 0.5)
    assert stopped_at == 0.5 and stop[0] == Signal.CANCEL and Signal.CANCEL not in stop[1:]
    assert all(t <= stopped_at for t, _ in sent)  # nothing sent after it
    held = index_values(board)[-1]
    assert 0 < held < 180  # where it was: neither the target nor back


@pytest.mark.parametrize("discards", [True, False])
@pytest.mark.parametrize("stop", [0.7 + k * 0.0037 for k in range(6)])
def test_after_a_stop_the_board_holds_what_the_drive_says(discards, stop):
    """The port drops what it holds (or, like a USB adapter's chip, cannot): either way
    the stop's CANCEL arrives within the horizon, the board then holds the pose the
    drive loop reports, and a take-over before it never made a servo jump."""
    timeline = Timeline([(0.0, Order("index 180 over 1s", "a")),
                         (0.3, Order("index 20, middle 150 over 1s", "b")),
                         (stop, Control("stop", "s"))])
    board = VirtualBoard(BoardCore.from_profile(RHAND, RHAND.boards[0]), 9600)
    port = ClockedPort(board, timeline, discards)
    loop = Drive([Link(181, port, "timeline")], RHAND, {}, PROGRAM, lambda note: None,
                 now=timeline.now, sleep=timeline.sleep)
    loop.run(timeline.next_line)
    board.advance(timeline.t + 1)
    assert board.positions() == {s.id: v for s, v in zip(RHAND.servos, loop.mirror.held(),
                                                         strict=True)}
    last = max(t for t, _ in board.log)
    # nothing of the moves after the stop: what the port kept, then CANCEL and the
    # values that may not have arrived (one pair a servo at most)
    assert last <= stop + LIVE_HORIZON + (2 + 2 * len(RHAND.servos)) / 960
    for servo in ("index", "middle"):
        values = [w.value for _, w in board.log if w.id == RHAND.servos[RHAND.index(servo)].id]
        assert max(abs(b - a) for a, b in itertools.pairwise(values)) <= 8  # no jump


def test_a_relax_lets_the_servos_go_until_the_next_request():
    told, board, _ = drive([(0.0, Order("index 90 over 0.5s", "a")),
                            (1.0, Control("relax", "r"))])
    assert told == [("started", "a"), ("finished", "a"), ("relax", "r")]
    assert board.core.relaxed


class LatePort(ClockedPort):
    """A board that reads ``lag`` s behind the wire (one in a simulator on a busy
    machine: the bytes wait in the pseudo-terminal); a drop loses what it has not read."""

    def __init__(self, board, timeline, lag):
        super().__init__(board, timeline)
        self.lag, self.waiting = lag, []

    def _deliver(self):
        now = self.timeline.t
        while self.waiting and self.waiting[0][0] + self.lag <= now:
            at, data = self.waiting.pop(0)
            self.board.write(data, at + self.lag)

    def write(self, data):
        self._deliver()
        self.waiting.append((self.timeline.t, bytes(data)))
        return len(data)

    def reset_output_buffer(self):
        self._deliver()
        self.waiting.clear()

    def read(self, size=1):
        self._deliver()
        return super().read(size)


@pytest.mark.parametrize("lag", [0.03, 0.1])
@pytest.mark.parametrize("stops", [[0.7], [0.7, 0.705], [0.7, 0.75, 0.9]])
def test_a_board_that_reads_late_holds_what_the_drive_says_after_any_stops(lag, stops):
    """Whatever a stop's drop took from a board that reads late, and however many stops
    come, each within the reach of the one before: the stop sends every servo it has
    moved its value again, so the board ends holding the pose the drive reports."""
    timeline = Timeline([(0.0, Order("fingers 180, wrist 180 over 2s", "a")),
                         (0.6, Order("index 0 over 2s", "b")),
                         *[(t, Control("stop", f"s{k}")) for k, t in enumerate(stops)]])
    board = VirtualBoard(BoardCore.from_profile(RHAND, RHAND.boards[0]), 9600)
    port = LatePort(board, timeline, lag)
    loop = Drive([Link(181, port, "timeline")], RHAND, {}, PROGRAM, lambda note: None,
                 now=timeline.now, sleep=timeline.sleep)
    loop.run(timeline.next_line)
    timeline.t += 1
    port.read()
    board.advance(timeline.t)
    assert board.positions() == {s.id: v for s, v in zip(RHAND.servos, loop.mirror.held(),
                                                         strict=True)}


def mixed_requests(seed: int) -> list:
    """A seeded sequence of requests, each some time after the one before (often at
    once): take-overs, queued requests, loops, stops and relaxes."""
    rng = random.Random(seed)
    fingers = ["index", "middle", "ring", "pinky", "thumb", "wrist"]
    t, script = 0.0, []
    for k in range(rng.randint(3, 8)):
        t += rng.choice([0.0, 0.001, 0.004, 0.011, 0.02, 0.05, 0.3, 0.7])
        kind = rng.choice(["take", "take", "after", "loop", "stop", "relax"])
        if kind in ("stop", "relax"):
            script.append((t, Control(kind, f"c{k}")))
            continue
        moved = rng.sample(fingers, rng.randint(1, 3))
        steps = ", ".join(f"{f} {rng.randint(0, 180)}" for f in moved)
        steps += f" over {rng.choice([0.1, 0.5, 2])}s"
        script.append((t, Order(steps, f"o{k}", after=kind == "after",
                                loop=2 if kind == "loop" else 1)))
    return script


@pytest.mark.parametrize("port", ["drops", "keeps", "late"])
def test_whatever_arrives_in_whatever_order_the_pose_reported_is_the_board_s(port):
    """Seeded sequences of take-overs, queued requests, loops, stops and relaxes, each
    at once after the one before or a little later: at the end, the pose the drive
    reports (what the service and the repl say) is the one the board answers to DUMP."""
    for seed in range(25):
        timeline = Timeline(mixed_requests(seed))
        board = VirtualBoard(BoardCore.from_profile(RHAND, RHAND.boards[0]), 9600)
        wire = (LatePort(board, timeline, 0.03) if port == "late"
                else ClockedPort(board, timeline, port == "drops"))
        loop = Drive([Link(181, wire, "timeline")], RHAND, {}, PROGRAM, lambda note: None,
                     now=timeline.now, sleep=timeline.sleep)
        loop.run(timeline.next_line)
        timeline.t += 5  # every move ends
        while loop.out.sending():
            loop.out.send(timeline.t)
            timeline.t += 0.01
        board.advance(timeline.t)
        board.read(timeline.t)  # (what it said before: WAITs)
        wire.write(bytes([Signal.CANCEL, Signal.DUMP]))
        timeline.t += 1
        if port == "late":
            wire._deliver()
        board.advance(timeline.t)
        answer = board.read(timeline.t)
        reply = answer[answer.index(Signal.START):answer.index(Signal.END)]
        dumped = dict(zip(reply[3::2], reply[4::2], strict=True))
        said = {s.id: v for s, v in zip(RHAND.servos, loop.mirror.held(), strict=True)}
        assert dumped == said, (seed, mixed_requests(seed))
