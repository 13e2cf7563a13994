//! A trained network's weights as a SafeTensors file, for people who want to look at them
//! or run them outside Rust (PyTorch, NumPy, JAX: `safetensors.numpy.load_file`).
//!
//! The project's own policy files (`container.rs`) stay the format `yokai` reads: they carry
//! the training state, check every byte and are written atomically. SafeTensors is the
//! interchange format the ML ecosystem already reads safely (no code execution on load),
//! so an export is burn's own `burn-store` writer, not a second hand-written container.
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
#[cfg(test)]
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
