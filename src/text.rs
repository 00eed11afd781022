//! Printing names users chose (file names, hand-in names, scene object
//! names) without letting them drive the terminal.
//!
//! A file named `ESC [2J` would clear the instructor's screen when listed,
//! `ESC ] 0 ; title BEL` would retitle the window, and a right-to-left
//! override would show `gnp.exe` as `exe.png`. Characters that show as
//! nothing make two names look alike (`alice`, and `alice` with a
//! zero-width space), and a line separator breaks a Markdown table's row.
//! Everything raylab prints that may hold such a name goes through
//! [`terminal_safe`].

/// `text` with every control character (C0 but the line break, DEL, C1),
/// every character that shows as nothing ([`invisible`]: zero-width
/// spaces and joiners, the soft hyphen, byte-order marks, directional
/// marks, overrides and isolates, variation selectors, tags) and the line
/// and paragraph separators written as a Rust-style escape (`\u{1b}`), so
/// that it prints as visible text. Line breaks are kept: multi-line
/// messages stay readable, and a line break moves no cursor anywhere a new
/// line would not.
pub fn terminal_safe(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        if (c.is_control() && c != '\n') || invisible(c) {
            out.extend(c.escape_unicode());
        } else {
            out.push(c);
        }
    }
    out
}

/// [`terminal_safe`] on one line: line breaks written as `\n` too. For a
/// text a student's code chose (a panic's message) quoted inside raylab's
/// own report, where a line of its own could pass for the report's.
pub fn one_line(text: &str) -> String {
    terminal_safe(text).replace('\n', "\\n")
}

/// Whether `c` shows as nothing, or breaks a line where no line break is:
/// Unicode's `Default_Ignorable_Code_Point` property, as
/// `DerivedCoreProperties.txt` of Unicode 16.0.0 lists it (the code points
/// a renderer shows as nothing when it cannot show them otherwise; the
/// bidirectional overrides and isolates are among them), and the line and
/// paragraph separators U+2028 and U+2029. The property's ranges include
/// the unassigned code points reserved for it, so that they stay right as
/// Unicode assigns more. (No crate fits: `icu_properties` has the property,
/// but needs a newer Rust than raylab's `rust-version` and two dozen crates
/// for seventeen ranges.)
pub fn invisible(c: char) -> bool {
    matches!(
        c,
        '\u{ad}'
            | '\u{34f}'
            | '\u{61c}'
            | '\u{115f}'..='\u{1160}'
            | '\u{17b4}'..='\u{17b5}'
            | '\u{180b}'..='\u{180f}'
            | '\u{200b}'..='\u{200f}'
            | '\u{202a}'..='\u{202e}'
            | '\u{2060}'..='\u{206f}'
            | '\u{3164}'
            | '\u{fe00}'..='\u{fe0f}'
            | '\u{feff}'
            | '\u{ffa0}'
            | '\u{fff0}'..='\u{fff8}'
            | '\u{1bca0}'..='\u{1bca3}'
            | '\u{1d173}'..='\u{1d17a}'
            | '\u{e0000}'..='\u{e0fff}'
            // Not default-ignorable, but a line break to whatever honours
            // them (a Markdown viewer, an editor).
            | '\u{2028}'
            | '\u{2029}'
    )
}

/// A file name as people see it in a report, a CSV or on the terminal:
/// its control characters and invisible characters escaped as by
/// [`terminal_safe`] (line breaks too), and each byte that is not UTF-8
/// written `\xNN`, so that two names that differ never look the same (a
/// lossy conversion shows both `a\xff` and `a\xfe` as `a\u{fffd}`).
pub fn visible_name(name: &std::ffi::OsStr) -> String {
    let mut out = String::new();
    #[cfg(unix)]
    {
        use std::os::unix::ffi::OsStrExt;
        for chunk in name.as_bytes().utf8_chunks() {
            // A backslash doubled first: a name with `\xff` in it must not
            // look like the byte 0xff.
            let valid = chunk.valid().replace('\\', "\\\\");
            out.push_str(&terminal_safe(&valid).replace('\n', "\\u{a}"));
            for byte in chunk.invalid() {
                out.push_str(&format!("\\x{byte:02x}"));
            }
        }
    }
    #[cfg(not(unix))]
    out.push_str(&terminal_safe(&name.to_string_lossy()).replace('\n', "\\u{a}"));
    out
}

