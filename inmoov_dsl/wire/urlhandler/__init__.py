"""pyserial URL handlers of inmoov-dsl (``sim://``), found through
``serial.protocol_handler_packages``."""
