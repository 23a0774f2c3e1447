"""The rule's fast engines: over integers (long exact runs) and over floats in batches (certified)."""
