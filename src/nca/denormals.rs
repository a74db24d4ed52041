//! Flush-to-zero for denormal floats on the threads that run the NCA.
//!
//! Measured (BENCHMARKS.md, "NCA"): backpropagating through more than ~16 steps produces
//! denormal floats (|x| < 1.2e-38) somewhere in the gradient chain, and x86 CPUs handle those
//! in microcode, 10-100x slower: a 128^3-grid iteration with 32^3 crops went from 4.2 s at 16
//! steps to 7.7 s at 18 steps; with denormals flushed, 4.5 s at 18 steps and the same loss to
//! four digits. Flushing numbers below 1.2e-38 to zero cannot change anything the NCA computes
//! at a visible scale, and it is deterministic, so training (`session::run_training`) and
//! synthesis (`synth::synthesise`) turn it on themselves.
//!
//! It is a per-thread CPU flag (MXCSR FTZ and DAZ bits): this sets it on the calling thread
//! and on every thread of rayon's global pool, which is where burn's flex and ndarray
//! backends run their kernels. Other architectures: no-op.

/// Sets flush-to-zero and denormals-are-zero on this thread and all rayon global threads.
pub fn flush_denormals_to_zero() {
    set_on_this_thread();
    rayon::broadcast(|_| set_on_this_thread());
}

#[cfg(target_arch = "x86_64")]
#[allow(deprecated)] // the intrinsics are deprecated in favour of inline asm; same effect
fn set_on_this_thread() {
    use std::arch::x86_64::{_mm_getcsr, _mm_setcsr};
    // FTZ (bit 15) flushes denormal results, DAZ (bit 6) treats denormal inputs as zero.
    const FTZ_DAZ: u32 = 0x8040;
    // SAFETY: only the two flush bits of this thread's SSE control register change; rounding
    // mode and exception masks are kept.
    unsafe { _mm_setcsr(_mm_getcsr() | FTZ_DAZ) };
}

#[cfg(not(target_arch = "x86_64"))]
fn set_on_this_thread() {}
