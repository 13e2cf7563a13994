//! A trained network's weights as a SafeTensors file, for people who want to look at them
//! or run them outside Rust (PyTorch, NumPy, JAX: `safetensors.numpy.load_file`).
//!
//! The project's own policy files (`container.rs`) carry the training state, check every
//! byte and are written atomically. SafeTensors is the interchange format the ML ecosystem
//! already reads safely (no code execution on load), so an export is burn's own
//! `burn-store` writer, not a second hand-written container. It is also the one weight
//! format shared with trainers outside Rust: a SafeTensors file with the metadata below
//! (written by `yokai export` or by Python's `yokai.torch_train`) is a policy every front
//! end loads (`yokai eval`, `play`, `serve`, `yokai.Agent`), see [`read_metadata`].
//!
//! Tensors are named by their path in the network (`encoder.…`, `memory.…`, `actor.…`,
//! `critic.…`), in burn's layouts: a linear layer's `weight` is `[d_in, d_out]` (PyTorch's
//! `nn.Linear` stores `[d_out, d_in]`). The metadata holds what is needed to rebuild the
//! inputs: the training config and the game (TOML), the observation encoding, and the
//! width of the recurrent state.

use crate::error::TrainError;
use burn::module::Module;
use burn::store::{ModuleSnapshot, SafetensorsStore};
use std::path::Path;

/// Metadata keys of an exported file.
pub const META_TRAIN_CONFIG: &str = "yokai.train_config";
pub const META_GAME: &str = "yokai.game";
pub const META_ENCODING: &str = "yokai.encoding";
pub const META_OBSERVATION_SHAPE: &str = "yokai.observation_shape";
pub const META_HIDDEN: &str = "yokai.hidden_size";
/// Optional: the run's seed, updates and env steps (0 where a file leaves them out).
pub const META_SEED: &str = "yokai.seed";
pub const META_UPDATE: &str = "yokai.update";
pub const META_ENV_STEPS: &str = "yokai.env_steps";

/// Whether `bytes` (a file's first bytes, at least 9) look like a SafeTensors file: a
/// little-endian u64 header length, then the JSON header's `{`.
pub(crate) fn looks_like(bytes: &[u8]) -> bool {
    bytes.len() > 8 && bytes[8] == b'{'
}

/// The string metadata of the SafeTensors file `bytes` (read from `path`): the JSON
/// header's `__metadata__`, without reading any tensor. A header that is cut short, not
/// JSON, or has no metadata is reported with the file.
pub(crate) fn read_metadata(
    bytes: &[u8],
    path: &Path,
) -> Result<std::collections::BTreeMap<String, String>, crate::error::FileError> {
    let corrupt = |what: String| crate::error::FileError::Corrupt {
        path: path.to_path_buf(),
        what,
    };
    let len = bytes
        .get(..8)
        .map(|b| u64::from_le_bytes(b.try_into().expect("8 bytes")) as usize)
        .ok_or_else(|| corrupt("shorter than a SafeTensors header".into()))?;
    let header = bytes.get(8..8usize.saturating_add(len)).ok_or_else(|| {
        corrupt(format!(
            "its SafeTensors header says {len} bytes; the file is shorter"
        ))
    })?;
    let json: serde_json::Value = serde_json::from_slice(header)
        .map_err(|e| corrupt(format!("its SafeTensors header is not JSON: {e}")))?;
    let meta = json
        .get("__metadata__")
        .and_then(|m| m.as_object())
        .ok_or_else(|| corrupt("its SafeTensors header has no `__metadata__`".into()))?;
    Ok(meta
        .iter()
        .filter_map(|(k, v)| Some((k.clone(), v.as_str()?.to_string())))
        .collect())
}

/// Write `model`'s parameters with `metadata` to `path` (replaced atomically if it exists).
pub(crate) fn write<M: Module>(
    model: &M,
    metadata: &[(&str, String)],
    path: &Path,
) -> Result<(), TrainError> {
    let mut store = metadata.iter().fold(
        SafetensorsStore::from_file(path).overwrite(true),
        |store, (key, value)| store.metadata(*key, value.clone()),
    );
    let existed = path.exists();
    model
        .save_into(&mut store)
        .map_err(|e| TrainError::Export {
            path: path.to_path_buf(),
            message: e.to_string(),
        })?;
    // burn-store writes through a private scratch file (mode 0600) and keeps the mode of a
    // file it replaces; a new export is meant to be shared, like the policy files.
    #[cfg(unix)]
    if !existed {
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(path, std::fs::Permissions::from_mode(0o644)).map_err(
            |source| TrainError::Io {
                path: path.to_path_buf(),
                source,
            },
        )?;
    }
    Ok(())
}

