"""The rule's fast loops: over integers (long exact runs), over balls, and over floats in batches (certified)."""
