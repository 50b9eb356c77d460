//! Error recovery: after a syntax error, the declarations before it are kept and
//! parsing resumes at the next line that starts a top-level declaration, so
//! independent mistakes are all reported and the rest of the file is still resolved.
//!
//! A line "starts a declaration" if, after its indentation, it begins with a top-level
//! keyword and either sits in column 0 or lies outside every `{ }` block (counted from
//! the broken declaration). The block test keeps `hand sah` inside a robot block from
//! being mistaken for a hand declaration.

use super::ast::File;
use super::parser::parse_all;
use super::SyntaxError;
use crate::diag::{FileId, Located, Span};

/// Most syntax errors reported for one file; after that the rest is likely noise.
const MAX_SYNTAX_ERRORS: usize = 20;

const KEYWORDS: [&str; 8] = ["scenario", "use", "hand", "robot", "fixed", "object", "planner", "target"];

/// Parses one file, recovering after errors: the declarations that parsed, and the errors.
pub fn parse_recovering(file: FileId, text: &str) -> (File, Vec<SyntaxError>) {
    let whole = Span::new(file, 0, text.len());
    // Most files parse: recording what pest expected at every token costs half a parse
    // and is needed only for the messages of one that does not. The setting is pest's,
    // one for the process: held while parsing, so that a file parsed on another thread
    // cannot turn it off under a failing one's messages.
    let _detail = DETAIL.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
    pest::set_error_detail(false);
    if let Ok(items) = parse_all(file, text) {
        return (File { items, span: whole }, Vec::new());
    }
    // Makes pest record the literal tokens (`(`, `,`, `}`) it expected, for the message.
    pest::set_error_detail(true);
    let mut errors = Vec::new();
    let mut items = Vec::new();
    let mut start = 0;
    loop {
        match parse_all(file, &masked(text, start, text.len())) {
            Ok(rest) => {
                items.extend(rest);
                break;
            }
            Err(e) => {
                let pos = e.primary_span().map_or(text.len(), |s| s.start as usize).clamp(start, text.len());
                let starts = declaration_lines(text, start);
                // The broken declaration starts at the last declaration line at or before the error.
                let cut = starts.iter().copied().rfind(|&s| s <= pos).unwrap_or(start);
                if cut > start {
                    // What precedes it parsed up to the error, so normally parses alone.
                    if let Ok(before) = parse_all(file, &masked(text, start, cut)) {
                        items.extend(before);
                    }
                }
                errors.push(e);
                let line_end = text.get(pos..).and_then(|t| t.find('\n')).map_or(text.len(), |i| pos + i);
                let next = declaration_lines(text, cut).into_iter().find(|&s| s > line_end);
                match next {
                    Some(next) if errors.len() < MAX_SYNTAX_ERRORS => start = next,
                    _ => break,
                }
            }
        }
    }
    (File { items, span: whole }, errors)
}

/// Held while a file is parsed (see [`parse_recovering`]).
static DETAIL: std::sync::Mutex<()> = std::sync::Mutex::new(());

/// `text` with everything outside `from..to` blanked, keeping byte offsets (and line
/// numbers) intact.
fn masked(text: &str, from: usize, to: usize) -> String {
    if from == 0 && to >= text.len() {
        return text.to_string();
    }
    text.char_indices()
        .map(|(i, c)| if (from..to).contains(&i) || c == '\n' { c.to_string() } else { " ".repeat(c.len_utf8()) })
        .collect()
}

/// Starts of the lines after `from` (and `from` itself) that start a declaration, in order.
fn declaration_lines(text: &str, from: usize) -> Vec<usize> {
    let mut out = Vec::new();
    let mut depth: i64 = 0;
    let mut at = from;
    while at < text.len() {
        let end = text[at..].find('\n').map_or(text.len(), |i| at + i);
        let line = &text[at..end];
        let body = line.trim_start_matches([' ', '\t']);
        let keyword = KEYWORDS.iter().any(|k| {
            body.strip_prefix(k).is_some_and(|rest| !rest.starts_with(|c: char| c.is_ascii_alphanumeric() || c == '_'))
        });
        if keyword && (body.len() == line.len() || depth <= 0) {
            out.push(at);
        }
        depth += brace_balance(line);
        at = end + 1;
    }
    out
}

/// `{` minus `}` on one line, outside strings and comments.
fn brace_balance(line: &str) -> i64 {
    let (mut n, mut in_string, mut escaped) = (0, false, false);
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            _ if escaped => escaped = false,
            '\\' if in_string => escaped = true,
            '"' => in_string = !in_string,
            '/' if !in_string && chars.peek() == Some(&'/') => break,
            '{' if !in_string => n += 1,
            '}' if !in_string => n -= 1,
            _ => {}
        }
    }
    n
}

/// Parses one file; on failure returns its syntax errors (see [`parse_recovering`]).
pub fn parse(file: FileId, text: &str) -> Result<File, Vec<SyntaxError>> {
    let (f, errors) = parse_recovering(file, text);
    if errors.is_empty() {
        Ok(f)
    } else {
        Err(errors)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::syntax::ast::Item;

    #[test]
    fn restarts_at_indented_declarations_outside_blocks() {
        let text = "robot r {\n  hand h\n}\n  object o sphere(radius: 1cm)\n";
        assert_eq!(declaration_lines(text, 0), [0, 21]);
    }

    #[test]
    fn keeps_declarations_around_an_error() {
        let text = "object a sphere(radius: 1cm)\nobject b sphere(radius: )\n  object c sphere(radius: 1cm)\n";
        let (f, errs) = parse_recovering(FileId(0), text);
        assert_eq!(errs.len(), 1);
        let names: Vec<&str> = f
            .items
            .iter()
            .filter_map(|i| if let Item::Body(b) = i { Some(b.name.name.as_str()) } else { None })
            .collect();
        assert_eq!(names, ["a", "c"]);
    }

    /// A file that fails lists what was expected (pest's detail) after good files were
    /// parsed (without it), also with good files parsed on other threads at the time (a
    /// race the lock prevents; these threads need not hit it to pass).
    #[test]
    fn a_failing_file_says_what_was_expected_while_others_parse() {
        let good = "object a sphere(radius: 1cm)\n";
        let bad = "object b sphere(radius: 1cm\n";
        let message = || format!("{:?}", parse_recovering(FileId(0), bad).1);
        let alone = message();
        assert!(alone.contains("`)`"), "{alone}");
        let (alone, message) = (&alone, &message);
        std::thread::scope(|s| {
            for k in 0..4 {
                s.spawn(move || {
                    for _ in 0..100 {
                        match k % 2 {
                            0 => assert!(parse_recovering(FileId(0), good).1.is_empty()),
                            _ => assert_eq!(&message(), alone),
                        }
                    }
                });
            }
        });
    }
}
