"""The rule's fast loops: in rate coordinates, over integers (long exact runs), over balls, and over floats in
batches (certified)."""
