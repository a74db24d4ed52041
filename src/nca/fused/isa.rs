//! The instruction sets the fused kernels are compiled for, and the proof that this CPU has
//! one: an [`Isa`] can only be obtained for a level the CPU supports, which is what makes
//! calling the `#[target_feature]` kernels sound.

use std::fmt;
use std::str::FromStr;

use crate::error::XylemError;

/// Instruction-set levels, best first.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Level {
    /// AVX-512F/VL with FMA: 32 vector registers of 16 floats.
    Avx512,
    /// AVX2 with FMA: 16 registers of 8 floats.
    Avx2,
    /// The x86-64 baseline or any other architecture: whatever the compiler targets by
    /// default, no FMA.
    Portable,
}

/// An instruction-set level this CPU supports (the only way to get one is to check).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Isa(Level);

impl Isa {
    /// The level if this CPU supports it.
    pub fn new(level: Level) -> Option<Self> {
        supported(level).then_some(Self(level))
    }

    /// The best level this CPU supports.
    pub fn best() -> Self {
        [Level::Avx512, Level::Avx2, Level::Portable]
            .into_iter()
            .find_map(Self::new)
            .expect("the portable level is always supported")
    }

    /// Every level this CPU supports, best first.
    pub fn all() -> Vec<Self> {
        [Level::Avx512, Level::Avx2, Level::Portable]
            .into_iter()
            .filter_map(Self::new)
            .collect()
    }

    pub fn level(self) -> Level {
        self.0
    }
}

impl fmt::Display for Isa {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self.0 {
            Level::Avx512 => "avx512",
            Level::Avx2 => "avx2",
            Level::Portable => "portable",
        })
    }
}

impl FromStr for Isa {
    type Err = XylemError;

    /// `avx512`, `avx2`, `portable` or `best`; an error if this CPU lacks it.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let level = match s.trim().to_ascii_lowercase().as_str() {
            "best" => return Ok(Self::best()),
            "avx512" => Level::Avx512,
            "avx2" => Level::Avx2,
            "portable" => Level::Portable,
            other => {
                return Err(XylemError::input(
                    format!("instruction set {other:?}"),
                    "expected avx512, avx2, portable or best",
                ));
            }
        };
        Self::new(level).ok_or_else(|| {
            XylemError::input(
                format!("instruction set {s:?}"),
                "this CPU does not support it",
            )
        })
    }
}

#[cfg(target_arch = "x86_64")]
fn supported(level: Level) -> bool {
    match level {
        Level::Avx512 => {
            is_x86_feature_detected!("avx512f")
                && is_x86_feature_detected!("avx512vl")
                && is_x86_feature_detected!("avx2")
                && is_x86_feature_detected!("fma")
        }
        Level::Avx2 => is_x86_feature_detected!("avx2") && is_x86_feature_detected!("fma"),
        Level::Portable => true,
    }
}

#[cfg(not(target_arch = "x86_64"))]
fn supported(level: Level) -> bool {
    level == Level::Portable
}
