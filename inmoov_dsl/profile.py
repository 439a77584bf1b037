"""Robot profiles: boards, servos, limits and groups, read from TOML."""

from __future__ import annotations

import hashlib
import re
import tomllib
from dataclasses import dataclass, replace
from functools import cached_property
from pathlib import Path
from typing import Any

from . import protocol
from .errors import Diagnostic, GestError, Pos, did_you_mean
from .resources import profiles_dir

NAME_RE = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")
KEYWORDS = frozenset({"use", "group", "pose", "wait", "hold", "repeat", "over", "stagger"})


@dataclass(frozen=True)
class Servo:
    """One servo, in command degrees (0..180 as sent on the wire)."""

    name: str
    id: int
    board: int
    lo: int  #: smallest value a gesture may command
    hi: int  #: largest value a gesture may command
    rest: int
    max_velocity: float  #: command degrees / s
    max_acceleration: float  #: command degrees / s^2
    max_jerk: float  #: command degrees / s^3
    calibration: tuple[int, int]  #: board side: 0..180 is mapped onto these servo angles
    reversed: bool  #: board side: 180..0 is mapped onto the calibration instead
    pin: int | None


@dataclass(frozen=True)
class Board:
    id: int
    name: str
    baud: int
    servos: tuple[str, ...]


@dataclass(frozen=True)
class Sensor:
    """One flex sensor of a glove: the servo it commands and how it reads."""

    servo: str
    pin: int  #: analog pin (14 is A0 on an Uno or Nano)
    calibration: tuple[int, int]  #: readings (0..1023) that map to 0 and 180
    reversed: bool = False  #: the low reading maps to 180 instead


@dataclass(frozen=True)
class Glove:
    """A flex-sensor glove: it reads its sensors and commands a servo board."""

    id: int
    name: str
    board: int  #: the servo board it sends to, on its software serial command port
    baud: int  #: USB, to the computer
    command_pins: tuple[int, int]  #: rx, tx of the command port
    deadband: int  #: command degrees a value must move before it is sent again
    frame_ms: int  #: ms between readings
    sensors: tuple[Sensor, ...]


@dataclass(frozen=True)
class Profile:
    name: str
    description: str
    boards: tuple[Board, ...]
    servos: tuple[Servo, ...]  #: board by board, in each board's order
    groups: dict[str, tuple[str, ...]]
    path: str = ""
    sha256: str = ""  #: of the TOML text it was read from
    gloves: tuple[Glove, ...] = ()

    def index(self, name: str) -> int:
        """The position of servo ``name`` in ``servos``; KeyError if there is none."""
        return self._indices[name]

    @cached_property
    def _indices(self) -> dict[str, int]:
        return {servo.name: i for i, servo in enumerate(self.servos)}

    @cached_property
    def names(self) -> tuple[str, ...]:
        return tuple(s.name for s in self.servos)

    @property
    def rest_pose(self) -> dict[str, int]:
        return {s.name: s.rest for s in self.servos}


def builtin_profiles() -> list[str]:
    """Names of the profiles shipped with the package."""
    return sorted(p.stem for p in profiles_dir().glob("*.toml"))


def profiles_with(name: str) -> list[str]:
    """The built-in profiles that have a servo or a group called ``name``."""
    found = []
    for builtin in builtin_profiles():
        try:
            profile = load_profile(builtin)
        except GestError:
            continue
        if name in profile.names or name in profile.groups:
            found.append(builtin)
    return found


def find_profile(name_or_path: str) -> Path:
    """A profile file from a built-in name (``rhand``) or a path."""
    path = Path(name_or_path)
    if path.suffix == ".toml" or len(path.parts) > 1:
        if not path.is_file():
            raise GestError(Diagnostic("error", f"profile file '{name_or_path}' not found"))
        return path
    builtin = profiles_dir() / f"{name_or_path}.toml"
    if builtin.is_file():
        return builtin
    names = builtin_profiles()
    hint = did_you_mean(name_or_path, names) or f"built-in profiles: {', '.join(names)}"
    raise GestError(Diagnostic("error", f"unknown profile '{name_or_path}'", hint=hint))


def load_profile(name_or_path: str) -> Profile:
    """Read and check a profile; any problem is a GestError naming the file."""
    path = find_profile(name_or_path)
    text = path.read_text(encoding="utf-8")
    return parse_profile(text, str(path))


def parse_profile(text: str, file: str = "<profile>") -> Profile:
    """Build a Profile from TOML text. Pure: no file access."""
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        match = re.search(r"\(at line (\d+), column (\d+)\)", str(exc))
        pos = Pos(file, int(match[1]), int(match[2])) if match else None
        message = re.sub(r"\s*\(at line.*\)", "", str(exc))
        lines = text.splitlines()
        line = lines[pos.line - 1] if pos and pos.line <= len(lines) else None
        raise GestError(Diagnostic("error", f"invalid TOML: {message}", pos, None, line)) from None
    profile = _Builder(data, file).build()
    return replace(profile, sha256=hashlib.sha256(text.encode("utf-8")).hexdigest())


