"""The wire: a board as the bytes leave it (``board``), the virtual board on a
simulated link (``sim``) and as the ``sim://`` port (``urlhandler``), serial ports by
name (``ports``), the link edge every command opens its ports through (``link``:
``--port`` read once, ``sim://`` completed for the profile and board), the player
that sends compiled streams on time (``player``), the glove (``glove``), and gestures
stored in a board's flash (``stored``) as a board plays them (``stored_play``). The
protocol and its reader are at the package's root (``protocol``, ``decode``)."""
