"""The ``illusio`` command line (typer)."""
