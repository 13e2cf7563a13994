//! Where the network's tensors live: the CPU (burn's pure-Rust `flex`), or a GPU through
//! burn's Vulkan (`vulkan` feature) or CUDA (`cuda` feature) runtime.
//!
//! The choice is made at run time (`yokai train --device`), so one binary built with a GPU
//! feature still trains on the CPU, and the training code is the same for every backend:
//! only the [`Device`] differs. The environment always steps on the CPU.
//!
//! Both GPU routes build from crates alone. burn 0.22's CUDA runtime (`cubecl-cuda` 0.11)
//! depends on `cubecl-llvm`, whose build script downloads an LLVM bundle, and this workplace
//! reaches only package registries; the `cuda` feature therefore turns on cubecl-cuda's
//! NVRTC backend (CUDA C++ compiled at run time, as cubecl-cuda 0.10 always did) and the
//! workspace patches `cubecl-llvm` out for a stand-in (`vendor/cubecl-llvm-nvrtc`). The
//! Vulkan runtime (`cubecl-wgpu` with SPIR-V) needs only a Vulkan loader and the GPU's
//! driver at run time (`docs/training.md`).

use burn::prelude::*;
use std::fmt;
use std::str::FromStr;

/// A compute backend for training and inference.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Backend {
    /// burn's `flex` CPU backend (always built).
    #[default]
    Cpu,
    /// burn's Vulkan runtime (SPIR-V kernels); needs the `vulkan` cargo feature.
    Vulkan,
    /// burn's CUDA runtime; needs the `cuda` cargo feature.
    Cuda,
}

/// Why a backend cannot be used.
#[derive(Debug, thiserror::Error, PartialEq, Eq)]
pub enum BackendError {
    #[error("unknown device `{0}`: expected cpu, vulkan or cuda")]
    Unknown(String),
    #[error(
        "device `{backend}` is not built into this binary: rebuild with \
         `cargo build --release -p yokai-cli --features {backend}` (built-in devices: {built})"
    )]
    NotBuilt { backend: Backend, built: String },
    #[error("device `{backend}` could not start: {message}")]
    Unavailable { backend: Backend, message: String },
}

impl Backend {
    pub const ALL: [Backend; 3] = [Backend::Cpu, Backend::Vulkan, Backend::Cuda];

