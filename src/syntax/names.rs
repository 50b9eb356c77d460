//! Did-you-mean suggestions by edit distance (shared by the syntax and resolve phases).

/// Names longer than this are not compared: no one misspells a 64-character name by
/// one letter and wants it guessed, and comparing is quadratic in the length.
const MAX_COMPARED_CHARS: usize = 64;

/// The closest candidate to `name`, if it is close enough to be a likely typo.
pub fn did_you_mean<'a>(name: &str, candidates: impl IntoIterator<Item = &'a str>) -> Option<&'a str> {
    let n = name.chars().count();
    if n > MAX_COMPARED_CHARS {
        return None;
    }
    let limit = (n / 3).clamp(1, 3);
    candidates
        .into_iter()
        // Lengths that differ by more than the limit cannot be within it; this also
        // skips every over-long candidate cheaply (`len` is bytes, an upper bound on chars).
        .filter(|c| c.len() <= MAX_COMPARED_CHARS * 4 && c.chars().count().abs_diff(n) <= limit)
        .map(|c| (levenshtein(name, c), c))
        .filter(|(d, _)| *d <= limit)
        .min_by_key(|(d, c)| (*d, *c))
        .map(|(_, c)| c)
}

/// Edit distance counting a swap of two neighbouring characters as one edit
/// (optimal string alignment), since `sha` for `sah` is one slip of the fingers.
/// Keeps three rows, not the whole table, so memory is linear in `b`'s length.
fn levenshtein(a: &str, b: &str) -> usize {
    let a: Vec<char> = a.chars().collect();
    let b: Vec<char> = b.chars().collect();
    let mut prev2 = vec![0usize; b.len() + 1];
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    let mut cur = vec![0usize; b.len() + 1];
    for i in 1..=a.len() {
        cur[0] = i;
        for j in 1..=b.len() {
            let cost = usize::from(a[i - 1] != b[j - 1]);
            let mut v = (prev[j] + 1).min(cur[j - 1] + 1).min(prev[j - 1] + cost);
            if i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] {
                v = v.min(prev2[j - 2] + 1);
            }
            cur[j] = v;
        }
        std::mem::swap(&mut prev2, &mut prev);
        std::mem::swap(&mut prev, &mut cur);
    }
    prev[b.len()]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn suggests_close_names() {
        assert_eq!(levenshtein("kitten", "sitting"), 3);
        assert_eq!(levenshtein("ca", "abc"), 3);
        assert_eq!(levenshtein("abcd", "acbd"), 1);
        assert_eq!(did_you_mean("lidd", ["lid", "can"]), Some("lid"));
        assert_eq!(did_you_mean("xyz", ["lid", "can"]), None);
        assert_eq!(did_you_mean("sha", ["sah", "sdh2"]), Some("sah"));
        assert_eq!(levenshtein("", "abc"), 3);
        assert_eq!(levenshtein("abc", ""), 3);
    }

    #[test]
    fn long_names_are_cheap() {
        let long = "a".repeat(100_000);
        let typo = format!("{}b", "a".repeat(99_999));
        let t = std::time::Instant::now();
        assert_eq!(did_you_mean(&typo, [long.as_str()]), None);
        assert_eq!(did_you_mean("aaa", [long.as_str()]), None);
        assert!(t.elapsed().as_secs_f64() < 0.5);
    }
}
