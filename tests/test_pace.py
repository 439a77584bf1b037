"""The continuous run (wire/pace.py): every byte of a stream at its place on the byte
grid, CANCEL between commands, written a horizon ahead; properties over any stream,
the library's streams read by the original firmware's model, and the pacer against a
wire that keeps its own time."""

from pathlib import Path

import numpy as np
import pytest
from boardmodel import read_stream
from conftest import library_profile
from hypothesis import given, settings
from hypothesis import strategies as st

from inmoov_dsl import clock
from inmoov_dsl.compiling.compiler import compile_program
from inmoov_dsl.language.library import scan_library
from inmoov_dsl.language.load import load
from inmoov_dsl.protocol import MAX_VALUE, Signal, byte_time
from inmoov_dsl.wire.pace import FILL, HORIZON, Pacer, commands, padded, places
from inmoov_dsl.wire.player import Link, cancel_all
from inmoov_dsl.wire.ports import open_port

ROOT = Path(__file__).resolve().parent.parent
LIBRARY = scan_library([ROOT / "gestures"])
TAU = byte_time(9600)


@st.composite
def streams(draw, on_grid=False):
    """A stream as the compiler lays it out: CANCEL, then (ID, value) pairs, each byte
    at least a byte-time after the one before (on the byte grid, or anywhere)."""
    n = draw(st.integers(0, 40))
    data = [Signal.CANCEL] + [b for _ in range(n) for b in
                              (draw(st.integers(0, MAX_VALUE)), draw(st.integers(0, MAX_VALUE)))]
    steps = st.integers(1, 60) if on_grid else st.floats(1.0, 60.0)
    # on the grid as compiled: a pair's value a byte-time after its ID
    gaps = [1 if on_grid and k % 2 == 0 else draw(steps) for k in range(1, len(data))]
    times = np.concatenate([[0.0], np.cumsum(gaps)]) * TAU
    return times, bytes(data)


@settings(max_examples=300, deadline=None)
@given(streams(), st.sampled_from([1.0, 0.5, 0.25, 2.0]))
def test_every_command_is_whole_in_place_and_in_order(stream, speed):
    times, data = stream
    where = places(times, data, TAU, speed)
    run = padded(times, data, TAU, speed)
    assert len(run) == (where[-1] + 1 if data else 0)
    assert bytes(run[p] for p in where) == data  # the stream's bytes, in order
    assert set(run) - set(data) <= {FILL}  # and CANCEL between them
    end = 0
    for first, stop in commands(data):
        at = where[first]
        assert where[first:stop] == list(range(at, at + stop - first))  # never split
        due = (times[first] - times[0]) / speed / TAU
        assert at >= end and (at <= round(due) or at == end)  # nearest, or right after
        assert at == max(end, round(due))
        end = at + stop - first


@settings(max_examples=200, deadline=None)
@given(streams(on_grid=True))
def test_at_full_speed_a_compiled_stream_keeps_its_times_exactly(stream):
    times, data = stream
    assert places(times, data, TAU) == [round(t / TAU) for t in times]


@settings(max_examples=200, deadline=None)
@given(streams(), st.sampled_from([1.0, 0.5]))
def test_the_original_firmware_reads_the_same_pairs_from_the_run(stream, speed):
    times, data = stream
    run = padded(times, data, TAU, speed)
    ran = read_stream(np.arange(len(run)) * TAU, run, 9600)
    bare = read_stream(times / speed, data, 9600)
    assert [p[1:] for p in ran] == [p[1:] for p in bare]


@pytest.mark.parametrize("name", sorted(n for n, e in LIBRARY.items()
                                        if e.path.parent.name == "gestures"))
def test_each_library_stream_padded_is_read_as_sent_bare(name):
    """The original firmware's model (boardmodel: facts.md) reads every library
    gesture's run as it reads the stream sent bare: the same pairs at the same times."""
    entry = LIBRARY[name]
    compiled, _ = compile_program(load(str(entry.path)), name, library_profile(entry.path))
    for stream in compiled.streams:
        tau = stream.byte_time
        run = padded(stream.times, stream.data, tau)
        baud = round(10 / tau)
        ran = read_stream(np.arange(len(run)) * tau, run, baud)
        bare = read_stream(stream.times, stream.data, baud)
        assert [p[1:] for p in ran] == [p[1:] for p in bare]
        assert np.allclose([p[0] for p in ran], [p[0] for p in bare], rtol=0, atol=1e-9)


class Wire:
    """A port whose wire keeps its own time: bytes leave one byte-time apart once
    written; ``reset_output_buffer`` drops those not yet begun."""

    def __init__(self, now, tau=TAU):
        self.now, self.tau, self.queue, self.sent, self.writes = now, tau, [], [], 0

    def _run(self):
        while self.queue and self.queue[0][0] <= self.now():
            self.sent.append(self.queue.pop(0))

    def write(self, data):
        self._run()
        self.writes += 1
        free = self.queue[-1][0] + self.tau if self.queue else \
            max(self.now(), self.sent[-1][0] + self.tau if self.sent else -1.0)
        for b in data:
            start = max(self.now(), free)
            self.queue.append((start, b))
            free = start + self.tau
        return len(data)

    def reset_output_buffer(self):
        self._run()
        self.queue = [q for q in self.queue if q[0] <= self.now()]

    def all(self):
        return self.sent + self.queue


@settings(max_examples=100, deadline=None)
@given(streams(), st.lists(st.floats(0.0, 0.03), min_size=1, max_size=30))
def test_the_pacer_never_sends_early_never_splits_and_catches_up(stream, naps):
    """Woken late by any amount, the pacer writes the run ahead of the wire, never a
    command's byte before its place, and leaves out filler to catch up."""
    times, data = stream
    t = [10.0]
    wire = Wire(lambda: t[0])
    pacer = Pacer(wire, TAU)
    for first, stop in commands(data):
        pacer.add(10.0 + times[first], data[first:stop])
    k = 0
    while pacer.pending():
        pacer.pump(t[0])
        t[0] = max(t[0] + 1e-4, pacer.next_wake(t[0])) + naps[k % len(naps)]
        k += 1
    sent = wire.all()
    where = places(times, data, TAU)
    got = iter(sent)
    for first, stop in commands(data):  # each command, whole, in order, never early
        due = 10.0 + where[first] * TAU
        while True:
            at, b = next(got)
            if b == data[first] and (at >= due - 1e-9):
                break
            assert b == FILL  # only filler comes between commands
        for j in range(first + 1, stop):
            at2, b2 = next(got)
            assert b2 == data[j] and at2 == pytest.approx(at + (j - first) * TAU)
        assert at - due <= pacer.late + 1e-9
    assert pacer.late <= max(naps) + HORIZON + 2 * TAU


def test_a_stop_drops_what_the_port_holds_and_cancel_arrives_at_once(virtual_clock):
    """cancel_all on a sim:// port that holds a second of a run: the CANCEL arrives
    within two byte-times (the byte on the wire, then the CANCEL). On the virtual clock:
    no time passes between the write and the stop, however busy the machine."""
    port = open_port("sim://?boot=0&fresh", 9600)
    try:
        board = port.board
        clock.sleep(0.01)
        board.read(clock.now())
        port.write(bytes([Signal.CANCEL, 2, 90]) + bytes([FILL]) * 960)
        cancel_all([Link(181, port)])
        sent = clock.now()
        assert board.sending_until() - sent <= 2 * TAU
        clock.sleep(0.01)
        board.advance(clock.now())
        assert board.positions()[2] == 0  # the pair had not begun: it was dropped
    finally:
        port.close()
