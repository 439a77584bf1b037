"""Gestures in and out of the animation tools makers use (pure): Blender Servo
Animation's JSON, binary commands and Arduino header, Bottango's curve commands, and a
CSV of ours; read back as samples for the recorder (docs/interchange.md).

This module names them for the command lines (importing it imports nothing heavy)."""

#: each format gestc export writes -> its file's suffix
SUFFIXES = {"bsa-json": ".json", "bsa-h": ".h", "bottango": ".txt", "csv": ".csv",
            "joint-states": ".csv"}
FORMATS_IN = ("bsa-json", "bsa-h", "bottango", "csv")  #: what gestc import reads
UNITS = ("us", "degrees", "ticks")  #: what another tool's positions may be in
