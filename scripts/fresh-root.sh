#!/usr/bin/env bash
# README's two commands on a bare machine: a minimal Debian root (debootstrap minbase, then only
# python3 python3-venv git ca-certificates), the commit under test cloned into it, README's demo
# command and then its test command run there as a new user would (as root, nothing else installed),
# each one's wall time printed; fails if either fails or if the demo's page lacks a section.
#
# Usage: scripts/fresh-root.sh [--rev REV] [--keep] [--write-constraints]
#   --rev REV              the commit to clone (default HEAD)
#   --keep                 leave the root in place afterwards (its path is printed); mounts are
#                          still undone
#   --write-constraints    install without the constraints file (the newest versions), and when
#                          both commands pass write the root's `pip freeze` over constraints.txt
# Environment: FRESH_ROOT_SUITE (bookworm), FRESH_ROOT_MIRROR (the host's first Debian source),
#   FRESH_ROOT_PARENT (/var/tmp: where the root is made).
# Exit status: 0 both commands passed; 77 skipped (not root, no debootstrap, mounts refused: said
# in one line); anything else a failure.
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
rev=HEAD keep=0 write_constraints=0
while [ $# -gt 0 ]; do
  case "$1" in
    --rev) rev="$2"; shift 2 ;;
    --keep) keep=1; shift ;;
    --write-constraints) write_constraints=1; shift ;;
    *) echo "fresh-root: unknown argument $1 (see the header of $0)" >&2; exit 2 ;;
  esac
done

skip() { echo "fresh-root: skipped: $*"; exit 77; }
[ "$(id -u)" = 0 ] || skip "needs root (debootstrap, chroot and mounts)"
command -v debootstrap >/dev/null || skip "no debootstrap (apt-get install -y debootstrap)"
commit=$(git -C "$repo" rev-parse --verify "$rev^{commit}")

demo_cmd="bash scripts/demo.sh"
test_cmd="bash scripts/test.sh"
for cmd in "$demo_cmd" "$test_cmd"; do
  grep -qxF "    $cmd" "$repo/README.md" || { echo "fresh-root: README.md no longer gives \`$cmd\` as a command" >&2; exit 1; }
done

