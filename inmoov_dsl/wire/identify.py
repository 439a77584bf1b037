"""Who answers on a serial port (``gestplay ports``): a board of ours or the original
firmware (its ID and servos, from DUMP), an Arduino running MyRobotLab's MrlComm (its
version), a Pololu Maestro (its errors), or nothing known. Only ports whose USB IDs
say Arduino or Maestro are asked: bytes sent to an unknown device could mean anything
to it."""

from __future__ import annotations

from .. import clock
from ..boards.maestro import commands as maestro
from ..boards.mrlcomm import messages as mrl
from ..decode import Replies
from ..errors import GestError
from ..protocol import ASK_POSE, DEFAULT_BAUD
from .player import DUMP_TIMEOUT, PROBE, READY_TIMEOUT, drain, wait_ready
from .ports import PortInfo, open_port

POLOLU = 0x1FFB  #: Pololu's USB vendor ID
MAESTRO_BAUD = 115_200
MEGA_BAUD = 115_200  #: a Mega of ours (the InMoov's), as MyRobotLab opens its Megas


def answer(info: PortInfo, baud: int = DEFAULT_BAUD) -> str:
    """What answers on ``info``'s port, in words (``baud``: a board of ours'; a Mega of
    ours at 115200 is asked too, before MrlComm's question, which it would read as a
    servo command)."""
    if info.vid == POLOLU:
        return _maestro(info.device)
    if info.likely is None:
        return "not asked (not an Arduino's USB IDs)"
    rates = list(dict.fromkeys((baud, MEGA_BAUD)))
    for rate in rates:
        said = _ours(info.device, rate)
        if said is not None:
            return said
    return _mrlcomm(info.device) or f"nothing answered at {' or '.join(map(str, rates))} " \
        f"baud, nor MrlComm at {mrl.BAUD}"


def _ours(device: str, baud: int) -> str | None:
    """A board of ours (or the original firmware) at ``baud``: its ID and servos, from
    DUMP; what went wrong with the port; or None if nothing of ours answered."""
    try:
        port = open_port(device, baud)
    except GestError as exc:
        return f"cannot open it: {exc.first.message}"
    try:
        ready = wait_ready(port)  # an Uno resets as its port opens: it boots first
        drain(port)
        port.write(ASK_POSE)
        replies, deadline = Replies(), clock.now() + DUMP_TIMEOUT
        while clock.now() < deadline:
            if (found := replies.feed(drain(port))) is not None:
                board, values = found
                at = f" at {baud} baud" if baud != DEFAULT_BAUD else ""
                return f"board {board}, {len(values)} servos{at} (our firmware or the original)"
            clock.sleep(0.005)
        if ready:
            return f"a board that sends WAIT at {baud} baud but did not answer DUMP"
    except OSError as exc:
        return f"the port failed: {exc}"
    finally:
        port.close()
    return None


def _mrlcomm(device: str) -> str | None:
    """MrlComm's board info, asked as MyRobotLab asks it (the board resets as its port
    opens, then prints its banner and begin message): its version, or None."""
    try:
        port = open_port(device, mrl.BAUD)
    except GestError:
        return None
    try:
        reader, deadline, probe = mrl.Reader(), clock.now() + READY_TIMEOUT, 0.0
        while clock.now() < deadline:
            if clock.now() >= probe:
                port.write(mrl.message(mrl.GET_BOARD_INFO))
                probe = clock.now() + PROBE
            for method, args in reader.feed(drain(port)):
                if method == mrl.BOARD_INFO and args:
                    known = "" if args[0] == mrl.VERSION else \
                        f" (gestplay speaks {mrl.VERSION}: {mrl.RELEASE})"
                    return f"MyRobotLab's MrlComm, version {args[0]}{known}: profile " \
                           "kind mrlcomm"
            clock.sleep(0.005)
    except OSError:
        return None
    finally:
        port.close()
    return None


def _maestro(device: str) -> str:
    """Get Errors on a Maestro's port: the Command Port answers it at once."""
    try:
        port = open_port(device, MAESTRO_BAUD)
    except GestError as exc:
        return f"cannot open it: {exc.first.message}"
    try:
        port.write(bytes([maestro.GET_ERRORS]))
        got, deadline = b"", clock.now() + DUMP_TIMEOUT
        while len(got) < 2 and clock.now() < deadline:
            got += drain(port)
            clock.sleep(0.005)
        if len(got) < 2:
            return "a Maestro's port that does not answer (its TTL Port, or the Maestro " \
                "is not in USB Dual Port mode: docs/controllers.md)"
        errors = got[0] | got[1] << 8
        return "a Pololu Maestro's Command Port: " + \
            (f"errors: {maestro.describe(errors)} (cleared now)" if errors else "no errors")
    except OSError as exc:
        return f"the port failed: {exc}"
    finally:
        port.close()
