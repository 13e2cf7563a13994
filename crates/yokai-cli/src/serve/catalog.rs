//! What a client may ask for: the games and seats the operator allowed, by name.
//!
//! A page never names a file. Games are the paper's presets (parsed from their names, no
//! file read) and the configs the operator gave with `--config`; seats are `human`, the
//! built-in bots, and the policies the operator named with `--seats` or put under
//! `--policies DIR`. Every policy is loaded once, when the server starts, so that a broken
//! file stops the start (where the operator reads the error) instead of answering a
//! participant with its contents.

use super::error::{quoted, ApiError, ApiResult};
use crate::play::session::Player;
use anyhow::{bail, Context};
use std::collections::BTreeMap;
use std::path::Path;
use std::sync::Arc;
use yokai_engine::Config;
use yokai_train::artifact::names::is_run;
use yokai_train::PolicySource;

/// The seat of a person at the page.
pub const HUMAN: &str = "human";
/// The built-in bots a client may seat by name (without parameters: those are the
/// operator's to choose, with `--seats`).
pub const BOTS: [&str; 3] = ["random", "greedy", "belief"];

/// The games and seats on offer, by the names the page uses.
pub struct Catalog {
    /// Offered games in order, the default first.
    configs: Vec<(String, Config)>,
    /// Offered bots and policies by name (`human` is always offered and not stored).
    seats: BTreeMap<String, Arc<PolicySource>>,
}

impl Catalog {
    /// The presets plus `configs` (names or TOML files, the first the default), and the
    /// built-in bots plus `seats` and every policy under `policies`.
    pub fn new(
        configs: &[String],
        seats: &[String],
        policies: Option<&Path>,
    ) -> anyhow::Result<Catalog> {
        let given = configs
            .iter()
            .map(|c| Config::resolve(c).with_context(|| format!("--config {c}")))
            .collect::<anyhow::Result<Vec<Config>>>()?;
        let mut offered: Vec<(String, Config)> = Vec::new();
        for config in given.into_iter().chain(Config::presets()) {
            let name = config.to_string();
            if !offered.iter().any(|(n, _)| *n == name) {
                offered.push((name, config));
            }
        }
        let mut catalog = Catalog {
            configs: offered,
            seats: BTreeMap::new(),
        };
        for bot in BOTS {
            catalog.add(bot, PolicySource::parse(bot)?);
        }
        for seat in seats.iter().filter(|s| s.as_str() != HUMAN) {
            let entry = PolicySource::parse(seat).with_context(|| format!("--seats: {seat}"))?;
            catalog.add(seat, entry);
        }
        if let Some(dir) = policies {
            for (name, path) in policies_under(dir)? {
                let entry = PolicySource::parse(&path.display().to_string())
                    .with_context(|| format!("--policies: {}", path.display()))?;
                catalog.add(&name, entry);
            }
        }
        Ok(catalog)
    }

    fn add(&mut self, name: &str, entry: PolicySource) {
        self.seats.insert(name.to_string(), Arc::new(entry));
    }

    /// The default game.
    pub fn default_config(&self) -> Config {
        self.configs[0].1
    }

    /// Every offered game's name, the default first.
    pub fn config_names(&self) -> Vec<&str> {
        self.configs.iter().map(|(n, _)| n.as_str()).collect()
    }

    /// Every offered seat's name: `human`, then the bots and policies.
    pub fn seat_names(&self) -> Vec<&str> {
        std::iter::once(HUMAN)
            .chain(self.seats.keys().map(String::as_str))
            .collect()
    }

    /// The offered game called `name` (a preset's name may be shortened, as
    /// `9c-2p` for `9c-2p-perfect`); anything else is refused with the list.
    pub fn config(&self, name: &str) -> ApiResult<Config> {
        if let Some((_, c)) = self.configs.iter().find(|(n, _)| n == name) {
            return Ok(*c);
        }
        // A short name is parsed, never opened: `Config::from_name` reads no file.
        if let Ok(parsed) = Config::from_name(name) {
            if self.configs.iter().any(|(_, c)| *c == parsed) {
                return Ok(parsed);
            }
        }
        Err(ApiError::BadRequest(format!(
            "game {} is not offered by this server; it offers: {}",
            quoted(name),
            self.config_names().join(", ")
        )))
    }

    /// The seat called `name`: `None` for a person, else the bot or policy. A name not
    /// offered (a path among them) is refused with the list.
    pub fn seat(&self, name: &str) -> ApiResult<Option<Arc<PolicySource>>> {
        if name == HUMAN {
            return Ok(None);
        }
        self.seats.get(name).cloned().map(Some).ok_or_else(|| {
            ApiError::BadRequest(format!(
                "seat {} is not offered by this server; it offers: {}",
                quoted(name),
                self.seat_names().join(", ")
            ))
        })
    }

