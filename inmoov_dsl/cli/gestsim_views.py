"""gestsim's live views in the terminal: a bar per servo (``BarsView``), the hand drawn
in coloured half blocks (``HandView``), or the whole robot's model in 3-D
(``RobotView``). Each shows every board gestsim serves: each board's turns hand over
its values (``Feed``); the view is drawn at once with the rest pose, then redrawn in
place when the values change."""

from __future__ import annotations

import sys
import threading
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

from ..views.posebars import bar_lines

if TYPE_CHECKING:
    from ..hardware import Board, Profile
    from ..wire.sim import VirtualBoard

FRAME = 0.05  #: s between redraws of the live view


class Feed:
    """One board's side of a view of several: what the board holds, handed to the view
    at each turn of the board's loop (``draw``, as the loop calls a view)."""

    def __init__(self, view: Any, board: Board):
        self.view, self.board = view, board.id

    def draw(self, board: VirtualBoard, now: float) -> None:
        """Hand the board's values to the view."""
        self.view.update(self.board, board.core.values, now)


class BarsView:
    """The boards' values in the terminal, redrawn in place when they change (at most
    every FRAME): a bar per servo, board after board."""

    def __init__(self, profile: Profile, boards: Sequence[Board]):
        self.profile = profile
        self.names = [name for b in boards for name in b.servos]
        self.values = {b.id: [profile.servos[profile.index(n)].rest for n in b.servos]
                       for b in boards}
        self.first = boards[0].id
        self.next = 0.0
        self.shown: list[int] | None = None
        self.height = 0  # lines drawn last time

    def lines(self, values: list[int]) -> list[str]:
        """A line per servo: its name, value and a bar (``posebars``)."""
        return bar_lines(zip(self.names, values, strict=True))

    def draw(self, board: VirtualBoard, now: float) -> None:
        """The first board's values (a view of one board, drawn by its loop)."""
        self.update(self.first, board.core.values, now)

    def update(self, board: int, values: Sequence[int], now: float) -> None:
        """Board ``board`` holds ``values``: redraw if anything changed and a frame has
        passed."""
        self.values[board] = values
        if now < self.next:
            return
        every = [v for held in self.values.values() for v in held]
        if every == self.shown:
            return
        self.next = now + FRAME
        self.shown = every
        lines = self.lines(every)
        out = sys.stderr
        if self.height:
            out.write(f"\x1b[{self.height}F")
        out.write("".join(f"\x1b[2K{line}\n" for line in lines))
        out.flush()
        self.height = len(lines)


class HandView(BarsView):
    """The hand drawn in the terminal (gestc preview's picture of a hand)."""

    def __init__(self, profile: Profile, boards: Sequence[Board]):
        from ..views.preview import draw_hand, hand_servos, pose_of, to_terminal

        super().__init__(profile, boards)
        hand_servos(profile)  # a profile without a hand is an error now, not later
        self.ids = [profile.servos[profile.index(n)].id for n in self.names]
        self.draw_hand, self.pose_of, self.to_terminal = draw_hand, pose_of, to_terminal
        draw_hand({})  # Pillow is there

    def lines(self, values: list[int]) -> list[str]:
        """The hand in that pose, as coloured half-block characters."""
        pose = self.pose_of(self.profile, values, self.ids)
        return self.to_terminal(self.draw_hand(pose), columns=48)


class RobotView(BarsView):
    """The robot's whole model in 3-D in the terminal (gestc preview's picture of a
    robot), every servo the boards do not hold at rest; fitted to the rest pose, and
    made larger whenever a pose leaves it, to hold every pose it has shown."""

    COLUMNS = 56

    def __init__(self, profile: Profile, boards: Sequence[Board]):
        from ..views.preview import to_terminal
        from ..views.render import Renderer

        super().__init__(profile, boards)
        self.slots = [profile.index(n) for n in self.names]
        self.renderer = Renderer(profile, (320, 368))
        self.seen = [[s.rest for s in profile.servos]]  #: the poses the picture holds
        self.to_terminal = to_terminal
        self._pending: dict[int, tuple[list[int], float]] = {}
        self._wake = threading.Event()
        threading.Thread(target=self._draws, name="gestsim-view", daemon=True).start()

    def update(self, board: int, values: Sequence[int], now: float) -> None:
        """Board ``board`` holds ``values``: drawn aside, by a thread of the view's own
        (a picture of the whole robot takes milliseconds, which the boards' loops, each
        reading its port, do not wait for)."""
        self._pending[board] = (list(values), now)
        self._wake.set()

    def _draws(self) -> None:
        while True:
            self._wake.wait()
            self._wake.clear()
            for board in list(self._pending):
                values, now = self._pending.pop(board)
                super().update(board, values, now)

    def lines(self, values: list[int]) -> list[str]:
        """The robot in that pose, as coloured half-block characters."""
        pose = [s.rest for s in self.profile.servos]
        for slot, value in zip(self.slots, values, strict=True):
            pose[slot] = value
        if not self.renderer.holds(pose):
            self.seen.append(pose)
            self.renderer.fit(self.seen)
        picture = self.renderer.draw(pose).convert("RGB")
        return self.to_terminal(picture, columns=self.COLUMNS)
