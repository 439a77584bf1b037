"""The boards' firmware: each profile's sketches (``sketches``), built and flashed with
avrdude (``upload``)."""
