"""Building a board's firmware and flashing it (``gestc upload``): an edge module.

A sketch is generated from its profile (``firmware.sketches``) into a sketchbook of its
own, with the InmoovDsl library and the Makefile beside it, built with ``make`` (gcc-avr,
avr-libc, Debian's Arduino core), and flashed with avrdude through the Arduino
bootloader: STK500v1 (``-c arduino``) at 115200 baud for an Uno or a new Nano, 57600 for
the old Nano bootloader; STK500v2 (``-c wiring``) at 115200 for a Mega. avrdude resets
the board into its bootloader itself (DTR).
What avrdude says goes to the user as it comes; a failure becomes one of our messages.
"""

from __future__ import annotations

import queue
import re
import shutil
import subprocess
import sys
import threading
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

from ..boards import arduino
from ..errors import Diagnostic, GestError, did_you_mean
from ..hardware import Profile
from ..profiles.profile import builtin_profiles, load_profile
from ..resources import data_dir, files_in
from ..wire.ports import not_found, permission_denied
from ..wire.stored import StoredSet
from .sketches import sketch_names, sketches

#: s avrdude may say nothing before the board is taken for gone (avrdude waits forever on
#: a port whose other end has gone: a cable pulled mid-upload); it prints a progress
#: mark every 2% of a write, and a line for each try to reach a board that is silent
STALL = 8.0
UNO_BAUD = 115200  #: Optiboot: an Uno, a Nano with the new bootloader
OLD_NANO_BAUD = 57600  #: the old Nano bootloader (ATmegaBOOT)


@dataclass(frozen=True)
class Loader:
    """An Arduino's bootloader, as avrdude talks to it."""

    part: str  #: avrdude's -p: the microcontroller
    programmer: str  #: avrdude's -c: the protocol (arduino: STK500v1, wiring: STK500v2)
    baud: int  #: avrdude's -b

    @property
    def mega(self) -> bool:
        """Is it a Mega's?"""
        return self.part == "atmega2560"


OPTIBOOT = Loader("atmega328p", "arduino", UNO_BAUD)  #: an Uno's, a new Nano's
OLD_NANO = Loader("atmega328p", "arduino", OLD_NANO_BAUD)  #: an old Nano's
MEGA = Loader("atmega2560", "wiring", 115200)  #: a Mega 2560's (STK500v2)


def loader(profile: Profile, ident: int, old_bootloader: bool = False) -> Loader:
    """The bootloader of the board (or glove: an Uno-class board) ``ident`` of
    ``profile``; ``old_bootloader``: an old Nano's, refused for a Mega."""
    board = next((b for b in profile.boards if b.id == ident), None)
    if board is None or arduino.mcu(board.options) == "atmega328p":
        return OLD_NANO if old_bootloader else OPTIBOOT
    if old_bootloader:
        raise GestError(Diagnostic("error", f"--old-bootloader is an old Nano's, and board "
                                   f"{board.id} ({board.name}) is a Mega",
                                   hint="leave it out: a Mega's bootloader speaks STK500v2 "
                                   "at 115200 baud"))
    return MEGA
BUILD_TOOLS = ("make", "avr-gcc", "avr-g++")
SHIPPED = ("libraries", "harness", "host", "Makefile", "size.awk")  #: beside the sketches

INSTALL_BUILD = ("on Debian or Ubuntu: sudo apt-get install make gcc-avr avr-libc "
                 "arduino-core-avr; elsewhere build the sketch in the Arduino IDE "
                 "(docs/firmware.md) and give its .hex with --hex")
INSTALL_AVRDUDE = ("on Debian or Ubuntu: sudo apt-get install avrdude; on macOS: brew "
                   "install avrdude; on Windows: the Arduino IDE has one "
                   "(hardware\\tools\\avr\\bin\\avrdude.exe), or get a release from "
                   "github.com/avrdudes/avrdude; or give its path with --avrdude")


