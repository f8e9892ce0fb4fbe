//! The known name closest to a mistyped one, for the "did you mean" of every crate's errors
//! (technique, scene, view, preset, config key). It lives in the lowest crate so the scene and
//! AO crates and the app share one rule.
//! Invariant: a suggestion is within an edit distance of about half the candidate's length
//! (at least 2), so an unrelated word suggests nothing rather than something arbitrary.

/// The candidate closest to `word` by Levenshtein distance, if any is reasonably close (ties:
/// the first in alphabetical order).
pub fn nearest_name<'a>(
    word: &str,
    candidates: impl IntoIterator<Item = &'a str>,
) -> Option<&'a str> {
    candidates
        .into_iter()
        .map(|c| (strsim::levenshtein(word, c), c))
        .filter(|(d, c)| *d <= (c.len().max(3) / 2).max(2))
        .min()
        .map(|(_, c)| c)
}

/// " (did you mean `x`?)" for the nearest candidate, or "" when none is close.
pub fn did_you_mean<'a>(word: &str, candidates: impl IntoIterator<Item = &'a str>) -> String {
    nearest_name(word, candidates).map_or_else(String::new, |n| format!(" (did you mean `{n}`?)"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_typo_suggests_the_closest_name_and_an_unrelated_word_nothing() {
        let known = ["ssao", "hbao", "gtao", "mssao", "pyramid-hbao"];
        assert_eq!(nearest_name("ssoa", known), Some("ssao"));
        assert_eq!(nearest_name("pyramid_hbao", known), Some("pyramid-hbao"));
        assert_eq!(nearest_name("mssa", known), Some("mssao"));
        assert_eq!(nearest_name("raytracing", known), None);
        assert_eq!(
            did_you_mean("outsde", ["outside", "default"]),
            " (did you mean `outside`?)"
        );
        assert_eq!(did_you_mean("zzzzzz", ["outside"]), "");
    }
}
