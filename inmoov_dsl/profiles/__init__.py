"""Robot profiles: the data a profile holds (``data``), finding and loading one with
its build and cross-table checks (``profile``), one validator per TOML table
(``tables``), one check per kind of value (``fields``) and the place of every key, for
errors (``keys``)."""
