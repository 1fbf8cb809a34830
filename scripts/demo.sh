#!/usr/bin/env bash
# Set everything up (with the viewer's window: `illusio view` afterwards), then render the demo
# gallery into demo-out/ (open demo-out/index.html).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh viewer,photo
.venv/bin/illusio info
.venv/bin/illusio demo --out demo-out "$@"
