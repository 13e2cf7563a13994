//! Game configurations (RULES §1): the presets `9c` and `16c`, custom sizes, validation, and
//! parsing from a short name (`9c-2p-perfect`) or a TOML file.
//!
//! A [`Config`] only exists validated: every constructor goes through [`ConfigSpec`] and
//! `Config::validate`, so code holding a `Config` never re-checks sizes. It is `Copy` and
//! small because every game and every batched environment carries one.

use crate::bitboard::{Geometry, MAX_GRID};
use crate::types::{MAX_CARDS, MAX_COLOURS, MAX_HINTS, MAX_PLAYERS};
use serde::{Deserialize, Serialize};
use std::fmt;
use std::path::Path;
use std::str::FromStr;

/// What a seat remembers of the colours it has observed (RULES §5).
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Memory {
    /// The paper's M=✓: a seat sees every colour it has observed in this episode.
    Perfect,
    /// The paper's M=✗: a seat sees only what it observed during its own current turn.
    Imperfect,
}

impl fmt::Display for Memory {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Memory::Perfect => "perfect",
            Memory::Imperfect => "imperfect",
        })
    }
}

/// Why a configuration was rejected. Messages are meant for the person who wrote it.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ConfigError {
    #[error("unknown config name `{name}`: {reason} (expected e.g. `9c-2p-perfect`, `16c-3p-imperfect`, `9c-4p`)")]
    Name { name: String, reason: String },
    #[error("config file {origin}: {message}")]
    Parse { origin: String, message: String },
    #[error("config field `{field}` is missing and no `preset` provides it")]
    Missing { field: &'static str },
    #[error("config field `{field}`: {message}")]
    Invalid {
        field: &'static str,
        message: String,
    },
    #[error("cannot read config file {path}: {message}")]
    Io { path: String, message: String },
}

/// A validated game configuration.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct Config {
    cards: u8,
    colours: u8,
    players: u8,
    memory: Memory,
    start_row: u8,
    start_col: u8,
    start_side: u8,
    /// `hint_counts[k-1]` = number of hints showing `k` colours.
    hint_counts: [u8; MAX_COLOURS],
    hints: u8,
    geometry: Geometry,
}

/// The two card sets of the paper.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Preset {
    /// 9 cards, 3 colours, 9×9 grid.
    NineCards,
    /// 16 cards, 4 colours, 10×10 grid: the original board game.
    SixteenCards,
}

impl Preset {
    fn parse(s: &str) -> Option<Preset> {
        match s {
            "9c" => Some(Preset::NineCards),
            "16c" => Some(Preset::SixteenCards),
            _ => None,
        }
    }

    fn name(self) -> &'static str {
        match self {
            Preset::NineCards => "9c",
            Preset::SixteenCards => "16c",
        }
    }

    /// RULES §1 hint table, for 2–4 players.
    fn hint_counts(self, players: u8) -> Option<Vec<u8>> {
        Some(match (self, players) {
            (Preset::NineCards, 2) => vec![1, 3],
            (Preset::NineCards, 3) => vec![2, 3],
            (Preset::NineCards, 4) => vec![3, 3],
            (Preset::SixteenCards, 2) => vec![2, 3, 2],
            (Preset::SixteenCards, 3) => vec![2, 4, 3],
            (Preset::SixteenCards, 4) => vec![3, 4, 3],
            _ => return None,
        })
    }

    fn spec(self, players: u8, memory: Memory) -> ConfigSpec {
        let (cards, colours, grid) = match self {
            Preset::NineCards => (9, 3, 9),
            Preset::SixteenCards => (16, 4, 10),
        };
        ConfigSpec {
            preset: None,
            cards: Some(cards),
            colours: Some(colours),
            grid: Some(grid),
            start: None,
            start_side: None,
            players: Some(players),
            memory: Some(memory),
            hints: self.hint_counts(players),
        }
    }
}

/// The written form of a configuration (TOML or JSON). Every field is optional so that a
/// file can name a `preset` and override only what differs; unknown keys are errors.
///
/// ```toml
/// preset = "9c-3p"        # a short name: 9c or 16c, optionally -Np and -perfect/-imperfect
/// memory = "imperfect"    # perfect | imperfect
/// # or a custom game:
/// cards = 12              # Y, a multiple of `colours`
/// colours = 3             # C, 2..=4
/// grid = 10               # g, the grid is g×g, g ≤ 11
/// start = [3, 3]          # top-left (row, col) of the start square; default: centred
/// start_side = 4          # side of the start square; default: ⌈√Y⌉
/// players = 2             # P, 2..=6
/// hints = [1, 3]          # number of hints showing 1, 2, … colours
/// ```
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ConfigSpec {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub preset: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cards: Option<u8>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub colours: Option<u8>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub grid: Option<u8>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub start: Option<[u8; 2]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub start_side: Option<u8>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub players: Option<u8>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub memory: Option<Memory>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub hints: Option<Vec<u8>>,
}

