//! The paper's table: per method (a group of seeds), SP and XP metrics as mean ± standard
//! error over seeds (SP: the diagonal; XP: every pair of different seeds).

use crate::paper::PaperTable;
use serde::{Deserialize, Serialize};
use yokai_engine::Metrics;

/// Mean and standard error of a set of per-seed values.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct MeanSe {
    pub mean: f64,
    /// 0 when there is a single value (then there is no spread to estimate).
    pub se: f64,
    /// How many values (seeds or pairs of seeds) the mean is over.
    pub n: usize,
}

impl MeanSe {
    pub fn of(xs: &[f64]) -> Option<MeanSe> {
        if xs.is_empty() {
            return None;
        }
        let n = xs.len() as f64;
        let mean = xs.iter().sum::<f64>() / n;
        let se = if xs.len() < 2 {
            0.0
        } else {
            (xs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0) / n).sqrt()
        };
        Some(MeanSe {
            mean,
            se,
            n: xs.len(),
        })
    }
}

/// R, SEE, EE, WEE, LEN of one side (SP or XP); shares in percent.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Side {
    pub entries: usize,
    pub reward: Option<MeanSe>,
    pub see: Option<MeanSe>,
    pub ee: Option<MeanSe>,
    pub wee: Option<MeanSe>,
    pub length: Option<MeanSe>,
}

impl Side {
    fn of(ms: &[&Metrics]) -> Side {
        let f = |g: &dyn Fn(&Metrics) -> Option<f64>| {
            MeanSe::of(&ms.iter().filter_map(|m| g(m)).collect::<Vec<_>>())
        };
        Side {
            entries: ms.len(),
            reward: f(&|m| Some(m.reward)),
            see: f(&|m| Some(100.0 * m.successful_early_end)),
            ee: f(&|m| Some(100.0 * m.early_end)),
            wee: f(&|m| m.win_given_early_end.map(|w| 100.0 * w)),
            length: f(&|m| Some(m.length)),
        }
    }
}

/// One method's row.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GroupSummary {
    pub name: String,
    pub seeds: Vec<String>,
    pub sp: Side,
    /// Cross-play of every pair of different seeds (filling a table of more than 2 seats
    /// with repeats).
    pub xp: Side,
    /// Games of more than 2 seats: cross-play of sets of n distinct seeds, each over every
    /// seating (the paper's J_XP), mean ± SE over the sets. The paper table shows it in
    /// place of the pairs' XP.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub xp_distinct: Option<Side>,
    /// The sets behind `xp_distinct`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub xp_sets: Vec<DistinctSet>,
    /// What the seeds trained with, where they all agree: the PPO entropy coefficient α
    /// (for HE's α selection, `yokai compare --select-entropy`) and the env steps trained.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub entropy_coef: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub env_steps: Option<u64>,
}

/// One set of n distinct seeds of a method in cross-play, and its games' metrics.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DistinctSet {
    pub seeds: Vec<String>,
    pub metrics: Metrics,
}

impl GroupSummary {
    /// The cross-play the paper's table shows: the sets of n distinct seeds where a game of
    /// more than 2 seats has them (the paper's J_XP), else the pairs.
    pub fn paper_xp(&self) -> &Side {
        self.xp_distinct.as_ref().unwrap_or(&self.xp)
    }

    /// Record the sets of n distinct seeds this method played (`xp_sets`, `xp_distinct`).
    pub fn set_distinct(&mut self, sets: Vec<DistinctSet>) {
        let metrics: Vec<&Metrics> = sets.iter().map(|s| &s.metrics).collect();
        self.xp_distinct = (!sets.is_empty()).then(|| Side::of(&metrics));
        self.xp_sets = sets;
    }
}

/// What `summary.json` of an evaluation holds, for `yokai compare`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct EvalSummary {
    /// The game's short name when it has one (e.g. `9c-2p-perfect`), else its description.
    pub game: String,
    pub games_per_pair: u64,
    pub groups: Vec<GroupSummary>,
}

/// Summarise the group of policies `members` (indices into the matrix) from the cells
/// `(row, col, metrics)` of the evaluation.
pub fn summarise(
    name: &str,
    names: &[String],
    cells: &[(usize, usize, Metrics)],
    members: &[usize],
) -> GroupSummary {
    let sp: Vec<&Metrics> = cells
        .iter()
        .filter(|(r, c, _)| r == c && members.contains(r))
        .map(|(_, _, m)| m)
        .collect();
    let xp: Vec<&Metrics> = cells
        .iter()
        .filter(|(r, c, _)| r != c && members.contains(r) && members.contains(c))
        .map(|(_, _, m)| m)
        .collect();
    GroupSummary {
        name: name.to_string(),
        seeds: members.iter().map(|&i| names[i].clone()).collect(),
        sp: Side::of(&sp),
        xp: Side::of(&xp),
        xp_distinct: None,
        xp_sets: Vec::new(),
        entropy_coef: None,
        env_steps: None,
    }
}

/// The value every seed has, or `None` where they differ (or there are none).
pub fn shared<T: PartialEq>(mut values: impl Iterator<Item = T>) -> Option<T> {
    let first = values.next()?;
    values.all(|v| v == first).then_some(first)
}

