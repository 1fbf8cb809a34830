#!/usr/bin/env bash
# Set everything up, then render the demo gallery into demo-out/ (open demo-out/index.html).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
.venv/bin/illusio info
.venv/bin/illusio demo --out demo-out "$@"