/// Binomial coefficient for the small numbers of colours.
fn choose(n: u32, k: u32) -> u32 {
    if k > n {
        return 0;
    }
    (0..k).fold(1, |acc, i| acc * (n - i) / (i + 1))
}

fn invalid(field: &'static str, message: impl Into<String>) -> ConfigError {
    ConfigError::Invalid {
        field,
        message: message.into(),
    }
}

impl ConfigSpec {
    /// Fill absent fields from the preset (if any), then validate.
    pub fn resolve(&self) -> Result<Config, ConfigError> {
        let base = match &self.preset {
            Some(name) => parse_name(name)?,
            None => ConfigSpec::default(),
        };
        let cards = self
            .cards
            .or(base.cards)
            .ok_or(ConfigError::Missing { field: "cards" })?;
        let colours = self
            .colours
            .or(base.colours)
            .ok_or(ConfigError::Missing { field: "colours" })?;
        let grid = self
            .grid
            .or(base.grid)
            .ok_or(ConfigError::Missing { field: "grid" })?;
        let players = self
            .players
            .or(base.players)
            .ok_or(ConfigError::Missing { field: "players" })?;
        let memory = self.memory.or(base.memory).unwrap_or(Memory::Perfect);
        // A preset's hint table depends on the player count, so overriding `players` on a
        // preset re-derives it (unless `hints` is given explicitly).
        let hints = match (&self.hints, &self.preset) {
            (Some(h), _) => h.clone(),
            (None, Some(name)) if self.players.is_some() => {
                let preset = Preset::parse(name.split('-').next().unwrap_or(""));
                preset
                    .and_then(|p| p.hint_counts(players))
                    .ok_or_else(|| {
                        invalid(
                            "hints",
                            format!("preset `{name}` has no hint table for {players} players; give `hints` explicitly"),
                        )
                    })?
            }
            (None, _) => base
                .hints
                .clone()
                .ok_or(ConfigError::Missing { field: "hints" })?,
        };
        Config::validate(
            cards,
            colours,
            grid,
            players,
            memory,
            self.start,
            self.start_side,
            &hints,
        )
    }
}

/// Parse a short name `9c`, `9c-2p`, `9c-2p-perfect`, `16c-3p-imperfect` into a full spec.
fn parse_name(name: &str) -> Result<ConfigSpec, ConfigError> {
    let err = |reason: &str| ConfigError::Name {
        name: name.to_string(),
        reason: reason.to_string(),
    };
    let mut parts = name.trim().split('-');
    let preset = parts
        .next()
        .and_then(Preset::parse)
        .ok_or_else(|| err("it must start with `9c` or `16c`"))?;
    let mut players = 2u8;
    let mut memory = Memory::Perfect;
    let mut seen_players = false;
    let mut seen_memory = false;
    for part in parts {
        if let Some(n) = part
            .strip_suffix('p')
            .filter(|_| !seen_players && !seen_memory)
        {
            players = n
                .parse::<u8>()
                .map_err(|_| err(&format!("`{part}` is not a player count like `2p`")))?;
            if preset.hint_counts(players).is_none() {
                return Err(err(&format!(
                    "the {} preset is defined for 2, 3 or 4 players, not {players}",
                    preset.name()
                )));
            }
            seen_players = true;
        } else if !seen_memory && (part == "perfect" || part == "imperfect") {
            memory = if part == "perfect" {
                Memory::Perfect
            } else {
                Memory::Imperfect
            };
            seen_memory = true;
        } else {
            return Err(err(&format!("unexpected part `{part}`")));
        }
    }
    Ok(preset.spec(players, memory))
}

