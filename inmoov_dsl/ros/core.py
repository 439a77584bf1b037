"""The ROS node's core, free of ROS: the hand it drives or listens to, the requests it
takes, what it says, and the joint states it gives.

An edge (``ros1.py`` for rospy) joins the ROS graph and calls ``Node.gesture`` and
``Node.trajectory`` from its subscriptions; it publishes ``Node.joint_positions`` at
its rate and says what ``Node`` says. Everything else is here and shared by any edge:

- Driving (the default): the ports open as gestplay opens them (``hand.opened``: the
  boards asked their pose; CANCEL on Ctrl-C, SIGTERM or a lost link), and the drive
  loop (drive.py) runs in the main thread; requests come through a queue, and each
  takes over the running move. The joint states are what the boards hold.
- Listening (``--listen``): the port sends the protocol stream (a flex glove's mirror,
  as the seed's serial_publisher read it); it opens, and its pairs are read, as
  ``gestc record`` does (``link.open_listener``; the ``RECORDER`` policy) into what
  the boards hold, and nothing is ever written to the port.
"""

from __future__ import annotations

import argparse
import functools
import queue
import threading
from collections.abc import Callable, Iterable, Sequence
from typing import Protocol

import serial

from ..cli import hand
from ..cli.common import (
    EXIT_OK,
    add_allow_contact,
    add_blind,
    add_lib,
    add_ports,
    add_version,
    guard_for,
    number,
)
from ..decode import RECORDER, Pair, Reader
from ..errors import Diagnostic, GestError
from ..hardware import Profile
from ..language.library import library_dirs
from ..live.drive import Drive, Next, Note, library_program
from ..live.outbox import Mirror
from ..model.joints import names, positions
from ..profiles.profile import load_profile
from ..wire.link import open_listener
from . import trajectory

PROG = "inmoov_dsl.ros"

#: what the node says: (kind: "error", "warning" or "info"; the status line)
Say = Callable[[str, str], None]


class Edge(Protocol):
    """What the node needs of a ROS (1 or 2) client library."""

    def check(self) -> None:
        """Raise a GestError if the node cannot join the graph (no master)."""

    def start(self, node: Node) -> None:
        """Join the graph: subscriptions to ``node.gesture`` and ``node.trajectory``,
        ``node.joint_positions`` published at the edge's rate, ``node.close`` on
        shutdown."""

    def say(self, kind: str, text: str) -> None:
        """Log ``text`` (kind "error", "warning" or "info") and publish it as the status."""

    def stop(self) -> None:
        """Leave the graph (safe to call when ``start`` never ran)."""


class Node:
    """The requests a hand takes and what it reports, for any edge."""

    def __init__(self, profile: Profile, mirror: Mirror, say: Say, listening: bool = False):
        self.profile, self.mirror, self.say = profile, mirror, say
        self.listening = listening
        self.requests: queue.Queue[Next] = queue.Queue()
        self.closed = threading.Event()

    def gesture(self, text: str) -> None:
        """A request by name (``fist``) or any line the repl takes (``index 90 over 1s``)."""
        if self._refused():
            return
        self.requests.put(text)

    def trajectory(self, joints: Sequence[str], points: Sequence[trajectory.Point]) -> None:
        """A joint trajectory, planned through the profile's limits (trajectory.py)."""
        if self._refused():
            return
        try:
            steps = trajectory.steps(self.profile, joints, points)
        except GestError as exc:
            self.say("error", status("error", exc.diagnostics))
            return
        self.requests.put(steps)

    def _refused(self) -> bool:
        if self.listening:
            self.say("error", "error: this node only listens (--listen): it sends nothing "
                     "to its port")
        return self.listening

    def close(self) -> None:
        """Stop taking requests; the node leaves once the hand is still."""
        self.closed.set()
        self.requests.put(None)

    def next_request(self, timeout: float) -> Next:
        """The next request within ``timeout`` s, None once closed, else False."""
        try:
            return self.requests.get(timeout=timeout) if timeout > 0 else \
                self.requests.get_nowait()
        except queue.Empty:
            return False

    def joint_names(self) -> list[str]:
        """The joints of the profile's servos, in its order."""
        return names(self.profile)

    def joint_positions(self) -> list[float]:
        """Where the joints are (radians): what the boards hold."""
        return positions(self.profile, self.mirror.held())

