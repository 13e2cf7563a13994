//! Training unchanged by a refactor: the first updates of the shipped presets `quick`,
//! `cpu` and `obl-quick` (seed 0, one thread) reproduce, bit for bit, every loss and game
//! metric stored in `tests/golden/training-NAME.jsonl`, and the network's parameters after
//! them (an FNV-1a hash of their f32 bits, the file's last line).
//!
//! A change meant to alter training (a new default, a fixed bug) writes the files again
//! with `YOKAI_BLESS=1 cargo test --release -p yokai-train --test golden_training`, and
//! says so in its commit. The figures are those of this machine's CPU: another CPU's
//! float instructions may round differently, which the failure message says.
//!
//! burn's CPU backend multiplies matrices with gemm, which picks its kernels at run time:
//! AVX-512 where the CPU has `avx512f`, FMA otherwise. The two sum in different orders, so
//! each has its own files: `training-NAME.jsonl` for FMA (AVX2) CPUs, and
//! `training-NAME.avx512.jsonl` for AVX-512 ones. Blessing writes the running CPU's kind.
//! On an AVX-512 CPU the FMA files are written by a build whose `burn-flex` dependency
//! (crates/yokai-train/Cargo.toml) leaves out the `x86-v4` feature, run with
//! `YOKAI_GOLDEN_KERNELS=fma`, which names the FMA files whatever the CPU has.

use serde_json::Value;
use yokai_train::{MlpEncoder, TrainConfig, Trainer};

/// Updates stored per preset: the first one from fresh weights, the later ones from
/// weights the learner changed (a refactor of the learner shows from the second on).
const UPDATES: usize = 3;

/// Fields of `UpdateStats` that measure time, which no two runs share.
const TIMINGS: [&str; 3] = ["sps", "rollout_seconds", "learn_seconds"];

fn fnv1a(values: &[f32]) -> String {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for v in values {
        for b in v.to_bits().to_le_bytes() {
            h = (h ^ b as u64).wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
    format!("{h:016x}")
}

/// The golden lines of preset `name`: one per update (timings removed), then the
/// parameters' hash and count.
fn lines_of(name: &str) -> Vec<String> {
    let path = format!("{}/../../configs/{name}.toml", env!("CARGO_MANIFEST_DIR"));
    let mut config = TrainConfig::from_file(std::path::Path::new(&path)).unwrap();
    config.run.threads = 1;
    // burn's CPU backend splits work over rayon's threads; one makes float sums exact.
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    pool.install(|| {
        let mut t = Trainer::<MlpEncoder>::new(config, 0).unwrap();
        let mut out: Vec<String> = (0..UPDATES)
            .map(|_| {
                let mut v = serde_json::to_value(t.update().unwrap()).unwrap();
                for k in TIMINGS {
                    v.as_object_mut().unwrap().remove(k);
                }
                v.to_string()
            })
            .collect();
        let params = t.parameters();
        out.push(
            serde_json::json!({"parameters": params.len(), "fnv1a": fnv1a(&params)}).to_string(),
        );
        out
    })
}

/// The golden files' suffix for this CPU's matrix kernels (see the module's docs).
#[cfg(target_arch = "x86_64")]
fn kernels() -> &'static str {
    if std::env::var("YOKAI_GOLDEN_KERNELS").as_deref() == Ok("fma") {
        return "";
    }
    if std::arch::is_x86_feature_detected!("avx512f") {
        ".avx512"
    } else {
        ""
    }
}

#[cfg(not(target_arch = "x86_64"))]
fn kernels() -> &'static str {
    ""
}

fn check(name: &str) {
    let path = format!(
        "{}/tests/golden/training-{name}{}.jsonl",
        env!("CARGO_MANIFEST_DIR"),
        kernels()
    );
    let got = lines_of(name);
    if std::env::var_os("YOKAI_BLESS").is_some() {
        std::fs::write(&path, got.join("\n") + "\n").unwrap();
        return;
    }
    let want: Vec<String> = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("{path}: {e}; write it with YOKAI_BLESS=1"))
        .lines()
        .map(String::from)
        .collect();
    assert_eq!(got.len(), want.len(), "{path}: lines");
    for (k, (g, w)) in got.iter().zip(&want).enumerate() {
        if g == w {
            continue;
        }
        // Name the fields that moved, so a failure says what the change touched.
        let (g, w): (Value, Value) = (
            serde_json::from_str(g).unwrap(),
            serde_json::from_str(w).unwrap(),
        );
        let mut moved: Vec<String> = w
            .as_object()
            .unwrap()
            .iter()
            .filter(|(key, value)| g.get(key.as_str()) != Some(value))
            .map(|(key, value)| {
                format!(
                    "{key}: stored {value}, now {}",
                    g.get(key.as_str()).unwrap_or(&Value::Null)
                )
            })
            .collect();
        moved.extend(
            g.as_object()
                .unwrap()
                .iter()
                .filter(|(key, _)| w.get(key.as_str()).is_none())
                .map(|(key, value)| format!("{key}: not stored, now {value}")),
        );
        panic!(
            "{name}: line {} of {path} differs (training changed, or this CPU rounds differently):\n  {}",
            k + 1,
            moved.join("\n  ")
        );
    }
}

#[test]
fn the_quick_preset_trains_as_stored() {
    check("quick");
}

#[test]
fn the_cpu_preset_trains_as_stored() {
    check("cpu");
}

#[test]
fn the_obl_quick_preset_trains_as_stored() {
    check("obl-quick");
}
