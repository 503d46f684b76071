//! The ordered set of a line sweep: a treap over `u32` ids (edges), each
//! carrying its segment, ordered by the caller's geometric comparisons, with
//! O(log n) expected insertion, removal, neighbours and search. Shared by the
//! simplicity test ([`super::simple`]) and the triangulation
//! ([`super::triangulate`]). A node keeps its links and its segment together,
//! so a step down the tree touches one cache line (a million-edge sweep is
//! bound by those misses).
//!
//! An id is its own node, so removal and the neighbours of an id take no
//! comparison at all: a sweep whose comparisons went wrong (input outside the
//! contract, say) still removes exactly what it inserted and never panics;
//! only the order of the ids would be wrong. Priorities are a hash of the id,
//! so the tree, and everything decided from it, is the same on every run.

use glam::DVec2;

const NIL: u32 = u32::MAX;

/// A segment, as the sweep's comparisons read it.
pub(super) type Seg = [DVec2; 2];

#[derive(Clone, Copy)]
struct Node {
    /// Left child, right child, parent.
    link: [u32; 3],
    seg: Seg,
}

/// An ordered set of ids `0..capacity`, each present at most once.
pub(super) struct Treap {
    nodes: Vec<Node>,
    root: u32,
}

const L: usize = 0;
const R: usize = 1;
const P: usize = 2;

/// The heap priority of an id (smaller is nearer the root): a fixed
/// pseudo-random permutation (splitmix32 finaliser), so any insertion order
/// gives a tree of expected depth O(log n).
#[inline]
fn priority(id: u32) -> u32 {
    let mut z = id.wrapping_add(0x9e37_79b9);
    z = (z ^ (z >> 16)).wrapping_mul(0x85eb_ca6b);
    z = (z ^ (z >> 13)).wrapping_mul(0xc2b2_ae35);
    z ^ (z >> 16)
}

impl Treap {
    /// An empty set for ids below `capacity`.
    pub(super) fn new(capacity: usize) -> Treap {
        Treap {
            nodes: vec![
                Node {
                    link: [NIL; 3],
                    seg: [DVec2::ZERO; 2],
                };
                capacity
            ],
            root: NIL,
        }
    }

    #[inline]
    fn get(x: u32) -> Option<u32> {
        (x != NIL).then_some(x)
    }

    /// Inserts `id` (not present) with its segment. `before(seg, other)`
    /// says whether `id` goes before `other`, of segment `seg`, in the
    /// order; it is asked about the nodes on one path from the root.
    pub(super) fn insert(&mut self, id: u32, seg: Seg, mut before: impl FnMut(&Seg, u32) -> bool) {
        let i = id as usize;
        self.nodes[i].seg = seg;
        self.nodes[i].link[L] = NIL;
        self.nodes[i].link[R] = NIL;
        let (mut at, mut parent, mut to_left) = (self.root, NIL, false);
        while at != NIL {
            parent = at;
            to_left = before(&self.nodes[at as usize].seg, at);
            at = if to_left {
                self.nodes[at as usize].link[L]
            } else {
                self.nodes[at as usize].link[R]
            };
        }
        self.nodes[i].link[P] = parent;
        if parent == NIL {
            self.root = id;
        } else if to_left {
            self.nodes[parent as usize].link[L] = id;
        } else {
            self.nodes[parent as usize].link[R] = id;
        }
        let p = priority(id);
        while self.nodes[i].link[P] != NIL && p < priority(self.nodes[i].link[P]) {
            self.rotate_up(id);
        }
    }

    /// Removes `id` (present).
    pub(super) fn remove(&mut self, id: u32) {
        let i = id as usize;
        // Rotate the node down until it has at most one child.
        while self.nodes[i].link[L] != NIL && self.nodes[i].link[R] != NIL {
            let (l, r) = (self.nodes[i].link[L], self.nodes[i].link[R]);
            self.rotate_up(if priority(l) < priority(r) { l } else { r });
        }
        let child = if self.nodes[i].link[L] != NIL {
            self.nodes[i].link[L]
        } else {
            self.nodes[i].link[R]
        };
        let parent = self.nodes[i].link[P];
        if child != NIL {
            self.nodes[child as usize].link[P] = parent;
        }
        self.replace_child(parent, id, child);
        self.nodes[i].link[L] = NIL;
        self.nodes[i].link[R] = NIL;
        self.nodes[i].link[P] = NIL;
    }

