//! Near misses of names: the edit distance behind "did you mean `lanes`?" (unknown keys and
//! vertex params, E0112) and the scenario's unknown waypoints (S0201).

/// Optimal string alignment distance (Levenshtein plus adjacent transpositions).
pub fn edit_distance(a: &str, b: &str) -> usize {
    let a: Vec<char> = a.chars().collect();
    let b: Vec<char> = b.chars().collect();
    let mut d = vec![vec![0usize; b.len() + 1]; a.len() + 1];
    for (i, row) in d.iter_mut().enumerate() {
        row[0] = i;
    }
    for (j, cell) in d[0].iter_mut().enumerate() {
        *cell = j;
    }
    for i in 1..=a.len() {
        for j in 1..=b.len() {
            let cost = usize::from(a[i - 1] != b[j - 1]);
            let mut v = (d[i - 1][j] + 1)
                .min(d[i][j - 1] + 1)
                .min(d[i - 1][j - 1] + cost);
            if i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] {
                v = v.min(d[i - 2][j - 2] + 1);
            }
            d[i][j] = v;
        }
    }
    d[a.len()][b.len()]
}

/// The known name `word` is probably a misspelling of: within one edit for short names,
/// two for names of more than five characters (case ignored). Ties go to the first listed.
pub fn closest<'k>(word: &str, known: &[&'k str]) -> Option<&'k str> {
    // Bounded: keys are short, and a long unknown key is no typo of a short one.
    if word.chars().count() > 64 {
        return None;
    }
    let lower = word.to_lowercase();
    let limit = if lower.chars().count() > 5 { 2 } else { 1 };
    known
        .iter()
        .map(|k| (edit_distance(&lower, k), *k))
        .filter(|(d, _)| *d <= limit)
        .min_by_key(|(d, _)| *d)
        .map(|(_, k)| k)
}

/// The candidate nearest to `word` (fewest edits, case ignored; ties to the first), however
/// far, for messages that name the closest existing name.
pub fn nearest<'c>(word: &str, candidates: impl IntoIterator<Item = &'c str>) -> Option<&'c str> {
    let lower = word.to_lowercase();
    candidates
        .into_iter()
        .map(|c| (edit_distance(&lower, &c.to_lowercase()), c))
        .min_by_key(|(d, _)| *d)
        .map(|(_, c)| c)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distances_and_matches() {
        assert_eq!(edit_distance("lane", "lanes"), 1);
        assert_eq!(edit_distance("is_chrager", "is_charger"), 1);
        assert_eq!(closest("lane", &["levels", "lanes"]), Some("lanes"));
        assert_eq!(closest("vendor_notes", &["lanes", "walls"]), None);
        assert_eq!(
            nearest("lobyy", ["ward_a", "lobby", "pharmacy"]),
            Some("lobby")
        );
    }
}
