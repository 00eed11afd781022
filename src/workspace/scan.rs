//! A small scanner for Rust source: enough to cut a chapter file into its
//! top-level items (with their doc comments and attributes) and to find a
//! function's body, without a parser dependency.
//!
//! It knows exactly what can hide a brace or a semicolon: comments (nested
//! block comments too), string literals (escaped, raw with any number of
//! `#`, byte and C strings), and character literals, told apart from
//! lifetimes. Everything else is words, brackets and punctuation. Brackets
//! must balance; anything it does not understand is an error, never a
//! silently wrong cut.

use std::ops::Range;

/// What a token is, as far as cutting items goes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Tok {
    Open(u8),
    Close(u8),
    Semi,
    Comma,
    Colon,
    Pound,
    Bang,
    /// An identifier or keyword (raw identifiers included).
    Word,
    /// A comment; `doc` for the outer doc forms `///` and `/** */`.
    Comment {
        doc: bool,
    },
    /// A string, byte string or character literal.
    Literal,
    /// A number, a lifetime, or any other punctuation.
    Other,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Token {
    pub kind: Tok,
    pub start: usize,
    pub end: usize,
}

/// Why the scanner refuses a text: what it could not cut, and the byte
/// offset where that starts when there is one.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ScanError {
    #[error("unterminated block comment at byte {at}")]
    UnterminatedComment { at: usize },
    #[error("unterminated string at byte {at}")]
    UnterminatedString { at: usize },
    #[error("bad byte literal at byte {at}")]
    BadByteLiteral { at: usize },
    #[error("unterminated raw string at byte {at}")]
    UnterminatedRawString { at: usize },
    #[error("unmatched `{bracket}` at byte {at}")]
    Unmatched { bracket: char, at: usize },
    /// `bracket` at `at` closes the different `opening` at `opening_at`.
    #[error("`{bracket}` at byte {at} closes `{opening}` at byte {opening_at}")]
    Mismatched {
        bracket: char,
        at: usize,
        opening: String,
        opening_at: usize,
    },
    #[error("unclosed bracket at byte {at}")]
    Unclosed { at: usize },
    /// A bracket with no partner, in the part of the text named.
    #[error("unbalanced {0}")]
    Unbalanced(&'static str),
    /// The item whose header starts at byte `header` has no `;` or block.
    #[error("item at byte {header} never ends")]
    NeverEnds { header: usize },
    #[error("item at byte {header} is cut short")]
    CutShort { header: usize },
    #[error("no `fn` in the signature")]
    NoFn,
    #[error("no parameter list")]
    NoParameterList,
    #[error("parameter `{pattern}` is not a plain name")]
    NotPlainName { pattern: String },
    #[error("unclosed generics")]
    UnclosedGenerics,
    #[error("a `const` generic parameter")]
    ConstGeneric,
}

/// Splits `src` into tokens. Errors name the byte offset of an unterminated
/// comment or literal.
pub fn lex(src: &str) -> Result<Vec<Token>, ScanError> {
    let bytes = src.as_bytes();
    let mut tokens = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i].is_ascii_whitespace() {
            i += 1;
            continue;
        }
        let start = i;
        let (kind, end) = token_at(src, start)?;
        tokens.push(Token { kind, start, end });
        i = end;
    }
    Ok(tokens)
}

/// The token that starts at `start` (not whitespace), and the offset just
/// past it.
fn token_at(src: &str, start: usize) -> Result<(Tok, usize), ScanError> {
    let bytes = src.as_bytes();
    let c = bytes[start];
    let next = bytes.get(start + 1).copied();
    Ok(match c {
        b'/' if next == Some(b'/') => line_comment(src, start),
        b'/' if next == Some(b'*') => block_comment(src, start)?,
        b'"' => {
            let end = end_of_string(bytes, start + 1)
                .ok_or(ScanError::UnterminatedString { at: start })?;
            (Tok::Literal, end)
        }
        b'\'' => match char_literal_end(src, start) {
            Some(end) => (Tok::Literal, end),
            // A lifetime or label: the quote and the name after it.
            None => (Tok::Other, word_end(bytes, start + 1)),
        },
        _ if c.is_ascii_digit() => (Tok::Other, number_end(bytes, start)),
        _ if is_word_byte(c) => word_or_prefixed_literal(src, start)?,
        _ => (punctuation(c), start + 1),
    })
}