impl Config {
    /// Every paper configuration in a fixed order: `9c` then `16c`, 2 to 4 players, perfect
    /// then imperfect memory (12 games). Tests, golden files, `yokai soak` and the Python
    /// package's `configs()` list them from here.
    pub fn presets() -> Vec<Config> {
        let mut out = Vec::new();
        for preset in [Preset::NineCards, Preset::SixteenCards] {
            for players in 2..=4 {
                for memory in [Memory::Perfect, Memory::Imperfect] {
                    out.push(
                        Config::preset(preset, players, memory)
                            .expect("every preset has a hint table for 2-4 players"),
                    );
                }
            }
        }
        out
    }

    /// A paper configuration: `9c`/`16c` with 2–4 players.
    pub fn preset(preset: Preset, players: u8, memory: Memory) -> Result<Config, ConfigError> {
        if preset.hint_counts(players).is_none() {
            return Err(invalid(
                "players",
                format!(
                    "the {} preset is defined for 2, 3 or 4 players, not {players}",
                    preset.name()
                ),
            ));
        }
        preset.spec(players, memory).resolve()
    }

    /// Parse a short name such as `9c-2p-perfect` (player count and memory are optional and
    /// default to 2 players, perfect memory).
    pub fn from_name(name: &str) -> Result<Config, ConfigError> {
        parse_name(name)?.resolve()
    }

    /// Parse TOML text; `origin` names the source in error messages.
    pub fn from_toml_str(text: &str, origin: &str) -> Result<Config, ConfigError> {
        let spec: ConfigSpec = toml::from_str(text).map_err(|e| ConfigError::Parse {
            origin: origin.to_string(),
            message: e.to_string().trim_end().to_string(),
        })?;
        spec.resolve()
    }

    pub fn from_toml_file(path: &Path) -> Result<Config, ConfigError> {
        let text = std::fs::read_to_string(path).map_err(|e| ConfigError::Io {
            path: path.display().to_string(),
            message: e.to_string(),
        })?;
        Config::from_toml_str(&text, &path.display().to_string())
    }

    /// A short name, or a path to a `.toml` file: what a command-line `--config` accepts.
    pub fn resolve(name_or_path: &str) -> Result<Config, ConfigError> {
        if name_or_path.ends_with(".toml") || Path::new(name_or_path).is_file() {
            Config::from_toml_file(Path::new(name_or_path))
        } else {
            Config::from_name(name_or_path)
        }
    }

    #[allow(clippy::too_many_arguments)]
    fn validate(
        cards: u8,
        colours: u8,
        grid: u8,
        players: u8,
        memory: Memory,
        start: Option<[u8; 2]>,
        start_side: Option<u8>,
        hints: &[u8],
    ) -> Result<Config, ConfigError> {
        if !(2..=MAX_COLOURS as u8).contains(&colours) {
            return Err(invalid(
                "colours",
                format!("{colours} colours; must be 2 to {MAX_COLOURS}"),
            ));
        }
        if !(2..=MAX_CARDS as u8).contains(&cards) {
            return Err(invalid(
                "cards",
                format!("{cards} cards; must be 2 to {MAX_CARDS}"),
            ));
        }
        if cards % colours != 0 {
            return Err(invalid(
                "cards",
                format!("{cards} cards cannot be split evenly into {colours} colours"),
            ));
        }
        if !(2..=MAX_PLAYERS as u8).contains(&players) {
            return Err(invalid(
                "players",
                format!("{players} players; must be 2 to {MAX_PLAYERS}"),
            ));
        }
        if !(2..=MAX_GRID as u8).contains(&grid) {
            return Err(invalid(
                "grid",
                format!("grid side {grid}; must be 2 to {MAX_GRID} (the board is one 128-bit set)"),
            ));
        }
        let side = match start_side {
            Some(s) => s,
            None => (1..=cards)
                .find(|s| (*s as u32) * (*s as u32) >= cards as u32)
                .unwrap_or(cards),
        };
        if side == 0 || (side as u32) * (side as u32) < cards as u32 {
            return Err(invalid(
                "start_side",
                format!("a {side}×{side} start square cannot hold {cards} cards"),
            ));
        }
        if side > grid {
            return Err(invalid(
                "start_side",
                format!("a {side}×{side} start square does not fit a {grid}×{grid} grid"),
            ));
        }
        let [start_row, start_col] = start.unwrap_or([(grid - side) / 2, (grid - side) / 2]);
        if start_row as u32 + side as u32 > grid as u32
            || start_col as u32 + side as u32 > grid as u32
        {
            return Err(invalid(
                "start",
                format!(
                    "a {side}×{side} start square at row {start_row}, column {start_col} does not fit a {grid}×{grid} grid"
                ),
            ));
        }
        if hints.len() > colours as usize {
            return Err(invalid(
                "hints",
                format!(
                    "{} hint sizes given but a hint can show at most {colours} colours",
                    hints.len()
                ),
            ));
        }
        let mut hint_counts = [0u8; MAX_COLOURS];
        for (i, &n) in hints.iter().enumerate() {
            let size = i as u32 + 1;
            let distinct = choose(colours as u32, size);
            if n as u32 > distinct {
                return Err(invalid(
                    "hints",
                    format!(
                        "{n} hints showing {size} colour(s), but only {distinct} distinct sets of {size} out of {colours} colours exist"
                    ),
                ));
            }
            hint_counts[i] = n;
        }
        let total: u32 = hints.iter().map(|&n| n as u32).sum();
        if total == 0 {
            return Err(invalid(
                "hints",
                "no hint cards: the game could never end by placing hints",
            ));
        }
        if total > grid as u32 || total > MAX_HINTS as u32 {
            return Err(invalid(
                "hints",
                format!("{total} hints, but the image encoding's hint column has only {grid} rows"),
            ));
        }
        if (cards as u32) < total + 2 {
            return Err(invalid(
                "hints",
                format!(
                    "{total} hints for {cards} cards leaves fewer than 2 unhinted cards to observe (need Y − H ≥ 2)"
                ),
            ));
        }
        Ok(Config {
            cards,
            colours,
            players,
            memory,
            start_row,
            start_col,
            start_side: side,
            hint_counts,
            hints: total as u8,
            geometry: Geometry::new(grid as usize),
        })
    }

