"""One validator per table of a profile (its own keys, ``[[board]]``, ``[servo.NAME]``,
``[groups]``, ``[sides]``, ``[[glove]]`` and a glove's sensors), and one for each kind
of table the top level holds (``board_tables``, ``servo_tables``, ``glove_tables``):
each takes the table's data and what the tables before it hold, and returns what it
reads, reporting every problem at the line of the key it is about. ``profile`` loops
over the tables, calls them in order and checks across tables; the values are checked
by ``fields``."""

from __future__ import annotations

from collections.abc import Collection, Mapping
from typing import Any

from .. import protocol
from ..boards import DEFAULT_KIND, TABLES
from ..errors import did_you_mean
from ..hardware import Board, Glove, Sensor, Servo
from ..language.syntax import KEYWORDS
from . import fields as check
from . import kinds
from .fields import NAME_RE, Check, Fields, Problem, cut, is_whole, shown
from .keys import Key, Report

BOARD_IDS = (protocol.FIRST_BOARD_ID, protocol.LAST_BOARD_ID)  #: a board's or glove's ID
FULL = (0, protocol.MAX_VALUE)
SENSOR = "{ servo = ..., pin = ..., calibration = [low, high] }"
#: the keys each table takes (a board's kind adds its own: ``boards.TABLES``)
TOP = ("name", "description", "board", "servo", "groups", "sides", "glove", "voice",
       "collision", "place")
BOARD = ("id", "name", "kind", "baud", "servos")
SERVO = ("id", "range", "rest", "pin", "reversed", "max_velocity", "max_acceleration",
         "max_jerk", "calibration", "joint", "pulse")
GLOVE = ("id", "board", "name", "baud", "command_pins", "deadband", "frame_ms", "sensors")
SENSOR_KEYS = ("servo", "pin", "calibration", "reversed")


def top(report: Report, data: dict[str, Any], stem: str) -> tuple[str, str]:
    """The profile's own ``name`` (``stem``, the file's name, when it has none) and
    ``description``."""
    fields = Fields(report, (), data, TOP)
    return fields.get("name", check.text, stem), fields.get("description", check.text, "")


def board_tables(report: Report, data: dict[str, Any]) -> list[Any]:
    """The profile's ``[[board]]`` tables: at least one, else an error that stops the
    build."""
    found = data.get("board", [])
    if not isinstance(found, list) or not found:
        report.error(("board",), "a profile needs at least one [[board]]")
        report.stop()
    return found


def servo_tables(report: Report, data: dict[str, Any]) -> dict[str, Any]:
    """The profile's ``[servo.NAME]`` tables, by name; anything else is an error that
    stops the build."""
    found = data.get("servo", {})
    if not isinstance(found, dict):
        report.error(("servo",), "[servo.NAME] tables expected")
        report.stop()
    return found


def glove_tables(report: Report, data: dict[str, Any]) -> list[dict[str, Any]]:
    """The profile's ``[[glove]]`` tables (none when it has none); anything else is an
    error, and no glove."""
    found = data.get("glove", [])
    if not isinstance(found, list) or not all(isinstance(g, dict) for g in found):
        report.error(("glove",), "[[glove]] tables expected")
        return []
    return found


def board(report: Report, k: int, data: Any, taken: Collection[int],
          listed: Mapping[str, int], servos: Collection[str]) -> Board | None:
    """The ``k``th ``[[board]]``, or None when it has no usable ID. ``taken``: the IDs
    of the boards before it; ``listed``: the servos they list, and by which board;
    ``servos``: the names of the ``[servo.NAME]`` tables."""
    at: Key = ("board", k)
    if not isinstance(data, dict):
        report.error(at, f"board {k + 1}: expected a [[board]] table, got {shown(data)}")
        return None
    bid = data.get("id")
    low, high = BOARD_IDS
    usable = is_whole(bid) and low <= bid <= high
    keys, elsewhere = kinds.keys(BOARD, data.get("kind", DEFAULT_KIND))
    fields = Fields(report, at, data, keys, f"board {bid if usable else k + 1}", elsewhere)
    if not usable:
        report.error((*at, "id"), f"board id must be a whole number in {low}..{high}, "
                     f"got {shown(bid)}")
        return None
    if bid in taken:
        report.error((*at, "id"), f"board {bid} is declared twice")
    what = fields.get("kind", kinds.kind, DEFAULT_KIND, fallback="")  # "": that error alone
    table = TABLES.get(what)
    speed = fields.get("baud", check.baud, table.baud if table else protocol.DEFAULT_BAUD)
    servo_names = fields.get("servos", check.names, [])
    mine: dict[str, int] = {}
    for i, name in enumerate(servo_names):
        other = mine.get(name, listed.get(name))
        if other is not None:
            report.error((*at, "servos", i), f"servo '{cut(name)}' is on board {other} and "
                         f"board {bid}")
        elif name not in servos:
            report.error((*at, "servos", i), f"board {bid} lists servo '{cut(name)}' but "
                         f"there is no [servo.{cut(name)}]", did_you_mean(name, servos))
        mine[name] = bid
    label = fields.get("name", check.text, f"board {bid}")
    return Board(bid, label, speed, tuple(mine), report.where((*at, "id")), what,
                 kinds.options(fields, table) if table else ())


