//! Where a seated policy comes from, as every front end names it: a built-in bot
//! (`random`, `greedy`, `belief:continue_win=0.9`), a pretrained agent built into the
//! library (`pretrained:quick/0`), or the path of a trained policy file, checkpoint or run
//! directory; and how a trained policy plays END. `yokai eval`, `play`,
//! `serve`, `train`'s evaluation and Python's `yokai.Agent` all read policies through this
//! one definition.

use crate::artifact::names::{CHECKPOINT, POLICY, SAFETENSORS_POLICY};
use crate::config::ActConfig;
use crate::error::TrainError;
use crate::policy::TrainedPolicy;
use std::path::{Path, PathBuf};
use yokai_agents::{Policy, PolicySpec};
use yokai_engine::Config;

/// How a trained policy chooses END when it plays.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum EndRule {
    /// As its training config says (`act.end_threshold`).
    #[default]
    File,
    /// Drawn like any other action.
    Draw,
    /// END where P(END) exceeds the threshold, a probability in (0, 1).
    Threshold(f64),
}

impl std::str::FromStr for EndRule {
    type Err = String;
    /// `file`, `draw`, or a probability in (0, 1).
    fn from_str(s: &str) -> Result<EndRule, String> {
        match s {
            "file" => Ok(EndRule::File),
            "draw" => Ok(EndRule::Draw),
            _ => s
                .parse::<f64>()
                .ok()
                .filter(|&t| ActConfig::end_threshold_from(t).is_ok())
                .map(EndRule::Threshold)
                .ok_or_else(|| {
                    format!("`{s}` is not an END rule: `file`, `draw` or a probability in (0, 1)")
                }),
        }
    }
}

/// How a trained policy plays where a front end overrides its file's `[act]`: the END rule
/// and the temperature of its other moves (`yokai eval --end --temperature`, Python's
/// `end=`, `temperature=`). The default keeps the file's rule in both.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PlayRule {
    pub end: EndRule,
    /// Draw the moves at this temperature (`act.temperature`); `None`: the file's.
    pub temperature: Option<f64>,
}

impl PlayRule {
    /// Make `policy` play by this rule; a threshold outside (0, 1) or a temperature outside
    /// [0, 100] is refused, naming the policy's file.
    pub fn apply(self, policy: &mut TrainedPolicy) -> Result<(), TrainError> {
        match self.end {
            EndRule::File => {}
            EndRule::Draw => policy.set_end_threshold(None)?,
            EndRule::Threshold(t) => policy.set_end_threshold(Some(t))?,
        }
        if let Some(t) = self.temperature {
            policy.set_temperature(t)?;
        }
        Ok(())
    }

    /// What of a trained policy's play this rule changes, as an error names it for a bot
    /// (`None` where it changes nothing).
    fn overrides(&self) -> Option<&'static str> {
        match (self.end, self.temperature) {
            (EndRule::File, None) => None,
            (EndRule::File, Some(_)) => {
                Some("a temperature sets how a trained policy draws its moves")
            }
            (_, None) => Some("an END rule sets how a trained policy plays END"),
            (_, Some(_)) => Some("an END rule and a temperature set how a trained policy plays"),
        }
    }
}

