#!/usr/bin/env bash
# Build the documentation site into docs/_build/html (Sphinx, warnings as errors), running the
# example gallery (examples/plot_*.py). Needs the docs extra: bash scripts/setup.sh docs
set -euo pipefail
cd "$(dirname "$0")/.."
exec .venv/bin/python -m sphinx -W --keep-going -b html docs docs/_build/html "$@"
