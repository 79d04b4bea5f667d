//! A robot's word on a task it will not do (DESIGN §8): one line of plain words, bounded, that
//! the registry stores and caretakers read beside the task. The registry refuses a reason
//! outside these bounds; a robot fits what it has to say into them.

/// The longest reason a robot may give, in characters.
pub const MAX_DECLINE_REASON_CHARS: usize = 500;

/// `words` as a decline's reason: on one line (line breaks and other control characters become
/// spaces, runs of spaces one), and cut after the last whole word that fits, with an ellipsis,
/// when longer than [`MAX_DECLINE_REASON_CHARS`].
pub fn decline_reason(words: &str) -> String {
    let line = words
        .split(|c: char| c.is_whitespace() || c.is_control())
        .filter(|word| !word.is_empty())
        .collect::<Vec<_>>()
        .join(" ");
    if line.chars().count() <= MAX_DECLINE_REASON_CHARS {
        return line;
    }
    // Room for the ellipsis and the space before it.
    let room = MAX_DECLINE_REASON_CHARS - 2;
    let cut = line.char_indices().nth(room).map_or(line.len(), |(at, _)| at);
    let kept = &line[..cut];
    let whole = match line[cut..].starts_with(' ') {
        true => kept,
        false => kept.rfind(' ').map_or(kept, |space| &kept[..space]),
    };
    format!("{} …", whole.trim_end())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_reason_is_one_line_of_words() {
        assert_eq!(
            decline_reason("  it could not\nfind\tthe tag \u{7} "),
            "it could not find the tag"
        );
    }

    #[test]
    fn a_long_reason_is_cut_after_a_whole_word() {
        let long = "wörd ".repeat(150);
        let reason = decline_reason(&long);
        assert!(reason.chars().count() <= MAX_DECLINE_REASON_CHARS, "{}", reason.len());
        assert!(reason.ends_with("wörd …"), "{reason}");
        assert!(reason.chars().count() > MAX_DECLINE_REASON_CHARS - 8, "as much as fits");
    }
}