    pub fn name(self) -> &'static str {
        match self {
            Backend::Cpu => "cpu",
            Backend::Vulkan => "vulkan",
            Backend::Cuda => "cuda",
        }
    }

    /// Whether this binary was built with the backend's cargo feature.
    pub fn is_built(self) -> bool {
        match self {
            Backend::Cpu => true,
            Backend::Vulkan => cfg!(feature = "vulkan"),
            Backend::Cuda => cfg!(feature = "cuda"),
        }
    }

    /// The backends built into this binary, by name.
    pub fn built() -> Vec<&'static str> {
        Backend::ALL
            .iter()
            .filter(|b| b.is_built())
            .map(|b| b.name())
            .collect()
    }

    /// Makes this backend burn's default device for the whole process (`BURN_DEVICE`).
    ///
    /// burn 0.22 puts a loaded optimiser's state on `Device::default()` (burn-optim's
    /// `ModuleOptimizer::load_record`) before the first step moves it to the parameters'
    /// device, and in a build with a GPU feature that default is the GPU, whatever device the
    /// run trains on: `--resume` of a CPU run then fails on a machine without the GPU. Call
    /// this once, before any thread starts: it sets an environment variable.
    pub fn make_burn_default(self) {
        let name = match self {
            Backend::Cpu => "flex",
            Backend::Vulkan | Backend::Cuda => self.name(),
        };
        std::env::set_var("BURN_DEVICE", name);
    }

    /// The backend's (inference) device, without checking that a GPU answers.
    fn raw_device(self) -> Result<Device, BackendError> {
        if !self.is_built() {
            return Err(BackendError::NotBuilt {
                backend: self,
                built: Backend::built().join(", "),
            });
        }
        match self {
            Backend::Cpu => Ok(crate::device::default_device()),
            // wgpu's best adapter: a discrete GPU first, else an integrated one, else a CPU
            // driver (Mesa's lavapipe starts, but crashes in burn's matrix-product kernels:
            // docs/results/vulkan-lavapipe.md); `CUBECL_WGPU_DEFAULT_DEVICE=IntegratedGpu(0)`
            // picks another. Was `DiscreteGpu(0)`, which refused every other adapter.
            #[cfg(feature = "vulkan")]
            Backend::Vulkan => Ok(Device::vulkan(burn::tensor::DeviceKind::DefaultDevice)),
            #[cfg(feature = "cuda")]
            Backend::Cuda => Ok(Device::cuda(0)),
            #[allow(unreachable_patterns)]
            _ => unreachable!("is_built checked the feature"),
        }
    }

    /// The backend's device, checked by a small computation on it. burn panics when a GPU
    /// runtime finds no driver or adapter; that panic is caught here and returned as an
    /// error that says what is missing, so that `yokai train --device vulkan` on a machine
    /// without a GPU fails with a sentence, not a backtrace.
    pub fn device(self) -> Result<Device, BackendError> {
        let device = self.raw_device()?;
        if self == Backend::Cpu {
            return Ok(device);
        }
        // NVRTC compiles every kernel against the CUDA headers, and cubecl-cuda panics deep
        // in its first kernel when they are missing: say so before that.
        #[cfg(feature = "cuda")]
        if self == Backend::Cuda {
            if let Some(message) = cuda_headers_missing(cubecl_cuda::install::cuda_path()) {
                return Err(BackendError::Unavailable {
                    backend: self,
                    message,
                });
            }
        }
        let probe = device.clone();
        // The runtime's own panic is often raised on its server thread, and the probe then
        // sees only a closed channel: record what every thread says while probing.
        let said = std::sync::Arc::new(std::sync::Mutex::new(Vec::<String>::new()));
        let hook = std::panic::take_hook();
        let record = said.clone();
        std::panic::set_hook(Box::new(move |info| {
            let text = info
                .payload()
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| info.payload().downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_else(|| "the runtime panicked".into());
            if let Ok(mut said) = record.lock() {
                said.push(text);
            }
        }));
        let answer = std::panic::catch_unwind(move || {
            let t = Tensor::<1>::from_floats([1.0, 2.0, 3.0], &probe);
            (t.clone() * t).sum().into_scalar::<f32>()
        });
        std::panic::set_hook(hook);
        match answer {
            Ok(v) if (v - 14.0).abs() < 1e-4 => Ok(device),
            Ok(v) => Err(BackendError::Unavailable {
                backend: self,
                message: format!("a test sum gave {v}, not 14"),
            }),
            Err(_) => {
                let said = said.lock().map(|s| s.join("; ")).unwrap_or_default();
                Err(BackendError::Unavailable {
                    backend: self,
                    message: format!("{said} ({})", self.requirement()),
                })
            }
        }
    }

    /// What the backend needs on the machine at run time.
    fn requirement(self) -> &'static str {
        match self {
            Backend::Cpu => "nothing",
            Backend::Vulkan => {
                "needs a Vulkan loader (libvulkan.so.1) and the GPU driver's Vulkan ICD; \
                 set VK_DRIVER_FILES to the driver's ICD json if the loader does not find it, \
                 CUBECL_WGPU_DEFAULT_DEVICE (e.g. `DiscreteGpu(1)`) to choose among adapters"
            }
            Backend::Cuda => {
                "needs the NVIDIA driver (libcuda.so), NVRTC (libnvrtc.so, on LD_LIBRARY_PATH) \
                 and the CUDA headers (CUDA_PATH or /usr/local/cuda)"
            }
        }
    }
}

/// What is wrong with the CUDA installation found at `root` (cubecl-cuda's `cuda_path()`:
/// `CUDA_PATH`, else /usr/local/cuda, /opt/cuda or /usr), or `None` when NVRTC will find the
/// headers every kernel includes.
#[cfg_attr(not(feature = "cuda"), allow(dead_code))]
fn cuda_headers_missing(root: Option<std::path::PathBuf>) -> Option<String> {
    let fix = "set CUDA_PATH to the CUDA toolkit (the folder that holds include/cuda_fp16.h)";
    let Some(root) = root else {
        return Some(format!("no CUDA installation found: {fix}"));
    };
    let header = root.join("include").join("cuda_fp16.h");
    if header.is_file() {
        None
    } else {
        Some(format!(
            "the CUDA headers are not at {}: {fix}",
            header.display()
        ))
    }
}

