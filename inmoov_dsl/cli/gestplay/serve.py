"""gestplay serve: the hand as a local service that other programs drive (HTTP and a
WebSocket), with a page for people (docs/service.md)."""

from __future__ import annotations

import argparse
import functools
import gc
import sys
from pathlib import Path

from ...compiling.compiler import compile_program
from ...errors import Diagnostic, GestError
from ...language.library import library_dirs, scan_library
from ...live.drive import Drive, library_program
from ...profiles.profile import load_profile
from ...wire.player import Link
from .. import hand
from ..common import EXIT_OK, add_allow_contact, add_blind, add_lib, add_ports, guard_for
from ..options import http_address, shown_address
from . import sounds

PROG = "gestplay serve"
DEFAULT_HTTP = "127.0.0.1:8180"
SWITCH = 0.0005  #: s; how often the threads take turns (Python's default is 5 ms)


def run(args: argparse.Namespace) -> int:
    """Open the boards, listen, and drive the hand until Ctrl-C or SIGTERM."""
    try:
        from ...access import Guard
        from ...service import hub, links
        from ...service.server import Server
    except ImportError:
        raise GestError(Diagnostic("error", "the service needs aiohttp, which is not "
                                   "installed", hint="pip install 'inmoov-dsl[serve]'")
                        ) from None
    host, port = args.http
    token = token_for(args, host)
    profile = load_profile(args.profile or "rhand")
    dirs = library_dirs(args.lib)
    program = library_program(dirs)
    service = hub.Service(program, profile, functools.cache(
        lambda: _listing(program, profile, dirs)))  # compiled when first asked
    with hand.opened(PROG, profile, args.port, args.blind) as on:
        kinds = [link.controller for link in on.links]
        ports = [links.Resilient(link, service.board_lost) for link in on.links]
        on.links[:] = [Link(p.board, p, p.name, k)  # closed and cancelled too
                       for p, k in zip(ports, kinds, strict=True)]
        watcher = links.Watcher(ports, profile, service.requests.put)
        speaker = sounds.speaker(args.audio, PROG, profile)
        service.collisions = guard_for(profile, args.allow_contact, PROG)
        service.drive = Drive(on.links, profile, on.pose, program, service.told,
                              speaker=speaker, guard=service.collisions.plan)
        service.make_view = lambda: _view(profile, service.drive.mirror.held())
        server = Server(service, Guard(host, port, token), host, port)
        try:
            port = server.start()
        except OSError as exc:
            raise GestError(Diagnostic("error", f"cannot listen on {host}:{port}: "
                                       f"{exc.strerror or exc}", hint="--http "
                                       f"{shown_address(host, port + 1 if port else 8181)}, "
                                       "or stop what listens there")) from None
        print(f"{PROG}: http://{shown_address(host, port)}/ drives {profile.name} on "
              f"{', '.join(link.name for link in on.links)}; Ctrl-C stops",
              file=sys.stderr, flush=True)
        gc.freeze()  # what is loaded stays: the collector's pauses do not grow with it
        # the drive loop spins for the last moments before a byte is due: hand the
        # interpreter to the server's thread often, so a request waits less than 1 ms
        sys.setswitchinterval(SWITCH)
        watcher.start()
        try:
            service.drive.run(service.next_request)
        finally:
            watcher.stop()
            server.stop()
            if service.view is not None:
                service.view.close()
            if speaker is not None:
                speaker.close()
            gc.unfreeze()  # what is left is collected before the interpreter ends
    return EXIT_OK


def _view(profile, pose: list[int]):
    """The hand in 3-D for the page, on 127.0.0.1 (a free port), where the ``web`` extra
    is installed; None where it is not (the page shows bars)."""
    try:
        from ...views.webview import WebView
        view = WebView(profile, profile.boards[0], 0)
    except GestError:  # viser is not installed
        return None
    view.pose(pose)
    return view


def token_for(args: argparse.Namespace, host: str, what: str = "the service") -> str | None:
    """The token every request must show: --token, or the first line of --token-file.
    Listening beyond this computer without one is refused."""
    from ...access import is_loopback

    token = args.token
    if args.token_file:
        try:
            token = Path(args.token_file).read_text(encoding="utf-8").splitlines()[0].strip()
        except (OSError, UnicodeDecodeError, IndexError) as exc:
            why = "it is a folder, not a file" if isinstance(exc, IsADirectoryError) else \
                "it is empty" if isinstance(exc, IndexError) else \
                exc.strerror if isinstance(exc, OSError) and exc.strerror else exc
            raise GestError(Diagnostic("error", f"cannot read the token from "
                                       f"{args.token_file}: {why}",
                                       hint="give a file whose first line is the token"))\
                from None
    if token is not None and len(token) < 16:
        raise GestError(Diagnostic("error", "a token has at least 16 characters",
                                   hint="python -c 'import secrets; print(secrets."
                                   "token_urlsafe())'"))
    if token is None and not is_loopback(host):
        raise GestError(Diagnostic(
            "error", f"{host} is reachable from other computers: {what} moves a "
            "machine, so it needs a token there", hint="--token-file FILE (a secret of 16 "
            "characters or more), or --http 127.0.0.1:8180 for this computer only"))
    return token


def _listing(program, profile, dirs) -> list[dict]:
    """The library gestures that play on ``profile``, with their durations."""
    from ...service.core import listing

    entries = scan_library(dirs)
    files = {name: (e.path.name, e.description) for name, e in entries.items()}

    def duration(name: str) -> float | None:
        try:
            return compile_program(program, name, profile)[0].duration
        except GestError:
            return None

    return listing(program, profile, files, duration)


def add_token(p: argparse.ArgumentParser) -> None:
    """``--token`` and ``--token-file``: what a listener beyond this computer asks."""
    p.add_argument("--token", help="a secret every request must show (Authorization: "
                   "Bearer TOKEN, or ?token=TOKEN); prefer --token-file, which other "
                   "users cannot see")
    p.add_argument("--token-file", metavar="FILE", help="read the token from FILE")


def add_parser(sub: argparse._SubParsersAction) -> None:
    """``gestplay serve --port PORT``."""
    p = sub.add_parser("serve", help="the hand as a local service (HTTP, WebSocket, a page)",
                       description="Open the boards and serve a JSON API, an events "
                       "WebSocket and a page on 127.0.0.1 (docs/service.md).")
    add_ports(p, "as for playing")
    p.add_argument("-p", "--profile", help="robot profile (default rhand)")
    p.add_argument("--http", type=http_address, default=DEFAULT_HTTP, metavar="HOST:PORT",
                   help=f"where to listen (default {DEFAULT_HTTP}: this computer only; a "
                   "bare PORT is on 127.0.0.1 too, 0 any free one; another address needs a "
                   "token)")
    add_token(p)
    sounds.add_argument(p)
    add_blind(p)
    add_allow_contact(p)
    add_lib(p)
    p.set_defaults(func=run)
