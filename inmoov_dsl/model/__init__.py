"""The robot as a model: joint positions from servo values (``joints``), the URDF
(``urdf``, ``urdf_parts``), the 3-D view in a browser (``webview``), the drawn hand
(``preview``), plots (``plot``), joint-state export (``export``), a pose as bars
(``posebars``), and the self-collision check (``collide``, on ``kinematics``, ``shapes``
and ``allowed``)."""
