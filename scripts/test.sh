#!/usr/bin/env bash
# Set everything up with the test extras, then run the whole test suite (2 workers). In CI (CI set)
# the documentation site is then built again from the wheel in a fresh environment
# (scripts/docs-from-wheel.sh): the suite builds it from the source tree.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh test
.venv/bin/illusio info
.venv/bin/python -m pytest -n 2 "$@"
if [ -n "${CI:-}" ]; then bash scripts/docs-from-wheel.sh; fi
