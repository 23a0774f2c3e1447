"""``python -m verify``: the same as the ``verify`` console script."""

from verify.cli import main

raise SystemExit(main())
