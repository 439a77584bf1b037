"""The one protocol reader (decode.py): the conformance vectors through it, its
policies against the rules each reader had before it, and properties of any bytes."""

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from vectors import BOARD as VECTORS
from vectors import board_servos

from inmoov_dsl import compile_source
from inmoov_dsl.decode import (
    BOARD,
    GLOVE,
    PLAYER,
    RECORDER,
    Noise,
    Pair,
    Reader,
    Replies,
    Reply,
    StreamReader,
    parse_dump,
)
from inmoov_dsl.protocol import MAX_VALUE, Signal

POLICIES = {"board": BOARD, "recorder": RECORDER, "glove": GLOVE, "player": PLAYER}
BYTES = st.lists(st.integers(0, 255), max_size=300)
PAIRS = st.lists(st.tuples(st.integers(0, MAX_VALUE), st.integers(0, MAX_VALUE)),
                 max_size=50)


@pytest.mark.parametrize("case", VECTORS["cases"], ids=lambda c: c["name"])
def test_the_conformance_vectors_through_the_reader(case):
    """A board made of the reader's events and nothing else: its servo writes, replies
    and RELAX are the vectors'; and its replies, read back, are its values."""
    servos = {s.id: s for s in board_servos()}
    values = {s.id: s.default for s in servos.values()}
    reader = Reader(BOARD)
    writes, out, dumped, relaxed = [], [], [], False
    for byte in case["in"]:
        for event in reader.feed(byte):
            match event:
                case Pair(id=sid, value=value) if sid in servos:
                    values[sid] = value
                    relaxed = False
                    writes.append([sid, value, servos[sid].angle(value)])
                case Signal.RELAX:
                    relaxed = True
                case Signal.DUMP:
                    body = [b for sid, v in values.items() for b in (sid, v)]
                    out += [Signal.START, VECTORS["board"], len(values), *body, Signal.END]
                    dumped.append(Reply(VECTORS["board"], tuple(values.items())))
    assert writes == case["writes"]
    assert out == case["out"]
    assert relaxed == case.get("relaxed", False)
    assert [e for e in Reader(PLAYER).read(out) if isinstance(e, Reply)] == dumped


@pytest.mark.parametrize("name", POLICIES)
@given(data=BYTES)
def test_any_bytes_are_read_without_raising(name, data):
    policy = POLICIES[name]
    events = list(Reader(policy).read(data))
    for event in events:
        assert isinstance(event, Pair | Signal | Reply | Noise)
        if isinstance(event, Pair):
            assert 0 <= event.value <= MAX_VALUE
            assert policy.clamp or event.id <= MAX_VALUE
        if isinstance(event, Signal):
            assert event in policy.breaking | policy.passing
    # every byte was read: each of the policy's signals among them is an event, in order
    signals = policy.breaking | policy.passing
    assert [e for e in events if isinstance(e, Signal)] == [b for b in data if b in signals]


@pytest.mark.parametrize("name", ["board", "recorder"])
@given(noise=BYTES, pairs=PAIRS)
def test_after_noise_a_cancel_then_pairs_reads_as_those_pairs(name, noise, pairs):
    reader = Reader(POLICIES[name])
    list(reader.read(noise))
    data = [Signal.CANCEL, *(b for pair in pairs for b in pair)]
    assert list(reader.read(data)) == [Signal.CANCEL, *(Pair(*p) for p in pairs)]


@pytest.mark.parametrize("name", ["board", "recorder"])
@given(data=BYTES)
def test_after_cancel_nothing_is_pending(name, data):
    reader = Reader(POLICIES[name])
    list(reader.read(data))
    assert reader.feed(Signal.CANCEL) == (Signal.CANCEL,)
    assert reader.pending is None
    assert reader.feed(3) == ()
    assert reader.feed(90) == (Pair(3, 90),)


def test_an_encoded_stream_reads_as_its_pairs():
    compiled = compile_source("g:\n    index 180, middle 90 over 0.4s\n    wrist 30 over 0.2s\n")
    (stream,) = compiled.streams
    pairs = list(zip(stream.data[1::2], stream.data[2::2], strict=True))
    assert len(pairs) > 20
    for policy in (BOARD, RECORDER):
        events = list(Reader(policy).read(stream.data))
        assert events == [Signal.CANCEL, *(Pair(*p) for p in pairs)]


def test_each_policy_reads_a_byte_above_180_its_own_way():
    # 200 as a value: clamped on the board, noise that loses the pair for the recorder
    assert list(Reader(BOARD).read([255, 1, 200])) == [Signal.CANCEL, Pair(1, 180)]
    assert list(Reader(RECORDER).read([255, 1, 200, 2, 9])) == [
        Signal.CANCEL, Noise(200), Pair(2, 9)]
    # a signal between an ID and its value: RELAX drops the ID on the board, WAIT
    # passes by for the recorder; on the board WAIT is a value, clamped
    assert list(Reader(BOARD).read([255, 1, 248, 2, 9])) == [
        Signal.CANCEL, Signal.RELAX, Pair(2, 9)]
    assert list(Reader(RECORDER).read([255, 1, 254, 9])) == [
        Signal.CANCEL, Signal.WAIT, Pair(1, 9)]
    assert list(Reader(BOARD).read([1, 254])) == [Pair(1, 180)]
    # the recorder waits for a CANCEL; the glove hears MIN and MAX only
    assert list(Reader(RECORDER).read([1, 2])) == [Noise(1), Noise(2)]
    assert list(Reader(GLOVE).read([255, 250, 1, 2, 249])) == [Signal.MIN, Signal.MAX]