/// A `//` comment, to the end of its line (the newline not included).
fn line_comment(src: &str, start: usize) -> (Tok, usize) {
    let end = src[start..].find('\n').map_or(src.len(), |n| start + n);
    let text = &src[start..end];
    let doc = text.starts_with("///") && !text.starts_with("////");
    (Tok::Comment { doc }, end)
}

/// A `/* */` comment, block comments nested in it included.
fn block_comment(src: &str, start: usize) -> Result<(Tok, usize), ScanError> {
    let bytes = src.as_bytes();
    let mut i = start;
    let mut depth = 0usize;
    loop {
        if i + 1 >= bytes.len() {
            return Err(ScanError::UnterminatedComment { at: start });
        }
        match (bytes[i], bytes[i + 1]) {
            (b'/', b'*') => {
                depth += 1;
                i += 2;
            }
            (b'*', b'/') => {
                depth -= 1;
                i += 2;
                if depth == 0 {
                    break;
                }
            }
            _ => i += 1,
        }
    }
    let text = &src[start..i];
    let doc = text.starts_with("/**") && !text.starts_with("/***") && text != "/**/";
    Ok((Tok::Comment { doc }, i))
}

/// The end of the run of word bytes from `from`.
fn word_end(bytes: &[u8], from: usize) -> usize {
    let mut i = from;
    while i < bytes.len() && is_word_byte(bytes[i]) {
        i += 1;
    }
    i
}

/// The end of a number literal: word bytes (suffixes, hex digits, exponents)
/// and a decimal point followed by a digit (`1.5`, but not the range `1..2`
/// nor the method call `1.max(2)`).
fn number_end(bytes: &[u8], from: usize) -> usize {
    let mut i = from;
    while i < bytes.len()
        && (is_word_byte(bytes[i])
            || (bytes[i] == b'.' && bytes.get(i + 1).is_some_and(u8::is_ascii_digit)))
    {
        i += 1;
    }
    i
}

/// A word at `start`, or the literal it prefixes: `b".."`, `c".."`,
/// `b'.'`, the raw strings `r".."`, `r#".."#`, `br".."` and `cr".."`, and
/// the raw identifier `r#type`.
fn word_or_prefixed_literal(src: &str, start: usize) -> Result<(Tok, usize), ScanError> {
    let bytes = src.as_bytes();
    let i = word_end(bytes, start);
    let word = &src[start..i];
    Ok(match (word, bytes.get(i).copied()) {
        // b"..", c"..": an escaped string with a prefix.
        ("b" | "c", Some(b'"')) => {
            let end =
                end_of_string(bytes, i + 1).ok_or(ScanError::UnterminatedString { at: start })?;
            (Tok::Literal, end)
        }
        ("b", Some(b'\'')) => {
            let end = char_literal_end(src, i).ok_or(ScanError::BadByteLiteral { at: start })?;
            (Tok::Literal, end)
        }
        ("r" | "br" | "cr", Some(b'"' | b'#')) => raw_string_or_identifier(src, start, i)?,
        _ => (Tok::Word, i),
    })
}

