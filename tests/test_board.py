"""The board's rules: the conformance vectors (shared with the firmware), the
calibration mapping, and the original firmware's reading of RELAX."""

import pytest
from hypothesis import given
from hypothesis import strategies as st
from vectors import BOARD as VECTORS
from vectors import vector_board

from inmoov_dsl.boards.rig.core import BoardCore


@pytest.mark.parametrize("case", VECTORS["cases"], ids=lambda c: c["name"])
def test_conformance_vectors(case):
    board = vector_board()
    writes, out = [], b""
    for byte in case["in"]:
        write, reply = board.feed(byte)
        if write:
            writes.append([write.id, write.value, write.angle])
        out += reply
    assert writes == case["writes"]
    assert list(out) == case["out"]
    assert board.relaxed == case.get("relaxed", False)


def test_the_right_hand_profile_is_the_vectors_board(rhand):
    core = BoardCore.from_profile(rhand, rhand.boards[0])
    assert core.servos == vector_board().servos


@given(st.lists(st.integers(0, 255), max_size=300))
def test_random_bytes_never_write_above_180_or_a_servo_it_lacks(data):
    board = vector_board()
    for byte in data:
        write, _ = board.feed(byte)
        if write:
            assert 0 <= write.value <= 180 and 0 <= write.id <= 5
            assert 35 <= write.angle <= 160
    # after a CANCEL the board is in step again, whatever came before
    board.feed(255)
    write, _ = board.feed(2)
    assert write is None
    write, _ = board.feed(77)
    assert (write.id, write.value) == (2, 77)


def test_the_original_firmware_ignores_the_relax_bytes_and_stays_in_step():
    """RELAX goes out as CANCEL RELAX CANCEL: the original board reads RELAX as a servo
    it does not have, and the CANCEL drops it before any value."""
    from boardmodel import read_stream

    from inmoov_dsl.protocol import RELAX_BOARD as RELAX

    data = [255, 2, 90, *RELAX, 3, 60, *RELAX, *RELAX, 4, 30]
    events = read_stream(range(len(data)), data, 9600, owned={0, 1, 2, 3, 4, 5})
    assert [(sid, v) for _, sid, v in events] == [(2, 90), (3, 60), (4, 30)]
    ours = vector_board()
    writes = [w for w in (ours.feed(b)[0] for b in data) if w]
    assert [(w.id, w.value) for w in writes] == [(2, 90), (3, 60), (4, 30)]