/// HE's rule for more than 2 players (the paper, §5.1): of the methods that differ in their
/// entropy coefficient α, the one with the lowest α whose SP and XP returns match (differ
/// by at most `tolerance`). XP is the paper's J_XP where the game has more than 2 seats.
pub fn select_entropy(groups: &[&GroupSummary], tolerance: f64) -> EntropySelection {
    let mut candidates: Vec<EntropyCandidate> = groups
        .iter()
        .filter_map(|g| {
            Some(EntropyCandidate {
                name: g.name.clone(),
                entropy_coef: g.entropy_coef?,
                sp: g.sp.reward?.mean,
                xp: g.paper_xp().reward?.mean,
            })
        })
        .collect();
    candidates.sort_by(|a, b| a.entropy_coef.total_cmp(&b.entropy_coef));
    let selected = candidates
        .iter()
        .position(|c| (c.sp - c.xp).abs() <= tolerance);
    EntropySelection {
        candidates,
        selected,
        tolerance,
    }
}

/// A method in HE's α selection.
#[derive(Clone, Debug, PartialEq)]
pub struct EntropyCandidate {
    pub name: String,
    pub entropy_coef: f64,
    pub sp: f64,
    pub xp: f64,
}

/// The candidates by ascending α and the one chosen, if any matched.
#[derive(Clone, Debug, PartialEq)]
pub struct EntropySelection {
    pub candidates: Vec<EntropyCandidate>,
    pub selected: Option<usize>,
    pub tolerance: f64,
}

impl EntropySelection {
    /// A Markdown table of the candidates, the chosen one marked, and a line saying which.
    pub fn report(&self) -> String {
        let mut out = format!(
            "The lowest entropy coefficient α whose SP and XP returns differ by at most {} \
             (the paper's rule for HE with more than 2 players).\n\n\
             | α | method | SP R | XP R | SP − XP |\n|---|---|---|---|---|\n",
            self.tolerance
        );
        for (i, c) in self.candidates.iter().enumerate() {
            let mark = if Some(i) == self.selected {
                " **selected**"
            } else {
                ""
            };
            out += &format!(
                "| {} | {}{mark} | {:.2} | {:.2} | {:+.2} |\n",
                c.entropy_coef,
                c.name,
                c.sp,
                c.xp,
                c.sp - c.xp
            );
        }
        out += &match self.selected {
            Some(i) => format!(
                "\nselected α {} ({})\n",
                self.candidates[i].entropy_coef, self.candidates[i].name
            ),
            None if self.candidates.is_empty() => {
                "\nno method with a known α and both SP and XP: nothing to select\n".to_string()
            }
            None => format!(
                "\nno α has SP and XP within {}: none selected (sweep higher α, or more seeds)\n",
                self.tolerance
            ),
        };
        out
    }
}

/// `mean ± SE`, or the mean alone when it rests on one value (an SE of 0 would mislead).
fn cell(v: Option<MeanSe>, digits: usize) -> String {
    v.map_or("–".into(), |v| {
        if v.n < 2 {
            format!("{:.d$}", v.mean, d = digits)
        } else {
            format!("{:.d$} ± {:.d$}", v.mean, v.se, d = digits)
        }
    })
}

pub const TABLE_HEAD: &str = "| method | seeds | SP R | SP SEE % | SP EE % | SP WEE % | SP LEN | XP R | XP SEE % | XP EE % | XP WEE % | XP LEN |\n\
                              |---|---|---|---|---|---|---|---|---|---|---|---|\n";

/// One Markdown row in the paper's layout, its XP [`GroupSummary::paper_xp`].
pub fn table_row(g: &GroupSummary) -> String {
    let xp = g.paper_xp();
    format!(
        "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |\n",
        g.name,
        g.seeds.len(),
        cell(g.sp.reward, 2),
        cell(g.sp.see, 1),
        cell(g.sp.ee, 1),
        cell(g.sp.wee, 1),
        cell(g.sp.length, 1),
        cell(xp.reward, 2),
        cell(xp.see, 1),
        cell(xp.ee, 1),
        cell(xp.wee, 1),
        cell(xp.length, 1),
    )
}

