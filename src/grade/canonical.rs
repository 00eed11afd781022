//! One spelling for Rust code that says the same thing, before it is
//! fingerprinted for the similarity report.
//!
//! Fingerprints are runs of tokens, so a copy reworded a token at a time
//! (`(2.0)` for `2.0`, `let x: _ =` for `let x =`, `Option::Some(` for
//! `Some(`) breaks every run and shares none. The file is parsed (by
//! `syn`, the parser Rust's procedural macros use) and each such choice
//! of spelling is made one way, the same for every file:
//!
//! - brackets and blocks around a single expression are dropped (`(e)`,
//!   `{ e }`);
//! - a path is its last name, without `<T>::` or turbofish (`Some`, `new`);
//! - `Type::function(a, b)` is `a.function(b)`;
//! - a `let` binding or closure argument loses its type and its `mut`;
//! - a last `return e;` is `e`; `Point { x: x }` is `Point { x }`;
//! - an empty statement (`;;`) is dropped;
//! - attributes are dropped (the tokeniser drops comments already).
//!
//! The canonical form is never compiled or shown: it only needs to be the
//! same for two spellings of one program. What it cannot see through is
//! code that does more, or does it in another order (a no-op statement
//! every few lines, `b * a` for `a * b`): a rewording that changes the
//! program's shape is left to the instructor's eye (docs/instructors.md).

use proc_macro2::TokenStream;
use quote::ToTokens;
use syn::visit_mut::{self, VisitMut};
use syn::{Expr, Pat, Stmt};

/// How deep a file's brackets may nest for it to be parsed. Course code
/// nests about a dozen deep; a deeper file is fingerprinted as written.
pub const PARSED_NESTING: usize = 48;

/// The most tokens of a file that is parsed: `syn`'s parser, the visitor
/// and the syntax tree's drop recurse once or more per level of the tree,
/// and a level can be a token or three (`- - - x`, `Vec<Vec<T>>`), not a
/// bracket. A chapter file of the course holds up to about 8,000.
pub const PARSED_TOKENS: usize = 16_000;

/// The stack the parse runs on. 16,000 levels of the deepest shapes the
/// parser recurses through (nested generics, prefix operators, closures,
/// `else if`) took less, unoptimised (`canonical`'s test builds them).
/// Only what a file's depth needs is touched.
const PARSER_STACK: usize = 1 << 30;

/// `source`'s tokens spelled one way and cut by `flatten`, on a thread
/// with a stack as deep as the parse can need; `None` when the file is
/// not parsed (deeper than [`PARSED_NESTING`], longer than
/// [`PARSED_TOKENS`], not a file `syn` parses, or no thread to spare),
/// for the caller to cut the tokens as written.
pub fn in_one_spelling<T: Send + 'static>(
    source: &str,
    stream: &TokenStream,
    flatten: fn(TokenStream) -> T,
) -> Option<T> {
    let (tokens, depth) = size(stream);
    if depth > PARSED_NESTING || tokens > PARSED_TOKENS {
        return None;
    }
    // Tokens are not `Send`: the thread reads the text again.
    let source = source.to_owned();
    std::thread::Builder::new()
        .name("similarity parse".into())
        .stack_size(PARSER_STACK)
        .spawn(move || {
            let stream = source.parse::<TokenStream>().ok()?;
            parsed(stream).map(flatten)
        })
        .ok()?
        .join()
        .ok()
        .flatten()
}

/// How many tokens `stream` holds, brackets and all, and how deep its
/// brackets nest, counted without recursion.
fn size(stream: &TokenStream) -> (usize, usize) {
    let (mut total, mut deepest) = (0, 0);
    let mut pending = vec![(stream.clone(), 0)];
    while let Some((stream, depth)) = pending.pop() {
        deepest = deepest.max(depth);
        for tree in stream {
            total += 1;
            if let proc_macro2::TokenTree::Group(group) = tree {
                pending.push((group.stream(), depth + 1));
            }
        }
    }
    (total, deepest)
}

/// The canonical tokens of `stream`, or `stream` itself when it is not a
/// Rust file `syn` can parse. (On a small stack, only for small files:
/// see [`in_one_spelling`].)
pub fn canonical(stream: TokenStream) -> TokenStream {
    parsed(stream.clone()).unwrap_or(stream)
}

fn parsed(stream: TokenStream) -> Option<TokenStream> {
    let mut file = syn::parse2::<syn::File>(stream).ok()?;
    file.attrs.clear();
    OneSpelling.visit_file_mut(&mut file);
    Some(file.into_token_stream())
}

struct OneSpelling;

impl VisitMut for OneSpelling {
    fn visit_expr_mut(&mut self, expr: &mut Expr) {
        loop {
            let inner = match expr {
                Expr::Paren(paren) => (*paren.expr).clone(),
                Expr::Group(group) => (*group.expr).clone(),
                Expr::Block(block)
                    if block.label.is_none()
                        && block.block.stmts.len() == 1
                        && matches!(block.block.stmts[0], Stmt::Expr(_, None)) =>
                {
                    match &block.block.stmts[0] {
                        Stmt::Expr(inner, None) => inner.clone(),
                        _ => break,
                    }
                }
                Expr::Call(call) => match method_form(call) {
                    Some(method) => method,
                    None => break,
                },
                _ => break,
            };
            *expr = inner;
        }
        visit_mut::visit_expr_mut(self, expr);
    }