def servo(report: Report, name: str, data: Any, board_id: int, ids: Mapping[int, str]
          ) -> Servo | None:
    """``[servo.NAME]`` of a servo on board ``board_id``, or None when it is not a
    table. ``ids``: the servo IDs taken before it, and by which servo."""
    if not isinstance(data, dict):
        report.error(("servo", name), f"servo '{cut(name)}': expected a [servo.{cut(name)}] "
                     f"table, got {shown(data)}")
        return None
    fields = Fields(report, ("servo", name), data, SERVO, f"servo '{cut(name)}'")
    if not NAME_RE.match(name) or name in KEYWORDS:
        fields.fail("a servo name must be a word (letters, digits, _) and not a keyword of "
                    "the language")
    sid = fields.get("id", check.whole(0, protocol.MAX_SERVO_ID))
    if sid in ids:
        fields.fail(f"id {sid} is already used by servo '{cut(ids[sid])}'", ("id",))
    lo, hi = fields.get("range", check.span, FULL)
    return Servo(
        name=name, id=sid or 0, board=board_id, lo=lo, hi=hi,
        rest=fields.get("rest", check.whole(lo, hi, f"its range {lo}..{hi}"), lo),
        pin=fields.get("pin", check.optional(check.whole(0, 255))),
        reversed=fields.get("reversed", check.flag, False),
        max_velocity=fields.get("max_velocity", check.limit, fallback=1.0),
        max_acceleration=fields.get("max_acceleration", check.limit, fallback=1.0),
        max_jerk=fields.get("max_jerk", check.limit, fallback=1.0),
        calibration=fields.get("calibration", check.span, FULL),
        joint=fields.get("joint", check.joint, name),
        joint_at=report.index.find(("servo", name, "joint")),
        pulse=fields.get("pulse", check.optional(kinds.pulse)),
    )


def groups(report: Report, data: Any, servos: tuple[str, ...]) -> dict[str, tuple[str, ...]]:
    """``[groups]``: each a list of the profile's ``servos``; ``all`` is every servo."""
    if not isinstance(data, dict):
        report.error(("groups",), "[groups] must map a group name to a list of servo names")
        return {}
    found: dict[str, tuple[str, ...]] = {}
    known = set(servos)
    for name, members in data.items():
        at: Key = ("groups", name)
        if not isinstance(members, list) or not all(isinstance(m, str) for m in members):
            report.error(at, f"group '{cut(name)}' must be a list of servo names")
            continue
        if not NAME_RE.match(name) or name in KEYWORDS:
            report.error(at, f"group '{cut(name)}': a group name must be a word (letters, "
                         f"digits, _) and not a keyword of the language")
        if name in known:
            report.error(at, f"group '{name}' has the name of a servo")
        for i, member in enumerate(members):
            if member not in known:
                report.error((*at, i), f"group '{cut(name)}' names unknown servo "
                             f"'{cut(member)}'", did_you_mean(member, servos))
        found[name] = tuple(members)
    found.setdefault("all", servos)
    return found


SIDES = ("right", "left")


