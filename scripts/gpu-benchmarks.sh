#!/usr/bin/env bash
# Runs benchmark suites on a GPU through EGL, for RESULTS.md's GPU figures:
#   bash scripts/gpu-benchmarks.sh OUT_DIR SECONDS_PER_SUITE SUITE [SUITE ...]
# Refuses to run on a software rasteriser (llvmpipe, softpipe, swrast): those figures are the CPU
# rows already. Each suite runs under its own time limit and a failing suite does not stop the
# others; OUT_DIR gets each suite's JSON (json/) and the log, and BENCH_TAR (default OUT_DIR/bench.tar)
# a tar of both, rewritten after each suite, so what finished is there even if the run is stopped.
set -u
out=${1:?OUT_DIR}
limit=${2:?SECONDS_PER_SUITE}
shift 2
mkdir -p "$out/json"
log="$out/log.txt"
tarball=${BENCH_TAR:-$out/bench.tar}
python=${PYTHON:-python3}
export PYTHONUNBUFFERED=1

renderer=$("$python" -c 'from illusio.core import Context; print(Context().info()["renderer"])' 2>>"$log")
echo "renderer: ${renderer:-none}" | tee -a "$log"
software=0
case "${renderer,,}" in
"" | *llvmpipe* | *softpipe* | *swrast*) software=1 ;;
esac
# ALLOW_SOFTWARE=1: a dry run of this script on a CPU rasteriser (its figures are not GPU figures)
if [ "$software" = 1 ] && ! { [ -n "${ALLOW_SOFTWARE:-}" ] && [ -n "$renderer" ]; }; then
    echo "gpu-benchmarks: no GPU renderer through EGL (got '${renderer}'; the error above)" | tee -a "$log" >&2
    tail -5 "$log" >&2
    exit 2
fi
command -v nvidia-smi >/dev/null && nvidia-smi --query-gpu=name,driver_version,clocks.sm --format=csv | tee -a "$log"

for suite in "$@"; do
    start=$(date +%s)
    timeout --kill-after=5 "$limit" "$python" -m benchmarks "$suite" --repeat "${REPEAT:-5}" --out "$out/json" >>"$log" 2>&1
    echo "== $suite: exit $? after $(($(date +%s) - start)) s" | tee -a "$log"
    tar -cf "$tarball.tmp" -C "$out" json log.txt && mv "$tarball.tmp" "$tarball"
done