/// After the prefix `src[start..i]` (`r`, `br` or `cr`) and before a `"` or
/// `#`: a raw string with any number of `#`, a raw identifier, or just the
/// word.
fn raw_string_or_identifier(src: &str, start: usize, i: usize) -> Result<(Tok, usize), ScanError> {
    let bytes = src.as_bytes();
    let hashes = bytes[i..].iter().take_while(|&&b| b == b'#').count();
    if bytes.get(i + hashes) == Some(&b'"') {
        let closing = format!("\"{}", "#".repeat(hashes));
        let body = i + hashes + 1;
        let end = src[body..]
            .find(&closing)
            .ok_or(ScanError::UnterminatedRawString { at: start })?;
        Ok((Tok::Literal, body + end + closing.len()))
    } else if &src[start..i] == "r" && hashes == 1 {
        // A raw identifier, r#type.
        Ok((Tok::Word, word_end(bytes, i + 1)))
    } else {
        Ok((Tok::Word, i))
    }
}

/// A one-byte token: a bracket or the punctuation that cutting items reads.
fn punctuation(c: u8) -> Tok {
    match c {
        b'(' | b'[' | b'{' => Tok::Open(c),
        b')' | b']' | b'}' => Tok::Close(c),
        b';' => Tok::Semi,
        b',' => Tok::Comma,
        b':' => Tok::Colon,
        b'#' => Tok::Pound,
        b'!' => Tok::Bang,
        _ => Tok::Other,
    }
}

fn is_word_byte(b: u8) -> bool {
    b.is_ascii_alphanumeric() || b == b'_' || b >= 0x80
}

/// The end of an escaped string whose body starts at `from` (just after
/// the opening quote).
fn end_of_string(bytes: &[u8], from: usize) -> Option<usize> {
    let mut i = from;
    while i < bytes.len() {
        match bytes[i] {
            b'\\' => i += 2,
            b'"' => return Some(i + 1),
            _ => i += 1,
        }
    }
    None
}

/// The end of a character literal starting with the quote at `at`, or
/// `None` when the quote starts a lifetime instead: `'a'` and `'\n'` are
/// characters, `'a` and `'static` are not.
fn char_literal_end(src: &str, at: usize) -> Option<usize> {
    let bytes = src.as_bytes();
    if bytes.get(at + 1) == Some(&b'\\') {
        // An escape: '\n', '\'', '\u{1F600}'. The closing quote is the
        // first one after the escaped character.
        let from = at + 3;
        return src.get(from..)?.find('\'').map(|n| from + n + 1);
    }
    let c = src.get(at + 1..)?.chars().next()?;
    let after = at + 1 + c.len_utf8();
    (bytes.get(after) == Some(&b'\'')).then_some(after + 1)
}

/// For each opening bracket token, the index of its closing one (and the
/// reverse), or an error when they do not balance.
pub fn match_brackets(src: &str, tokens: &[Token]) -> Result<Vec<Option<usize>>, ScanError> {
    let mut partner = vec![None; tokens.len()];
    let mut open: Vec<usize> = Vec::new();
    for (index, token) in tokens.iter().enumerate() {
        match token.kind {
            Tok::Open(_) => open.push(index),
            Tok::Close(c) => {
                let Some(opening) = open.pop() else {
                    return Err(ScanError::Unmatched {
                        bracket: c as char,
                        at: token.start,
                    });
                };
                let expected = match tokens[opening].kind {
                    Tok::Open(b'(') => b')',
                    Tok::Open(b'[') => b']',
                    _ => b'}',
                };
                if c != expected {
                    return Err(ScanError::Mismatched {
                        bracket: c as char,
                        at: token.start,
                        opening: src[tokens[opening].start..tokens[opening].end].to_string(),
                        opening_at: tokens[opening].start,
                    });
                }
                partner[opening] = Some(index);
                partner[index] = Some(opening);
            }
            _ => {}
        }
    }
    match open.pop() {
        Some(index) => Err(ScanError::Unclosed {
            at: tokens[index].start,
        }),
        None => Ok(partner),
    }
}

