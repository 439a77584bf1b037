"""The robot as a model: joint positions from servo values (``joints``), the URDF
(``urdf``, ``urdf_parts``), the 3-D view in a browser (``webview``), the drawn hand
(``preview``), plots (``plot``), joint-state export (``export``) and a pose as bars
(``posebars``)."""
