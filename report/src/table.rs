//! Markdown tables: a header, then rows of cells, written by one writer.
//!
//! Every table a report or study writes is built as a [`Table`] from its
//! rows and written by [`Table::markdown`], so the layout (`| a | b |`
//! lines under a `|---|` rule) is stated once.

/// A markdown table under construction.
///
/// ```
/// use platefield_report::table::Table;
/// let mut t = Table::new(["target", "shape"]);
/// t.row(["sink", "4.9 %"]);
/// assert_eq!(t.markdown(), "| target | shape |\n|---|---|\n| sink | 4.9 % |\n");
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Table {
    header: Vec<String>,
    rows: Vec<Vec<String>>,
}

impl Table {
    /// A table with these column heads and no rows.
    pub fn new<I, S>(header: I) -> Table
    where
        I: IntoIterator<Item = S>,
        S: Into<String>,
    {
        Table {
            header: header.into_iter().map(Into::into).collect(),
            rows: Vec::new(),
        }
    }

    /// Appends one row. A row with fewer cells than the header is padded
    /// with empty cells; one with more is a bug in the caller (debug
    /// builds stop on it).
    pub fn row<I, S>(&mut self, cells: I) -> &mut Table
    where
        I: IntoIterator<Item = S>,
        S: Into<String>,
    {
        let mut cells: Vec<String> = cells.into_iter().map(Into::into).collect();
        debug_assert!(
            cells.len() <= self.header.len(),
            "a row of {} cells under {} heads",
            cells.len(),
            self.header.len()
        );
        if cells.len() < self.header.len() {
            cells.resize(self.header.len(), String::new());
        }
        self.rows.push(cells);
        self
    }

    /// The table in markdown: the header, the rule, one line per row, each
    /// line ending in a newline.
    pub fn markdown(&self) -> String {
        let mut md = line(&self.header);
        md.push('|');
        md.push_str(&"---|".repeat(self.header.len()));
        md.push('\n');
        for r in &self.rows {
            md.push_str(&line(r));
        }
        md
    }
}

/// `| a | b |` and a newline (an empty cell is `|  |`).
fn line(cells: &[String]) -> String {
    let mut s = String::from("|");
    for c in cells {
        s.push(' ');
        s.push_str(c);
        s.push_str(" |");
    }
    s.push('\n');
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn short_rows_are_padded_and_empty_tables_keep_their_header() {
        let mut t = Table::new(["a", "b", "c"]);
        assert_eq!(t.markdown(), "| a | b | c |\n|---|---|---|\n");
        t.row(["1"]).row(["x", "y", "z"]);
        assert_eq!(
            t.markdown(),
            "| a | b | c |\n|---|---|---|\n| 1 |  |  |\n| x | y | z |\n"
        );
    }
}
