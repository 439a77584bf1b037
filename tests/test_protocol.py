import pytest
from hypothesis import given
from hypothesis import strategies as st

from inmoov_dsl import protocol
from inmoov_dsl.decode import Reply, parse_dump
from inmoov_dsl.protocol import Signal


def test_signals_are_the_seed_protocol():
    assert (Signal.CANCEL, Signal.WAIT, Signal.DUMP, Signal.START, Signal.END) == (
        255, 254, 253, 252, 251)
    assert (Signal.MIN, Signal.MAX) == (250, 249)
    assert protocol.MAX_VALUE == 180
    assert protocol.FIRST_BOARD_ID == 181


def test_link_timing_at_9600_baud():
    # 8N1: 10 bits a byte, 960 bytes/s, 1.04 ms a byte
    assert abs(protocol.byte_time(9600) - 1 / 960) < 1e-12
    # a 20 ms servo frame holds 9 pairs after the CANCEL byte: room for 6 servos
    assert protocol.pairs_per_frame(9600) == 9
    assert protocol.pairs_per_frame(115200) >= 100


# -- framing: frame(pairs) and pairs(data), one layout for every module ----------------
PAIRS = st.lists(st.tuples(st.integers(0, protocol.MAX_SERVO_ID),
                           st.integers(0, protocol.MAX_VALUE)), max_size=60)


def test_a_frame_is_cancel_then_each_pair_id_first():
    assert protocol.frame([(2, 90), (5, 30)]) == bytes([255, 2, 90, 5, 30])
    assert protocol.frame(()) == bytes([255]) == protocol.CANCEL_PENDING
    assert protocol.pairs(bytes([255, 2, 90, 5, 30])) == [(2, 90), (5, 30)]
    assert protocol.pairs(bytes([255])) == []
    assert protocol.pairs(bytes([255, 2, 90, 5])) == [(2, 90)]  # a half pair is not one


@given(PAIRS)
def test_pairs_reads_back_what_frame_wrote(pairs):
    data = protocol.frame(pairs)
    assert protocol.pairs(data) == pairs
    assert len(data) == 1 + protocol.PAIR_BYTES * len(pairs)
    assert protocol.frame_fault(data) is None


@given(st.binary(max_size=80))
def test_any_bytes_are_a_frame_exactly_when_frame_would_write_them(data):
    fault = protocol.frame_fault(data)
    if protocol.frame(protocol.pairs(data)) != data:  # not CANCEL, or a pair cut short
        assert fault is not None and fault[1] in ("CANCEL", "pair")
    elif fault is not None:  # the layout holds: a byte above MAX_VALUE, the first one
        n, what = fault
        assert data[n] > protocol.MAX_VALUE
        assert all(b <= protocol.MAX_VALUE for b in data[1:n])
        assert (what, data[n]) in [(w, p[k]) for p in protocol.pairs(data)
                                   for k, w in enumerate(("servo ID", "value"))]
    else:
        assert all(b <= protocol.MAX_VALUE for b in data[1:])


def test_frame_fault_names_the_byte_and_what_it_should_be():
    assert protocol.frame_fault(b"") == (0, "CANCEL")
    assert protocol.frame_fault(bytes([2, 90, 5])) == (0, "CANCEL")
    assert protocol.frame_fault(bytes([255, 2, 90, 5])) == (3, "pair")
    assert protocol.frame_fault(bytes([255, 200, 90])) == (1, "servo ID")
    assert protocol.frame_fault(bytes([255, 2, 90, 5, 253])) == (4, "value")


@given(st.integers(protocol.FIRST_BOARD_ID, protocol.LAST_BOARD_ID), PAIRS)
def test_a_dump_reply_reads_back(board, pairs):
    pose = dict(pairs)
    data = protocol.reply(board, pose.items())
    assert data[0] == Signal.START and data[-1] == Signal.END
    assert len(data) == Reply(board, tuple(pose.items())).size
    assert parse_dump(bytes([Signal.WAIT]) + data, board) == (board, pose)


def test_the_named_sequences():
    assert bytes([Signal.CANCEL, Signal.DUMP]) == protocol.ASK_POSE
    assert bytes([Signal.CANCEL, Signal.RELAX, Signal.CANCEL]) == protocol.RELAX_BOARD


def test_board_ids_end_below_the_signals_and_values():
    assert protocol.LAST_BOARD_ID == min(Signal) - 1 == 247
    assert protocol.FIRST_BOARD_ID == protocol.MAX_VALUE + 1


@pytest.mark.parametrize(("baud", "usable"), [
    (protocol.DEFAULT_BAUD, True), (115200, True), (protocol.MAX_BAUD, True),
    (protocol.MAX_BAUD + 1, False), (0, False), (-9600, False),
    (1000, False),  # 10 ms a byte: no pair fits in a 20 ms frame after the CANCEL
    (1500, True),
])
def test_a_usable_baud_carries_a_pair_every_servo_frame(baud, usable):
    assert protocol.usable_baud(baud) is usable


def test_every_baud_a_sketch_may_use_is_usable():
    from inmoov_dsl.cli.gestc.firmware import BAUDS

    assert protocol.DEFAULT_BAUD in BAUDS
    assert all(protocol.usable_baud(b) for b in BAUDS)


@pytest.mark.parametrize(("value", "clamped"), [(-5, 0), (0, 0), (90, 90), (180, 180),
                                                 (181, 180), (400, 180)])
def test_clamp_keeps_a_value_within_0_to_max_value(value, clamped):
    assert protocol.clamp(value) == clamped


def test_a_streams_pairs_are_read_with_their_times_in_protocol_alone():
    """The stream's layout (CANCEL, then ID and value bytes) is read in protocol: the
    firmware's stored form takes each pair's time from there."""
    import inspect

    from inmoov_dsl.firmware import store
    from inmoov_dsl.protocol import frame, timed_pairs

    data = frame([(2, 90), (3, 45)])
    assert timed_pairs([0.0, 0.1, 0.2, 0.3, 0.4], data) == [(0.2, 2, 90), (0.4, 3, 45)]
    assert "[2::2]" not in inspect.getsource(store)