/// What kind of item an [`Item`] is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ItemKind {
    /// `#![...]` at the top of a file or block.
    InnerAttribute,
    Use,
    Fn,
    Const,
    Static,
    Struct,
    Enum,
    Union,
    Trait,
    Impl,
    TypeAlias,
    Mod,
    MacroRules,
    ExternCrate,
    /// Anything else, such as a macro invocation at item level.
    Other,
}

/// One top-level item, as byte ranges into the scanned text.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Item {
    pub kind: ItemKind,
    /// The item's name (`None` for `impl`, `use` and the like).
    pub name: Option<String>,
    /// From its first comment or attribute to its closing `}` or `;`.
    pub range: Range<usize>,
    /// Where the item proper begins, after its comments and attributes.
    pub header: usize,
    /// The end of the last outer doc comment before `header`, if any.
    pub doc_end: Option<usize>,
    /// A function's body, braces included.
    pub body: Option<Range<usize>>,
}

impl Item {
    /// Whether the item is declared `pub` (in any form).
    pub fn is_pub(&self, src: &str) -> bool {
        src[self.header..].starts_with("pub")
    }
}

/// The items of `src` in order. Comments after the last item are dropped.
pub fn items(src: &str) -> Result<Vec<Item>, ScanError> {
    let cutter = Cutter::new(src)?;
    let mut items = Vec::new();
    let mut i = 0;
    while i < cutter.tokens.len() {
        let start = cutter.tokens[i].start;
        let (at, doc_end) = match cutter.leading(i, start)? {
            Leading::End => break,
            Leading::InnerAttribute { item, next } => {
                items.push(item);
                i = next;
                continue;
            }
            Leading::Header { at, doc_end } => (at, doc_end),
        };
        let header = cutter.tokens[at].start;
        let (keyword, kind, name) = cutter.keyword(at, header)?;
        let (end, body) = cutter.item_end(keyword, kind, header)?;
        items.push(Item {
            kind,
            name: name.map(str::to_string),
            range: start..cutter.tokens[end].end,
            header,
            doc_end,
            body: if kind == ItemKind::Fn { body } else { None },
        });
        i = end + 1;
    }
    Ok(items)
}

/// A text's tokens with their bracket partners: what cutting it into items
/// reads.
struct Cutter<'a> {
    src: &'a str,
    tokens: Vec<Token>,
    partner: Vec<Option<usize>>,
}

/// What comes first at an item's start, past its comments and attributes.
enum Leading {
    /// The item proper starts at token `at`.
    Header { at: usize, doc_end: Option<usize> },
    /// An inner attribute, an item of its own; the next item starts at
    /// token `next`.
    InnerAttribute { item: Item, next: usize },
    /// Only comments were left.
    End,
}

impl<'a> Cutter<'a> {
    fn new(src: &'a str) -> Result<Self, ScanError> {
        let tokens = lex(src)?;
        let partner = match_brackets(src, &tokens)?;
        Ok(Cutter {
            src,
            tokens,
            partner,
        })
    }

    /// The bracket that closes the one at token `index`.
    fn closing(&self, index: usize) -> Result<usize, ScanError> {
        self.partner[index].ok_or(ScanError::Unbalanced("brackets"))
    }

    fn kind(&self, index: usize) -> Option<Tok> {
        self.tokens.get(index).map(|token| token.kind)
    }