    /// Makes `x` take its parent's place (a rotation), keeping the order.
    fn rotate_up(&mut self, x: u32) {
        let xi = x as usize;
        let p = self.nodes[xi].link[P];
        let pi = p as usize;
        let g = self.nodes[pi].link[P];
        if self.nodes[pi].link[L] == x {
            let b = self.nodes[xi].link[R];
            self.nodes[pi].link[L] = b;
            if b != NIL {
                self.nodes[b as usize].link[P] = p;
            }
            self.nodes[xi].link[R] = p;
        } else {
            let b = self.nodes[xi].link[L];
            self.nodes[pi].link[R] = b;
            if b != NIL {
                self.nodes[b as usize].link[P] = p;
            }
            self.nodes[xi].link[L] = p;
        }
        self.nodes[pi].link[P] = x;
        self.nodes[xi].link[P] = g;
        self.replace_child(g, p, x);
    }

    /// Hangs `new` from `parent` where `old` hung (the root, for `parent`
    /// NIL): [`Treap::remove`] and [`Treap::rotate_up`] both move a node
    /// into another's place.
    fn replace_child(&mut self, parent: u32, old: u32, new: u32) {
        if parent == NIL {
            self.root = new;
        } else if self.nodes[parent as usize].link[L] == old {
            self.nodes[parent as usize].link[L] = new;
        } else {
            self.nodes[parent as usize].link[R] = new;
        }
    }

    /// The id just before `id` (present) in the order.
    pub(super) fn prev(&self, id: u32) -> Option<u32> {
        self.beside(id, L)
    }

    /// The id just after `id` (present) in the order.
    pub(super) fn next(&self, id: u32) -> Option<u32> {
        self.beside(id, R)
    }

    /// The id next to `id` (present) on `side` of it in the order (`L`:
    /// before, `R`: after): [`Treap::prev`] and [`Treap::next`] are the
    /// same walk, mirrored.
    #[inline]
    fn beside(&self, id: u32, side: usize) -> Option<u32> {
        let other = if side == L { R } else { L };
        let mut x = id;
        if self.nodes[x as usize].link[side] != NIL {
            x = self.nodes[x as usize].link[side];
            while self.nodes[x as usize].link[other] != NIL {
                x = self.nodes[x as usize].link[other];
            }
            return Some(x);
        }
        loop {
            let p = self.nodes[x as usize].link[P];
            if p == NIL || self.nodes[p as usize].link[other] == x {
                return Self::get(p);
            }
            x = p;
        }
    }

    /// The last id for which `pred(seg, id)` holds, where it holds on a
    /// prefix of the order (else: some id on one search path for which it
    /// holds).
    pub(super) fn last_where(&self, mut pred: impl FnMut(&Seg, u32) -> bool) -> Option<u32> {
        let (mut at, mut best) = (self.root, NIL);
        while at != NIL {
            if pred(&self.nodes[at as usize].seg, at) {
                best = at;
                at = self.nodes[at as usize].link[R];
            } else {
                at = self.nodes[at as usize].link[L];
            }
        }
        Self::get(best)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The ids in order, walking `next` from the first.
    fn in_order(t: &Treap) -> Vec<u32> {
        let mut x = t.root;
        if x == NIL {
            return Vec::new();
        }
        while t.nodes[x as usize].link[L] != NIL {
            x = t.nodes[x as usize].link[L];
        }
        let mut out = vec![x];
        while let Some(y) = t.next(x) {
            out.push(y);
            x = y;
        }
        out
    }

    proptest::proptest! {
        /// Against a sorted Vec: ids keyed by a random value, inserted and
        /// removed in random order; the order, neighbours and search agree.
        #[test]
        fn agrees_with_a_sorted_vec(
            keys in proptest::collection::vec(0u32..50, 1..120),
            ops in proptest::collection::vec(proptest::bool::ANY, 1..300),
        ) {
            let n = keys.len();
            let key = |id: u32| (keys[id as usize], id);
            let mut t = Treap::new(n);
            let mut model: Vec<u32> = Vec::new();
            let mut next_in = 0usize;
            for &ins in &ops {
                if (ins || model.is_empty()) && next_in < n {
                    let id = next_in as u32;
                    next_in += 1;
                    t.insert(id, [DVec2::ZERO; 2], |_, o| key(id) < key(o));
                    let at = model.partition_point(|&o| key(o) < key(id));
                    model.insert(at, id);
                } else if !model.is_empty() {
                    let victim = model[keys[model.len() % n] as usize % model.len()];
                    t.remove(victim);
                    model.retain(|&o| o != victim);
                }
                proptest::prop_assert_eq!(in_order(&t), model.clone());
                for (i, &id) in model.iter().enumerate() {
                    proptest::prop_assert_eq!(t.prev(id), i.checked_sub(1).map(|j| model[j]));
                    proptest::prop_assert_eq!(t.next(id), model.get(i + 1).copied());
                }
                let bound = keys[ops.len() % n];
                let want = model.iter().rev().find(|&&o| keys[o as usize] < bound).copied();
                proptest::prop_assert_eq!(t.last_where(|_, o| keys[o as usize] < bound), want);
            }
        }
    }
}
