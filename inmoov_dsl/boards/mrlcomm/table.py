"""An Arduino running MyRobotLab's MrlComm in a profile (an InMoov's Mega): ``arduino``
(``mega``), 115200 baud, and every servo's pin given (MrlComm attaches it at once)."""

from .. import arduino
from ..table import KindTable
from .messages import BAUD

TABLE = KindTable("mrlcomm", BAUD, (arduino.key("mega"),), "pin",
                  arduino.pins(required=True))
