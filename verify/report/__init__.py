"""The main job's reports (``verify all``, ``verify report``): every feature's findings computed once
(:mod:`~verify.report.findings`), each page rendered by its feature (:mod:`~verify.report.pages`), and the
summary that ``verify all`` prints (:mod:`~verify.report.summary`)."""
