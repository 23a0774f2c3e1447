"""An engine adapter whose engine is never installed (for tests/engines/test_engines.py)."""

from __future__ import annotations

from verify.engines.protocol import Adapter, NotInstalled


class Ghost(Adapter):
    """An engine that cannot be imported."""

    name = "ghost"
    package = "ghost-engine"

    def version(self) -> str:
        raise NotInstalled("No module named 'ghost'")


if __name__ == "__main__":
    raise SystemExit(Ghost.main())