    /// The text of token `index` if it is a word.
    fn word(&self, index: usize) -> Option<&'a str> {
        self.tokens
            .get(index)
            .filter(|token| token.kind == Tok::Word)
            .map(|token| &self.src[token.start..token.end])
    }

    /// Skips the comments and outer attributes from token `i` (the item's
    /// `start` byte), noting where the last doc comment ends.
    fn leading(&self, mut i: usize, start: usize) -> Result<Leading, ScanError> {
        let mut doc_end = None;
        loop {
            let Some(token) = self.tokens.get(i) else {
                return Ok(Leading::End);
            };
            match token.kind {
                Tok::Comment { doc } => {
                    if doc {
                        doc_end = Some(token.end);
                    }
                    i += 1;
                }
                Tok::Pound
                    if self.kind(i + 1) == Some(Tok::Bang)
                        && self.kind(i + 2) == Some(Tok::Open(b'[')) =>
                {
                    let end = self.closing(i + 2)?;
                    let item = Item {
                        kind: ItemKind::InnerAttribute,
                        name: None,
                        range: start..self.tokens[end].end,
                        header: token.start,
                        doc_end,
                        body: None,
                    };
                    return Ok(Leading::InnerAttribute {
                        item,
                        next: end + 1,
                    });
                }
                Tok::Pound if self.kind(i + 1) == Some(Tok::Open(b'[')) => {
                    i = self.closing(i + 1)? + 1;
                }
                _ => return Ok(Leading::Header { at: i, doc_end }),
            }
        }
    }

    /// From token `j`, the item's keyword past visibility and qualifiers:
    /// its token, the kind of item it makes, and the item's name.
    fn keyword(
        &self,
        mut j: usize,
        header: usize,
    ) -> Result<(usize, ItemKind, Option<&'a str>), ScanError> {
        let word = |index| self.word(index);
        let (kind, name) = loop {
            let Some(token) = self.tokens.get(j) else {
                return Err(ScanError::NeverEnds { header });
            };
            let text = &self.src[token.start..token.end];
            match (token.kind, text) {
                (Tok::Word, "pub") => {
                    j += 1;
                    if self.kind(j) == Some(Tok::Open(b'(')) {
                        j = self.closing(j)? + 1;
                    }
                }
                (Tok::Word, "const")
                    if !matches!(word(j + 1), Some("fn" | "unsafe" | "async" | "extern")) =>
                {
                    break (ItemKind::Const, word(j + 1));
                }
                (Tok::Word, "extern") if word(j + 1) == Some("crate") => {
                    break (ItemKind::ExternCrate, word(j + 2));
                }
                (Tok::Word, "const" | "unsafe" | "async" | "extern" | "default" | "safe")
                | (Tok::Literal, _) => j += 1,
                (Tok::Word, "fn") => break (ItemKind::Fn, word(j + 1)),
                (Tok::Word, "static") => {
                    let name_at = if word(j + 1) == Some("mut") {
                        j + 2
                    } else {
                        j + 1
                    };
                    break (ItemKind::Static, word(name_at));
                }
                (Tok::Word, "struct") => break (ItemKind::Struct, word(j + 1)),
                (Tok::Word, "enum") => break (ItemKind::Enum, word(j + 1)),
                (Tok::Word, "union") => break (ItemKind::Union, word(j + 1)),
                (Tok::Word, "trait") => break (ItemKind::Trait, word(j + 1)),
                (Tok::Word, "type") => break (ItemKind::TypeAlias, word(j + 1)),
                (Tok::Word, "mod") => break (ItemKind::Mod, word(j + 1)),
                (Tok::Word, "use") => break (ItemKind::Use, None),
                (Tok::Word, "impl") => break (ItemKind::Impl, None),
                (Tok::Word, "macro_rules") => break (ItemKind::MacroRules, word(j + 2)),
                _ => break (ItemKind::Other, None),
            }
        };
        Ok((j, kind, name))
    }

    /// The token that ends the item of `kind` whose keyword is token `k`,
    /// and its block when a block ends it: a `;` outside brackets, or, for
    /// the items that have one, the block that closes it. A constant's value
    /// may hold a block (`Foo { x: 1 }`), so for those only the `;` counts.
    fn item_end(
        &self,
        mut k: usize,
        kind: ItemKind,
        header: usize,
    ) -> Result<(usize, Option<Range<usize>>), ScanError> {
        let block_ends = !matches!(
            kind,
            ItemKind::Const
                | ItemKind::Static
                | ItemKind::TypeAlias
                | ItemKind::Use
                | ItemKind::ExternCrate
        );
        loop {
            let Some(token) = self.tokens.get(k) else {
                return Err(ScanError::NeverEnds { header });
            };
            match token.kind {
                Tok::Semi => return Ok((k, None)),
                Tok::Open(b'{') if block_ends => {
                    let end = self.closing(k)?;
                    return Ok((end, Some(token.start..self.tokens[end].end)));
                }
                Tok::Open(_) => k = self.closing(k)? + 1,
                Tok::Close(_) => return Err(ScanError::CutShort { header }),
                _ => k += 1,
            }
        }
    }
}