def read_hex(path: Path) -> dict[int, int]:
    """The bytes an Intel HEX file puts in flash: address -> byte. A file that is not
    Intel HEX (or fails its checksums) is a GestError."""
    memory: dict[int, int] = {}
    base = 0
    try:
        lines = path.read_text(encoding="ascii").split()
    except IsADirectoryError:
        files = ", ".join(files_in(path, ".hex")) or "firmware/build/BOARD.hex"
        raise GestError(Diagnostic("error", f"'{path}' is a folder, not a HEX file",
                                   hint=f"give the .hex file a build wrote: {files}")
                        ) from None
    except (OSError, UnicodeDecodeError) as exc:
        raise GestError(Diagnostic("error", f"cannot read {path}: {exc}")) from None
    for n, line in enumerate(lines, 1):
        try:
            record = bytes.fromhex(line[1:]) if line.startswith(":") else b""
        except ValueError:
            record = b""
        if len(record) < 5 or len(record) != record[0] + 5 or sum(record) % 256 or \
                (record[3] in (2, 4) and record[0] != 2):  # an address record: 2 bytes
            raise GestError(Diagnostic("error", f"{path}:{n}: not an Intel HEX record",
                                       hint="give the .hex that the build wrote"))
        address, kind, data = record[1] << 8 | record[2], record[3], record[4:-1]
        if kind == 0:
            memory.update((base + address + k, b) for k, b in enumerate(data))
        elif kind == 1:
            break
        elif kind == 2:
            base = (data[0] << 8 | data[1]) * 16
        elif kind == 4:
            base = (data[0] << 8 | data[1]) << 16
    return memory


def find_sketch(name: str) -> Profile:
    """The built-in profile that has a sketch called ``name`` (``servo_rhand``)."""
    known: list[str] = []
    for profile_name in builtin_profiles():
        profile = load_profile(profile_name)
        names = list(sketch_names(profile))  # (a Maestro's or a PCA9685's: none)
        if name in names:
            return profile
        known += names
    hint = did_you_mean(name, known) or f"the boards: {', '.join(sorted(known))}"
    raise GestError(Diagnostic("error", f"no board called '{name}'", hint=hint))


def stale_files(profile: Profile, out: Path, baud: int | None = None,
                stored: Mapping[int, StoredSet] | None = None) -> dict[Path, str | None]:
    """The sketch files under ``out`` that differ from what ``profile`` generates (with
    ``stored``: board ID -> its stored gestures); None for a ``stored.h`` that should
    no longer be there."""
    stale: dict[Path, str | None] = {}
    for folder, files in sketches(profile, baud, stored).items():
        for name, text in files.items():
            path = out / folder / name
            current = path.read_text(encoding="utf-8") if path.is_file() else None
            if current != text:
                stale[path] = text
        if "stored.h" not in files and (out / folder / "stored.h").is_file():
            stale[out / folder / "stored.h"] = None
    return stale


def write_sketchbook(profile: Profile, out: Path, baud: int | None = None,
                     stored: Mapping[int, StoredSet] | None = None) -> list[Path]:
    """Write ``profile``'s sketches under ``out`` (only the files that changed; a
    ``stored.h`` of gestures no longer stored removed), and the library and the build
    beside them if ``out`` has none: a sketchbook the Arduino IDE opens and ``make -C
    out`` builds. Returns the files written or removed."""
    stale = stale_files(profile, out, baud, stored)
    for path, text in stale.items():
        if text is None:
            path.unlink()
            continue
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text, encoding="utf-8")
    if not (out / "libraries" / "InmoovDsl").exists():
        shipped = data_dir("firmware")
        for part in SHIPPED:
            source = shipped / part
            if source.is_dir():
                shutil.copytree(source, out / part, dirs_exist_ok=True)
            else:
                shutil.copy2(source, out / part)
    return list(stale)


def build(profile: Profile, names: Sequence[str], where: Path, baud: int | None = None,
          stored: Mapping[int, StoredSet] | None = None) -> dict[str, Path]:
    """Build the sketches ``names`` of ``profile`` in the sketchbook ``where`` (with
    ``stored``: board ID -> its stored gestures): sketch name -> its .hex. make's
    output goes to the user."""
    missing = [tool for tool in BUILD_TOOLS if shutil.which(tool) is None]
    if missing:
        raise GestError(Diagnostic("error", f"cannot build the firmware: {missing[0]} not "
                                   f"found", hint=INSTALL_BUILD))
    write_sketchbook(profile, where, baud, stored)
    done = subprocess.run(["make", "-s", "-C", str(where), "-j2", *names],
                          stdout=sys.stderr, stderr=subprocess.PIPE, text=True)
    if done.returncode != 0:
        sys.stderr.write(done.stderr)
        last = done.stderr.strip().splitlines()[-1:] or ["(no message)"]
        raise GestError(Diagnostic("error", f"building {', '.join(names)} failed: {last[0]}",
                                   hint=INSTALL_BUILD if "No such file" in done.stderr
                                   else None))
    return {name: where / "build" / f"{name}.hex" for name in names}