    /// The explicit written form (every field present).
    pub fn spec(&self) -> ConfigSpec {
        let sizes = self
            .hint_counts
            .iter()
            .rposition(|&n| n > 0)
            .map_or(0, |i| i + 1);
        ConfigSpec {
            preset: None,
            cards: Some(self.cards),
            colours: Some(self.colours),
            grid: Some(self.geometry.side() as u8),
            start: Some([self.start_row, self.start_col]),
            start_side: Some(self.start_side),
            players: Some(self.players),
            memory: Some(self.memory),
            hints: Some(self.hint_counts[..sizes].to_vec()),
        }
    }

    pub fn to_toml(&self) -> String {
        toml::to_string(&self.spec()).expect("a config spec always serializes")
    }

    /// The short name if this is a paper preset, e.g. `9c-2p-perfect`.
    pub fn short_name(&self) -> Option<String> {
        for preset in [Preset::NineCards, Preset::SixteenCards] {
            if let Ok(c) = Config::preset(preset, self.players, self.memory) {
                if c == *self {
                    return Some(format!(
                        "{}-{}p-{}",
                        preset.name(),
                        self.players,
                        self.memory
                    ));
                }
            }
        }
        None
    }

    /// The same game with another memory mode.
    pub fn with_memory(mut self, memory: Memory) -> Config {
        self.memory = memory;
        self
    }

    // --- sizes -------------------------------------------------------------------------

    /// Y, the number of cards.
    #[inline(always)]
    pub fn cards(&self) -> usize {
        self.cards as usize
    }
    /// C, the number of colours.
    #[inline(always)]
    pub fn colours(&self) -> usize {
        self.colours as usize
    }
    /// Y / C.
    #[inline(always)]
    pub fn cards_per_colour(&self) -> usize {
        (self.cards / self.colours) as usize
    }
    /// P, the number of players.
    #[inline(always)]
    pub fn players(&self) -> usize {
        self.players as usize
    }
    /// H, the number of hint cards in a game.
    #[inline(always)]
    pub fn hints(&self) -> usize {
        self.hints as usize
    }
    /// Number of hints showing `size` colours.
    pub fn hints_of_size(&self, size: usize) -> usize {
        if (1..=MAX_COLOURS).contains(&size) {
            self.hint_counts[size - 1] as usize
        } else {
            0
        }
    }
    /// g, the side of the grid.
    #[inline(always)]
    pub fn grid(&self) -> usize {
        self.geometry.side()
    }
    #[inline(always)]
    pub fn memory(&self) -> Memory {
        self.memory
    }
    #[inline(always)]
    pub fn geometry(&self) -> &Geometry {
        &self.geometry
    }
    /// Top-left cell (row, col) and side of the start square.
    pub fn start_square(&self) -> (usize, usize, usize) {
        (
            self.start_row as usize,
            self.start_col as usize,
            self.start_side as usize,
        )
    }
    /// The longest possible game: 8 substeps for each hint (RULES §2).
    pub fn max_episode_len(&self) -> usize {
        8 * self.hints()
    }
    /// Largest terminal reward: END on the first step of a clustered deal (RULES §4).
    pub fn max_reward(&self) -> i32 {
        5 * self.hints() as i32
    }
    /// Smallest terminal reward: lost after an early end, nothing clustered, every hint wrong.
    pub fn min_reward(&self) -> i32 {
        -1 - self.colours() as i32 - self.hints() as i32
    }
}

