//! The binary tree collapsed into wide nodes ([`widen`]), apart from the binned build that
//! makes the binary tree.
//!
//! The wide nodes are made by collapsing the binned-SAH binary tree: each wide node takes the
//! largest interior child's two children in its place until it has 8 ([`widen`]). A subtree
//! of at most 4 triangles becomes one leaf (its triangles are contiguous), or of at most 8 in
//! a dense mesh (`bvh::leaf_max`). On the 1M-triangle mesh: 70 MB and 17.9 Mrays/s (640×360
//! flat, 2 threads), against 92 MB and 15.2 Mrays/s merging subtrees of at most 3
//! (interleaved runs) and 102 MB merging none; 4% more instructions than merging none, but
//! fewer cache misses. Leaves of up to 8 took it to 55 MB and its frame 20% faster at
//! 640×360, 11% at 1280×720 (2 threads, 7 interleaved rounds), Igea's (269k triangles) 19%
//! and 6%, where the bunny's (69k) 640×360 frame was 14% slower with them, the bunny
//! field's 13% (6% with its meshes' leaves prepared 8 at a time).
//! A walk's stack holds at most [`STACK`] entries: a node stops taking grandchildren where
//! the deepest path below could need more.
//!
//! [`STACK`]: super::node::STACK

use super::node::{leaf_ref, Node, WideNode, LEAF, WIDTH};
use rayon::prelude::*;

/// The wide nodes over the binary tree `nodes` (depth first, as the build makes it), root
/// first, children after their parents, such that no walk needs more than `stack` entries
/// (`stack` must exceed the binary tree's height, which the build keeps below 70). Subtrees
/// of at least `parallel_min` binary nodes collapse their children's subtrees on several
/// threads.
pub(super) fn widen(nodes: &[Node], stack: usize, parallel_min: usize) -> Vec<WideNode> {
    if nodes.is_empty() {
        return Vec::new();
    }
    assert!(
        usize::from(nodes[0].height) < stack,
        "a BVH of height {}",
        nodes[0].height
    );
    let collapse = Collapse {
        nodes,
        stack,
        parallel_min,
    };
    let root = Subtree {
        root: 0,
        end: nodes.len(),
    };
    collapse.subtree(root, 0)
}

/// A binary node and the end of its subtree in the depth-first list.
#[derive(Clone, Copy)]
struct Subtree {
    root: usize,
    end: usize,
}

impl Subtree {
    /// Its two children's subtrees (it must be interior).
    fn halves(self, nodes: &[Node]) -> [Subtree; 2] {
        let [a, b] = Node::children(nodes, self.root);
        [
            Subtree { root: a, end: b },
            Subtree {
                root: b,
                end: self.end,
            },
        ]
    }
}

/// The binary tree with what [`widen`] needs.
struct Collapse<'a> {
    nodes: &'a [Node],
    stack: usize,
    parallel_min: usize,
}

impl Collapse<'_> {
    /// Whether binary node `k` is interior (it holds more than the build's `leaf_max` items).
    fn interior(&self, k: usize) -> bool {
        self.nodes[k].count == 0
    }

    /// The children of the wide node made from binary subtree `root`, walked with `above`
    /// entries below it: its children, then the largest interior one's in its place, up to
    /// 8 (in an array: one allocation per wide node cost the build as many small ones).
    fn children(&self, root: Subtree, above: usize) -> ([Subtree; WIDTH], usize) {
        let mut kids = [root; WIDTH];
        let mut len = 1;
        if self.interior(root.root) {
            [kids[0], kids[1]] = root.halves(self.nodes);
            len = 2;
        }
        let h = |k: Subtree| usize::from(self.nodes[k.root].height);
        let mut area = [0.0f64; WIDTH];
        for slot in 0..len {
            area[slot] = self.nodes[kids[slot].root].bounds.half_area();
        }
        while len < WIDTH {
            let largest = (0..len)
                .filter(|&slot| self.interior(kids[slot].root))
                .max_by(|&a, &b| area[a].total_cmp(&area[b]));
            let Some(slot) = largest else { break };
            // Walking this node pushes `len` children; below each, a walk through nodes of
            // two children pushes at most one entry a level. Expand only while that fits.
            let others = (0..len).filter(|&s| s != slot).map(|s| h(kids[s])).max();
            let deepest = others.unwrap_or(0).max(h(kids[slot]) - 1);
            if above + len + 1 + deepest > self.stack {
                break;
            }
            [kids[slot], kids[len]] = kids[slot].halves(self.nodes);
            area[slot] = self.nodes[kids[slot].root].bounds.half_area();
            area[len] = self.nodes[kids[len].root].bounds.half_area();
            len += 1;
        }
        debug_assert!(above + len <= self.stack);
        (kids, len)
    }

    /// The wide node over `kids`, with their boxes and leaves (interior children: [`NONE`],
    /// to be set).
    ///
    /// [`NONE`]: super::node::NONE
    fn wide_node(&self, kids: &[Subtree]) -> WideNode {
        let mut w = WideNode::EMPTY;
        for (c, k) in kids.iter().enumerate() {
            let n = &self.nodes[k.root];
            for a in 0..3 {
                w.lo[a][c] = n.bounds.lo[a];
                w.hi[a][c] = n.bounds.hi[a];
            }
            if n.count > 0 {
                w.child[c] = leaf_ref(n.offset, u32::from(n.count));
            }
        }
        w
    }

    /// The wide nodes of `root`'s subtree (walked with `above` entries below it), its root
    /// first, child references counted from there.
    fn subtree(&self, root: Subtree, above: usize) -> Vec<WideNode> {
        if root.end - root.root < self.parallel_min {
            return self.subtree_serial(root, above);
        }
        let (kids, len) = self.children(root, above);
        let kids = &kids[..len];
        let mut w = self.wide_node(kids);
        let inner: Vec<(usize, Subtree)> = (kids.iter().enumerate())
            .filter(|&(_, k)| self.interior(k.root))
            .map(|(c, &k)| (c, k))
            .collect();
        let parts: Vec<Vec<WideNode>> = inner
            .par_iter()
            .map(|&(_, k)| self.subtree(k, above + len - 1))
            .collect();
        let mut out = Vec::with_capacity(1 + parts.iter().map(Vec::len).sum::<usize>());
        out.push(w);
        for (&(c, _), part) in inner.iter().zip(parts) {
            let base = out.len() as u32;
            w.child[c] = base;
            out.extend(part.into_iter().map(|mut n| {
                for r in &mut n.child {
                    if *r & LEAF == 0 {
                        *r += base;
                    }
                }
                n
            }));
        }
        out[0] = w;
        out
    }

    /// [`Collapse::subtree`] on one thread, depth first from the root.
    fn subtree_serial(&self, root: Subtree, above: usize) -> Vec<WideNode> {
        // A guess with room: the 1M mesh has one wide node per 6.2 binary ones.
        let mut wide = Vec::with_capacity((root.end - root.root) / 3 + 1);
        wide.push(WideNode::EMPTY);
        // (binary subtree, wide slot to fill, stack entries left below it while it is walked)
        let mut todo = vec![(root, 0usize, above)];
        while let Some((root, at, above)) = todo.pop() {
            let (kids, len) = self.children(root, above);
            wide[at] = self.wide_node(&kids[..len]);
            for (c, k) in kids[..len].iter().enumerate() {
                if self.interior(k.root) {
                    wide[at].child[c] = wide.len() as u32;
                    todo.push((*k, wide.len(), above + len - 1));
                    wide.push(WideNode::EMPTY);
                }
            }
        }
        wide
    }
}