impl fmt::Display for Backend {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Backend {
    type Err = BackendError;
    fn from_str(s: &str) -> Result<Backend, BackendError> {
        match s.to_ascii_lowercase().as_str() {
            "cpu" | "flex" => Ok(Backend::Cpu),
            "vulkan" => Ok(Backend::Vulkan),
            "cuda" => Ok(Backend::Cuda),
            // The GPU backend built in, CUDA first; in a CPU build, CUDA, so that the error
            // names the feature to build.
            "gpu" if !Backend::Cuda.is_built() && Backend::Vulkan.is_built() => Ok(Backend::Vulkan),
            "gpu" => Ok(Backend::Cuda),
            _ => Err(BackendError::Unknown(s.to_string())),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_unknown_names_are_errors() {
        for b in Backend::ALL {
            assert_eq!(b.name().parse::<Backend>(), Ok(b));
            assert_eq!(b.name().to_uppercase().parse::<Backend>(), Ok(b));
        }
        let e = "tpu".parse::<Backend>().unwrap_err().to_string();
        assert!(
            e.contains("`tpu`") && e.contains("cpu, vulkan or cuda"),
            "{e}"
        );
    }

    /// `gpu` is the GPU backend built in, CUDA first; in a build with none it still names
    /// CUDA, whose device then says which feature builds it.
    #[test]
    fn gpu_names_the_gpu_backend_built_in() {
        let want = match (cfg!(feature = "cuda"), cfg!(feature = "vulkan")) {
            (false, true) => Backend::Vulkan,
            _ => Backend::Cuda,
        };
        assert_eq!("gpu".parse::<Backend>(), Ok(want));
        let mut built = vec!["cpu"];
        if cfg!(feature = "vulkan") {
            built.push("vulkan");
        }
        if cfg!(feature = "cuda") {
            built.push("cuda");
        }
        assert_eq!(Backend::built(), built);
    }

    /// Each backend built in maps to its runtime's device, without touching a GPU; the
    /// others are refused, naming the feature that builds them and what is built.
    #[test]
    fn each_backend_maps_to_its_runtimes_device_or_names_its_feature() {
        assert_eq!(Backend::Cpu.raw_device().unwrap(), Device::flex());
        assert_eq!(Backend::Cpu.device().unwrap(), Device::flex());
        #[cfg(feature = "vulkan")]
        assert_eq!(
            Backend::Vulkan.raw_device().unwrap(),
            Device::vulkan(burn::tensor::DeviceKind::DefaultDevice)
        );
        #[cfg(feature = "cuda")]
        assert_eq!(Backend::Cuda.raw_device().unwrap(), Device::cuda(0));
        for b in Backend::ALL.into_iter().filter(|b| !b.is_built()) {
            let e = b.device().unwrap_err().to_string();
            assert!(e.contains(&format!("--features {}", b.name())), "{e}");
            assert!(e.contains(&Backend::built().join(", ")), "{e}");
        }
    }

    /// In a GPU build burn's own default is the GPU; after this call it is the CPU backend
    /// the trainer uses, so a resumed CPU run loads its optimiser state there. (In the CPU
    /// build burn's default is the CPU anyway: the test bites in the GPU builds, whose test
    /// targets CI compiles.)
    #[test]
    fn the_selected_backend_becomes_burns_default_device() {
        Backend::Cpu.make_burn_default();
        assert_eq!(Device::default(), Device::flex());
    }

    #[test]
    fn a_cuda_installation_without_headers_is_named_with_the_fix() {
        let e = cuda_headers_missing(None).unwrap();
        assert!(
            e.contains("no CUDA installation") && e.contains("CUDA_PATH"),
            "{e}"
        );
        let dir = tempfile::tempdir().unwrap();
        let e = cuda_headers_missing(Some(dir.path().to_path_buf())).unwrap();
        assert!(
            e.contains("include/cuda_fp16.h") && e.contains("CUDA_PATH"),
            "{e}"
        );
        std::fs::create_dir(dir.path().join("include")).unwrap();
        std::fs::write(dir.path().join("include").join("cuda_fp16.h"), "").unwrap();
        assert_eq!(cuda_headers_missing(Some(dir.path().to_path_buf())), None);
    }

    /// The CUDA build must never select cubecl-cuda's LLVM backend: in this workspace that
    /// backend is a stand-in that refuses every kernel (vendor/cubecl-llvm-nvrtc).
    #[cfg(feature = "cuda")]
    #[test]
    fn the_cuda_build_compiles_kernels_with_nvrtc() {
        use cubecl_cuda::compiler::CudaBackend;
        assert_eq!(CudaBackend::default(), CudaBackend::Cpp);
    }
}
