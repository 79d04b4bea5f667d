//! Numbered parameters for statements that insert many rows at once. sqlx's `QueryBuilder`
//! writes `?` for the `Any` driver, which PostgreSQL does not read; `$1, $2, …` both engines do.

use std::fmt::Write;

/// `($1, $2, $3), ($4, $5, $6)` for `rows` rows of `columns` values each.
pub fn rows(rows: usize, columns: usize) -> String {
    let mut text = String::with_capacity(rows * columns * 5);
    for row in 0..rows {
        text.push_str(if row == 0 { "(" } else { ", (" });
        for column in 0..columns {
            let separator = if column == 0 { "" } else { ", " };
            let _ = write!(text, "{separator}${}", row * columns + column + 1);
        }
        text.push(')');
    }
    text
}

#[cfg(test)]
mod tests {
    #[test]
    fn rows_are_numbered_across() {
        assert_eq!(super::rows(2, 3), "($1, $2, $3), ($4, $5, $6)");
        assert_eq!(super::rows(1, 1), "($1)");
        assert_eq!(super::rows(0, 4), "");
    }
}
