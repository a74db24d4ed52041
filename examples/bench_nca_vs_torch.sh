#!/usr/bin/env bash
# Side-by-side NCA speed: burn (flex, ndarray) vs the PyTorch CPU reference, interleaved so
# both see the same machine load. Usage (from the repository root):
#   cargo build --release --example bench_nca
#   bash examples/bench_nca_vs_torch.sh [ROUNDS] [PYTHON]      # PYTHON: a venv with torch
# Each line: the load average before the run, the program's own figure, and the peak
# resident memory from /usr/bin/time -v.
set -euo pipefail
rounds=${1:-1}
python=${2:-/work/venv-torch/bin/python}
torch_bench=${TORCH_BENCH:-../shared/bench/nca_torch.py}
burn=${CARGO_TARGET_DIR:-target}/release/examples/bench_nca
for f in "$torch_bench" "$burn" "$python"; do
  [ -e "$f" ] || { echo "missing $f (set TORCH_BENCH / CARGO_TARGET_DIR / PYTHON)" >&2; exit 1; }
done

run() {
  local load
  load=$(cut -d' ' -f1 /proc/loadavg)
  local out
  out=$(/usr/bin/time -v "$@" 2>/tmp/bench_nca_time.$$ | tail -1) || { cat /tmp/bench_nca_time.$$ >&2; exit 1; }
  local rss
  rss=$(awk -F: '/Maximum resident/ {gsub(/ /, "", $2); print int($2 / 1024)}' /tmp/bench_nca_time.$$)
  echo "load=$load peak_rss_mb=$rss $out"
}

for _ in $(seq "$rounds"); do
  run "$python" "$torch_bench" unroll 64 8
  run "$burn" unroll 64 8 flex shifted
  run "$burn" unroll 64 8 flex conv
  run "$burn" unroll 64 8 ndarray shifted
  run "$python" "$torch_bench" train 32 12 3
  run "$burn" train 32 12 3 flex shifted 0
  run "$burn" train 32 12 3 flex conv 0
  run "$burn" train 32 12 3 flex shifted 4
  run "$burn" train 32 12 3 ndarray shifted 0
done
rm -f /tmp/bench_nca_time.$$