impl fmt::Display for Config {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.short_name() {
            Some(name) => f.write_str(&name),
            None => {
                let hints: Vec<String> = self
                    .spec()
                    .hints
                    .unwrap_or_default()
                    .iter()
                    .map(|h| h.to_string())
                    .collect();
                write!(
                    f,
                    "custom-{}y{}c-g{}-{}p-h{}-{}",
                    self.cards,
                    self.colours,
                    self.grid(),
                    self.players,
                    hints.join("."),
                    self.memory
                )
            }
        }
    }
}

impl FromStr for Config {
    type Err = ConfigError;
    fn from_str(s: &str) -> Result<Config, ConfigError> {
        Config::from_name(s)
    }
}

impl Serialize for Config {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        self.spec().serialize(serializer)
    }
}

impl<'de> Deserialize<'de> for Config {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Config, D::Error> {
        let spec = ConfigSpec::deserialize(deserializer)?;
        spec.resolve().map_err(serde::de::Error::custom)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn presets_have_the_rules_hint_tables() {
        let expect = [
            ("9c-2p", 4, [1, 3, 0]),
            ("9c-3p", 5, [2, 3, 0]),
            ("9c-4p", 6, [3, 3, 0]),
            ("16c-2p", 7, [2, 3, 2]),
            ("16c-3p", 9, [2, 4, 3]),
            ("16c-4p", 10, [3, 4, 3]),
        ];
        for (name, h, sizes) in expect {
            let c = Config::from_name(name).unwrap();
            assert_eq!(c.hints(), h, "{name}");
            for (i, n) in sizes.iter().enumerate() {
                assert_eq!(c.hints_of_size(i + 1), *n, "{name} size {}", i + 1);
            }
        }
        let c9 = Config::from_name("9c-2p-perfect").unwrap();
        assert_eq!(
            (c9.cards(), c9.colours(), c9.grid(), c9.start_square()),
            (9, 3, 9, (3, 3, 3))
        );
        let c16 = Config::from_name("16c-2p-imperfect").unwrap();
        assert_eq!(
            (c16.cards(), c16.colours(), c16.grid(), c16.start_square()),
            (16, 4, 10, (3, 3, 4))
        );
        assert_eq!(c16.memory(), Memory::Imperfect);
    }

    #[test]
    fn the_presets_are_the_twelve_named_games() {
        let names: Vec<String> = Config::presets().iter().map(|c| c.to_string()).collect();
        let mut want = Vec::new();
        for cards in ["9c", "16c"] {
            for players in 2..=4 {
                for memory in ["perfect", "imperfect"] {
                    want.push(format!("{cards}-{players}p-{memory}"));
                }
            }
        }
        assert_eq!(names, want);
    }

    #[test]
    fn short_names_round_trip() {
        for name in ["9c-2p-perfect", "9c-4p-imperfect", "16c-3p-perfect"] {
            let c = Config::from_name(name).unwrap();
            assert_eq!(c.short_name().as_deref(), Some(name));
            assert_eq!(c.to_string(), name);
        }
        assert_eq!(
            Config::from_name("9c").unwrap().to_string(),
            "9c-2p-perfect"
        );
    }

    #[test]
    fn bad_names_are_errors() {
        for bad in [
            "",
            "8c-2p",
            "9c-5p",
            "9c-xp",
            "9c-2p-perfect-extra",
            "9c-perfect-2p",
            "9c-2p-good",
        ] {
            let err = Config::from_name(bad).unwrap_err();
            assert!(matches!(err, ConfigError::Name { .. }), "{bad}: {err}");
        }
    }

    #[test]
    fn toml_with_preset_and_override() {
        let c = Config::from_toml_str(
            "preset = \"9c\"\nplayers = 3\nmemory = \"imperfect\"\n",
            "t",
        )
        .unwrap();
        assert_eq!(c, Config::from_name("9c-3p-imperfect").unwrap());
    }