    /// The seats named `names` at a game of `config`, each a fresh player.
    pub fn players(
        &self,
        config: &Config,
        names: &[String],
        seed: u64,
    ) -> ApiResult<Vec<(String, Player)>> {
        if names.len() != config.players() {
            return Err(ApiError::BadRequest(format!(
                "{config} has {} seats, but {} were given",
                config.players(),
                names.len()
            )));
        }
        names
            .iter()
            .enumerate()
            .map(|(s, name)| {
                let player = match self.seat(name)? {
                    None => Player::Human,
                    Some(entry) => {
                        entry.check_game(config).map_err(|_| {
                            ApiError::BadRequest(format!(
                                "seat {} was trained on another game than {config}",
                                quoted(name)
                            ))
                        })?;
                        Player::Bot(entry.build(seed ^ s as u64))
                    }
                };
                Ok((name.clone(), player))
            })
            .collect()
    }
}

/// The policies under `dir`, named by their path relative to it: every run directory (one
/// holding a policy file or checkpoint) and every policy file outside one, three levels
/// deep at most, in name order.
fn policies_under(dir: &Path) -> anyhow::Result<Vec<(String, std::path::PathBuf)>> {
    if !dir.is_dir() {
        bail!("--policies {}: not a directory", dir.display());
    }
    let mut found = Vec::new();
    let mut stack = vec![(dir.to_path_buf(), 0)];
    while let Some((here, depth)) = stack.pop() {
        let entries =
            std::fs::read_dir(&here).with_context(|| format!("cannot list {}", here.display()))?;
        for entry in entries.flatten() {
            let path = entry.path();
            let name = || {
                path.strip_prefix(dir)
                    .expect("under dir")
                    .components()
                    .map(|c| c.as_os_str().to_string_lossy())
                    .collect::<Vec<_>>()
                    .join("/")
            };
            if path.is_dir() && is_run(&path) {
                found.push((name(), path.clone()));
            } else if path.is_dir() && depth < 2 {
                stack.push((path.clone(), depth + 1));
            } else if path.extension().is_some_and(|e| e == "ykp") {
                found.push((name(), path.clone()));
            }
        }
    }
    if found.is_empty() {
        bail!(
            "--policies {}: no run directory or policy file (.ykp) in it",
            dir.display()
        );
    }
    found.sort();
    Ok(found)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn catalog() -> Catalog {
        Catalog::new(
            &["9c-2p-imperfect".into()],
            &["human".into(), "belief".into()],
            None,
        )
        .unwrap()
    }

    #[test]
    fn the_default_game_comes_first_and_every_preset_is_offered_once() {
        let c = catalog();
        let names = c.config_names();
        assert_eq!(names[0], "9c-2p-imperfect");
        assert_eq!(names.len(), Config::presets().len());
        assert_eq!(c.config("9c-3p").unwrap().players(), 3);
    }

    #[test]
    fn a_path_or_an_unknown_name_is_refused_with_what_is_offered() {
        let c = catalog();
        for name in [
            "/etc/passwd",
            "../configs/quick.toml",
            "belief:samples=9",
            "runs/x",
        ] {
            let Err(ApiError::BadRequest(m)) = c.seat(name) else {
                panic!("{name}: not a bad request")
            };
            assert!(
                m.contains("not offered") && m.contains("human, belief, greedy, random"),
                "{m}"
            );
            assert!(c.config(name).is_err(), "{name}");
        }
        assert!(c.seat("human").unwrap().is_none());
        assert!(c.seat("greedy").unwrap().is_some());
    }

    #[test]
    fn a_policies_folder_with_nothing_in_it_is_refused_at_start() {
        let dir = tempfile::tempdir().unwrap();
        let e = Catalog::new(&["9c-2p".into()], &[], Some(dir.path()))
            .err()
            .unwrap();
        assert!(format!("{e:#}").contains("no run directory"), "{e:#}");
    }

    /// A PyTorch run (`python -m yokai.torch_train`) holds `policy.safetensors` alone: it
    /// is a run directory like a Rust one, offered under its name; stray files are not.
    #[test]
    fn a_pytorch_run_directory_is_offered_as_a_run() {
        let dir = tempfile::tempdir().unwrap();
        for (run, file) in [
            ("torch/seed-0", "policy.safetensors"),
            ("rust", "policy.ykp"),
        ] {
            std::fs::create_dir_all(dir.path().join(run)).unwrap();
            std::fs::write(dir.path().join(run).join(file), b"x").unwrap();
        }
        std::fs::write(dir.path().join("notes.safetensors"), b"x").unwrap();
        let names: Vec<String> = policies_under(dir.path())
            .unwrap()
            .into_iter()
            .map(|(name, _)| name)
            .collect();
        assert_eq!(names, ["rust", "torch/seed-0"]);
    }
}