/// The names of a list, each shown as [`visible_name`] shows it, but
/// where two would still look alike, both spelled out: every character
/// that is not printable ASCII written as an escape ([`spelled_out`]).
/// Names look alike when they share a skeleton, as Unicode's
/// confusable detection defines it (UTS #39: `jos\u{e9}` and
/// `jose\u{301}`, the Latin `alice` and one with a Cyrillic `\u{430}`,
/// `a\u{a0}b` and `a b` share one), with runs of spaces counted as one
/// and the spaces at either end dropped (an HTML page shows `alice ` as
/// `alice`). Printable ASCII is left as it is: two names made of it
/// differ visibly, even where a skeleton equates `rn` and `m`.
pub fn told_apart(names: &[&std::ffi::OsStr]) -> Vec<String> {
    let keys: Vec<String> = names
        .iter()
        .map(|name| look(&name.to_string_lossy()))
        .collect();
    let mut count = std::collections::HashMap::<&str, usize>::new();
    for key in &keys {
        *count.entry(key.as_str()).or_default() += 1;
    }
    names
        .iter()
        .zip(&keys)
        .map(|(name, key)| {
            if count[key.as_str()] > 1 {
                spelled_out(name)
            } else {
                visible_name(name)
            }
        })
        .collect()
}

/// How `text` looks: its confusable skeleton (UTS #39, which maps
/// look-alike characters to one and decomposes accents), with runs of
/// spaces counted as one and the spaces at either end dropped. Two texts
/// of one look may be told apart by no one reading them.
pub fn look(text: &str) -> String {
    let skeleton: String = unicode_security::confusable_detection::skeleton(text).collect();
    skeleton.split_whitespace().collect::<Vec<_>>().join(" ")
}

