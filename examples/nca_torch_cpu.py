#!/usr/bin/env python3
"""Runs the PyTorch NCA reference with CPU seconds instead of wall seconds.

usage: nca_torch_cpu.py PATH/TO/nca_torch.py unroll|train ARGS...

The reference times its loops with time.perf_counter (wall clock). On a shared machine the
wall clock includes waiting for a core, so this runs the very same script with
time.perf_counter replaced by time.process_time (CPU seconds of all the process's
threads): its figures become per CPU-second, comparable to the `cpu` figures of
examples/bench_fused.rs and examples/bench_nca.rs.
"""
import runpy
import sys
import time

script = sys.argv[1]
sys.argv = [script] + sys.argv[2:]
time.perf_counter = time.process_time
runpy.run_path(script, run_name="__main__")
