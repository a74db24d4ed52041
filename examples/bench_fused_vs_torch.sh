#!/usr/bin/env bash
# Fused NCA (issue 8) beside burn flex and the PyTorch CPU reference, one after the other in
# one session so all see the same machine load. Usage (from the repository root):
#   cargo build --release --example bench_fused --example bench_nca
#   bash examples/bench_fused_vs_torch.sh [PYTHON]      # PYTHON: a venv with torch
# Each line: the load average before the run, the peak resident memory (/usr/bin/time -v)
# and the program's own figures. PyTorch runs twice per configuration: as is (wall seconds)
# and through examples/nca_torch_cpu.py (CPU seconds), since its script prints only one.
set -euo pipefail
python=${1:-/work/venv-torch/bin/python}
torch_bench=${TORCH_BENCH:-../shared/bench/nca_torch.py}
bin=${CARGO_TARGET_DIR:-target}/release/examples
fused=$bin/bench_fused
burn=$bin/bench_nca
for f in "$torch_bench" "$fused" "$burn" "$python"; do
  [ -e "$f" ] || { echo "missing $f (set TORCH_BENCH / CARGO_TARGET_DIR / PYTHON)" >&2; exit 1; }
done
log=$(mktemp)
trap 'rm -f "$log"' EXIT

run() {
  local load out rss
  load=$(cut -d' ' -f1-3 /proc/loadavg)
  out=$(/usr/bin/time -v "$@" 2>"$log" | tail -1) || { cat "$log" >&2; exit 1; }
  rss=$(awk -F: '/Maximum resident/ {gsub(/ /, "", $2); print int($2 / 1024)}' "$log")
  echo "load=[$load] peak_rss_mb=$rss $out"
}

torch() {
  run "$python" "$torch_bench" "$@"
  run "$python" examples/nca_torch_cpu.py "$torch_bench" "$@"
}

# sgemm throughput of this machine (PyTorch's BLAS, 2048^2 x 2048^2, all threads): the
# practical FLOP ceiling that the percentages of the FLOP limit refer to.
run "$python" -c '
import time, torch
n = 2048
a, b = torch.randn(n, n), torch.randn(n, n)
a @ b
w, c = time.perf_counter(), time.process_time()
for _ in range(20):
    a @ b
w, c = time.perf_counter() - w, time.process_time() - c
f = 20 * 2 * n ** 3
print(f"torch sgemm n={n} threads={torch.get_num_threads()} gflops={f / w / 1e9:.1f} gflops_per_cpu_s={f / c / 1e9:.1f}")
'

for size in 64 128; do
  RAYON_NUM_THREADS=1 run "$fused" unroll "$size" 8
  RAYON_NUM_THREADS=2 run "$fused" unroll "$size" 8
  run "$burn" unroll "$size" 8 flex shifted
  torch unroll "$size" 8
done
# Iterations after the warm-up one: 3 at 32^3, 2 at 64^3 (PyTorch and burn take tens of
# seconds per iteration there).
for spec in "32 3" "64 2"; do
  read -r size iters <<<"$spec"
  run "$fused" train "$size" 12 "$iters"
  run "$burn" train "$size" 12 "$iters" flex shifted 0
  torch train "$size" 12 "$iters"
done
