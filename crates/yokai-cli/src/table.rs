//! CSV tables for the commands' outputs, written by the `csv` crate so that fields holding
//! commas, quotes or line breaks (policy names are paths) are quoted as RFC 4180 says.

/// The CSV text of `header` and `rows` (each row as many fields as the header).
pub fn csv_text(header: &[&str], rows: impl IntoIterator<Item = Vec<String>>) -> String {
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record(header).expect("writing to memory");
    for row in rows {
        debug_assert_eq!(row.len(), header.len(), "a row per header field");
        w.write_record(&row).expect("writing to memory");
    }
    String::from_utf8(w.into_inner().expect("writing to memory")).expect("fields are UTF-8")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A run directory named with a comma and a quote reads back as one field.
    #[test]
    fn fields_with_commas_and_quotes_read_back_whole() {
        let name = "runs/a,b \"c\"/seed-0".to_string();
        let text = csv_text(&["run", "R"], [vec![name.clone(), "1.5".into()]]);
        let mut r = csv::Reader::from_reader(text.as_bytes());
        let rows: Vec<csv::StringRecord> = r.records().map(|x| x.unwrap()).collect();
        assert_eq!(rows.len(), 1);
        assert_eq!(&rows[0][0], name);
        assert_eq!(&rows[0][1], "1.5");
    }
}
