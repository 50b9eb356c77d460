//! pest's "expected one of these rules" -> a [`SyntaxError`] a person can act on: rule
//! names become words, literal tokens are added from pest's parse attempts, and a few
//! common slips (a space before a unit, an unknown shape, an open string) get a hint.

use super::parser::Rule;
use super::SyntaxError;
use crate::diag::{FileId, Span};

/// What a user would call the thing a rule matches.
fn describe(r: Rule) -> &'static str {
    match r {
        Rule::EOI => "the end of the file",
        Rule::scenario_decl | Rule::k_scenario => "`scenario`",
        Rule::use_decl | Rule::k_use => "`use`",
        Rule::hand_decl | Rule::k_hand | Rule::hand_stmt => "`hand`",
        Rule::robot_decl | Rule::k_robot => "`robot`",
        Rule::body_decl | Rule::body_kind => "`fixed` or `object`",
        Rule::planner_decl | Rule::k_planner => "`planner`",
        Rule::target_decl | Rule::k_target => "`target`",
        Rule::urdf_stmt | Rule::k_urdf => "`urdf`",
        Rule::tcp_stmt | Rule::k_tcp => "`tcp`",
        Rule::base_stmt | Rule::k_base => "`base`",
        Rule::flange_stmt | Rule::k_flange => "`flange`",
        Rule::srdf_stmt | Rule::k_srdf => "`srdf`",
        Rule::home_stmt | Rule::k_home => "`home`",
        Rule::drop_stmt | Rule::k_drop => "`drop`",
        Rule::open_stmt | Rule::k_open => "`open`",
        Rule::closed_stmt | Rule::k_closed => "`closed`",
        Rule::contact_stmt | Rule::k_allow_contact => "`allow_contact`",
        Rule::body_block => "a `{` block of shapes and grasps",
        Rule::part | Rule::shape | Rule::shape_kind => "a shape (box, cylinder, capsule, sphere, mesh)",
        Rule::arg => "a shape argument (a quantity, `name: quantity` or a \"string\")",
        Rule::scale | Rule::k_scale => "`scale`",
        Rule::grasp | Rule::k_grasp => "`grasp`",
        Rule::approach | Rule::k_approach => "`approach`",
        Rule::width | Rule::k_width => "`width`",
        Rule::repeat | Rule::k_repeat => "`repeat`",
        Rule::k_about => "`about`",
        Rule::axis => "an axis (x, y or z)",
        Rule::for_hands | Rule::k_for => "`for`",
        Rule::planner_entry => "a planner setting (`key value`)",
        Rule::pose | Rule::k_at => "`at`",
        Rule::k_rot => "`rot`",
        Rule::quat | Rule::k_quat => "`quat(x, y, z, w)`",
        Rule::tuple => "a tuple like `(x, y, z)`",
        Rule::list => "a list of joint values like `[0, 90deg]`",
        Rule::quantity | Rule::number => "a number",
        Rule::unit => "a unit",
        Rule::string | Rule::string_raw => "a \"string\"",
        Rule::ident => "a name",
        Rule::file | Rule::item => "a declaration (scenario, use, hand, robot, fixed, object, planner, target)",
        // Silent rules never show up in errors; keep the match exhaustive anyway.
        _ => "something else",
    }
}

/// Top-level declarations are listed as one item, not seven.
fn collapse(words: &mut Vec<String>) {
    let top = ["`scenario`", "`use`", "`robot`", "`fixed` or `object`", "`planner`", "`target`"];
    if top.iter().all(|t| words.iter().any(|w| w == t)) {
        words.retain(|w| !top.contains(&w.as_str()) && w != "`hand`");
        words.insert(0, "a declaration (scenario, use, hand, robot, fixed, object, planner, target)".to_string());
    }
}

