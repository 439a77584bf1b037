"""Gestures in and out of the animation tools makers use (pure): Blender Servo
Animation's JSON, binary commands and Arduino header, Bottango's curve commands, and a
CSV of ours; read back as samples for the recorder (docs/interchange.md)."""
