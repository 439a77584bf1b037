"""A PCA9685 on an I2C bus in a profile: ``oscillator`` (Hz, the chip's measured clock,
25,000,000), ``bus_speed`` (Hz, the bus's clock, 100,000 or 400,000); a servo gives its
channel (0..15) as ``pin``."""

from ..table import KindTable, Whole, channels

TABLE = KindTable("pca9685", 115_200,
                  (Whole("oscillator", 20_000_000, 30_000_000, 25_000_000,
                         "20,000,000..30,000,000 Hz"),
                   Whole("bus_speed", 10_000, 1_000_000, 100_000, "10,000..1,000,000 Hz",
                         option="bus")),
                  "channel", channels("pca9685", lambda options: 16))
