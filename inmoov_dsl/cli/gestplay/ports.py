"""gestplay ports: the serial ports on this machine, the likely Arduinos marked."""

from __future__ import annotations

import argparse
import sys

from ...wire.ports import available
from ..common import EXIT_OK


def run(args: argparse.Namespace) -> int:
    """One line per port: device, description, USB VID:PID, what it likely is."""
    found = available()
    for port in found:
        usb = f"USB {port.usb}" if port.usb else "-"
        likely = f"\tlikely {port.likely}" if port.likely else ""
        print(f"{port.device}\t{port.description}\t{usb}{likely}")
    if not found:
        print("no serial ports found (sim:// is the virtual board)", file=sys.stderr)
    elif not any(p.likely for p in found):
        print("none of these looks like an Arduino: is the board plugged in, with a data "
              "cable (some USB cables only charge)?", file=sys.stderr)
    return EXIT_OK


def add_parser(sub: argparse._SubParsersAction) -> None:
    """``gestplay ports``."""
    p = sub.add_parser("ports", help="the serial ports on this machine")
    p.set_defaults(func=run)