def sides(report: Report, data: Any, servos: tuple[str, ...]) -> dict[str, tuple[str, ...]]:
    """``[sides]``: ``right`` and ``left``, lists of servos of the same length, the k-th
    of each the mirror image of the other's; no servo on both sides or twice."""
    if isinstance(data, dict) and Fields(report, ("sides",), data, SIDES, "[sides]").unknown:
        return {}
    if not isinstance(data, dict) or set(data) != set(SIDES):
        report.error(("sides",), "[sides] must have 'right' and 'left': lists of servos, "
                     "each the mirror image of the other's at the same place")
        return {}
    found: dict[str, tuple[str, ...]] = {}
    seen: dict[str, str] = {}
    for side in SIDES:
        names = data[side]
        if not isinstance(names, list) or not all(isinstance(n, str) for n in names):
            report.error(("sides", side), f"[sides] {side} must be a list of servo names")
            return {}
        for i, name in enumerate(names):
            if name not in servos:
                report.error(("sides", side, i), f"[sides] {side} names unknown servo "
                             f"'{cut(name)}'", did_you_mean(name, servos))
            elif name in seen:
                report.error(("sides", side, i), f"servo '{name}' is on the {seen[name]} "
                             f"side already")
            seen[name] = side
        found[side] = tuple(names)
    if len(found["right"]) != len(found["left"]):
        report.error(("sides", "left"), f"[sides] right has {len(found['right'])} servos "
                     f"and left {len(found['left'])}: each needs its mirror image")
    return found


def glove(report: Report, k: int, data: dict[str, Any], boards: Mapping[int, Board],
          taken: Collection[int]) -> Glove | None:
    """The ``k``th ``[[glove]]``, commanding one of ``boards``; None when it cannot be
    built. ``taken``: the IDs of the boards and of the gloves before it."""
    at: Key = ("glove", k)
    gid = data.get("id")
    low, high = BOARD_IDS
    usable = is_whole(gid) and low <= gid <= high and gid not in taken
    fields = Fields(report, at, data, GLOVE, f"glove {gid if usable else k + 1}")
    if not usable:
        report.error((*at, "id"), f"glove id must be a board ID in {low}..{high} that no "
                     f"other board has, got {shown(gid)}")
        return None
    target = fields.get("board", _board_of(boards))
    if target is None:
        return None
    command_pins = fields.get("command_pins", check.pins, (10, 11))
    sensors_data = data.get("sensors", [])
    if not isinstance(sensors_data, list):
        fields.fail(f"'sensors' must be a list of {SENSOR}", ("sensors",))
        return None
    sensors = [s for n, one in enumerate(sensors_data)
               if (s := sensor(report, at, n, one, target, f"glove {gid}")) is not None]
    if not sensors:
        fields.fail("a glove needs at least one sensor", ("sensors",))
        return None
    label = fields.get("name", check.text, f"glove {gid}")
    baud = fields.get("baud", check.whole(300, protocol.MAX_BAUD), protocol.DEFAULT_BAUD)
    return Glove(gid, label, target.id, baud,
                 command_pins, fields.get("deadband", check.whole(0, protocol.MAX_VALUE), 2),
                 fields.get("frame_ms", check.whole(1, 1000), 20), tuple(sensors))


def _board_of(boards: Mapping[int, Board]) -> Check[Board]:
    """The check of a glove's ``board``: the ID of one of ``boards``."""
    def of_profile(key: str, value: Any) -> Board:
        """The board whose ID ``value`` is."""
        if not is_whole(value) or value not in boards:
            raise Problem(f"'{key}' must be the ID of a servo board of the profile, got "
                          f"{shown(value)}")
        return boards[value]
    return of_profile


def sensor(report: Report, glove_at: Key, n: int, data: Any, board: Board, where: str
           ) -> Sensor | None:
    """The ``n``th sensor of the glove at ``glove_at`` (named ``where`` in errors),
    reading for a servo of ``board``; None when it cannot be built."""
    fields = Fields(report, (*glove_at, "sensors", n), data, SENSOR_KEYS,
                    f"{where}, sensor {n + 1}")
    if not isinstance(data, dict):
        fields.fail(f"expected {SENSOR}")
        return None

    def of_board(key: str, value: Any) -> str:
        """A servo of the glove's board."""
        if value not in board.servos:
            raise Problem(f"'{key}' must be a servo of board {board.id}, got {shown(value)}",
                          did_you_mean(str(value), board.servos))
        return value

    name = fields.get("servo", of_board)
    if name is None:
        return None
    calibration = fields.get("calibration", check.readings)
    if calibration is None:
        return None
    reverse = fields.get("reversed", check.flag, False)
    return Sensor(name, fields.get("pin", check.whole(0, 255), 14), calibration, reverse)
