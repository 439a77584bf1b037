"""Who answers on a serial port (``gestplay ports``): a board of ours or the original
firmware (its ID and servos, from DUMP), an Arduino running MyRobotLab's MrlComm (its
version), a Pololu Maestro (its errors), or nothing known. Only ports whose USB IDs
say Arduino or Maestro are asked, and a port the user names: bytes sent to an unknown
device could mean anything to it. An Arduino that opening its port reset is listened
to first, as the player does (``player.hear_boot``): a Mega's bootloader would take a
question for its own and not start the sketch for seconds."""

from __future__ import annotations

from .. import clock
from ..boards.arduino import ANY, Bootloader
from ..boards.maestro import commands as maestro
from ..boards.mrlcomm import messages as mrl
from ..decode import Replies
from ..errors import GestError
from ..protocol import ASK_POSE, DEFAULT_BAUD
from .ports import PortInfo, open_port
from .ready import DUMP_TIMEOUT, READY_TIMEOUT, ask, drain, hear_boot, wait_ready

POLOLU = 0x1FFB  #: Pololu's USB vendor ID
MAESTRO_BAUD = 115_200
MEGA_BAUD = 115_200  #: a Mega of ours (the InMoov's), as MyRobotLab opens its Megas
#: which Arduino is behind a port is not known: the longest a bootloader takes. Once
#: listened to, the board cannot be trapped by the questions: no waiting out a trap
ARDUINO = Bootloader("an Arduino's", "", ANY.window)


ASKS = 3  #: DUMPs asked of a board that said WAIT (a slow link, a busy computer)


def answer(info: PortInfo, baud: int = DEFAULT_BAUD, named: bool = False) -> str:
    """What answers on ``info``'s port, in words (``baud``: a board of ours'; a Mega of
    ours at 115200 is asked too, before MrlComm's question, which it would read as a
    servo command). ``named``: the user named the port; it is asked whatever its USB
    IDs, and a Maestro's question comes last."""
    if info.vid == POLOLU:
        return _maestro(info.device)
    if info.likely is None and not named:
        return "not asked (not an Arduino's USB IDs)"
    rates = list(dict.fromkeys((baud, MEGA_BAUD)))
    for rate in rates:
        said = _ours(info.device, rate)
        if said is not None:
            return said
    if said := _mrlcomm(info.device):
        return said
    if named and info.vid is None and (said := _maestro(info.device, quiet=True)):
        return said
    return f"nothing answered at {' or '.join(map(str, rates))} baud, nor MrlComm at " \
        f"{mrl.BAUD}" + (", nor a Maestro" if named and info.vid is None else "")


def _ours(device: str, baud: int) -> str | None:
    """A board of ours (or the original firmware) at ``baud``: its ID and servos, from
    DUMP; what went wrong with the port; or None if nothing of ours answered."""
    try:
        port = open_port(device, baud)
    except GestError as exc:
        return f"cannot open it: {exc.first.message}"
    try:
        ready = wait_ready(port, bootloader=ARDUINO)  # an Uno resets as its port opens
        drain(port)
        replies = Replies()
        for _ in range(ASKS if ready else 1):  # a board that said WAIT is asked again
            port.write(ASK_POSE)
            deadline = clock.now() + DUMP_TIMEOUT
            while clock.now() < deadline:
                if (found := replies.feed(drain(port))) is not None:
                    board, values = found
                    at = f" at {baud} baud" if baud != DEFAULT_BAUD else ""
                    return (f"board {board}, {len(values)} servos{at} (our firmware or the "
                            f"original)")
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
        answer = bytearray(hear_boot(port, ARDUINO))
        if not _board_info(answer) and not ask(port, mrl.message(mrl.GET_BOARD_INFO),
                                               _board_info, answer,
                                               clock.now() + READY_TIMEOUT, clock.now,
                                               clock.sleep):
            return None
        version = _board_info(answer)[0]
        known = "" if version == mrl.VERSION else \
            f" (gestplay speaks {mrl.VERSION}: {mrl.RELEASE})"
        return f"MyRobotLab's MrlComm, version {version}{known}: profile kind mrlcomm"
    except OSError:
        return None
    finally:
        port.close()


def _board_info(data: bytes) -> list | None:
    """The arguments of MrlComm's board info in ``data``, or None."""
    return next((args for method, args in mrl.Reader().feed(bytes(data))
                 if method == mrl.BOARD_INFO and args), None)


def _maestro(device: str, quiet: bool = False) -> str | None:
    """Get Errors on a Maestro's port: the Command Port answers it at once. ``quiet``:
    a port that may be no Maestro's: None unless it answers as one."""
    try:
        port = open_port(device, MAESTRO_BAUD)
    except GestError as exc:
        return None if quiet else f"cannot open it: {exc.first.message}"
    try:
        port.write(bytes([maestro.GET_ERRORS]))
        got, deadline = b"", clock.now() + DUMP_TIMEOUT
        while len(got) < 2 and clock.now() < deadline:
            got += drain(port)
            clock.sleep(0.005)
        if quiet and (len(got) != 2 or (got[0] | got[1] << 8) & ~maestro.ERROR_BITS):
            return None
        if len(got) < 2:
            return "a Maestro's port that does not answer (its TTL Port, or the Maestro " \
                "is not in USB Dual Port mode: docs/controllers.md)"
        errors = got[0] | got[1] << 8
        return "a Pololu Maestro's Command Port: " + \
            (f"errors: {maestro.describe(errors)} (cleared now)" if errors else "no errors")
    except OSError as exc:
        return None if quiet else f"the port failed: {exc}"
    finally:
        port.close()
