"""Compiling, stage by stage: the robot a program is for (``robot``), what a name
means (``names``), steps as actions for a profile (``actions``, ``sides``,
``resolve``), jerk-limited planning (``tracks``, ``flow``, ``plan``), the timed byte
streams (``encode``), what the compiler makes and its file (``compiled``, read back by
``compiled_reader`` through ``jsonfields`` and ``jsonpos``), the measures of a plan
against its streams (``metrics``), and the entry points that run the stages
(``compiler``)."""
