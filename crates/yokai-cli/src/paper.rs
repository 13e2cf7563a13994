//! The YLE paper's published figures that reports print beside ours: its table for 9c-2p
//! (self-play and cross-play of each method) and its environment's speed on an H100. One
//! place for both, checked by a test against docs/spec/training.md, where they are stated.

/// One method's row of the paper's table (9c, 2 players, perfect memory), as printed.
pub struct PaperRow {
    pub method: &'static str,
    pub seeds: &'static str,
    pub sp_r: &'static str,
    pub sp_see: &'static str,
    pub xp_r: &'static str,
    pub xp_see: &'static str,
    pub xp_len: &'static str,
}

const fn row(
    method: &'static str,
    seeds: &'static str,
    [sp_r, sp_see, xp_r, xp_see, xp_len]: [&'static str; 5],
) -> PaperRow {
    PaperRow {
        method,
        seeds,
        sp_r,
        sp_see,
        xp_r,
        xp_see,
        xp_len,
    }
}

/// The paper's table for 9c-2p-perfect (12 seeds per method).
pub const TABLE_9C_2P: [PaperRow; 5] = [
    row("IPPO", "12", ["7.5", "89", "1.6", "18", "29.7"]),
    row("HE", "12", ["7.5", "95", "4.1", "50", "27.2"]),
    row("OP", "12", ["6.6", "84", "4.8", "63", "26.7"]),
    row(
        "OBL levels 1..5",
        "12",
        ["4.0–4.8", "68–80", "2.1–2.8", "38–53", "28.5–29.5"],
    ),
    row(
        "uniformly random legal play",
        "–",
        ["−4.0", "0.6", "−4.0", "0.6", "20.2"],
    ),
];

/// Env steps/s of the paper's JAX environment on an NVIDIA H100 with random legal actions,
/// for `base` (`9c-2p` or `16c-2p`, either memory mode) and a number of games; `None` where
/// the paper did not measure.
pub fn h100_steps_per_second(base: &str, envs: usize) -> Option<f64> {
    H100_SPEED
        .iter()
        .find(|(b, e, _)| *b == base && *e == envs)
        .map(|&(_, _, sps)| sps)
}

const H100_SPEED: [(&str, usize, f64); 6] = [
    ("9c-2p", 512, 139_107.0),
    ("9c-2p", 1024, 274_669.0),
    ("9c-2p", 2048, 559_251.0),
    ("16c-2p", 512, 135_662.0),
    ("16c-2p", 1024, 144_636.0),
    ("16c-2p", 2048, 148_269.0),
];

#[cfg(test)]
mod tests {
    use super::*;

    const SPEC: &str = include_str!("../../../docs/spec/training.md");

    /// The cells of the Markdown table row that starts with `| first |` in the spec's
    /// section "The paper's figures".
    fn spec_row(first: &str) -> Vec<String> {
        let section = &SPEC[SPEC.find("## The paper's figures").expect("the section")..];
        let line = section
            .lines()
            .find(|l| l.starts_with(&format!("| {first} |")))
            .unwrap_or_else(|| panic!("no row `{first}` in docs/spec/training.md"));
        line.trim_matches('|')
            .split('|')
            .map(|c| c.trim().to_string())
            .collect()
    }

    #[test]
    fn the_paper_table_is_the_one_the_spec_states() {
        for r in &TABLE_9C_2P {
            let cells = spec_row(r.method);
            assert_eq!(
                cells[1..],
                [r.sp_r, r.sp_see, r.xp_r, r.xp_see, r.xp_len],
                "{}",
                r.method
            );
        }
    }

    #[test]
    fn the_h100_speeds_are_the_ones_the_spec_states() {
        for base in ["9c-2p", "16c-2p"] {
            let cells = spec_row(base);
            let stated: Vec<f64> = cells[1..]
                .iter()
                .map(|c| c.replace(',', "").parse().unwrap())
                .collect();
            let ours: Vec<f64> = [512, 1024, 2048]
                .iter()
                .map(|&e| h100_steps_per_second(base, e).unwrap())
                .collect();
            assert_eq!(ours, stated, "{base}");
        }
        assert_eq!(h100_steps_per_second("9c-3p", 1024), None);
    }
}
