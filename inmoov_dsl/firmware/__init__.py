"""The boards' firmware: each profile's sketches (``sketches``), built and flashed with
avrdude (``upload``), and the gestures a board stores in its flash (``store``)."""