def avrdude_command(hex_file: Path, port: str, boot: Loader = OPTIBOOT,
                    avrdude: str = "avrdude", options: Sequence[str] = ()) -> list[str]:
    """The avrdude command line that flashes ``hex_file`` through the bootloader ``boot``
    on ``port`` (-D: the bootloader erases each page as it writes it)."""
    return [avrdude, "-p", boot.part, "-c", boot.programmer, "-P", port, "-b",
            str(boot.baud), "-D", *options, "-U", f"flash:w:{hex_file}:i"]


def explain(output: str, port: str, boot: Loader = OPTIBOOT) -> Diagnostic:
    """avrdude's failure, from what it printed, as a message with what to try."""
    baud = boot.baud
    if re.search(r"cannot open port|can't open device|ser_open\(\)", output):
        if re.search(r"[Pp]ermission denied|[Aa]ccess is denied", output):
            return permission_denied(port)
        return not_found(port, virtual=False)
    if re.search(r"not in sync|not responding|programmer is not responding|"
                 r"timeout|failed to sync|cannot get sync", output):
        other = OLD_NANO_BAUD if baud != OLD_NANO_BAUD else UNO_BAUD
        option = "--old-bootloader" if other == OLD_NANO_BAUD else "no --old-bootloader"
        board = ("is it a Mega 2560 with its bootloader?" if boot.mega
                 else f"an old Nano needs {other} baud ({option})")
        return Diagnostic("error", f"no bootloader answered on {port} at {baud} baud",
                          hint=f"is it the board's port ('gestplay ports')? {board}; a "
                          "board without the Arduino bootloader needs an ISP programmer")
    if re.search(r"verification error|content mismatch", output):
        return Diagnostic("error", f"the flash read back from the board on {port} is not "
                          "what was written", hint="a loose cable or a weak power supply? "
                          "try again")
    lines = [line for line in output.strip().splitlines() if "error" in line.lower()]
    last = (lines or output.strip().splitlines() or ["(no message)"])[-1]
    return Diagnostic("error", f"avrdude failed on {port}: {last.strip()}")


def flash(hex_file: Path, port: str, boot: Loader = OPTIBOOT, avrdude: str = "avrdude",
          options: Sequence[str] = ()) -> None:
    """Flash ``hex_file`` with avrdude, its progress shown as it comes; a failure is a
    GestError saying what to do. An avrdude silent for STALL s is stopped: the board is
    gone. Whatever happens (Ctrl-C too), no avrdude is left running."""
    found = shutil.which(avrdude)
    if found is None:
        raise GestError(Diagnostic("error", f"{avrdude} not found", hint=INSTALL_AVRDUDE))
    proc = subprocess.Popen(avrdude_command(hex_file, port, boot, found, options),
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
    chunks: queue.Queue[bytes] = queue.Queue()
    threading.Thread(target=_pipe, args=(proc.stdout, chunks), daemon=True).start()
    said = bytearray()
    raw = getattr(sys.stderr, "buffer", None)  # a text-only stderr gets decoded text
    try:
        while chunk := _next(chunks, port):  # progress bars come a character at a time
            said += chunk
            if raw is not None:
                raw.write(chunk)
            else:
                sys.stderr.write(chunk.decode(errors="replace"))
            sys.stderr.flush()
    finally:
        if proc.poll() is None:
            proc.kill()
        proc.wait()
    if proc.returncode != 0:
        raise GestError(explain(said.decode(errors="replace"), port, boot))


def _pipe(stream, chunks: queue.Queue) -> None:
    """What avrdude prints, as it comes; b"" at its end."""
    while chunk := stream.read1(4096):
        chunks.put(chunk)
    chunks.put(b"")


def _next(chunks: queue.Queue, port: str) -> bytes:
    """avrdude's next words (b"": it is done); a GestError after STALL s of silence."""
    try:
        return chunks.get(timeout=STALL)
    except queue.Empty:
        raise GestError(Diagnostic(
            "error", f"the board on {port} stopped answering: avrdude heard nothing for "
            f"{STALL:.0f} s, and was stopped",
            hint="was the cable pulled or the board reset? plug it in and upload again: "
            "the bootloader is still there")) from None