/// The names of a function's parameters, in order, from its signature
/// (`fn f<C: X>(a: &A, mut b: (u32, u32)) -> R`). Patterns other than a
/// plain name (with `mut`) are an error.
pub fn parameter_names(signature: &str) -> Result<Vec<String>, ScanError> {
    let tokens = lex(signature)?;
    let partner = match_brackets(signature, &tokens)?;
    let fn_at = tokens
        .iter()
        .position(|t| t.kind == Tok::Word && &signature[t.start..t.end] == "fn")
        .ok_or(ScanError::NoFn)?;
    // The first `(` after the name outside the generics' angle brackets.
    let mut angle = 0i32;
    let mut open = None;
    for (index, token) in tokens.iter().enumerate().skip(fn_at + 2) {
        let text = &signature[token.start..token.end];
        match token.kind {
            Tok::Other if text == "<" => angle += 1,
            Tok::Other if text == ">" && !signature[..token.start].ends_with('-') => angle -= 1,
            Tok::Open(b'(') if angle == 0 => {
                open = Some(index);
                break;
            }
            _ => {}
        }
    }
    let open = open.ok_or(ScanError::NoParameterList)?;
    let close = partner[open].ok_or(ScanError::Unbalanced("parameter list"))?;
    let mut names = Vec::new();
    let mut k = open + 1;
    while k < close {
        // One parameter: its name, `:`, then its type up to a `,` outside
        // brackets.
        let mut name_tokens = Vec::new();
        while k < close && tokens[k].kind != Tok::Colon {
            name_tokens.push(&signature[tokens[k].start..tokens[k].end]);
            k += 1;
        }
        match name_tokens.as_slice() {
            [name] | ["mut", name]
                if !name.contains(|c: char| !(c.is_alphanumeric() || c == '_')) =>
            {
                names.push((*name).to_string())
            }
            _ => {
                return Err(ScanError::NotPlainName {
                    pattern: name_tokens.join(" "),
                });
            }
        }
        while k < close && tokens[k].kind != Tok::Comma {
            k = match tokens[k].kind {
                Tok::Open(_) => partner[k].ok_or(ScanError::Unbalanced("type"))? + 1,
                _ => k + 1,
            };
        }
        k += 1;
    }
    Ok(names)
}

/// A type parameter of a function's generics.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TypeParameter {
    pub name: String,
    /// Its bounds as written after the `:` (empty when it has none).
    pub bounds: String,
    /// Whether a parameter's type names it, so that a call can infer it.
    pub in_parameters: bool,
}

