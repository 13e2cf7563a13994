//! Policies by name: `random`, `greedy`, `belief`, with parameters as
//! `belief:continue_win=0.9,end_margin=0.5` or `belief:grounded=true`.

use crate::{BeliefParams, BeliefPolicy, GreedyPolicy, Policy, RandomPolicy};
use std::fmt;
use std::str::FromStr;

/// A built-in policy and its parameters, parsed from a name.
#[derive(Clone, Debug, PartialEq)]
pub enum PolicySpec {
    Random,
    Greedy,
    Belief(BeliefParams),
}

#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum SpecError {
    #[error("unknown policy `{0}` (built-in: random, greedy, belief)")]
    Unknown(String),
    #[error("policy `{policy}` has no parameter `{param}` (it has: {known})")]
    UnknownParam {
        policy: String,
        param: String,
        known: &'static str,
    },
    #[error("parameter `{param}` of `{policy}`: `{value}` is not {expected}")]
    BadValue {
        policy: String,
        param: String,
        value: String,
        expected: &'static str,
    },
    #[error("`{0}` is not `name` or `name:key=value,...`")]
    Syntax(String),
}

impl PolicySpec {
    /// A fresh policy for one seat.
    pub fn build(&self, seed: u64) -> Box<dyn Policy> {
        match self {
            PolicySpec::Random => Box::new(RandomPolicy::new(seed)),
            PolicySpec::Greedy => Box::new(GreedyPolicy::new()),
            PolicySpec::Belief(params) => Box::new(BeliefPolicy::new(*params, seed)),
        }
    }

    /// Names of the built-in policies.
    pub fn builtin_names() -> &'static [&'static str] {
        &["random", "greedy", "belief"]
    }
}

impl FromStr for PolicySpec {
    type Err = SpecError;
    fn from_str(text: &str) -> Result<PolicySpec, SpecError> {
        let text = text.trim();
        let (name, params) = match text.split_once(':') {
            Some((n, p)) => (n, p),
            None => (text, ""),
        };
        let pairs: Vec<(&str, &str)> = params
            .split(',')
            .filter(|p| !p.trim().is_empty())
            .map(|p| p.split_once('=').map(|(k, v)| (k.trim(), v.trim())))
            .collect::<Option<_>>()
            .ok_or_else(|| SpecError::Syntax(text.to_string()))?;
        let no_params = |spec: PolicySpec, known: &'static str| match pairs.first() {
            Some((k, _)) => Err(SpecError::UnknownParam {
                policy: name.to_string(),
                param: k.to_string(),
                known,
            }),
            None => Ok(spec),
        };
        match name {
            "random" => no_params(PolicySpec::Random, "none"),
            "greedy" => no_params(PolicySpec::Greedy, "none"),
            "belief" => {
                let mut p = BeliefParams::default();
                for (k, v) in pairs {
                    let number = || {
                        v.parse::<f64>().map_err(|_| SpecError::BadValue {
                            policy: name.to_string(),
                            param: k.to_string(),
                            value: v.to_string(),
                            expected: "a number",
                        })
                    };
                    match k {
                        "continue_win" => {
                            p.continue_win = number()?;
                            if !(0.0..=1.0).contains(&p.continue_win) {
                                return Err(SpecError::BadValue {
                                    policy: name.to_string(),
                                    param: k.to_string(),
                                    value: v.to_string(),
                                    expected: "a probability in [0, 1]",
                                });
                            }
                        }
                        "end_margin" => p.end_margin = number()?,
                        "grounded" => {
                            p.grounded = v.parse::<bool>().map_err(|_| SpecError::BadValue {
                                policy: name.to_string(),
                                param: k.to_string(),
                                value: v.to_string(),
                                expected: "`true` or `false`",
                            })?
                        }
                        _ => {
                            return Err(SpecError::UnknownParam {
                                policy: name.to_string(),
                                param: k.to_string(),
                                known: "continue_win, end_margin, grounded",
                            })
                        }
                    }
                }
                Ok(PolicySpec::Belief(p))
            }
            _ => Err(SpecError::Unknown(name.to_string())),
        }
    }
}

impl fmt::Display for PolicySpec {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            PolicySpec::Random => write!(f, "random"),
            PolicySpec::Greedy => write!(f, "greedy"),
            PolicySpec::Belief(p) if *p == BeliefParams::default() => write!(f, "belief"),
            PolicySpec::Belief(p) => {
                write!(
                    f,
                    "belief:continue_win={},end_margin={}",
                    p.continue_win, p.end_margin
                )?;
                if p.grounded {
                    write!(f, ",grounded=true")?;
                }
                Ok(())
            }
        }
    }
}
