//! The levels of a large map lowered on two threads.
//!
//! Why: lowering (every element's parameters, numbers and names) takes about as long as
//! reading the YAML (hotel: 0.45 ms of a 7 ms first compile), and ran on one thread while
//! the other waited. Levels are independent of each other until lifts, which are lowered
//! after them: the later levels go to a helper thread, into a building of their own, which
//! is appended afterwards ([`mapc_ir::Building::append_levels`]). The IR and the
//! diagnostics are exactly those of lowering the levels one after the other (tested on
//! every fixture and demo map, valid or not).

use crate::lower::Lower;
use crate::yaml::{Lists, Node};
use mapc_ir::{Building, Params, Span};

/// Levels are lowered on two threads from this much level text on: below it, the helper's
/// start (0.06-0.2 ms for a thread to wake here) costs about what it saves.
pub(crate) const PARALLEL_FROM: usize = 48 << 10;

/// How much longer the helper takes for the same text: it starts later and fills a fresh
/// heap arena (as for the split YAML read).
const HELPER_SLOWER: f64 = 1.2;

/// A level to lower: its node, its name, the span of its key.
pub(crate) type LevelEntry<'n, 's> = (&'n mut Node<'s>, String, Span);

/// On how many threads levels are lowered.
#[derive(Clone, Copy)]
pub(crate) enum LevelThreads {
    One,
    /// Two when the levels hold [`PARALLEL_FROM`] bytes of text or more and can be cut
    /// into two parts that each take a good share.
    Auto,
    /// Two, the helper's part from this level on (tests: every cut must give the same).
    #[cfg(test)]
    CutAt(usize),
}

/// Lowers `levels` into `b` in order, the later ones on a helper thread as `threads` says.
pub(crate) fn lower_levels<'s>(
    l: &mut Lower,
    b: &mut Building,
    mut levels: Vec<LevelEntry<'_, 's>>,
    lists: &Lists<'s>,
    threads: LevelThreads,
) {
    let sizes: Vec<usize> = levels
        .iter()
        .map(|(n, _, _)| n.span.end.saturating_sub(n.span.start) as usize)
        .collect();
    let cut = match threads {
        LevelThreads::One => None,
        LevelThreads::Auto => (sizes.iter().sum::<usize>() >= PARALLEL_FROM)
            .then(|| cut(&sizes))
            .flatten(),
        #[cfg(test)]
        LevelThreads::CutAt(k) => (1..levels.len()).contains(&k).then_some(k),
    };
    let Some(cut) = cut else {
        for (node, name, span) in levels {
            l.level(b, &name, node, span, lists);
        }
        return;
    };
    let theirs = levels.split_off(cut);
    let coordinate_system = b.coordinate_system;
    let helper = mapc_ir::par::task(move || {
        let mut diags = Vec::new();
        let mut part = Building::new(String::new(), coordinate_system, Params::default());
        let mut l = Lower { diags: &mut diags };
        for (node, name, span) in theirs {
            l.level(&mut part, &name, node, span, lists);
        }
        (part, diags)
    });
    for (node, name, span) in levels {
        l.level(b, &name, node, span, lists);
    }
    let (part, diags) = helper.get();
    b.append_levels(part);
    l.diags.extend(diags);
}

/// Where to cut levels of these sizes: the first level of the helper's part, chosen so
/// that the longer of the two parts (the helper's counted [`HELPER_SLOWER`] times) is
/// shortest; `None` when even that part holds nearly all the text.
fn cut(sizes: &[usize]) -> Option<usize> {
    let total: usize = sizes.iter().sum();
    let mut ours = 0;
    let mut best: Option<(f64, usize)> = None;
    for k in 1..sizes.len() {
        ours += sizes[k - 1];
        let longer = (ours as f64).max((total - ours) as f64 * HELPER_SLOWER);
        if best.is_none_or(|(t, _)| longer < t) {
            best = Some((longer, k));
        }
    }
    best.filter(|&(t, _)| t < 0.85 * total as f64)
        .map(|(_, k)| k)
}

#[cfg(test)]
mod tests {
    use super::cut;

    #[test]
    fn the_cut_balances_the_parts() {
        // Three levels, the last two large (hotel): the helper takes the last one.
        assert_eq!(cut(&[10, 45, 45]), Some(2));
        // Equal levels: the helper's part is the smaller one.
        assert_eq!(cut(&[25, 25, 25, 25]), Some(2));
        // One level holds nearly everything, or there is one level: no cut.
        assert_eq!(cut(&[95, 5]), None);
        assert_eq!(cut(&[100]), None);
        assert_eq!(cut(&[]), None);
    }
}