class _Builder:
    def __init__(self, data: dict[str, Any], file: str):
        self.data = data
        self.file = file
        self.errors: list[Diagnostic] = []

    def fail(self, message: str, hint: str | None = None) -> None:
        self.errors.append(Diagnostic("error", message, Pos(self.file, 1, 1), hint))

    def number(self, where: str, table: dict, key: str, default=None, positive=True):
        value = table.get(key, default)
        if value is None:
            self.fail(f"{where}: missing '{key}'")
            return 1.0
        if isinstance(value, bool) or not isinstance(value, int | float):
            self.fail(f"{where}: '{key}' must be a number, got {value!r}")
            return 1.0
        if positive and not value > 0:
            self.fail(f"{where}: '{key}' must be greater than 0, got {value}")
            return 1.0
        return value

    def pair(self, where: str, table: dict, key: str, default: tuple[int, int]) -> tuple[int, int]:
        value = table.get(key, list(default))
        ok = (
            isinstance(value, list)
            and len(value) == 2
            and all(isinstance(v, int) and not isinstance(v, bool) for v in value)
            and 0 <= value[0] <= value[1] <= protocol.MAX_VALUE
        )
        if not ok:
            self.fail(f"{where}: '{key}' must be [low, high] with 0 <= low <= high <= 180, "
                      f"got {value!r}")
            return default
        return (value[0], value[1])

    def build(self) -> Profile:
        data = self.data
        name = data.get("name", Path(self.file).stem)
        boards_data = data.get("board", [])
        servos_data = data.get("servo", {})
        if not isinstance(boards_data, list) or not boards_data:
            self.fail("a profile needs at least one [[board]]")
            raise GestError(self.errors)
        if not isinstance(servos_data, dict):
            self.fail("[servo.NAME] tables expected")
            raise GestError(self.errors)

        boards: list[Board] = []
        servos: list[Servo] = []
        owner: dict[str, int] = {}
        for b in boards_data:
            bid = b.get("id")
            where = f"board {bid}"
            low, high = protocol.FIRST_BOARD_ID, min(protocol.Signal) - 1
            if not isinstance(bid, int) or not low <= bid <= high:
                self.fail(f"board id must be a whole number in {low}..{high}, got {bid!r}")
                continue
            if any(x.id == bid for x in boards):
                self.fail(f"board {bid} is declared twice")
            baud = b.get("baud", 9600)
            if not isinstance(baud, int) or baud <= 0:
                self.fail(f"{where}: 'baud' must be a positive whole number, got {baud!r}")
                baud = 9600
            elif protocol.pairs_per_frame(baud) < 1:
                self.fail(f"{where}: baud {baud} is too slow: not one servo command fits "
                          f"in a 20 ms servo frame", hint="use 9600 or more")
            names = b.get("servos", [])
            if not isinstance(names, list) or not all(isinstance(n, str) for n in names):
                self.fail(f"{where}: 'servos' must be a list of servo names")
                names = []
            for n in names:
                if n in owner:
                    self.fail(f"servo '{n}' is on board {owner[n]} and board {bid}")
                owner[n] = bid
            boards.append(Board(bid, str(b.get("name", f"board {bid}")), baud, tuple(names)))

        for servo_name in owner:
            if servo_name not in servos_data:
                hint = did_you_mean(servo_name, servos_data)
                self.fail(f"board {owner[servo_name]} lists servo '{servo_name}' "
                          f"but there is no [servo.{servo_name}]", hint)
        for servo_name in servos_data:
            if servo_name not in owner:
                self.fail(f"servo '{servo_name}' is on no board",
                          hint="add it to the 'servos' list of a [[board]]")

        ids: dict[int, str] = {}
        for board in boards:
            for servo_name in board.servos:
                s = servos_data.get(servo_name)
                if not isinstance(s, dict):
                    continue
                servos.append(self.servo(servo_name, s, board.id, ids))

        groups = self.groups(data.get("groups", {}), [s.name for s in servos])
        gloves = self.gloves(data.get("glove", []), boards)
        if self.errors:
            raise GestError(self.errors)
        return Profile(str(name), str(data.get("description", "")), tuple(boards),
                       tuple(servos), groups, self.file, gloves=gloves)

    def servo(self, name: str, s: dict, board: int, ids: dict[int, str]) -> Servo:
        where = f"servo '{name}'"
        if not NAME_RE.match(name) or name in KEYWORDS:
            self.fail(f"{where}: a servo name must be a word (letters, digits, _) "
                      f"and not a keyword of the language")
        sid = s.get("id")
        if not isinstance(sid, int) or isinstance(sid, bool) or not 0 <= sid <= 180:
            self.fail(f"{where}: 'id' must be a whole number in 0..180, got {sid!r}")
            sid = 0
        elif sid in ids:
            self.fail(f"{where}: id {sid} is already used by servo '{ids[sid]}'")
        ids[sid] = name
        lo, hi = self.pair(where, s, "range", (0, protocol.MAX_VALUE))
        rest = s.get("rest", lo)
        if not isinstance(rest, int) or not lo <= rest <= hi:
            self.fail(f"{where}: 'rest' must be a whole number in its range {lo}..{hi}, "
                      f"got {rest!r}")
            rest = lo
        pin = s.get("pin")
        if pin is not None and (not isinstance(pin, int) or pin < 0):
            self.fail(f"{where}: 'pin' must be a whole number, got {pin!r}")
        return Servo(
            name=name, id=sid, board=board, lo=lo, hi=hi, rest=rest,
            max_velocity=float(self.number(where, s, "max_velocity")),
            max_acceleration=float(self.number(where, s, "max_acceleration")),
            max_jerk=float(self.number(where, s, "max_jerk")),
            calibration=self.pair(where, s, "calibration", (0, protocol.MAX_VALUE)),
            reversed=bool(s.get("reversed", False)),
            pin=pin,
        )

    def whole(self, where: str, table: dict, key: str, default: int, low: int, high: int
              ) -> int:
        value = table.get(key, default)
        if isinstance(value, bool) or not isinstance(value, int) or not low <= value <= high:
            self.fail(f"{where}: '{key}' must be a whole number in {low}..{high}, "
                      f"got {value!r}")
            return default
        return value

    def gloves(self, data: Any, boards: list[Board]) -> tuple[Glove, ...]:
        if not isinstance(data, list) or not all(isinstance(g, dict) for g in data):
            self.fail("[[glove]] tables expected")
            return ()
        taken = {b.id for b in boards}
        out = []
        for g in data:
            gid = g.get("id")
            where = f"glove {gid}"
            low, high = protocol.FIRST_BOARD_ID, min(protocol.Signal) - 1
            if not isinstance(gid, int) or not low <= gid <= high or gid in taken:
                self.fail(f"glove id must be a board ID in {low}..{high} that no other "
                          f"board has, got {gid!r}")
                continue
            taken.add(gid)
            board = g.get("board")
            target = next((b for b in boards if b.id == board), None)
            if target is None:
                self.fail(f"{where}: 'board' must be the ID of a servo board of the profile, "
                          f"got {board!r}")
                continue
            pins = g.get("command_pins", [10, 11])
            if not (isinstance(pins, list) and len(pins) == 2
                    and all(isinstance(p, int) and 0 <= p <= 255 for p in pins)):
                self.fail(f"{where}: 'command_pins' must be [rx, tx], got {pins!r}")
                pins = [10, 11]
            sensors = []
            for k, sd in enumerate(g.get("sensors", [])):
                swhere = f"{where}, sensor {k + 1}"
                if not isinstance(sd, dict):
                    self.fail(f"{swhere}: expected {{ servo = ..., pin = ..., "
                              f"calibration = [low, high] }}")
                    continue
                servo = sd.get("servo")
                if servo not in target.servos:
                    self.fail(f"{swhere}: 'servo' must be a servo of board {board}, "
                              f"got {servo!r}", did_you_mean(str(servo), target.servos))
                    continue
                cal = sd.get("calibration")
                if not (isinstance(cal, list) and len(cal) == 2
                        and all(isinstance(c, int) and not isinstance(c, bool) for c in cal)
                        and 0 <= cal[0] < cal[1] <= 1023):
                    self.fail(f"{swhere}: 'calibration' must be [low, high] readings with "
                              f"0 <= low < high <= 1023, got {cal!r}")
                    continue
                sensors.append(Sensor(servo, self.whole(swhere, sd, "pin", 14, 0, 255),
                                      (cal[0], cal[1]), bool(sd.get("reversed", False))))
            if not sensors:
                self.fail(f"{where}: a glove needs at least one sensor")
                continue
            out.append(Glove(gid, str(g.get("name", f"glove {gid}")), board,
                             self.whole(where, g, "baud", 9600, 300, 2_000_000),
                             (pins[0], pins[1]), self.whole(where, g, "deadband", 2, 0, 180),
                             self.whole(where, g, "frame_ms", 20, 1, 1000), tuple(sensors)))
        return tuple(out)

    def groups(self, data: Any, servo_names: list[str]) -> dict[str, tuple[str, ...]]:
        groups: dict[str, tuple[str, ...]] = {}
        if not isinstance(data, dict):
            self.fail("[groups] must map a group name to a list of servo names")
            return groups
        for gname, members in data.items():
            if not isinstance(members, list) or not all(isinstance(m, str) for m in members):
                self.fail(f"group '{gname}' must be a list of servo names")
                continue
            if gname in servo_names:
                self.fail(f"group '{gname}' has the name of a servo")
            for m in members:
                if m not in servo_names:
                    self.fail(f"group '{gname}' names unknown servo '{m}'",
                              did_you_mean(m, servo_names))
            groups[gname] = tuple(members)
        groups.setdefault("all", tuple(servo_names))
        return groups
