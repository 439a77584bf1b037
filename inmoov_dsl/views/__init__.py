"""What people look at, drawn from the model (``model``): plots (``plot``), the GIF of
``gestc preview`` (``film``: the drawn hand, ``preview``, or the whole model in 3-D,
``render``), a pose as bars (``posebars``), the 3-D pages in a browser (``scene`` behind
``gate``; ``webview`` for ``gestsim --web``) and the live preview page (``livepage``, on
``timeline``, ``livedraw``, ``liveclock``, ``livepanel``, ``lookout``)."""