    #[test]
    fn toml_custom_round_trip() {
        let text = "cards = 12\ncolours = 3\ngrid = 10\nplayers = 5\nhints = [2, 3]\n";
        let c = Config::from_toml_str(text, "t").unwrap();
        assert_eq!((c.cards(), c.hints(), c.start_square()), (12, 5, (3, 3, 4)));
        let again = Config::from_toml_str(&c.to_toml(), "again").unwrap();
        assert_eq!(c, again);
        let json = serde_json::to_string(&c).unwrap();
        assert_eq!(serde_json::from_str::<Config>(&json).unwrap(), c);
    }

    #[test]
    fn toml_errors_name_the_problem() {
        let unknown =
            Config::from_toml_str("preset = \"9c\"\nplayrs = 3\n", "my.toml").unwrap_err();
        assert!(unknown.to_string().contains("playrs"), "{unknown}");
        assert!(unknown.to_string().contains("my.toml"), "{unknown}");
        let syntax = Config::from_toml_str("cards = = 3", "x.toml").unwrap_err();
        assert!(matches!(syntax, ConfigError::Parse { .. }));
        let missing = Config::from_toml_str("cards = 9\ncolours = 3\n", "x").unwrap_err();
        assert_eq!(missing, ConfigError::Missing { field: "grid" });
    }

    fn custom(text: &str) -> ConfigError {
        Config::from_toml_str(text, "t").unwrap_err()
    }

    #[test]
    fn unplayable_configs_are_rejected() {
        // Y − H < 2
        let e = custom("cards = 6\ncolours = 3\ngrid = 9\nplayers = 2\nhints = [3, 2]\n");
        assert!(e.to_string().contains("Y − H ≥ 2"), "{e}");
        // start square does not fit
        let e = custom(
            "cards = 9\ncolours = 3\ngrid = 9\nstart = [7, 3]\nplayers = 2\nhints = [1, 3]\n",
        );
        assert!(
            matches!(e, ConfigError::Invalid { field: "start", .. }),
            "{e}"
        );
        // more hints of a size than distinct colour sets
        let e = custom("cards = 9\ncolours = 3\ngrid = 9\nplayers = 2\nhints = [4]\n");
        assert!(e.to_string().contains("only 3 distinct"), "{e}");
        // more hints than grid rows
        let e = custom("cards = 16\ncolours = 4\ngrid = 5\nplayers = 2\nhints = [4, 6]\n");
        assert!(e.to_string().contains("hint column"), "{e}");
        // grid too large for the bitboard
        let e = custom("cards = 9\ncolours = 3\ngrid = 12\nplayers = 2\nhints = [1, 3]\n");
        assert!(
            matches!(e, ConfigError::Invalid { field: "grid", .. }),
            "{e}"
        );
        // cards not divisible by colours
        let e = custom("cards = 10\ncolours = 3\ngrid = 9\nplayers = 2\nhints = [1, 3]\n");
        assert!(
            matches!(e, ConfigError::Invalid { field: "cards", .. }),
            "{e}"
        );
        // too many players / colours
        let e = custom("cards = 9\ncolours = 3\ngrid = 9\nplayers = 7\nhints = [1, 3]\n");
        assert!(
            matches!(
                e,
                ConfigError::Invalid {
                    field: "players",
                    ..
                }
            ),
            "{e}"
        );
        let e = custom("cards = 10\ncolours = 5\ngrid = 9\nplayers = 2\nhints = [1, 3]\n");
        assert!(
            matches!(
                e,
                ConfigError::Invalid {
                    field: "colours",
                    ..
                }
            ),
            "{e}"
        );
        // no hints at all
        let e = custom("cards = 9\ncolours = 3\ngrid = 9\nplayers = 2\nhints = []\n");
        assert!(
            matches!(e, ConfigError::Invalid { field: "hints", .. }),
            "{e}"
        );
        // preset without a hint table for 5 players
        let e = custom("preset = \"9c\"\nplayers = 5\n");
        assert!(
            matches!(e, ConfigError::Invalid { field: "hints", .. }),
            "{e}"
        );
    }

    #[test]
    fn action_space_sizes_match_rules() {
        assert_eq!(Config::from_name("9c-2p").unwrap().num_actions(), 777);
        assert_eq!(Config::from_name("16c-2p").unwrap().num_actions(), 1731);
    }
}
