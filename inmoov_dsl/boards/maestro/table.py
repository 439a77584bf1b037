"""A Pololu Maestro in a profile: ``model`` (``micro6``, ``mini12``, ``mini18``,
``mini24``; ``mini12``), ``device`` (its device number: the Pololu protocol; none: the
compact protocol), ``baud`` (115200: the pace its commands are timed at); a servo gives
its channel as ``pin``."""

from ..table import Choice, KindTable, Options, Whole, channels

MODELS = ("micro6", "mini12", "mini18", "mini24")
CHANNELS = {"micro6": 6, "mini12": 12, "mini18": 18, "mini24": 24}


def count(options: Options) -> int:
    """The channels of the model its options name."""
    return CHANNELS[MODELS[dict(options).get("model", 1)]]


BAUD = 115_200  #: the pace its commands are timed at (its Command Port is USB)
TABLE = KindTable("maestro", BAUD,
                  (Choice("model", MODELS, "mini12"), Whole("device", 0, 127)),
                  "channel", channels("maestro", count))