/// Why a policy name was refused.
#[derive(Debug, thiserror::Error)]
pub enum SourceError {
    /// A path that exists but does not hold a trained policy.
    #[error(transparent)]
    Trained(#[from] TrainError),
    /// Neither an existing path nor a built-in name.
    #[error(
        "{0}; a trained policy is given as the path of a policy file, checkpoint or run directory, or as pretrained:PRESET/SEED"
    )]
    Unknown(#[source] yokai_agents::SpecError),
    /// `pretrained:…` naming no agent built in, or a damaged one.
    #[error(transparent)]
    Pretrained(#[from] crate::pretrained::PretrainedError),
    /// A play rule (END rule, temperature) given to a bot, which keeps its own.
    #[error("{what}; `{bot}` is not a trained policy but a built-in bot")]
    PlayRuleForBot { bot: String, what: &'static str },
}

/// A policy that can be seated: a built-in bot or a trained network.
#[derive(Clone, Debug)]
pub enum PolicySource {
    Builtin(PolicySpec),
    Trained(Box<TrainedPolicy>),
}

impl PolicySource {
    /// `pretrained:PRESET/SEED` is an agent built into the library; an existing path is a
    /// trained policy (policy file, checkpoint or run directory); anything else must be a
    /// built-in name.
    pub fn parse(text: &str) -> Result<PolicySource, SourceError> {
        if text.starts_with(crate::pretrained::PREFIX) {
            let policy = crate::pretrained::load(text)?;
            return Ok(PolicySource::Trained(Box::new(policy)));
        }
        let path = Path::new(text);
        if path.exists() {
            return Ok(PolicySource::Trained(Box::new(TrainedPolicy::load(path)?)));
        }
        text.parse::<PolicySpec>()
            .map(PolicySource::Builtin)
            .map_err(SourceError::Unknown)
    }

    /// The name tables show: a bot's spec, or a trained policy's run directory with its
    /// play rule where it is not the trained distribution (` (END > t, T = 0)`).
    pub fn name(&self) -> String {
        match self {
            PolicySource::Builtin(spec) => spec.to_string(),
            PolicySource::Trained(p) => {
                format!("{}{}", run_dir_of(p.path()).display(), play_rule_label(p))
            }
        }
    }

    /// Make a trained policy play by `rule`; bots keep their own END rules and draws, so a
    /// rule that changes anything is refused for one when `strict` (Python's `end=` or
    /// `temperature=` for a bot is a mistake) and left alone otherwise (`yokai eval --end`
    /// over a mixed list).
    pub fn set_play_rule(&mut self, rule: PlayRule, strict: bool) -> Result<(), SourceError> {
        match (self, rule.overrides()) {
            (PolicySource::Trained(p), _) => Ok(rule.apply(p)?),
            (PolicySource::Builtin(spec), Some(what)) if strict => {
                Err(SourceError::PlayRuleForBot {
                    bot: spec.to_string(),
                    what,
                })
            }
            (PolicySource::Builtin(_), _) => Ok(()),
        }
    }

    /// A fresh seat-holder; `seed` drives its randomness.
    pub fn build(&self, seed: u64) -> Box<dyn Policy> {
        match self {
            PolicySource::Builtin(spec) => spec.build(seed),
            PolicySource::Trained(p) => p.build(seed),
        }
    }

    /// The trained network, if this is one.
    pub fn trained(&self) -> Option<&TrainedPolicy> {
        match self {
            PolicySource::Trained(p) => Some(p),
            PolicySource::Builtin(_) => None,
        }
    }

    /// The game a trained policy was trained on (a bot plays any).
    pub fn game(&self) -> Option<Config> {
        self.trained().map(|p| *p.game())
    }

    /// A trained network fits only the game it was trained on.
    pub fn check_game(&self, config: &Config) -> Result<(), TrainError> {
        match self {
            PolicySource::Trained(p) => p.check_game(config),
            PolicySource::Builtin(_) => Ok(()),
        }
    }
}

/// How a trained policy's name shows how it plays in tables: ` (END > t)` where it decides
/// END, `T = x` where it draws its moves at a temperature other than 1, nothing where it
/// plays the trained distribution as it is.
pub fn play_rule_label(p: &TrainedPolicy) -> String {
    let mut parts = Vec::new();
    if let Some(t) = p.end_threshold() {
        parts.push(format!("END > {t}"));
    }
    if p.temperature() != 1.0 {
        parts.push(format!("T = {}", p.temperature()));
    }
    if parts.is_empty() {
        String::new()
    } else {
        format!(" ({})", parts.join(", "))
    }
}

/// The run directory of a policy file or checkpoint inside one (else the path itself).
pub fn run_dir_of(path: &Path) -> PathBuf {
    match path.file_name().and_then(|f| f.to_str()) {
        Some(POLICY) | Some(CHECKPOINT) | Some(SAFETENSORS_POLICY) => {
            path.parent().map_or(path.to_path_buf(), Path::to_path_buf)
        }
        _ => path.to_path_buf(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn end_rules_parse_and_refuse_what_is_not_a_probability() {
        assert_eq!("file".parse(), Ok(EndRule::File));
        assert_eq!("draw".parse(), Ok(EndRule::Draw));
        assert_eq!("0.3".parse(), Ok(EndRule::Threshold(0.3)));
        for bad in ["0", "1", "1.5", "-0.2", "NaN", "sometimes", ""] {
            let err = bad.parse::<EndRule>().unwrap_err();
            assert!(err.contains("not an END rule"), "{bad}: {err}");
        }
    }

    #[test]
    fn names_that_are_not_paths_are_bots_or_refused() {
        let belief = PolicySource::parse("belief:continue_win=0.9").unwrap();
        assert!(belief.trained().is_none() && belief.game().is_none());
        assert!(belief.name().starts_with("belief:continue_win=0.9"));
        let err = PolicySource::parse("runs/nowhere/seed-0").unwrap_err();
        assert!(matches!(err, SourceError::Unknown(_)), "{err}");
        assert!(err.to_string().contains("path of a policy file"), "{err}");
        // A bot keeps its END rule and draws: a rule that changes either is refused when
        // strict, naming what it changes, and left alone otherwise.
        let mut greedy = PolicySource::parse("greedy").unwrap();
        let draw = PlayRule {
            end: EndRule::Draw,
            temperature: None,
        };
        let sharp = PlayRule {
            end: EndRule::File,
            temperature: Some(0.25),
        };
        assert!(greedy.set_play_rule(draw, false).is_ok());
        assert!(greedy.set_play_rule(sharp, false).is_ok());
        let both = PlayRule {
            end: EndRule::Threshold(0.6),
            temperature: Some(0.25),
        };
        assert!(greedy.set_play_rule(both, false).is_ok());
        assert!(greedy.set_play_rule(PlayRule::default(), true).is_ok());
        let cases = [
            (draw, "plays END"),
            (sharp, "draws its moves"),
            (both, "an END rule and a temperature"),
        ];
        for (rule, what) in cases {
            let err = greedy.set_play_rule(rule, true).unwrap_err().to_string();
            assert!(
                err.contains("`greedy` is not a trained policy") && err.contains(what),
                "{err}"
            );
        }
    }

    #[test]
    fn a_run_directory_names_its_policy_files() {
        let run = Path::new("runs/cpu/seed-1");
        assert_eq!(run_dir_of(&run.join(POLICY)), run);
        assert_eq!(run_dir_of(&run.join(CHECKPOINT)), run);
        assert_eq!(run_dir_of(run), run);
        assert_eq!(run_dir_of(Path::new("a.ykp")), Path::new("a.ykp"));
    }
}
