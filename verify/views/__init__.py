"""The views toolkit that every feature renders with: the page frame (:mod:`~verify.views.pages`) and the
figure style (:mod:`~verify.views.figures`: matplotlib loaded on demand, deterministic PNGs written whole).
Each feature owns its own text, pages and figures (``verify.FEATURE.text``, ``.pages``, ``.figures``)."""