    fn visit_attributes_mut(&mut self, attributes: &mut Vec<syn::Attribute>) {
        attributes.clear();
    }

    fn visit_path_mut(&mut self, path: &mut syn::Path) {
        if let Some(last) = path.segments.pop() {
            let mut last = last.into_value();
            last.arguments = match last.arguments {
                // A type's arguments are part of what it is (`Option<f32>`);
                // a turbofish only repeats what inference knows.
                syn::PathArguments::AngleBracketed(arguments)
                    if arguments.colon2_token.is_none() =>
                {
                    syn::PathArguments::AngleBracketed(arguments)
                }
                syn::PathArguments::Parenthesized(arguments) => {
                    syn::PathArguments::Parenthesized(arguments)
                }
                _ => syn::PathArguments::None,
            };
            path.segments.clear();
            path.segments.push(last);
        }
        path.leading_colon = None;
        visit_mut::visit_path_mut(self, path);
    }

    fn visit_expr_path_mut(&mut self, path: &mut syn::ExprPath) {
        path.qself = None;
        visit_mut::visit_expr_path_mut(self, path);
    }

    fn visit_type_path_mut(&mut self, path: &mut syn::TypePath) {
        path.qself = None;
        visit_mut::visit_type_path_mut(self, path);
    }

    fn visit_pat_struct_mut(&mut self, pattern: &mut syn::PatStruct) {
        pattern.qself = None;
        visit_mut::visit_pat_struct_mut(self, pattern);
    }

    fn visit_pat_tuple_struct_mut(&mut self, pattern: &mut syn::PatTupleStruct) {
        pattern.qself = None;
        visit_mut::visit_pat_tuple_struct_mut(self, pattern);
    }

    fn visit_expr_method_call_mut(&mut self, call: &mut syn::ExprMethodCall) {
        call.turbofish = None;
        visit_mut::visit_expr_method_call_mut(self, call);
    }

    fn visit_local_mut(&mut self, local: &mut syn::Local) {
        untyped(&mut local.pat);
        visit_mut::visit_local_mut(self, local);
    }

    fn visit_expr_closure_mut(&mut self, closure: &mut syn::ExprClosure) {
        closure.inputs.iter_mut().for_each(untyped);
        closure.output = syn::ReturnType::Default;
        visit_mut::visit_expr_closure_mut(self, closure);
    }

    fn visit_block_mut(&mut self, block: &mut syn::Block) {
        // An empty statement (`;;`) is nothing: syn keeps each as an empty
        // expression with its `;`.
        block.stmts.retain(|statement| {
            !matches!(statement, Stmt::Expr(Expr::Verbatim(tokens), Some(_)) if tokens.is_empty())
        });
        if let Some(Stmt::Expr(Expr::Return(last), Some(_))) = block.stmts.last() {
            if let Some(value) = &last.expr {
                let value = (**value).clone();
                block.stmts.pop();
                block.stmts.push(Stmt::Expr(value, None));
            }
        }
        visit_mut::visit_block_mut(self, block);
    }

    fn visit_field_value_mut(&mut self, field: &mut syn::FieldValue) {
        visit_mut::visit_field_value_mut(self, field);
        if let (syn::Member::Named(name), Expr::Path(value)) = (&field.member, &field.expr) {
            if value.path.is_ident(name) {
                field.colon_token = None;
            }
        }
    }
}

/// A pattern of a binding, without its type or `mut`.
fn untyped(pattern: &mut Pat) {
    if let Pat::Type(typed) = pattern {
        *pattern = (*typed.pat).clone();
    }
    if let Pat::Ident(binding) = pattern {
        binding.mutability = None;
    }
}

