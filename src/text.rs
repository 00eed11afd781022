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
