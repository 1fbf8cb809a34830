"""Benchmarks: one module per technique, each timing it against its baseline in one run."""
