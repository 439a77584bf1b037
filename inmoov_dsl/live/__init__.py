"""Live control: steps that take over a moving hand (``session``) and the one loop that
drives the boards for the repl, the ROS node and the service (``drive``); the bench
tools' pure cores: the key map (``keymap``), teaching poses (``teach``), calibrating a
servo (``calibrate``) and recording a glove's motion (``record``)."""
