"""The wire: a board as the bytes leave it (``board``), the virtual board on a
simulated link (``sim``) and as the ``sim://`` port (``urlhandler``), serial ports by
name (``ports``), the link edge every command opens its ports through (``link``:
``--port`` read once, ``sim://`` completed for the profile and board), the player
that sends compiled streams on time (``player``) and the glove (``glove``). The
protocol and its reader are at the package's root (``protocol``, ``decode``)."""
