#!/usr/bin/env bash
# Set up illusio on a fresh Debian/Ubuntu machine: system GL libraries (installed when running as
# root, otherwise the one apt-get line is printed), a virtual environment in .venv, the package.
# Usage: scripts/setup.sh [pip extras, comma-separated: viewer, docs (the site: scripts/docs.sh),
# photo (also installs libatomic1, which Mitsuba's JIT loads), test (viewer + photo + cluster + docs;
# also installs xvfb, xauth and chromium)]
# Versions are those of constraints.txt (a fresh install that passed the suite); ILLUSIO_CONSTRAINTS=none
# installs the newest instead (how constraints.txt is refreshed: README, "Versions").
set -euo pipefail
cd "$(dirname "$0")/.."
extra="${1:-}"
has_extra() { case ",$extra," in *",$1,"*) return 0 ;; *) return 1 ;; esac; }

need=()
ldconfig_bin=$(command -v ldconfig || echo /sbin/ldconfig)  # /sbin is not on every user's PATH
have_lib() { "$ldconfig_bin" -p 2>/dev/null | grep -q "$1"; }
have_lib 'libEGL.so.1' || need+=(libegl1)
have_lib 'libGL.so.1' || need+=(libgl1)
ls /usr/lib/*/dri/swrast_dri.so /usr/lib/*/dri/*_dri.so >/dev/null 2>&1 || need+=(libgl1-mesa-dri)
python3 -c 'import venv, ensurepip' >/dev/null 2>&1 || need+=(python3-venv)
if has_extra photo || has_extra test; then
  have_lib 'libatomic.so.1' || need+=(libatomic1)  # drjit (Mitsuba) links it; a bare root lacks it
fi
if has_extra test; then
  # the viewer's window tests run under a virtual X server; the gallery is checked in Chromium
  command -v Xvfb >/dev/null || need+=(xvfb)
  command -v xauth >/dev/null || need+=(xauth)
  command -v chromium >/dev/null || need+=(chromium)
fi
if [ ${#need[@]} -gt 0 ]; then
  if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then
    echo "setup: installing ${need[*]}" >&2
    DEBIAN_FRONTEND=noninteractive apt-get update -qq
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${need[@]}" >/dev/null
  else
    echo "setup: missing system packages; run as root:" >&2
    echo "  apt-get install -y --no-install-recommends ${need[*]}" >&2
    exit 1
  fi
fi

python3 -c 'import sys; sys.exit(sys.version_info < (3, 10))' || { echo "setup: Python 3.10 or newer is needed" >&2; exit 1; }
[ -x .venv/bin/python ] || python3 -m venv .venv
constraints=()
[ "${ILLUSIO_CONSTRAINTS:-}" = none ] || constraints=(-c constraints.txt)
.venv/bin/python -m pip install -q "${constraints[@]}" --upgrade pip >/dev/null
.venv/bin/python -m pip install -q "${constraints[@]}" -e ".${extra:+[$extra]}"
# numba's kernels compiled into their cache now, so the first command does not wait a minute for them
echo "setup: compiling the numba kernels once (about 45 s)" >&2
.venv/bin/illusio --quiet compile >/dev/null
