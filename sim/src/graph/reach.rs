//! Which vertices reach which on one graph: its strongly connected components (Kosaraju)
//! and, when there are not too many, the transitive closure of their condensation. Every
//! task asks whether a robot can reach its places; a search of the whole graph per task was
//! a twentieth of a 1,000-robot warehouse run.

/// A vertex without an edge in the graph: it reaches only itself.
const ALONE: u32 = u32::MAX;
/// Components with a closure kept (bits: `MAX_CLOSED`² / 8 bytes at most, 2 MiB).
const MAX_CLOSED: usize = 4096;

#[derive(Debug, Clone, Default)]
pub(super) struct Reach {
    /// Per vertex: its component (`ALONE` when it has no edge); empty when not built.
    comp: Vec<u32>,
    /// Per component, the components it reaches (bit sets of `words` words), when there
    /// are at most `MAX_CLOSED` components (`closed`).
    closure: Vec<u64>,
    words: usize,
    closed: bool,
}

impl Reach {
    /// Over `n` vertices and the graph's `edges` (from, to).
    pub(super) fn build(n: usize, edges: &[(usize, usize)]) -> Reach {
        let mut out: Vec<Vec<usize>> = vec![Vec::new(); n];
        let mut inn: Vec<Vec<usize>> = vec![Vec::new(); n];
        for &(a, z) in edges {
            out[a].push(z);
            inn[z].push(a);
        }
        // Finishing order of a depth-first search (iterative: graphs of any size).
        let mut order = Vec::with_capacity(n);
        let mut seen = vec![false; n];
        for s in 0..n {
            if seen[s] || out[s].is_empty() && inn[s].is_empty() {
                continue;
            }
            seen[s] = true;
            let mut stack = vec![(s, 0usize)];
            while let Some(top) = stack.last_mut() {
                let (v, k) = *top;
                if let Some(&w) = out[v].get(k) {
                    top.1 += 1;
                    if !seen[w] {
                        seen[w] = true;
                        stack.push((w, 0));
                    }
                } else {
                    order.push(v);
                    stack.pop();
                }
            }
        }
        // Components on the reversed graph, latest finished first: they come out in a
        // topological order of the condensation (a component reaches only later ones).
        let mut comp = vec![ALONE; n];
        let mut count = 0u32;
        for &s in order.iter().rev() {
            if comp[s] != ALONE {
                continue;
            }
            comp[s] = count;
            let mut stack = vec![s];
            while let Some(v) = stack.pop() {
                for &w in &inn[v] {
                    if comp[w] == ALONE {
                        comp[w] = count;
                        stack.push(w);
                    }
                }
            }
            count += 1;
        }
        let count = count as usize;
        let mut closure = Vec::new();
        let words = count.div_ceil(64);
        let closed = count <= MAX_CLOSED;
        if closed {
            let mut succ: Vec<Vec<u32>> = vec![Vec::new(); count];
            for &(a, z) in edges {
                if comp[a] != comp[z] {
                    succ[comp[a] as usize].push(comp[z]);
                }
            }
            closure = vec![0u64; count * words];
            for c in (0..count).rev() {
                closure[c * words + c / 64] |= 1 << (c % 64);
                for &d in &succ[c] {
                    let d = d as usize;
                    // d > c: its closure is complete.
                    let (head, tail) = closure.split_at_mut(d * words);
                    let mine = &mut head[c * words..(c + 1) * words];
                    for (m, o) in mine.iter_mut().zip(&tail[..words]) {
                        *m |= o;
                    }
                }
            }
        }
        Reach {
            comp,
            closure,
            words,
            closed,
        }
    }

    /// Whether some vertex of `starts` reaches `to` (a vertex reaches itself); None when
    /// not known here (not built, or too many components).
    pub(super) fn reached_from_any(
        &self,
        starts: &mut dyn Iterator<Item = usize>,
        to: usize,
    ) -> Option<bool> {
        let &target = self.comp.get(to)?;
        if !self.closed {
            return None;
        }
        let mut any = false;
        for s in starts {
            let &c = self.comp.get(s)?;
            any |= s == to
                || c != ALONE
                    && target != ALONE
                    && (c == target || {
                        let c = c as usize;
                        let t = target as usize;
                        self.closure[c * self.words + t / 64] >> (t % 64) & 1 == 1
                    });
            if any {
                break;
            }
        }
        Some(any)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Reachability by a plain search, for comparison.
    fn search(n: usize, edges: &[(usize, usize)], from: usize, to: usize) -> bool {
        let mut seen = vec![false; n];
        let mut stack = vec![from];
        while let Some(v) = stack.pop() {
            if v == to {
                return true;
            }
            if !std::mem::replace(&mut seen[v], true) {
                stack.extend(edges.iter().filter(|e| e.0 == v).map(|e| e.1));
            }
        }
        false
    }

    #[test]
    fn a_one_way_chain_a_loop_and_a_vertex_alone() {
        // 0 -> 1 -> 2 <-> 3, 4 alone.
        let edges = [(0, 1), (1, 2), (2, 3), (3, 2)];
        let r = Reach::build(5, &edges);
        let reaches = |a: usize, b: usize| r.reached_from_any(&mut std::iter::once(a), b);
        assert_eq!(reaches(0, 3), Some(true));
        assert_eq!(reaches(3, 2), Some(true));
        assert_eq!(reaches(2, 1), Some(false));
        assert_eq!(reaches(4, 4), Some(true));
        assert_eq!(reaches(4, 0), Some(false));
        assert_eq!(reaches(0, 4), Some(false));
        assert_eq!(r.reached_from_any(&mut [4, 3].into_iter(), 2), Some(true));
        assert_eq!(r.reached_from_any(&mut [4, 3].into_iter(), 0), Some(false));
    }

    #[test]
    fn agrees_with_a_search_on_random_graphs() {
        let mut rng = fastrand::Rng::with_seed(7);
        for case in 0..200 {
            let n = rng.usize(1..=40);
            let m = rng.usize(0..3 * n);
            let edges: Vec<(usize, usize)> =
                (0..m).map(|_| (rng.usize(0..n), rng.usize(0..n))).collect();
            let r = Reach::build(n, &edges);
            for a in 0..n {
                for b in 0..n {
                    let got = r.reached_from_any(&mut std::iter::once(a), b);
                    assert_eq!(
                        got,
                        Some(search(n, &edges, a, b)),
                        "case {case}: {a} -> {b}"
                    );
                }
            }
        }
    }

    #[test]
    fn too_many_components_are_not_closed() {
        // A one-way chain: every vertex is a component of its own.
        let n = MAX_CLOSED + 2;
        let edges: Vec<(usize, usize)> = (1..n).map(|v| (v - 1, v)).collect();
        let r = Reach::build(n, &edges);
        assert_eq!(r.reached_from_any(&mut std::iter::once(0), n - 1), None);
    }
}