/// The type parameters of the function `signature` (from `fn` to its
/// body), in order; lifetimes are left out (a call never names them).
/// `const` parameters are an error: no chapter function has one.
pub fn type_parameters(signature: &str) -> Result<Vec<TypeParameter>, ScanError> {
    let tokens = lex(signature)?;
    let partner = match_brackets(signature, &tokens)?;
    let fn_at = tokens
        .iter()
        .position(|t| t.kind == Tok::Word && &signature[t.start..t.end] == "fn")
        .ok_or(ScanError::NoFn)?;
    let text = |index: usize| &signature[tokens[index].start..tokens[index].end];
    let generics_open = fn_at + 2;
    // Each parameter's tokens, split at the commas of the generics' top
    // level; `<>` of a bound (`Fn(u32) -> u32`, `Tracer<C>`) nest.
    let mut params: Vec<Vec<usize>> = Vec::new();
    let mut after_generics = generics_open;
    if tokens
        .get(generics_open)
        .is_some_and(|_| text(generics_open) == "<")
    {
        let mut angle = 0i32;
        let mut current = Vec::new();
        let mut k = generics_open + 1;
        loop {
            let Some(token) = tokens.get(k) else {
                return Err(ScanError::UnclosedGenerics);
            };
            let word = text(k);
            let arrow = signature[..token.start].ends_with('-');
            match token.kind {
                Tok::Other if word == "<" => angle += 1,
                Tok::Other if word == ">" && !arrow && angle == 0 => break,
                Tok::Other if word == ">" && !arrow => angle -= 1,
                Tok::Comma if angle == 0 => {
                    params.push(std::mem::take(&mut current));
                    k += 1;
                    continue;
                }
                Tok::Open(_) => {
                    let close = partner[k].ok_or(ScanError::Unbalanced("generics"))?;
                    current.extend(k..=close);
                    k = close + 1;
                    continue;
                }
                _ => {}
            }
            current.push(k);
            k += 1;
        }
        params.push(current);
        after_generics = k + 1;
    }
    let open = (after_generics..tokens.len())
        .find(|&k| tokens[k].kind == Tok::Open(b'('))
        .ok_or(ScanError::NoParameterList)?;
    let close = partner[open].ok_or(ScanError::Unbalanced("parameter list"))?;
    let mut out = Vec::new();
    for param in params.iter().filter(|param| !param.is_empty()) {
        let first = text(param[0]);
        if first.starts_with('\'') {
            continue;
        }
        if first == "const" {
            return Err(ScanError::ConstGeneric);
        }
        let bounds = match param.iter().position(|&k| tokens[k].kind == Tok::Colon) {
            Some(colon) if colon + 1 < param.len() => signature
                [tokens[param[colon + 1]].start..tokens[*param.last().unwrap_or(&0)].end]
                .to_string(),
            _ => String::new(),
        };
        let in_parameters =
            (open + 1..close).any(|k| tokens[k].kind == Tok::Word && text(k) == first);
        out.push(TypeParameter {
            name: first.to_string(),
            bounds,
            in_parameters,
        });
    }
    Ok(out)
}

