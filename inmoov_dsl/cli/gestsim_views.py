"""gestsim's live views in the terminal: a bar per servo (``BarsView``), or the hand
drawn in coloured half blocks (``HandView``). Each is drawn at once with the board's
rest pose, then redrawn in place when the board's values change."""

from __future__ import annotations

import sys
from typing import TYPE_CHECKING

from ..model.posebars import bar_lines

if TYPE_CHECKING:
    from ..wire.sim import VirtualBoard

FRAME = 0.05  #: s between redraws of the live view


class BarsView:
    """The board's values in the terminal, redrawn in place when they change (at most
    every FRAME): a bar per servo."""

    def __init__(self, profile, board_cfg):
        self.names = board_cfg.servos
        self.next = 0.0
        self.shown: list[int] | None = None
        self.height = 0  # lines drawn last time

    def lines(self, values: list[int]) -> list[str]:
        """A line per servo: its name, value and a bar (``posebars``)."""
        return bar_lines(zip(self.names, values, strict=True))

    def draw(self, board: VirtualBoard, now: float) -> None:
        """Redraw if the values changed and a frame has passed."""
        if now < self.next or board.core.values == self.shown:
            return
        self.next = now + FRAME
        self.shown = list(board.core.values)
        lines = self.lines(self.shown)
        out = sys.stderr
        if self.height:
            out.write(f"\x1b[{self.height}F")
        out.write("".join(f"\x1b[2K{line}\n" for line in lines))
        out.flush()
        self.height = len(lines)


class HandView(BarsView):
    """The hand drawn in the terminal (gestc preview's picture)."""

    def __init__(self, profile, board_cfg):
        from ..model.preview import draw_hand, hand_servos, pose_of, to_terminal

        super().__init__(profile, board_cfg)
        hand_servos(profile)  # a profile without a hand is an error now, not later
        self.profile, self.ids = profile, [profile.servos[profile.index(n)].id
                                           for n in board_cfg.servos]
        self.draw_hand, self.pose_of, self.to_terminal = draw_hand, pose_of, to_terminal
        draw_hand({})  # Pillow is there

    def lines(self, values: list[int]) -> list[str]:
        """The hand in that pose, as coloured half-block characters."""
        pose = self.pose_of(self.profile, values, self.ids)
        return self.to_terminal(self.draw_hand(pose), columns=48)
