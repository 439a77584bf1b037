"""The DTR line between a host's port and a virtual board (``sim://``, gestsim's pty):
what resets an Uno, a Nano or a Mega as a program opens the port."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass
class DtrLine:
    """The DTR line from a host's port to a board: an Uno or a Nano resets when it
    rises. Opening the port raises it unless it is up already; closing drops it unless
    the program cleared HUPCL (``hupcl``, what the program with the port open asks)."""

    up: bool = False
    is_open: bool = False  #: a program has the port open
    hupcl: bool = True

    def opened(self) -> bool:
        """A program opened the port: True if DTR rose (the board resets)."""
        rose = not self.up
        self.up = self.is_open = True
        return rose

    def closed(self) -> None:
        """The program closed the port (once is enough; again changes nothing)."""
        if self.is_open:
            self.up = not self.hupcl
        self.is_open = False