def tell(note: Note, say: Say) -> None:
    """Say what the drive loop tells: errors, warnings, "playing NAME" and "done"."""
    if note.kind in ("error", "warning"):
        say(note.kind, status(note.kind, note.diagnostics))
    elif note.kind == "start":
        say("info", f"playing {note.text}")
    elif note.kind == "done":
        say("info", "done")


def status(kind: str, diagnostics: Iterable[Diagnostic]) -> str:
    """Diagnostics as one status line: ``error: message (hint); ...``."""
    said = "; ".join(d.message + (f" ({d.hint})" if d.hint else "") for d in diagnostics)
    return f"{kind}: {said}"


def serve(args: argparse.Namespace, edge: Edge) -> int:
    """Run the node until the edge closes it (or a signal stops it)."""
    profile = load_profile(args.profile)
    if args.listen and len(args.port) != 1:
        raise GestError(Diagnostic("error", "--listen reads one port",
                                   hint="give one --port: the glove's, or the board's "
                                   "that mirrors the stream"))
    edge.check()
    try:
        return (_listen if args.listen else _drive)(args, profile, edge)
    finally:
        edge.stop()


def _drive(args: argparse.Namespace, profile: Profile, edge: Edge) -> int:
    """Drive the hand on its ports, requests taking over one another."""
    with hand.opened(PROG, profile, args.port, args.blind) as on:
        program = library_program(library_dirs(args.lib))
        guard = guard_for(profile, args.allow_contact, PROG)
        drive = Drive(on.links, profile, on.pose, program,
                      functools.partial(tell, say=edge.say), guard=guard.plan)
        node = Node(profile, drive.mirror, edge.say)
        edge.start(node)
        edge.say("info", f"ready: {profile.name} on {', '.join(args.port)}")
        drive.run(node.next_request)
    return EXIT_OK


def _listen(args: argparse.Namespace, profile: Profile, edge: Edge) -> int:
    """Read the protocol stream of a port into the joint states; never write to it."""
    port = open_listener(args.port[0], profile)
    mirror = Mirror(profile, [b.id for b in profile.boards])
    mirror.set([s.rest for s in profile.servos])
    node = Node(profile, mirror, edge.say, listening=True)
    reader = Reader(RECORDER)
    try:
        edge.start(node)
        edge.say("info", f"listening: {profile.name} on {args.port[0]}, {port.baud} baud")
        while not node.closed.is_set():
            for event in reader.read(port.read()):
                if isinstance(event, Pair):
                    mirror.put(event.id, event.value)
    except serial.SerialException as exc:
        raise GestError(Diagnostic("error", f"lost the link ({args.port[0]}): {exc}")) \
            from None
    finally:
        port.close()
    return EXIT_OK


def parser() -> argparse.ArgumentParser:
    """The node's arguments (after ROS's own ``name:=value`` ones are taken out)."""
    p = argparse.ArgumentParser(
        prog=f"python -m {PROG}",
        description="The hand as a ROS node: joint states on /joint_states, gestures "
        "from /inmoov/gesture and /inmoov/trajectory, what it does on /inmoov/status "
        "(docs/ros.md).")
    add_ports(p, "as for gestplay: COM3, /dev/ttyACM0, sim:// (a virtual board)")
    p.add_argument("-p", "--profile", default="rhand", help="robot profile (default rhand)")
    p.add_argument("--listen", action="store_true",
                   help="only read the port's protocol stream (a glove's mirror) into the "
                   "joint states; never write to it")
    p.add_argument("--rate", type=number(0, 1000, above=True), default=50.0,
                   help="joint states per second (default 50)")
    add_blind(p)
    add_allow_contact(p)
    add_lib(p)
    add_version(p)
    return p
