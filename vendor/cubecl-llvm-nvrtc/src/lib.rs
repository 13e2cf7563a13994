//! The part of `cubecl-llvm` 0.11.3's interface that `cubecl-cuda` 0.11.3 names, without LLVM.
//!
//! `cubecl-cuda` compiles kernels with one of two backends, chosen once per process by
//! `CudaBackend::default()`: CUDA C++ handed to NVRTC at run time (with its `cpp` feature) or
//! LLVM → PTX. yokai's CUDA build enables `cpp` (see `crates/yokai-train/Cargo.toml`), so
//! nothing here runs in practice: the types exist so that `cubecl-cuda` compiles, and
//! [`PlironCompiler`] refuses any kernel it is given, with a message that names the cause,
//! rather than emitting something wrong. Signatures follow the real crate exactly (checked by
//! `cubecl-cuda` compiling against them).

use core::fmt;

use cubecl_core::ir::DeviceProperties;
use cubecl_core::ir::nvidia::SmArch;
use cubecl_environment::backtrace::BackTrace;
use cubecl_runtime::compiler::{CompilationError, Compiler};
use cubecl_runtime::kernel::{BufferIOAttr, KernelDefinition};

/// Why every kernel is refused, in the words a user of `yokai train --device cuda` needs.
pub const NO_LLVM: &str = "this build of cubecl-cuda has no LLVM backend (yokai patches \
    cubecl-llvm out because its build downloads an LLVM bundle); it compiles kernels with \
    NVRTC, which needs cubecl-cuda's `cpp` feature to be enabled";

/// LLVM compilation targets. Only the ones `cubecl-cuda` names.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum LlvmTarget {
    #[default]
    Cpu,
    Nvptx,
}

/// The LLVM compiler's options; `cubecl-cuda` fills these four fields.
#[derive(Clone, Debug, Default)]
pub struct PlironOptions {
    /// AMDGPU architecture: never set by the CUDA runtime.
    pub arch: Option<()>,
    pub sm_arch: Option<SmArch>,
    pub ptx_version: Option<nvptx::ptx_version::PtxVersion>,
    pub grid_constants: bool,
}

/// A compiled PTX module, as the real crate describes one.
#[derive(Clone, Debug)]
pub struct NvptxModule {
    pub ptx: Vec<core::ffi::c_char>,
    pub entrypoint: String,
    pub ir: String,
    pub shared_memory_size: usize,
    pub io: Vec<BufferIOAttr>,
}

/// What the LLVM compiler produces. `Refused` stands in for the real crate's CPU JIT variant,
/// so that `cubecl-cuda`'s match on `NvptxCode` keeps its fallback arm.
#[derive(Clone, Debug)]
pub enum PlironArtifact {
    NvptxCode(NvptxModule),
    Refused,
}

impl fmt::Display for PlironArtifact {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            PlironArtifact::NvptxCode(module) => f.write_str(&module.ir),
            PlironArtifact::Refused => f.write_str(NO_LLVM),
        }
    }
}

/// The LLVM compiler, which in this build compiles nothing.
#[derive(Clone, Debug, Default)]
pub struct PlironCompiler {
    pub target: LlvmTarget,
}

impl Compiler for PlironCompiler {
    type Representation = PlironArtifact;
    type CompilationOptions = PlironOptions;

    fn compile(
        &mut self,
        _kernel: KernelDefinition,
        _options: &Self::CompilationOptions,
    ) -> Result<Self::Representation, CompilationError> {
        Err(CompilationError::Generic {
            reason: NO_LLVM.to_string(),
            backtrace: BackTrace::capture(),
        })
    }

    fn extension(&self) -> &'static str {
        "ll"
    }

    fn lang_tag(&self) -> &'static str {
        "llvm"
    }
}

pub mod nvptx {
    pub mod ptx_version {
        use core::fmt;

        /// A PTX ISA version (8.7 is `87`), read only by the LLVM backend.
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
        pub struct PtxVersion(u32);

        impl PtxVersion {
            /// `None`: this build emits no PTX itself. NVRTC picks the version it writes, and
            /// `cubecl-cuda` reads this value only on its LLVM path.
            pub fn for_driver(_driver: i32) -> Option<Self> {
                None
            }
        }

        impl fmt::Display for PtxVersion {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                write!(f, "ptx{}", self.0)
            }
        }
    }
}

pub mod shared {
    pub mod lowered_features {
        use super::super::DeviceProperties;

        /// The GPU a device's features would be narrowed for.
        #[derive(Clone, Copy, Debug, PartialEq, Eq)]
        pub enum GpuTarget {
            Nvptx,
        }

        /// Leaves `props` as the runtime built them. `cubecl-cuda` calls this only when the
        /// LLVM backend is selected, which the CUDA build's `cpp` feature rules out; the C++
        /// backend honours everything the runtime advertises.
        pub fn restrict_features(_props: &mut DeviceProperties, _target: GpuTarget) {}
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_refusal_names_nvrtc_and_the_cpp_feature() {
        assert!(NO_LLVM.contains("NVRTC") && NO_LLVM.contains("`cpp`"));
        assert_eq!(nvptx::ptx_version::PtxVersion::for_driver(12080), None);
        assert_eq!(PlironArtifact::Refused.to_string(), NO_LLVM);
    }
}