/// `name` in printable ASCII alone: each other character written as a
/// Rust-style escape (`\u{e9}`, a space `\u{20}`), each byte that is not
/// UTF-8 as `\xNN`, and a backslash doubled, so that no two names are
/// spelled alike and none can be confused with another's spelling.
pub fn spelled_out(name: &std::ffi::OsStr) -> String {
    fn spell(valid: &str, out: &mut String) {
        for c in valid.chars() {
            match c {
                '\\' => out.push_str("\\\\"),
                '!'..='~' => out.push(c),
                _ => out.extend(c.escape_unicode()),
            }
        }
    }
    let mut out = String::new();
    #[cfg(unix)]
    {
        use std::os::unix::ffi::OsStrExt;
        for chunk in name.as_bytes().utf8_chunks() {
            spell(chunk.valid(), &mut out);
            for byte in chunk.invalid() {
                out.push_str(&format!("\\x{byte:02x}"));
            }
        }
    }
    #[cfg(not(unix))]
    spell(&name.to_string_lossy(), &mut out);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_line_keeps_a_quoted_text_on_its_line() {
        assert_eq!(one_line("a\n\nb\u{1b}"), "a\\n\\nb\\u{1b}");
    }

    #[test]
    fn names_that_differ_look_different() {
        use std::os::unix::ffi::OsStrExt;
        let name = |bytes: &[u8]| visible_name(std::ffi::OsStr::from_bytes(bytes));
        assert_eq!(name(b"a\xff"), "a\\xff");
        assert_ne!(name(b"a\xff"), name(b"a\xfe"));
        assert_eq!(name("gnp.\u{202e}exe".as_bytes()), "gnp.\\u{202e}exe");
        assert_eq!(name(b"two\nlines\x1b[2J"), "two\\u{a}lines\\u{1b}[2J");
        assert_eq!(name("caf\u{e9}".as_bytes()), "caf\u{e9}");
        // A literal backslash is not an escape.
        assert_ne!(name(br"a\xff"), name(b"a\xff"));
        assert_eq!(name(br"a\xff"), r"a\\xff");
    }

    /// Characters that show as nothing (default-ignorable code points:
    /// zero-width spaces and joiners, the soft hyphen, byte-order marks,
    /// directional marks, variation selectors, tags) and the line and
    /// paragraph separators are escaped too: `alice` and `alice` with a
    /// zero-width space must not look alike, nor may a name split a
    /// Markdown row.
    #[test]
    fn invisible_characters_and_separators_are_shown() {
        for invisible in [
            '\u{200b}',
            '\u{ad}',
            '\u{feff}',
            '\u{200f}',
            '\u{61c}',
            '\u{2028}',
            '\u{2029}',
            '\u{34f}',
            '\u{115f}',
            '\u{180e}',
            '\u{2060}',
            '\u{3164}',
            '\u{fe0f}',
            '\u{ffa0}',
            '\u{1bca0}',
            '\u{1d173}',
            '\u{e0001}',
            '\u{e0fff}',
        ] {
            let text = format!("ali{invisible}ce");
            let escaped = format!("ali\\u{{{:x}}}ce", u32::from(invisible));
            assert_eq!(terminal_safe(&text), escaped);
            assert_eq!(visible_name(std::ffi::OsStr::new(&text)), escaped);
        }
        // Visible neighbours of those ranges stay as they are.
        for visible in [
            '\u{ac}', '\u{ae}', '\u{200a}', '\u{2027}', '\u{2030}', '\u{3163}',
        ] {
            let text = format!("a{visible}b");
            assert_eq!(terminal_safe(&text), text);
        }
    }

    /// Names that differ only in how a character is composed, in a
    /// look-alike letter of another script, or in spaces that show alike,
    /// are spelled out; names alone in looking as they do are not.
    #[test]
    fn names_that_would_look_alike_are_spelled_out() {
        let names = [
            "jos\u{e9}",
            "jose\u{301}",
            "alice",
            "\u{430}lice",
            "alice ",
            "bob",
            "ali ce",
            "ali\u{a0}ce",
            "ali\u{3000}ce",
            "ali\u{2800}ce",
            "ali  ce",
            "zo\u{eb}",
            "rn",
            "m",
        ];
        let os: Vec<&std::ffi::OsStr> = names.iter().map(std::ffi::OsStr::new).collect();
        let shown = told_apart(&os);
        assert_eq!(
            shown,
            [
                "jos\\u{e9}",
                "jose\\u{301}",
                "alice",
                "\\u{430}lice",
                "alice\\u{20}",
                "bob",
                "ali\\u{20}ce",
                "ali\\u{a0}ce",
                "ali\\u{3000}ce",
                "ali\\u{2800}ce",
                "ali\\u{20}\\u{20}ce",
                // Alone: shown as it is, accent and all.
                "zo\u{eb}",
                "rn",
                "m",
            ]
        );
        let mut distinct = shown.clone();
        distinct.sort();
        distinct.dedup();
        assert_eq!(distinct.len(), shown.len());
        // A spelling is never another name's plain form.
        assert_ne!(
            spelled_out(std::ffi::OsStr::new("jos\u{e9}")),
            visible_name(std::ffi::OsStr::new(r"jos\u{e9}"))
        );
        assert_eq!(spelled_out(std::ffi::OsStr::new(r"a\b")), r"a\\b");
    }

    #[test]
    fn control_characters_are_shown_not_obeyed() {
        assert_eq!(terminal_safe("a\u{1b}[2Jb"), "a\\u{1b}[2Jb");
        assert_eq!(
            terminal_safe("\u{9b}31m\r\t\u{7f}"),
            "\\u{9b}31m\\u{d}\\u{9}\\u{7f}"
        );
        assert_eq!(terminal_safe("gnp.\u{202e}exe"), "gnp.\\u{202e}exe");
        assert_eq!(terminal_safe("two\nlines, café ✓"), "two\nlines, café ✓");
    }
}

/// `n` things: "1 run", "5 runs" (a regular plural, `s` added).
pub fn count(n: u64, thing: &str) -> String {
    if n == 1 {
        format!("1 {thing}")
    } else {
        format!("{n} {thing}s")
    }
}

#[cfg(test)]
mod count_tests {
    #[test]
    fn one_is_singular_and_every_other_count_plural() {
        assert_eq!(super::count(1, "run"), "1 run");
        assert_eq!(super::count(0, "run"), "0 runs");
        assert_eq!(super::count(5, "run"), "5 runs");
    }
}
