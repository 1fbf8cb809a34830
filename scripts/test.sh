#!/usr/bin/env bash
# Set everything up with the test extras, then run the whole test suite (2 workers).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh test
.venv/bin/illusio info
exec .venv/bin/python -m pytest -n 2 "$@"