pub(super) fn convert_error(file: FileId, text: &str, e: &pest::error::Error<Rule>) -> SyntaxError {
    let mut pos = match e.location {
        pest::error::InputLocation::Pos(p) => p,
        pest::error::InputLocation::Span((s, _)) => s,
    };
    let mut words: Vec<String> = Vec::new();
    if let pest::error::ErrorVariant::ParsingError { positives, .. } = &e.variant {
        for r in positives {
            let w = describe(*r).to_string();
            if !words.contains(&w) {
                words.push(w);
            }
        }
    }
    // Rules do not list punctuation; the parse attempts do, sometimes further on (after
    // skipping whitespace), where the real mistake is.
    if let Some(attempts) = e.parse_attempts() {
        let punct: Vec<String> = attempts
            .expected_tokens()
            .iter()
            .map(|t| t.to_string())
            .filter(|t| !t.is_empty() && t != "//" && t.chars().all(|c| c.is_ascii_punctuation()))
            .map(|t| format!("`{t}`"))
            .collect();
        if attempts.max_position > pos && !punct.is_empty() {
            pos = attempts.max_position;
            words.clear();
        }
        if attempts.max_position == pos {
            for w in punct {
                if !words.contains(&w) {
                    words.push(w);
                }
            }
        }
    }
    // The first characters of a number, string or name are that rule's business, not
    // tokens worth listing next to it: `a number` covers `+`, `-` and `.`.
    for (rule_word, firsts) in
        [("a number", &["`+`", "`-`", "`.`"][..]), ("a \"string\"", &["`\"`"]), ("a name", &["`_`"])]
    {
        if words.iter().any(|w| w == rule_word) {
            words.retain(|w| !firsts.contains(&w.as_str()));
        }
    }
    // `_` shows up because a name could continue; that is never what the user missed.
    if words.len() > 1 {
        words.retain(|w| w != "`_`");
    }
    // A unit can always follow a number; saying so only helps when nothing else fits.
    if words.len() > 1 {
        words.retain(|w| w != "a unit");
    }
    // `(` is how a tuple starts, and so on: say it once.
    for (rule_word, punct) in [("tuple", "`(`"), ("list of joint", "`[`"), ("block", "`{`")] {
        if words.iter().any(|w| w.contains(rule_word)) {
            words.retain(|w| w != punct);
        }
    }
    collapse(&mut words);
    // The most specific expectations first; "a declaration" and "the end of the file" last.
    words.sort_by_key(|w| w.starts_with("a declaration") || w.starts_with("the end"));
    let mut pos = pos.min(text.len());
    // In `box(NaN, 1, 1)` the grammar reads `NaN` as an argument's name and stops at the
    // `,` for want of a `:`; the mistake is the word, a number that is not finite.
    if words.iter().any(|w| w == "`:`") {
        if let Some(start) = non_finite_word_before(text, pos) {
            pos = start;
            words = vec!["a number".to_string()];
        }
    }
    let (found, found_span) = token_at(text, pos);
    // At the end of the file, point at the last character so the report shows a line.
    let at_end = found.is_empty();
    let (pos, found_span) = if at_end {
        let last = text.trim_end().char_indices().next_back().map_or(0, |(i, _)| i);
        (last, text[last..].chars().next().map_or(0, char::len_utf8))
    } else {
        (pos, found_span)
    };
    let after = text.get(pos + found_span..).unwrap_or("");
    let mut expected = join_or(&words);
    if expected.is_empty() {
        expected = "something else".to_string();
    }
    let raw = text.get(..pos).unwrap_or("");
    let trimmed = raw.trim_end_matches([' ', '\t']);
    let spaced_number = trimmed.len() < raw.len() && trimmed.ends_with(|c: char| c.is_ascii_digit());
    let in_string = open_string_before(text, pos);
    let help = hint(&found, spaced_number, &words, after, in_string);
    let label = if at_end {
        "the file ends after this".to_string()
    } else if expected.len() <= 40 {
        format!("expected {expected}")
    } else {
        "unexpected here".to_string()
    };
    // Only where the block surely ended (the file did, or a new declaration starts):
    // elsewhere a `}` is merely one of the things that could come next.
    let starts_declaration =
        ["scenario", "use", "robot", "fixed", "object", "planner", "target"].contains(&found.as_str());
    let open_brace = if words.iter().any(|w| w == "`}`") && (at_end || starts_declaration) {
        unclosed_brace_before(text, pos)
    } else {
        None
    };
    SyntaxError::Expected {
        expected,
        found: describe_found(&found),
        span: Span::new(file, pos, pos + found_span),
        label,
        open_brace: open_brace.map(|b| Span::new(file, b, b + 1)),
        help,
    }
}

/// The innermost `{` left open before `pos`, strings and comments aside.
fn unclosed_brace_before(text: &str, pos: usize) -> Option<usize> {
    let before = text.get(..pos)?;
    let mut open = Vec::new();
    let mut chars = before.char_indices().peekable();
    while let Some((i, c)) = chars.next() {
        match c {
            '{' => open.push(i),
            '}' => {
                open.pop();
            }
            '"' => {
                // To the closing quote or the end of the line, escapes skipped.
                while let Some((_, c)) = chars.next() {
                    match c {
                        '\\' => {
                            chars.next();
                        }
                        '"' | '\n' => break,
                        _ => {}
                    }
                }
            }
            '/' if chars.peek().is_some_and(|&(_, n)| n == '/') => {
                for (_, c) in chars.by_ref() {
                    if c == '\n' {
                        break;
                    }
                }
            }
            _ => {}
        }
    }
    open.pop()
}

