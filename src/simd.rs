//! Which vector instruction sets the fast paths may use.
//!
//! Every fast path with processor-specific code (the fringe-assembly block
//! kernel, the 8-bit pixel interleave, the mesh renderer's coverage, span and
//! shading loops) asks a [`Simd`] before taking it. The portable path is what
//! a processor without AVX2 (or SSSE3) runs; forcing it lets the tests check
//! that path against the reference on machines that do have the vector ones.

use std::sync::OnceLock;

/// The instruction-set choice of a fast path.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Simd {
    /// The widest paths the processor has (detected at run time), unless the
    /// environment variable `HOLO_FORCE_PORTABLE=1` forbids vector paths for
    /// the whole process.
    #[default]
    Detect,
    /// The portable paths only, whatever the processor has.
    Portable,
}

impl Simd {
    /// Vector paths are allowed at all.
    fn vectors(self) -> bool {
        self == Simd::Detect && !forced_portable()
    }

    /// AVX2 and FMA may be used.
    pub(crate) fn avx2_fma(self) -> bool {
        #[cfg(target_arch = "x86_64")]
        {
            self.vectors() && std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma")
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            false
        }
    }

    /// AVX2 may be used.
    pub(crate) fn avx2(self) -> bool {
        #[cfg(target_arch = "x86_64")]
        {
            self.vectors() && std::arch::is_x86_feature_detected!("avx2")
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            false
        }
    }

    /// F16C (with AVX, which its 256-bit forms need) may be used.
    pub(crate) fn f16c(self) -> bool {
        #[cfg(target_arch = "x86_64")]
        {
            self.vectors() && std::arch::is_x86_feature_detected!("f16c") && std::arch::is_x86_feature_detected!("avx")
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            false
        }
    }

    /// SSSE3 may be used.
    pub(crate) fn ssse3(self) -> bool {
        #[cfg(target_arch = "x86_64")]
        {
            self.vectors() && std::arch::is_x86_feature_detected!("ssse3")
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            false
        }
    }
}

/// `HOLO_FORCE_PORTABLE=1`, read once.
fn forced_portable() -> bool {
    static FORCED: OnceLock<bool> = OnceLock::new();
    *FORCED.get_or_init(|| std::env::var("HOLO_FORCE_PORTABLE").as_deref() == Ok("1"))
}