def test_a_dump_is_found_among_wait_bytes_and_noise():
    reply = bytes([252, 181, 2, 0, 10, 1, 20, 251])
    assert parse_dump(bytes([254, 254, 7]) + reply + bytes([254])) == (181, {0: 10, 1: 20})
    assert parse_dump(bytes([252, 254]) + reply) == (181, {0: 10, 1: 20})
    assert parse_dump(reply[:-1]) is None
    assert parse_dump(bytes([254, 254])) is None
    assert parse_dump(reply, 183) is None
    assert list(Reader(PLAYER).read(bytes([254]) + reply)) == [
        Signal.WAIT, Reply(181, ((0, 10), (1, 20)))]


# -- the rules each reader had before the one reader, kept here as the reference -----
def reference_parse_dump(data, board_id=None):
    """parse_dump as board.py had it."""
    start = 0
    while True:
        start = data.find(bytes([Signal.START]), start)
        if start < 0 or start + 2 >= len(data):
            return None
        board, count = data[start + 1], data[start + 2]
        end = start + 3 + 2 * count
        if end < len(data) and data[end] == Signal.END:
            body = data[start + 3:end]
            pairs = dict(zip(body[0::2], body[1::2], strict=True))
            if all(v <= MAX_VALUE for v in pairs.values()) and len(pairs) == count \
                    and board_id in (None, board) and 181 <= board <= 250:
                return board, pairs
        start += 1


def reference_recorder(chunks, ids):
    """StreamReader.feed as record.py had it: (samples, skipped)."""
    samples, skipped, pending, synced = [], 0, None, False
    for t, data in chunks:
        for byte in data:
            if byte == Signal.CANCEL:
                pending, synced = None, True
            elif not synced:
                skipped += 1
            elif byte > MAX_VALUE:
                skipped += 1
                if pending is not None and byte < min(Signal):
                    pending = None
            elif pending is None:
                pending = byte
            else:
                sid, pending = pending, None
                if sid in ids:
                    samples.append((t, sid, byte))
                else:
                    skipped += 1
    return samples, skipped


@st.composite
def replies_among_noise(draw):
    """Bytes from a board: WAIT, noise, and DUMP replies (some cut short, some with a
    value above 180 or an ID twice), small numbers so that pieces collide."""
    small = st.sampled_from([0, 1, 2, 181, 183, 200, 251, 252, 254])
    out = []
    for _ in range(draw(st.integers(0, 6))):
        if draw(st.booleans()):
            out += draw(st.lists(small, max_size=6))
        else:
            n = draw(st.integers(0, 3))
            body = [b for _ in range(n) for b in (draw(small), draw(small))]
            reply = [252, draw(st.sampled_from([181, 183])), n, *body, 251]
            out += reply[:draw(st.integers(1, len(reply)))] if draw(st.booleans()) else reply
    return bytes(out)


def test_of_two_replies_that_overlap_parse_dump_takes_the_one_that_starts_first():
    # a reply of 252 pairs, its count byte the START of a short reply inside it, which
    # ends (on an ID of the long one) before the long one does
    ids = [181, 5, 251, *(i for i in range(256) if i not in (181, 5, 251, 252))][:252]
    values = [1, 7] + [0] * 250
    long = bytes([252, 181, 252, *(b for p in zip(ids, values, strict=True) for b in p), 251])
    inner = [e for e in Reader(PLAYER).read(long) if isinstance(e, Reply)]
    assert [len(r.pairs) for r in inner] == [1, 252]  # the short one completes first
    assert parse_dump(long) == (181, dict(zip(ids, values, strict=True)))
    assert parse_dump(long) == reference_parse_dump(long)


@settings(max_examples=500)
@given(data=replies_among_noise(), board=st.sampled_from([None, 181, 183]))
def test_parse_dump_keeps_its_rule(data, board):
    assert parse_dump(data, board) == reference_parse_dump(data, board)


@settings(max_examples=300)
@given(data=replies_among_noise(), board=st.sampled_from([None, 181, 183]),
       cuts=st.lists(st.integers(0, 60), max_size=6))
def test_a_reply_read_as_it_comes_is_the_one_the_whole_bytes_hold(data, board, cuts):
    # ask_dump reads the board's bytes as they come, each byte once: it stops at the
    # first read that completes a reply, which is the one parse_dump finds in the bytes
    # up to there
    replies, seen = Replies(board), 0
    for cut in [*sorted(cuts), len(data)]:
        chunk, seen = data[seen:max(cut, seen)], max(cut, seen)
        found = replies.feed(chunk)
        if found is not None:
            assert found == parse_dump(data[:seen], board)
            return
    assert parse_dump(data, board) is None


@given(chunks=st.lists(st.tuples(st.floats(0, 10), st.lists(
    st.one_of(st.integers(0, 255), st.sampled_from([1, 2, 9, 200, 248, 254, 255])),
    max_size=20)), max_size=10))
def test_the_recorder_keeps_its_rule(chunks):
    reader = StreamReader(frozenset({1, 2}))
    for t, data in chunks:
        reader.feed(t, data)
    assert (reader.samples, reader.skipped) == reference_recorder(chunks, {1, 2})
