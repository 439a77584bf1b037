"""A board of ours (or the original firmware) in a profile: ``arduino`` (``uno``,
``nano``, ``mega``; ``uno``) is the board it runs on (its pins, the image built); its
link runs at the protocol's default baud; a servo's pin may wait for the sketch."""

from ... import protocol
from .. import arduino
from ..table import KindTable

TABLE = KindTable("rig", protocol.DEFAULT_BAUD, (arduino.key("uno"),), "pin",
                  arduino.pins(required=False))