suite=${FRESH_ROOT_SUITE:-bookworm}
host_mirror() {  # the first Debian archive the host's apt uses (deb822 or one-line sources)
  cat /etc/apt/sources.list.d/*.sources /etc/apt/sources.list 2>/dev/null |
    awk '/^URIs:/ && $2 !~ /security/ {print $2; exit} /^deb / && $0 !~ /security/ {for (i = 2; i <= NF; i++) if ($i ~ /^[a-z]+:\/\//) {print $i; exit}}' || true
}
mirror=${FRESH_ROOT_MIRROR:-$(host_mirror)}
mirror=${mirror:-http://deb.debian.org/debian}
root=$(mktemp -d "${FRESH_ROOT_PARENT:-/var/tmp}/illusio-fresh-root.XXXXXX")
chmod 755 "$root"  # mktemp makes it 0700: apt inside drops to its _apt user, who must reach its lists

mounts_under_root() { awk -v r="$root" '$5 == r || index($5, r "/") == 1 {print $5}' /proc/self/mountinfo | sort -r; }
cleanup() {
  local status=$?
  rm -f "$root.debootstrap.log"
  trap - EXIT INT TERM
  # what the commands left running (Xvfb, Ray, a test's server) holds the mounts: end it first
  local pid pids=()
  for pid in /proc/[0-9]*; do
    [ "$(readlink "$pid/root" 2>/dev/null)" = "$root" ] && pids+=("${pid#/proc/}")
  done
  if [ ${#pids[@]} -gt 0 ]; then kill -TERM "${pids[@]}" 2>/dev/null || true; sleep 2; kill -KILL "${pids[@]}" 2>/dev/null || true; fi
  local m
  for m in $(mounts_under_root); do umount "$m" 2>/dev/null || umount -l "$m" 2>/dev/null || true; done
  if [ -n "$(mounts_under_root)" ]; then
    # never remove a tree that still has the host's /dev or shared/ mounted inside it
    echo "fresh-root: could not unmount $(mounts_under_root | tr '\n' ' '); $root left in place" >&2
    [ "$status" = 0 ] && status=1
  elif [ "$keep" = 1 ]; then
    echo "fresh-root: the root is kept at $root"
  else
    rm -rf "$root"
  fi
  exit "$status"
}
trap cleanup EXIT
trap 'echo "fresh-root: interrupted" >&2; exit 130' INT TERM

elapsed() { local s=$(( $(date +%s) - $1 )); printf '%dm%02ds' $((s / 60)) $((s % 60)); }
t0=$(date +%s)
echo "fresh-root: debootstrap --variant=minbase $suite from $mirror into $root"
# long steps run in the background and are waited for: bash runs a trap for TERM only once the
# foreground command ends, `wait` returns at once. Job control (set -m) keeps SIGINT as it is in
# them: a non-interactive shell starts background jobs with SIGINT ignored, and Python then never
# raises KeyboardInterrupt (the suite's interrupt tests failed so)
set -m
debootstrap --variant=minbase --include=python3,python3-venv,git,ca-certificates "$suite" "$root" "$mirror" \
  >"$root.debootstrap.log" 2>&1 &
wait $! || { tail -20 "$root.debootstrap.log" >&2; rm -f "$root.debootstrap.log"; exit 1; }
rm -f "$root.debootstrap.log"
echo "fresh-root: root made in $(elapsed "$t0")"

# The same registries as the host: its CA bundle, apt sources and pip configuration (less what
# points at this machine's own folders: a new user has none of them), its DNS.
cp /etc/ssl/certs/ca-certificates.crt "$root/etc/ssl/certs/ca-certificates.crt"
if ls /etc/apt/sources.list.d/*.sources /etc/apt/sources.list.d/*.list >/dev/null 2>&1 || [ -s /etc/apt/sources.list ]; then
  rm -f "$root/etc/apt/sources.list"
  cp /etc/apt/sources.list.d/*.sources /etc/apt/sources.list.d/*.list "$root/etc/apt/sources.list.d/" 2>/dev/null || true
  [ -s /etc/apt/sources.list ] && cp /etc/apt/sources.list "$root/etc/apt/sources.list"
fi
for f in /etc/apt/apt.conf.d/*; do
  [ -e "$root$f" ] || cp "$f" "$root$f"
done
for f in /etc/pip.conf /etc/xdg/pip/pip.conf; do
  [ -f "$f" ] || continue
  mkdir -p "$root$(dirname "$f")"
  grep -vE '^\s*(constraint|find-links|find_links)\s*=|file://' "$f" >"$root$f" || true
done
cp -L /etc/resolv.conf "$root/etc/resolv.conf" 2>/dev/null || true
[ -f /etc/hosts ] && cp /etc/hosts "$root/etc/hosts"

# The commit under test, with shared/ beside it read-only, as CI lays them out.
mkdir -p "$root/work"
git clone -q --no-hardlinks "$repo" "$root/work/illusio"
git -C "$root/work/illusio" checkout -q "$commit"
mount -t proc proc "$root/proc" || skip "mounts are refused here (mount -t proc)"
mount -t sysfs sys "$root/sys"
mount --rbind /dev "$root/dev" && mount --make-rslave "$root/dev"
if [ -d "$repo/../shared" ]; then
  mkdir -p "$root/work/shared"
  mount --bind "$repo/../shared" "$root/work/shared"
  mount -o remount,bind,ro "$root/work/shared"
fi

# A new user's shell: no variables of this one but the proxies and CI's flag.
env_keep=(HOME=/root PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin LANG=C.UTF-8 TERM=dumb)
for v in CI http_proxy https_proxy no_proxy HTTP_PROXY HTTPS_PROXY NO_PROXY PIP_INDEX_URL ILLUSIO_TEST_SEED; do
  [ -n "${!v:-}" ] && env_keep+=("$v=${!v}")
done
[ "$write_constraints" = 1 ] && env_keep+=(ILLUSIO_CONSTRAINTS=none)
inside() { chroot "$root" /usr/bin/env -i "${env_keep[@]}" bash -c "cd /work/illusio && $1" & wait $!; }

echo "fresh-root: $commit; README's demo command: $demo_cmd"
t=$(date +%s)
inside "$demo_cmd"
demo_time=$(elapsed "$t")
echo "fresh-root: demo command passed in $demo_time"
sections=$(inside ".venv/bin/python -c 'from illusio.gallery import SHOWCASES; print(len(SHOWCASES))'")
python3 "$repo/scripts/check_gallery.py" "$root/work/illusio/demo-out/index.html" --sections "$sections"

echo "fresh-root: README's test command: $test_cmd"
t=$(date +%s)
inside "$test_cmd"
test_time=$(elapsed "$t")
echo "fresh-root: test command passed in $test_time"

if [ "$write_constraints" = 1 ]; then
  { echo "# Versions of a fresh install (Debian $suite, $(inside 'python3 --version')) that passed the suite:"
    echo "# scripts/fresh-root.sh --write-constraints, at $commit"
    inside ".venv/bin/python -m pip freeze --exclude-editable" | grep -v '^illusio'; } >"$repo/constraints.txt.tmp"
  mv "$repo/constraints.txt.tmp" "$repo/constraints.txt"
  echo "fresh-root: wrote constraints.txt"
fi
echo "fresh-root: passed — demo $demo_time, tests $test_time, whole run $(elapsed "$t0")"
