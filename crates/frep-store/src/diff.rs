//! Line diff of two sources, with line numbers on both sides.
//!
//! Algorithm: `similar`'s Myers diff over lines (`TextDiff::from_lines`),
//! with a deadline. Past it the diff stays correct: applying it still turns
//! one text into the other. But it may be longer than minimal. So a huge
//! pathological pair cannot hold a store call for long.
//!
//! Every line of both texts appears once, in order. `same` lines carry both
//! line numbers, `removed` only the old one, `added` only the new one.

use std::time::Duration;

use frep_wire::{DiffKind, DiffLine};
use similar::{Algorithm, ChangeTag, TextDiff};

/// The lines of `old` and `new`, in order, each marked same, added or
/// removed, with 1-based line numbers in the texts they belong to. Line
/// endings (`\n`, `\r\n`) are not part of a line's text.
pub fn line_diff(old: &str, new: &str, timeout: Duration) -> Vec<DiffLine> {
    let diff = TextDiff::configure()
        .algorithm(Algorithm::Myers)
        .timeout(timeout)
        .diff_lines(old, new);
    diff.iter_all_changes()
        .map(|c| {
            let kind = match c.tag() {
                ChangeTag::Equal => DiffKind::Same,
                ChangeTag::Insert => DiffKind::Added,
                ChangeTag::Delete => DiffKind::Removed,
            };
            let text = c.value();
            let text = text.strip_suffix('\n').unwrap_or(text);
            let text = text.strip_suffix('\r').unwrap_or(text);
            DiffLine {
                kind,
                old_line: c.old_index().map(line_number),
                new_line: c.new_index().map(line_number),
                text: text.to_string(),
            }
        })
        .collect()
}

/// A 0-based index as a 1-based line number (sources are bounded far below
/// `u32::MAX` lines by `max_source_bytes`; saturate rather than wrap).
fn line_number(index: usize) -> u32 {
    u32::try_from(index + 1).unwrap_or(u32::MAX)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn kinds(lines: &[DiffLine]) -> Vec<(DiffKind, Option<u32>, Option<u32>, &str)> {
        lines
            .iter()
            .map(|l| (l.kind, l.old_line, l.new_line, l.text.as_str()))
            .collect()
    }

    #[test]
    fn numbers_on_both_sides() {
        let d = line_diff("a\nb\nc\n", "a\nx\nc\nd", Duration::from_secs(1));
        use DiffKind::*;
        assert_eq!(
            kinds(&d),
            vec![
                (Same, Some(1), Some(1), "a"),
                (Removed, Some(2), None, "b"),
                (Added, None, Some(2), "x"),
                (Same, Some(3), Some(3), "c"),
                (Added, None, Some(4), "d"),
            ]
        );
    }

    #[test]
    fn crlf_and_empty() {
        let d = line_diff("", "p\r\nq\r\n", Duration::from_secs(1));
        assert_eq!(d.len(), 2);
        assert_eq!(d[0].text, "p");
        assert_eq!(d[1].new_line, Some(2));
        assert!(line_diff("", "", Duration::from_secs(1)).is_empty());
    }
}