/// The published rows of the paper's table `table` for `game`, as Markdown rows of the same
/// table ("paper: METHOD"); the human baseline (imperfect memory) stands in every 9c-2p
/// table as the score to reach. Empty where the table has no row for the game.
pub fn paper_rows(table: &PaperTable, game: &str) -> String {
    table
        .rows
        .iter()
        .filter(|r| r.game == game || (r.method == "humans" && game.starts_with("9c-2p-")))
        .map(|r| {
            let method = if r.game == game {
                r.method.to_string()
            } else {
                format!("{} ({})", r.method, r.game)
            };
            format!(
                "| paper: {method} | {} | {} | {} |\n",
                r.seeds,
                r.sp.join(" | "),
                r.xp.join(" | ")
            )
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use yokai_engine::{MetricsAccumulator, Outcome};

    fn metrics(rewards: &[(i32, bool, bool)]) -> Metrics {
        let mut acc = MetricsAccumulator::default();
        for &(reward, won, early_end) in rewards {
            acc.add(&Outcome {
                reward,
                score: reward,
                won,
                early_end,
                length: 10,
                correct_hints: 0,
                wrong_hints: 0,
                clustered: 0,
                face_down: 0,
                revealed_unplaced: 0,
            });
        }
        acc.metrics().unwrap()
    }

    #[test]
    fn sp_is_the_diagonal_and_xp_the_pairs_of_different_seeds() {
        let names: Vec<String> = vec!["s0".into(), "s1".into(), "bot".into()];
        let cells = vec![
            (0, 0, metrics(&[(10, true, true), (-4, false, true)])), // SP 3, SEE 50, EE 100
            (1, 1, metrics(&[(5, true, false)])),                    // SP 5, SEE 0, EE 0
            (0, 1, metrics(&[(-2, false, false)])),                  // XP -2
            (0, 2, metrics(&[(100, true, true)])),                   // not in the group
            (2, 2, metrics(&[(100, true, true)])),
        ];
        let g = summarise("m", &names, &cells, &[0, 1]);
        let r = g.sp.reward.unwrap();
        assert_eq!(r.mean, 4.0);
        assert!((r.se - 1.0).abs() < 1e-12, "sd of (3, 5) is √2, se 1");
        assert_eq!(g.sp.see.unwrap().mean, 25.0);
        assert_eq!(g.sp.ee.unwrap().mean, 50.0);
        // WEE is undefined for seed 1 (no early end): averaged over seeds that have one.
        assert_eq!(g.sp.wee.unwrap().mean, 50.0);
        assert_eq!(g.xp.entries, 1);
        assert_eq!(g.xp.reward.unwrap().mean, -2.0);
        let row = table_row(&g);
        assert!(
            row.starts_with("| m | 2 | 4.00 ± 1.00 | 25.0 ± 25.0 |"),
            "{row}"
        );
        assert!(
            row.contains("| -2.00 |"),
            "one XP pair: the mean alone, {row}"
        );
        // One printed row per method of the paper's table, in the table's columns.
        let main = crate::paper::table(2).unwrap();
        let rows = paper_rows(main, "9c-2p-perfect");
        // IPPO, HE, OP, OBL levels 1–5 and the humans.
        assert_eq!(rows.lines().count(), 9, "{rows}");
        assert!(
            rows.contains("| paper: humans (9c-2p-imperfect) | – | – |"),
            "{rows}"
        );
        for line in rows.lines() {
            assert_eq!(
                line.matches('|').count(),
                TABLE_HEAD.lines().next().unwrap().matches('|').count(),
                "{line}"
            );
        }
        assert_eq!(paper_rows(main, "16c-2p-perfect").lines().count(), 1);
        assert!(paper_rows(main, "16c-3p-perfect").is_empty());
    }

    #[test]
    fn he_selects_the_lowest_entropy_whose_sp_and_xp_match() {
        let names: Vec<String> = vec!["s0".into(), "s1".into()];
        // A method of two seeds with SP returns `sp` each and XP `xp`, trained at α.
        let method = |name: &str, alpha: Option<f64>, sp: i32, xp: i32| {
            let cells = vec![
                (0, 0, metrics(&[(sp, false, false)])),
                (1, 1, metrics(&[(sp, false, false)])),
                (0, 1, metrics(&[(xp, false, false)])),
            ];
            let mut g = summarise(name, &names, &cells, &[0, 1]);
            g.entropy_coef = alpha;
            g
        };
        let groups = [
            method("a5", Some(0.05), 3, 3),
            method("a2", Some(0.02), 6, 1), // far apart: not chosen though lowest
            method("a4", Some(0.04), 2, 1),
            method("a7", Some(0.07), 1, 1),
            method("none", None, 0, 0), // α unknown: no candidate
        ];
        let refs: Vec<&GroupSummary> = groups.iter().collect();
        let s = select_entropy(&refs, 0.1);
        let alphas: Vec<f64> = s.candidates.iter().map(|c| c.entropy_coef).collect();
        assert_eq!(alphas, [0.02, 0.04, 0.05, 0.07]);
        assert_eq!(s.candidates[s.selected.unwrap()].name, "a5");
        assert!(
            s.report()
                .contains("| 0.05 | a5 **selected** | 3.00 | 3.00 | +0.00 |"),
            "{}",
            s.report()
        );
        // A wider tolerance takes the lower α whose gap it covers.
        let s = select_entropy(&refs, 1.0);
        assert_eq!(s.candidates[s.selected.unwrap()].name, "a4");
        // More than 2 seats: the n-distinct cross-play decides, not the pairs.
        let mut g = method("a3", Some(0.03), 2, 2);
        g.xp_distinct = Some(method("x", None, 0, 0).xp);
        let s = select_entropy(&[&g], 0.1);
        assert_eq!(s.selected, None);
        assert!(s.report().contains("none selected"), "{}", s.report());
        assert_eq!(shared([1, 1, 1].into_iter()), Some(1));
        assert_eq!(shared([1, 2].into_iter()), None);
    }
}