/// Where the word right before `pos` (spaces aside) starts, if it is `nan`, `inf` or
/// `infinity` in any case.
fn non_finite_word_before(text: &str, pos: usize) -> Option<usize> {
    let before = text.get(..pos)?.trim_end_matches([' ', '\t']);
    let start = before.rfind(|c: char| !(c.is_ascii_alphanumeric() || c == '_')).map_or(0, |i| i + 1);
    is_non_finite(&before[start..]).then_some(start)
}

fn is_non_finite(word: &str) -> bool {
    ["nan", "inf", "infinity"].contains(&word.to_ascii_lowercase().trim_start_matches(['+', '-']))
}

/// True if the line up to `pos` holds a `"` that is not closed: the parser stopped inside a string.
fn open_string_before(text: &str, pos: usize) -> bool {
    let before = text.get(..pos).unwrap_or("");
    let line = &before[before.rfind('\n').map_or(0, |i| i + 1)..];
    let (mut open, mut escaped) = (false, false);
    for c in line.chars() {
        match c {
            _ if escaped => escaped = false,
            '\\' if open => escaped = true,
            '"' => open = !open,
            _ => {}
        }
    }
    open
}

fn hint(found: &str, spaced_number: bool, words: &[String], after: &str, in_string: bool) -> Option<String> {
    let unterminated = found.strip_prefix('"').is_some_and(|rest| !rest.contains('"'));
    if unterminated || (in_string && words.iter().any(|w| w == "`\"`")) {
        return Some("a string must end with `\"` on the same line".to_string());
    }
    if is_non_finite(found) && words.iter().any(|w| w == "a number") {
        return Some("non-finite numbers (nan, inf) are not allowed; write a finite quantity like `3cm`".to_string());
    }
    if found == "=" {
        return Some("planner settings are written `key value`, without `=`: `seed 3`".to_string());
    }
    if let Some(c) = found.chars().next().filter(|c| !c.is_ascii() && c.is_alphanumeric()) {
        return Some(format!("names are ASCII letters, digits and `_`; `{c}` is not one of them"));
    }
    let is_word = found.chars().next().is_some_and(|c| c.is_alphabetic() || c == '_');
    if is_word && after.starts_with('(') && words.iter().any(|w| w.starts_with("a shape")) {
        let shapes = ["box", "cylinder", "capsule", "sphere", "mesh"];
        let close = super::did_you_mean(found, shapes);
        return Some(match close {
            Some(s) => format!("did you mean `{s}`? The shapes are box, cylinder, capsule, sphere and mesh"),
            None => "the shapes are box, cylinder, capsule, sphere and mesh".to_string(),
        });
    }
    if spaced_number && matches!(found, "m" | "cm" | "mm" | "deg" | "rad" | "s" | "ms") {
        return Some("a unit goes right after its number, without a space: `16cm`".to_string());
    }
    None
}

fn join_or(words: &[String]) -> String {
    match words {
        [] => String::new(),
        [one] => one.clone(),
        [init @ .., last] => format!("{} or {}", init.join(", "), last),
    }
}

/// The token starting at `pos`, for "found ..." and the label width.
fn token_at(text: &str, pos: usize) -> (String, usize) {
    let rest = text.get(pos..).unwrap_or("");
    let mut chars = rest.char_indices();
    let Some((_, first)) = chars.next() else { return (String::new(), 0) };
    let len = if first.is_alphanumeric() || first == '_' || first == '.' {
        rest.find(|c: char| !(c.is_alphanumeric() || c == '_' || c == '.')).unwrap_or(rest.len())
    } else if first == '"' {
        rest[1..].find(['"', '\n']).map_or(rest.len(), |i| i + 2).min(rest.len())
    } else {
        first.len_utf8()
    };
    let len = len.min(40);
    // Keep the cut on a char boundary.
    let mut cut = len;
    while cut > 0 && !rest.is_char_boundary(cut) {
        cut -= 1;
    }
    (rest[..cut].to_string(), cut)
}

fn describe_found(tok: &str) -> String {
    match tok.chars().next() {
        None => "the end of the file".to_string(),
        Some('\n') => "the end of the line".to_string(),
        Some(c) if c.is_ascii_digit() => format!("the number `{tok}`"),
        Some(c) if c.is_alphabetic() || c == '_' => format!("`{tok}`"),
        Some('"') => format!("the string {tok}"),
        Some(c) if c.is_control() => format!("the control character U+{:04X}", c as u32),
        Some(_) => format!("`{tok}`"),
    }
}
