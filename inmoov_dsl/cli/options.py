"""How the tools' options are spelled, shared so that one idea has one name: the
subcommands' parsers (each with a description, its usage naming it), ``--http
[HOST:]PORT``, the forms ``--port`` takes, and an old spelling kept for a while."""

from __future__ import annotations

import argparse
import sys

LOCAL = "127.0.0.1"  #: this computer only
#: what ``--port`` takes for a profile with several boards (said in each --port's help)
PORT_FORMS = ("for a profile with several boards, one per board, by its name or ID: "
              "right=COM3,left=COM4 (or --port right=COM3 --port left=COM4)")


class Commands(argparse._SubParsersAction):
    """The subcommands' action: a subcommand without a description of its own has its
    one-line help as one, so that its ``--help`` says what it does (the usage line names
    the subcommand: ``gestplay serve``, unless a parser sets its own ``prog``)."""

    def add_parser(self, name: str, **kwargs) -> argparse.ArgumentParser:
        """The subcommand ``name``'s parser."""
        said = kwargs.get("help")
        if kwargs.get("description") is None and said:
            kwargs["description"] = f"{said[0].upper()}{said[1:]}."
        return super().add_parser(name, **kwargs)


def http_address(text: str) -> tuple[str, int]:
    """An argparse type: ``--http``'s ``HOST:PORT`` (``[::1]:8180`` for IPv6), or a
    bare ``PORT`` (or ``:PORT``) on this computer, 127.0.0.1; port 0 is any free one."""
    host, _, port = text.rpartition(":")
    bracketed = host.startswith("[") and host.endswith("]")
    host = host[1:-1] if bracketed else host
    if not (port.isascii() and port.isdigit() and int(port) <= 65535) or \
            (":" in host and not bracketed):
        raise argparse.ArgumentTypeError(f"'{text}' is not HOST:PORT or PORT (a port is "
                                         "0 to 65535; an IPv6 host in brackets: [::1]:8180)")
    return host or LOCAL, int(port)


def shown_address(host: str, port: int) -> str:
    """``HOST:PORT`` as ``--http`` takes it (an IPv6 host in brackets)."""
    return f"[{host}]:{port}" if ":" in host else f"{host}:{port}"


class Renamed(argparse.Action):
    """An option's old spelling, kept working for a while and hidden from ``--help``:
    it stores what the new one does (``dest``, its ``type``), after a one-line notice on
    stderr naming the new spelling: ``new``, formatted with the value
    (``"--http {1}"``: a ``--http`` value's port)."""

    def __init__(self, option_strings: list[str], dest: str, new: str = "", **kwargs):
        super().__init__(option_strings, dest, help=argparse.SUPPRESS, **kwargs)
        self.new = new

    def __call__(self, parser: argparse.ArgumentParser, namespace: argparse.Namespace,
                 values, option_string: str | None = None) -> None:
        """Say the new spelling, then store the value as it would."""
        new = self.new.format(*values) if isinstance(values, tuple) else \
            self.new.format(values)
        print(f"{parser.prog}: warning: {option_string} is deprecated: use {new}",
              file=sys.stderr)
        setattr(namespace, self.dest, values)
