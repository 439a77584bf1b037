"""``gestc preview --live FILE``: the live page of a gesture file, fed from the disk.

The file is looked at every POLL (its size and time of change, then its text): each new
text is analysed as the language server analyses an editor's (``editor.analysis``, its
memo kept, so an edit costs what it touches) and shown (``editor.preview_view``). The
cursor is the gesture's name (``--gesture``, else the file's first gesture), then the
step last clicked on the page.
"""

from __future__ import annotations

import argparse
import os
import sys
import threading
import webbrowser
from pathlib import Path

from ...errors import Diagnostic, GestError
from ..common import EXIT_OK
from ..options import LOCAL, shown_address
from . import PROG

POLL = 0.02  #: s between two looks at the file


class Follower:
    """The file, analysed as it changes, and the cursor the page last picked."""

    def __init__(self, path: str, gesture: str | None, robot: str | None, lib: list[str]):
        from ...compiling.robot import DEFAULT
        from ...editor.memo import Memo

        self.path, self.gesture, self.lib = path, gesture, lib
        self.robot = robot or DEFAULT
        self.memo = Memo()
        self.seen: tuple[int, int] | None = None
        self.text: str | None = None
        self.emptied = False  #: the last read found the file empty (once, not believed)
        self.found = None
        self.line: int | None = None  #: the step picked on the page (0-based line)
        self.view = None
        self.picked = threading.Event()

    def changed(self) -> bool:
        """Has the file changed since it was last read (and analysed again)?"""
        from ...editor.analysis import Analysis, analyse
        from ...language.load import read_text

        try:
            stat = os.stat(self.path)
            seen = (stat.st_mtime_ns, stat.st_size)
        except OSError:
            seen = None
        if seen == self.seen and self.found is not None:
            return False
        self.seen = seen
        try:
            text = read_text(self.path)
        except (GestError, OSError, ValueError) as exc:
            said = exc.diagnostics if isinstance(exc, GestError) else \
                [Diagnostic("error", f"cannot read {self.path}: {exc}")]
            self.text, self.found = None, Analysis("", self.path, diagnostics=list(said))
            return True
        if text == self.text:
            return False
        if not text and self.text and not self.emptied:
            # read between a writer's truncate and its write: believed at the next look
            self.seen, self.emptied = None, True
            return False
        self.text, self.emptied = text, False
        self.found = analyse(text, self.path, self.robot, self.lib, self.memo)
        return True

    def pick(self, span) -> None:
        """A step clicked on the page: the cursor goes to its line (``on_pick``)."""
        if span.file == self.found.path and span.line is not None:
            self.line = span.line
            self.picked.set()

    def make_view(self):
        """The view of the text and the cursor, the last one kept when it has errors."""
        from ...editor.preview_view import view_of

        self.view = view_of(self.found, self.line, 0, self.view, self.gesture)
        return self.view


def live(args: argparse.Namespace) -> int:
    """Serve the page until Ctrl-C."""
    from ...language.library import find_gesture, library_dirs
    from ...views.livepage import LivePage

    host, port = args.http
    if host not in (LOCAL, "localhost"):
        raise GestError(Diagnostic("error", f"--http {shown_address(host, port)}: the "
                                   f"preview page is for this computer only ({LOCAL})",
                                   hint=f"--http {port}"))
    if args.start:
        raise GestError(Diagnostic("error", "--from does not go with --live (the page "
                                   "plays the gesture from the robot's rest pose)"))
    path, gesture = find_gesture(args.target, args.gesture, library_dirs(args.lib))
    if os.path.isdir(path):
        from ...language.load import folder_given

        raise GestError(folder_given(path))
    follower = Follower(str(Path(path)), gesture, args.profile, args.lib)
    page = LivePage(port)
    try:
        page.on_pick = follower.pick
        if args.serve:
            from ...editor.preview_play import Player

            page.on_play = Player(args.serve, args.token)
        # the address last on its line: a terminal that makes it a link takes no more
        print(f"{PROG}: the live preview of {path} (Ctrl-C stops) at {page.url}",
              file=sys.stderr, flush=True)
        if not args.no_open:
            webbrowser.open(page.url)
        while True:
            if follower.changed() or follower.picked.is_set():
                follower.picked.clear()
                page.show(follower.make_view())
            follower.picked.wait(POLL)
    finally:
        page.close()
    return EXIT_OK
