"""``python -m inmoov_dsl.ros --port PORT [--profile NAME] [--listen] [--rate HZ]``, and
``python -m inmoov_dsl.ros --package-path``."""

from __future__ import annotations

import sys

from ..cli.common import EXIT_ERROR, EXIT_OK, parse_args, report, run
from ..errors import Diagnostic
from ..resources import data_dir
from .core import PROG, parser, serve

HINT = ("ROS 1's Python is Debian's /usr/bin/python3 with python3-rospy: make a venv "
        "with '/usr/bin/python3 -m venv --system-site-packages' and install inmoov-dsl "
        "in it")


def main(argv: list[str] | None = None) -> int:
    """Run the node under ROS 1 (rospy); a clear message where rospy is missing.
    ``--package-path`` prints where the ROS package (launch files, rviz views) is, for
    ROS_PACKAGE_PATH; ``--version`` and ``--help`` answer without rospy too."""
    given = sys.argv[1:] if argv is None else argv
    if given == ["--package-path"]:
        print(data_dir("ros"))
        return EXIT_OK
    if {"--version", "-h", "--help"} & set(given):  # answered with or without rospy
        parse_args(parser(), [a for a in given if ":=" not in a])
    try:
        from . import ros1
    except ImportError as exc:
        missing = exc.name or "rospy"
        if missing.startswith("inmoov_dsl"):
            raise
        report([Diagnostic("error", f"{missing} not found: run under ROS 1's Python, see "
                           "docs/ros.md", hint=HINT)], PROG)
        return EXIT_ERROR
    args = parse_args(parser(), ros1.argv(sys.argv if argv is None else [PROG, *argv])[1:])
    return run(PROG, lambda: serve(args, ros1.Ros1(args.rate)))


if __name__ == "__main__":
    sys.exit(main())