/// `text` with every path `crate::` replaced by `raylab::`: the chapter
/// files live inside raylab, where `crate` is raylab, but a workspace's
/// copy lives in the student's crate.
pub fn crate_paths_to_raylab(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(at) = rest.find("crate::") {
        let before = rest[..at].chars().next_back();
        let part_of_word =
            before.is_some_and(|c| c.is_alphanumeric() || c == '_' || c == '$' || c == ':');
        out.push_str(&rest[..at]);
        out.push_str(if part_of_word { "crate::" } else { "raylab::" });
        rest = &rest[at + "crate::".len()..];
    }
    out.push_str(rest);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn kinds_and_names(src: &str) -> Vec<(ItemKind, Option<String>)> {
        items(src)
            .expect("scans")
            .into_iter()
            .map(|item| (item.kind, item.name))
            .collect()
    }

    #[test]
    fn braces_in_strings_chars_and_comments_do_not_count() {
        let src = r####"
/// A brace in a doc comment: {
pub fn a() -> char { let _s = "}{"; let _r = r#"}"}"#; '}' }
/* nested /* } */ still a comment { */
fn b<'a>(x: &'a str) -> &'a str { let _c = '\''; let _d = b'{'; x }
// }
const C: Point = Point { x: 1 };
"####;
        assert_eq!(
            kinds_and_names(src),
            vec![
                (ItemKind::Fn, Some("a".into())),
                (ItemKind::Fn, Some("b".into())),
                (ItemKind::Const, Some("C".into())),
            ]
        );
        let b = &items(src).expect("scans")[1];
        // The block comment before `b` belongs to it; its body is exact.
        assert!(src[b.range.clone()].starts_with("/* nested"));
        let body = b.body.clone().expect("a body");
        assert_eq!(&src[body], "{ let _c = '\\''; let _d = b'{'; x }");
    }

    #[test]
    fn docs_attributes_and_headers() {
        let src = "#![doc = include_str!(\"x.md\")]\n\nuse a::{b, c};\n\n/// Doc.\n#[inline]\npub(crate) const fn f() {}\n\n#[cfg(test)]\nmod tests {\n    fn g() {}\n}\n";
        let found = items(src).expect("scans");
        let kinds: Vec<_> = found.iter().map(|item| item.kind).collect();
        assert_eq!(
            kinds,
            [
                ItemKind::InnerAttribute,
                ItemKind::Use,
                ItemKind::Fn,
                ItemKind::Mod
            ]
        );
        let f = &found[2];
        assert_eq!(f.name.as_deref(), Some("f"));
        assert_eq!(&src[f.header..f.range.end], "pub(crate) const fn f() {}");
        assert_eq!(&src[f.range.start..f.doc_end.expect("doc")], "/// Doc.");
        assert!(f.is_pub(src));
        assert!(src[found[3].range.clone()].starts_with("#[cfg(test)]"));
    }

    #[test]
    fn lifetimes_are_not_characters() {
        let src = "fn f<'a, 'b: 'a>(x: &'a u8, y: &'b u8) -> &'a u8 { 'outer: loop { break 'outer x; } }\nstruct S;";
        assert_eq!(
            kinds_and_names(src),
            vec![
                (ItemKind::Fn, Some("f".into())),
                (ItemKind::Struct, Some("S".into()))
            ]
        );
    }

    #[test]
    fn unbalanced_or_unterminated_text_is_an_error() {
        assert!(items("fn f() { ").is_err());
        assert!(items("fn f() { \"} ").is_err());
        assert!(items("fn f() ) {}").is_err());
        assert!(items("fn f() { /* }").is_err());
        assert!(items("fn f() (}").is_err());
    }

    #[test]
    fn parameter_names_skip_generics_and_tuple_types() {
        let names = parameter_names(
            "fn f<C: Chapters, F: Fn(u32) -> u32>(tracer: &mut Tracer<C>, mut pixel: (u32, u32), seed: u64) -> Vec3",
        )
        .expect("parses");
        assert_eq!(names, ["tracer", "pixel", "seed"]);
        assert_eq!(
            parameter_names("fn g()").expect("parses"),
            Vec::<String>::new()
        );
        assert!(parameter_names("fn h((a, b): (u8, u8))").is_err());
    }

    #[test]
    fn type_parameters_skip_lifetimes_and_say_whether_a_call_infers_them() {
        let found = type_parameters(
            "pub fn f<'a, C: Chapters, F: Fn(u32) -> Vec<u32>>(p: HitPoint<'a>, g: F) -> HitPoint<'a>",
        )
        .expect("parses");
        let summary: Vec<_> = found
            .iter()
            .map(|p| (p.name.as_str(), p.bounds.as_str(), p.in_parameters))
            .collect();
        assert_eq!(
            summary,
            [("C", "Chapters", false), ("F", "Fn(u32) -> Vec<u32>", true)]
        );
        let tracer =
            type_parameters("fn g<C: Chapters>(tracer: &mut Tracer<C>) -> Vec3").expect("parses");
        assert!(tracer[0].in_parameters);
        assert_eq!(type_parameters("fn h(x: u8)").expect("parses"), []);
        assert!(type_parameters("fn k<const N: usize>(x: [u8; N])").is_err());
    }

    #[test]
    fn crate_paths_become_raylab_paths() {
        assert_eq!(
            crate_paths_to_raylab("crate::unit_vector(n); x::crate::y; $crate::z; [`crate::a`]"),
            "raylab::unit_vector(n); x::crate::y; $crate::z; [`raylab::a`]"
        );
    }
}