/// `Type::method(first, rest...)` as `first.method(rest...)`, when the
/// call's function is a path of more than one name, its last in lower
/// case (a function, not a tuple struct or variant such as
/// `Option::Some`), and it has arguments.
fn method_form(call: &syn::ExprCall) -> Option<Expr> {
    let Expr::Path(function) = &*call.func else {
        return None;
    };
    if function.path.segments.len() < 2 && function.qself.is_none() {
        return None;
    }
    let method = function.path.segments.last()?.ident.clone();
    if method
        .to_string()
        .starts_with(|first: char| first.is_uppercase())
    {
        return None;
    }
    let mut arguments = call.args.iter().cloned();
    let receiver = arguments.next()?;
    Some(Expr::MethodCall(syn::ExprMethodCall {
        attrs: Vec::new(),
        receiver: Box::new(receiver),
        dot_token: Default::default(),
        method,
        turbofish: None,
        paren_token: call.paren_token,
        args: arguments.collect(),
    }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::str::FromStr;

    fn spelled(source: &str) -> String {
        canonical(TokenStream::from_str(source).expect("Rust tokens")).to_string()
    }

    /// Each rewording the tokens alone are fooled by reads as the plain
    /// spelling.
    #[test]
    fn rewordings_of_one_program_read_the_same() {
        let pairs = [
            (
                "fn f() { let x = 2.0 * a; }",
                "fn f() { let x: _ = (2.0) * (a); }",
            ),
            (
                "fn f() { let x = 1; }",
                "fn f() { let mut x: f32 = { 1 }; }",
            ),
            (
                "fn f() -> Option<f32> { Some(t) }",
                "fn f() -> Option<f32> { Option::Some(t) }",
            ),
            (
                "fn f() { Vec3::new(1.0, 2.0, 3.0) }",
                "fn f() { <Vec3>::new(1.0, 2.0, 3.0) }",
            ),
            ("fn f() { a.dot(b) }", "fn f() { glam::Vec3::dot(a, b) }"),
            (
                "fn f() { v.iter().collect() }",
                "fn f() { v.iter().collect::<Vec<_>>() }",
            ),
            ("fn f() -> f32 { t }", "fn f() -> f32 { return t; }"),
            ("fn f() { Hit { t } }", "fn f() { Hit { t: t } }"),
            (
                "fn f() { xs.map(|x| x + 1.0) }",
                "fn f() { xs.map(|x: f32| -> f32 { x + 1.0 }) }",
            ),
            ("fn f() { }", "#[inline] #[allow(unused)] fn f() { }"),
            (
                "fn f() { let a = 1; g(a); a }",
                "fn f() { let a = 1;; g(a);;; a }",
            ),
            (
                "fn f() { match o { Some(x) => x, None => 0 } }",
                "fn f() { match o { ::std::option::Option::Some(x) => x, Option::None => 0 } }",
            ),
        ];
        for (plain, reworded) in pairs {
            assert_eq!(spelled(plain), spelled(reworded), "{reworded}");
        }
    }

    /// Code that does something else stays different.
    #[test]
    fn different_programs_stay_different() {
        assert_ne!(spelled("fn f() { a + b }"), spelled("fn f() { a - b }"));
        assert_ne!(
            spelled("fn f() { a.dot(b) }"),
            spelled("fn f() { a.cross(b) }")
        );
        assert_ne!(
            spelled("fn f() -> Option<f32> { None }"),
            spelled("fn f() -> Vec<f32> { None }")
        );
    }

    /// A file too deep or too long to parse safely, or not a Rust file,
    /// is left to be cut as written.
    #[test]
    fn what_cannot_be_parsed_is_kept_as_it_is() {
        let cut = |source: &str| {
            let stream = TokenStream::from_str(source).expect("Rust tokens");
            in_one_spelling(source, &stream, |stream| stream.to_string())
        };
        let deep = format!("const _: () = {}{};", "(".repeat(200), ")".repeat(200));
        assert_eq!(cut(&deep), None);
        assert_eq!(cut("let x = 1;"), None);
        let long = format!("fn f() {{ x{} }}", " + x".repeat(PARSED_TOKENS / 2));
        assert_eq!(cut(&long), None);
        assert_eq!(cut("fn f() { (1) }"), Some(spelled("fn f() { 1 }")));
    }

    /// The deepest shapes the parser recurses through, each as deep as
    /// [`PARSED_TOKENS`] allows, parse on the thread's stack (an overflow
    /// would abort the grader, not fail a test).
    #[test]
    fn the_deepest_files_parsed_fit_the_parsers_stack() {
        let levels = PARSED_TOKENS - 10;
        let shapes = [
            format!("fn f() {{ {}x }}", "- ".repeat(levels)),
            format!("fn f() {{ {}x }}", "|| ".repeat(levels / 2)),
            format!("fn f() {{ {}x }}", "& ".repeat(levels)),
            format!("fn f() {{ {}x }}", "return ".repeat(levels)),
            format!(
                "fn f() -> {}T{} {{}}",
                "Vec<".repeat(levels / 3),
                ">".repeat(levels / 3)
            ),
            format!(
                "fn f() {{ if a {{}}{} }}",
                " else if a {}".repeat(levels / 4)
            ),
            format!("fn f() {{ x{} }}", ".m()".repeat(levels / 3)),
            format!("fn f() {{ x{} }}", " as f32".repeat(levels / 2)),
            format!("fn f() -> {}T {{}}", "& ".repeat(levels)),
            format!("fn f() {{ let {}x = y; }}", "& ".repeat(levels)),
            format!(
                "fn f() -> {}T{} {{}}",
                "Box<dyn Fn() -> ".repeat(levels / 8),
                ">".repeat(levels / 8)
            ),
            format!("fn f() {{ {}x }}", "* ".repeat(levels)),
        ];
        for source in shapes {
            let stream = TokenStream::from_str(&source).expect("Rust tokens");
            assert!(size(&stream).0 <= PARSED_TOKENS, "{:?}", size(&stream));
            let kept = in_one_spelling(&source, &stream, |stream| stream.into_iter().count());
            assert!(kept.is_some(), "{}", &source[..40]);
        }
    }
}
