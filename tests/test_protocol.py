from inmoov_dsl import protocol
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