/// Load the parameters of a file [`write`] wrote into `model` (the same network): every
/// tensor must be found and fit, and none be left over, else the error names the file.
pub(crate) fn read_into<M: Module>(mut model: M, path: &Path) -> Result<M, TrainError> {
    let shown = path.display().to_string();
    let mut store = SafetensorsStore::from_file(path);
    let applied = model
        .load_from(&mut store)
        .map_err(|e| TrainError::Mismatch {
            path: shown.clone(),
            message: format!("not a SafeTensors export of this network: {e}"),
        })?;
    if !applied.missing.is_empty() || !applied.errors.is_empty() || !applied.unused.is_empty() {
        return Err(TrainError::Mismatch {
            path: shown,
            message: format!(
                "not a SafeTensors export of this network: missing {:?}, unused {:?}, errors {:?}",
                applied.missing, applied.unused, applied.errors
            ),
        });
    }
    Ok(model)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::TrainConfig;
    use crate::network::{ActorCritic, GruCell, MlpEncoder};
    use crate::tensor::parameters;
    use burn::prelude::Device;

    /// A SafeTensors file with the training config and the game as metadata is a policy
    /// `TrainedPolicy::load` seats, with the file's parameters; one without them, or cut
    /// short, is refused naming the file and what is missing.
    #[test]
    fn an_export_with_its_config_is_a_policy_and_a_bare_or_cut_one_is_refused() {
        let text = "[network]\npreset = \"compact\"\nhead = \"pointer\"\nhidden = 16\n";
        let config = TrainConfig::from_toml_str(text, "t").unwrap();
        let game = config.game_config().unwrap();
        let net = ActorCritic::<MlpEncoder, GruCell>::new(&config, &game, 5, &Device::flex());
        let dir = std::env::temp_dir().join(format!("yokai-st-policy-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("net.safetensors");
        let meta = [
            (META_TRAIN_CONFIG, config.to_toml()),
            (META_GAME, game.to_toml()),
            (META_ENV_STEPS, "4096".to_string()),
        ];
        write(&net, &meta, &path).unwrap();
        let policy = crate::TrainedPolicy::load(&path).unwrap();
        assert_eq!(policy.parameters(), parameters(&net));
        assert_eq!(policy.header().kind, "safetensors");
        assert_eq!(policy.header().env_steps, 4096);
        assert_eq!(policy.game(), &game);
        // Without the config in its metadata.
        write(&net, &meta[1..], &path).unwrap();
        let e = crate::TrainedPolicy::load(&path).unwrap_err().to_string();
        assert!(
            e.contains("net.safetensors") && e.contains("metadata yokai.train_config"),
            "{e}"
        );
        // Cut inside its header.
        write(&net, &meta, &path).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        std::fs::write(&path, &bytes[..40]).unwrap();
        let e = crate::TrainedPolicy::load(&path).unwrap_err().to_string();
        assert!(
            e.contains("net.safetensors is corrupt") && e.contains("header says"),
            "{e}"
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn an_export_loads_back_into_the_same_network_parameter_for_parameter() {
        let config = TrainConfig::from_toml_str(
            "[network]\npreset = \"compact\"\nhead = \"pointer\"\nhidden = 16\npointer_pool = true\n",
            "t",
        )
        .unwrap();
        let game = config.game_config().unwrap();
        let d = Device::flex();
        let net = ActorCritic::<MlpEncoder, GruCell>::new(&config, &game, 1, &d);
        let dir = std::env::temp_dir().join(format!("yokai-export-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("net.safetensors");
        write(&net, &[(META_HIDDEN, "16".into())], &path).unwrap();
        // Written twice: the second replaces the first.
        write(&net, &[(META_HIDDEN, "16".into())], &path).unwrap();
        let other = ActorCritic::<MlpEncoder, GruCell>::new(&config, &game, 2, &d);
        assert_ne!(parameters(&other), parameters(&net));
        let back = read_into(other, &path).unwrap();
        assert_eq!(parameters(&back), parameters(&net));
        // A network of another width is refused, naming the file.
        let wider = TrainConfig::from_toml_str(
            "[network]\npreset = \"compact\"\nhead = \"pointer\"\nhidden = 32\npointer_pool = true\n",
            "t",
        )
        .unwrap();
        let e = read_into(
            ActorCritic::<MlpEncoder, GruCell>::new(&wider, &game, 1, &d),
            &path,
        )
        .unwrap_err()
        .to_string();
        assert!(
            e.contains("net.safetensors") && e.contains("not a SafeTensors export"),
            "{e}"
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
