//! Lists of seeds as every front end reads them (`yokai train --seeds`, `--levels`, the
//! sweep files of `python -m yokai.sweep`): `0..3` (0, 1, 2), `0,4,7` or `5`.

/// Why a seed list was refused (the message quotes the text, not the option it came from).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum SeedsError {
    #[error("`{0}` is empty (A..B excludes B)")]
    Empty(String),
    #[error("`{0}` is not A..B, a comma-separated list or a number")]
    Syntax(String),
}

/// The seeds `text` names: `A..B` (A up to B, B excluded), a comma-separated list, or one
/// number.
pub fn parse_seeds(text: &str) -> Result<Vec<u64>, SeedsError> {
    let bad = || SeedsError::Syntax(text.to_string());
    if let Some((a, b)) = text.split_once("..") {
        let a: u64 = a.trim().parse().map_err(|_| bad())?;
        let b: u64 = b.trim().parse().map_err(|_| bad())?;
        if b <= a {
            return Err(SeedsError::Empty(text.to_string()));
        }
        return Ok((a..b).collect());
    }
    text.split(',')
        .map(|s| s.trim().parse::<u64>().map_err(|_| bad()))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_lists_and_numbers() {
        assert_eq!(parse_seeds("0..3"), Ok(vec![0, 1, 2]));
        assert_eq!(parse_seeds(" 2 .. 4"), Ok(vec![2, 3]));
        assert_eq!(parse_seeds("4, 7"), Ok(vec![4, 7]));
        assert_eq!(parse_seeds("5"), Ok(vec![5]));
        assert_eq!(parse_seeds("3..3"), Err(SeedsError::Empty("3..3".into())));
        for bad in ["a..b", "", "1,,2", "-1", "1..x", "0.5"] {
            assert_eq!(
                parse_seeds(bad),
                Err(SeedsError::Syntax(bad.into())),
                "{bad}"
            );
        }
    }
}
