"""Whether a profile can play a compiled gesture (a file people share): its boards, their
servo IDs and bauds are the profile's, and what each servo is sent keeps the limits the
compiler keeps: one value a 20 ms servo frame, no step faster than the servo's
max_velocity allows (the degree a value may be rounded by, and a frame, aside).
Errors point at the board in the profile (the servo's board, for its limits)."""

from __future__ import annotations

from ..boards import controller
from ..errors import Diagnostic, GestError, Pos
from ..hardware import Board, Profile
from ..protocol import SERVO_FRAME
from .compiled import Compiled
from .metrics import values_sent


def check_profile(c: Compiled, profile: Profile) -> None:
    """Raise GestError unless ``profile`` can play ``c``: each stream's board is a board
    of the profile, its servo IDs are that board's servos', and its baud is no faster
    than the board's link (bytes timed for a faster link would pile up); then what each
    servo is sent keeps its limits (``within_limits``). Errors point at the board in
    the profile."""
    boards = {b.id: b for b in profile.boards}
    hint = f"compile it for this profile: gestc compile GESTURE --profile {profile.name}"
    errors = []
    for s in c.streams:
        board = boards.get(s.board)
        if board is None:
            errors.append(Diagnostic(
                "error", f"'{c.gesture}' has a stream for board {s.board}, and profile "
                f"'{profile.name}' has no board {s.board} (its boards: "
                f"{', '.join(str(b) for b in boards)})", _board_pos(profile, None), hint))
            continue
        if s.kind != board.kind:
            errors.append(Diagnostic(
                "error", f"'{c.gesture}' is for board {s.board} as a {s.kind}, and profile "
                f"'{profile.name}' has a {board.kind} there", _board_pos(profile, board),
                hint))
            continue
        kind = controller(profile, board)
        if not kind.ours:
            if stray := sorted(kind.addressed(s.data) - kind.addresses()):
                errors.append(Diagnostic(
                    "error", f"'{c.gesture}' sets {kind.address} {stray[0]} of board "
                    f"{s.board}, which profile '{profile.name}' gives no servo",
                    _board_pos(profile, board), hint))
            continue
        ids = {profile.servos[profile.index(n)].id for n in board.servos}
        foreign = sorted(s.servo_ids - ids)
        if foreign:
            errors.append(Diagnostic(
                "error", f"'{c.gesture}' commands servo ID{'s' if len(foreign) > 1 else ''} "
                f"{', '.join(map(str, foreign))} on board {s.board}, which profile "
                f"'{profile.name}' does not give that board", _board_pos(profile, board), hint))
        if s.baud > board.baud:
            errors.append(Diagnostic(
                "error", f"'{c.gesture}' is timed for board {s.board} at {s.baud} baud, and "
                f"profile '{profile.name}' runs that board at {board.baud}",
                _board_pos(profile, board), "compile it again for the board's baud"))
    if errors:
        raise GestError(errors)
    if errors := within_limits(c, profile):
        raise GestError(errors)


def within_limits(c: Compiled, profile: Profile) -> list[Diagnostic]:
    """What ``c`` sends each servo, held to the servo's limits: the first value a servo
    is sent twice in a frame, and the first step faster than its max_velocity (from
    the start pose: the player first brings the hand there)."""
    errors = []
    hint = (f"it was not made by gestc compile for profile '{profile.name}', or was "
            "changed since: compile it again")
    for i, (times, values) in sorted(values_sent(profile, c.streams).items()):
        servo = profile.servos[i]
        where = _board_pos(profile, next(b for b in profile.boards if servo.name in b.servos))
        frames = (times / SERVO_FRAME - 1e-9).astype(int)  # frame f: (f, f + 1] * 20 ms
        twice = [k for k in range(1, len(frames)) if frames[k] == frames[k - 1]]
        if twice:
            k = twice[0]
            errors.append(Diagnostic(
                "error", f"'{c.gesture}' sends {servo.name} (ID {servo.id}) two values in "
                f"the servo frame ending at {(frames[k] + 1) * SERVO_FRAME:.2f} s: a servo "
                "takes one value a 20 ms frame", where, hint))
            continue
        before = [c.start[i], *values[:-1].tolist()]
        since = [0.0, *times[:-1].tolist()]
        for t, v, t0, v0 in zip(times.tolist(), values.tolist(), since, before,
                                strict=True):
            if abs(v - v0) > servo.max_velocity * (t - t0 + SERVO_FRAME) + 1:
                errors.append(Diagnostic(
                    "error", f"'{c.gesture}' moves {servo.name} (ID {servo.id}) from {v0} "
                    f"to {v} between {t0:.3f} s and {t:.3f} s: faster than its "
                    f"max_velocity, {servo.max_velocity:g} degrees a second", where, hint))
                break
    return errors


def _board_pos(profile: Profile, board: Board | None) -> Pos:
    """Where ``board`` (or the first board) is in the profile's file."""
    board = board or (profile.boards[0] if profile.boards else None)
    return (board.pos if board is not None and board.pos is not None
            else Pos(profile.path or "<profile>", 1, 1))
