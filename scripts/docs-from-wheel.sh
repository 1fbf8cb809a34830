#!/usr/bin/env bash
# Build the documentation site against the built wheel, not the source tree: the wheel is built,
# installed with the docs and photo extras into a fresh virtual environment (versions of
# constraints.txt), and Sphinx runs the example gallery with that environment's illusio (warnings as
# errors), then checks the site's links. CI runs it after the suite (scripts/test.sh with CI set).
# Needs the test extra in .venv (build) and the network the setup needs. Usage: bash scripts/docs-from-wheel.sh
set -euo pipefail
cd "$(dirname "$0")/.."
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
constraints=()
[ "${ILLUSIO_CONSTRAINTS:-}" = none ] || constraints=(-c constraints.txt)
.venv/bin/python -m build -q --wheel --outdir "$work/dist" . >/dev/null
wheel=$(ls "$work"/dist/illusio-*.whl)
python3 -m venv "$work/venv"
"$work/venv/bin/python" -m pip install -q "${constraints[@]}" --upgrade pip >/dev/null
"$work/venv/bin/python" -m pip install -q "${constraints[@]}" "$wheel[docs,photo]"
# the site documents the installed package: refuse a source-tree import
(cd "$work" && "$work/venv/bin/python" -c 'import illusio, sys; sys.exit("/site-packages/" not in illusio.__file__)') \
  || { echo "docs-from-wheel: illusio is not imported from the installed wheel" >&2; exit 1; }
export ILLUSIO_DOCS_INSTALLED=1 MPLBACKEND=Agg
"$work/venv/bin/python" -m sphinx -W --keep-going -q -b html docs "$work/html"
"$work/venv/bin/python" -m sphinx -W --keep-going -q -b linkcheck docs "$work/linkcheck"
echo "docs-from-wheel: $(basename "$wheel"): the site and its $(ls examples/plot_*.py | wc -l) examples built, links checked"
