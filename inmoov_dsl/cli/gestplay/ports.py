"""gestplay ports: the serial ports on this machine, the likely boards marked, and
(unless ``--no-ask``) what answers on each of them."""

from __future__ import annotations

import argparse
import sys

from ...protocol import DEFAULT_BAUD
from ...wire.identify import answer
from ...wire.ports import PortInfo, available
from ..common import EXIT_OK


def run(args: argparse.Namespace) -> int:
    """One line per port: device, description, USB VID:PID, what it likely is, and what
    answers on it. ``--port``: that port alone, asked whatever its USB IDs."""
    found = available()
    if args.port:
        known = {p.device: p for p in found}
        found = [known.get(name, PortInfo(name, "named")) for name in args.port]
        for port in found:
            print(f"{port.device}\t{port.description}\tanswers: "
                  f"{answer(port, args.baud, named=True)}", flush=True)
        return EXIT_OK
    for port in found:
        usb = f"USB {port.usb}" if port.usb else "-"
        likely = f"\tlikely {port.likely}" if port.likely else ""
        said = f"\tanswers: {answer(port, args.baud)}" if args.ask and port.likely else ""
        print(f"{port.device}\t{port.description}\t{usb}{likely}{said}", flush=True)
    if not found:
        print("no serial ports found (sim:// is the virtual board)", file=sys.stderr)
    elif not any(p.likely for p in found):
        print("none of these looks like an Arduino or a Maestro: is the board plugged in, "
              "with a data cable (some USB cables only charge)?", file=sys.stderr)
    return EXIT_OK


def add_parser(sub: argparse._SubParsersAction) -> None:
    """``gestplay ports``."""
    p = sub.add_parser("ports", help="the serial ports on this machine, and who answers")
    p.add_argument("--no-ask", dest="ask", action="store_false",
                   help="only list them (asking opens each likely board's port: an Uno "
                   "resets, and keeps its pose)")
    p.add_argument("--port", action="append", metavar="PORT",
                   help="ask this port only (again for more), whatever its USB IDs: a "
                   "board behind a USB adapter gestplay does not know, a port with no "
                   "USB IDs, a URL")
    p.add_argument("--baud", type=int, default=DEFAULT_BAUD,
                   help=f"the baud a board of ours is asked at (default {DEFAULT_BAUD})")
    p.set_defaults(func=run)
