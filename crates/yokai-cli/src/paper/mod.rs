//! The YLE paper's published figures that reports print beside ours: its Tables 2–6 (self-play
//! and cross-play of each method and setting, [`TABLES`]) and its environment's speed on an
//! H100. One place for both, checked by tests against the paper's numbers that
//! docs/spec/training.md states.

mod tables;
pub use tables::TABLES;

/// One of the paper's result tables (2: the main table, 3: OP's entropy sweep, 4: OP's
/// symmetry groups, 5: encoders, 6: imperfect memory).
pub struct PaperTable {
    pub number: u8,
    pub title: &'static str,
    pub rows: &'static [PaperRow],
}

/// One row as printed: mean ± SE over seeds, shares in %, "–" where the paper has no figure.
pub struct PaperRow {
    pub method: &'static str,
    /// The game's short name (`9c-2p-perfect`), as `Config`'s `Display` writes it.
    pub game: &'static str,
    pub seeds: &'static str,
    /// R, SEE, EE, WEE, LEN.
    pub sp: [&'static str; 5],
    pub xp: [&'static str; 5],
}

/// The paper's main table (Table 2), which evaluations print their rows beside.
pub fn main_table() -> &'static PaperTable {
    &TABLES[0]
}

/// The paper's table `number` (2–6), if it has one of that number.
pub fn table(number: u8) -> Option<&'static PaperTable> {
    TABLES.iter().find(|t| t.number == number)
}

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

    const SPEC: &str = include_str!("../../../../docs/spec/training.md");

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

    /// The mean of a printed cell ("7.5 ± 0.3" → "7.5").
    fn mean(cell: &str) -> &str {
        cell.split(" ± ").next().unwrap()
    }

    /// "4.0–4.8": the least and greatest mean of `cells`, as the spec's summary writes them.
    fn range<'a>(cells: impl Iterator<Item = &'a str>) -> String {
        let mut v: Vec<(f64, &str)> = cells
            .map(|c| (mean(c).parse::<f64>().unwrap(), mean(c)))
            .collect();
        v.sort_by(|a, b| a.0.total_cmp(&b.0));
        format!("{}–{}", v[0].1, v[v.len() - 1].1)
    }

    #[test]
    fn the_spec_states_the_main_tables_2_player_rows() {
        let rows: Vec<&PaperRow> = table(2)
            .unwrap()
            .rows
            .iter()
            .filter(|r| r.game == "9c-2p-perfect")
            .collect();
        let summary = |r: &PaperRow| [r.sp[0], r.sp[1], r.xp[0], r.xp[1], r.xp[4]].map(mean);
        for method in ["IPPO", "HE", "OP"] {
            let r = rows.iter().find(|r| r.method == method).unwrap();
            assert_eq!(spec_row(method)[1..], summary(r), "{method}");
        }
        let obl: Vec<&&PaperRow> = rows
            .iter()
            .filter(|r| r.method.starts_with("OBL"))
            .collect();
        assert_eq!(obl.len(), 5);
        let ranges: Vec<String> = [(0, 0), (0, 1), (1, 0), (1, 1), (1, 4)]
            .iter()
            .map(|&(side, col)| range(obl.iter().map(|r| [r.sp, r.xp][side][col])))
            .collect();
        assert_eq!(spec_row("OBL levels 1..5")[1..], ranges);
        let humans = table(2)
            .unwrap()
            .rows
            .iter()
            .find(|r| r.method == "humans")
            .unwrap();
        assert_eq!(
            spec_row("people (imperfect memory)")[3..5],
            [humans.xp[0], humans.xp[1]].map(mean)
        );
    }

    #[test]
    fn every_table_is_there_with_well_formed_cells() {
        assert_eq!(TABLES.map(|t| t.number), [2, 3, 4, 5, 6]);
        // Table 2: 15 trained rows (9c-2p: IPPO, HE, OP, OBL 1–5; 9c-3p and 9c-4p: IPPO, HE,
        // OP; 16c-2p: IPPO) and the humans.
        let t2 = table(2).unwrap();
        assert_eq!(t2.rows.len(), 16);
        for game in ["9c-3p-perfect", "9c-4p-perfect"] {
            let methods: Vec<&str> = t2
                .rows
                .iter()
                .filter(|r| r.game == game)
                .map(|r| r.method)
                .collect();
            assert_eq!(methods, ["IPPO", "HE", "OP"], "{game}");
        }
        for t in &TABLES {
            for r in t.rows {
                yokai_engine::Config::from_name(r.game)
                    .unwrap_or_else(|e| panic!("{}: {e}", r.game));
                for c in r.sp.iter().chain(&r.xp) {
                    let ok = *c == "–"
                        || c.split(" ± ")
                            .map(|x| x.parse::<f64>().is_ok())
                            .collect::<Vec<_>>()
                            == [true, true];
                    assert!(ok, "table {} {}: `{c}`", t.number, r.method);
                }
            }
        }
        // Table 5 reports self-play only.
        assert!(table(5).unwrap().rows.iter().all(|r| r.xp == ["–"; 5]));
        assert!(table(7).is_none());
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
