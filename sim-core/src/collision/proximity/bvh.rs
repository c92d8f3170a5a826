//! A bounding volume hierarchy over a fixed set of items (the cloth's triangles or
//! edges): built once for a mesh from where its items are, then refitted to each search's
//! boxes. A cloth keeps its neighbourhoods as it moves (what is near in the pattern stays
//! near in space), so the tree built on the flat cloth stays tight enough on the draped
//! one, and a refit costs one pass over the nodes.
//!
//! Unlike a uniform grid, it does not care how the boxes are shaped: the motion boxes of a
//! falling cloth are long along the fall and thin across it, and a grid's cubic cells
//! then hold dozens of boxes each (the 128 x 128 drape's edge search spent 80% of its time
//! scanning cells).

use glam::Vec3;

use super::grid::Aabb;

/// Most items in a leaf.
const LEAF: usize = 4;

#[derive(Clone, Copy, Debug)]
struct Node {
    b: Aabb,
    /// A leaf: its items are `order[first..first + count]`. An inner node (`count` 0):
    /// its children are nodes `first` and `first + 1`.
    first: u32,
    count: u32,
}

/// The hierarchy (see the module's doc).
#[derive(Clone, Debug, Default)]
pub struct Bvh {
    nodes: Vec<Node>,
    order: Vec<u32>,
    /// Each item's box, as last refitted.
    boxes: Vec<Aabb>,
}

impl Bvh {
    /// A tree over items whose places are `centers` (ids are their indices): each node
    /// split at the median of its longest side.
    pub fn build(centers: &[Vec3]) -> Self {
        let n = centers.len();
        let mut t = Self {
            nodes: Vec::with_capacity(2 * n / LEAF + 2),
            order: (0..n as u32).collect(),
            boxes: vec![Aabb::EMPTY; n],
        };
        t.nodes.push(Node {
            b: Aabb::EMPTY,
            first: 0,
            count: n as u32,
        });
        // (node, first item, item count) still to split.
        let mut todo = vec![(0usize, 0usize, n)];
        while let Some((node, first, count)) = todo.pop() {
            if count <= LEAF {
                t.nodes[node] = Node {
                    b: Aabb::EMPTY,
                    first: first as u32,
                    count: count as u32,
                };
                continue;
            }
            let items = &mut t.order[first..first + count];
            let bounds = items.iter().fold(Aabb::EMPTY, |b, &i| {
                b.with(finite_or_zero(centers[i as usize]))
            });
            let ext = bounds.hi - bounds.lo;
            let axis = if ext.x >= ext.y && ext.x >= ext.z {
                0
            } else if ext.y >= ext.z {
                1
            } else {
                2
            };
            let half = count / 2;
            items.select_nth_unstable_by(half, |&a, &b| {
                let (pa, pb) = (
                    finite_or_zero(centers[a as usize])[axis],
                    finite_or_zero(centers[b as usize])[axis],
                );
                pa.total_cmp(&pb).then(a.cmp(&b))
            });
            let left = t.nodes.len();
            t.nodes.push(Node {
                b: Aabb::EMPTY,
                first: 0,
                count: 0,
            });
            t.nodes.push(Node {
                b: Aabb::EMPTY,
                first: 0,
                count: 0,
            });
            t.nodes[node] = Node {
                b: Aabb::EMPTY,
                first: left as u32,
                count: 0,
            };
            todo.push((left, first, half));
            todo.push((left + 1, first + half, count - half));
        }
        t
    }

    /// How many items the tree was built over.
    pub fn len(&self) -> usize {
        self.boxes.len()
    }

    pub fn is_empty(&self) -> bool {
        self.boxes.is_empty()
    }

    /// Gives every item its box for this search (`boxes` in item order; an item whose
    /// box is not finite is never reported) and every node the union of its items'.
    pub fn refit(&mut self, boxes: impl IntoIterator<Item = Aabb>) {
        self.boxes.clear();
        self.boxes.extend(boxes);
        self.boxes.resize(self.order.len(), Aabb::EMPTY);
        for b in &mut self.boxes {
            if !b.is_finite() {
                *b = Aabb::EMPTY;
            }
        }
        // Children always come after their parent.
        for k in (0..self.nodes.len()).rev() {
            let Node { first, count, .. } = self.nodes[k];
            let (first, count) = (first as usize, count as usize);
            self.nodes[k].b = if count > 0 {
                self.order[first..first + count]
                    .iter()
                    .fold(Aabb::EMPTY, |b, &i| b.union(self.boxes[i as usize]))
            } else if first > 0 {
                self.nodes[first].b.union(self.nodes[first + 1].b)
            } else {
                // The root of an empty tree.
                Aabb::EMPTY
            };
        }
    }

    /// Calls `f` with every item whose box overlaps `q`.
    pub fn query(&self, q: &Aabb, stack: &mut Vec<u32>, mut f: impl FnMut(u32)) {
        if self.order.is_empty() || !q.is_finite() {
            return;
        }
        stack.clear();
        stack.push(0);
        while let Some(k) = stack.pop() {
            let node = &self.nodes[k as usize];
            if !node.b.overlaps(q) {
                continue;
            }
            let (first, count) = (node.first as usize, node.count as usize);
            if count > 0 {
                for &i in &self.order[first..first + count] {
                    if self.boxes[i as usize].overlaps(q) {
                        f(i);
                    }
                }
            } else {
                stack.push(node.first);
                stack.push(node.first + 1);
            }
        }
    }

    /// Calls `f(a, b)`, `a < b`, once for every two items whose boxes overlap.
    pub fn self_pairs(&self, stack: &mut Vec<(u32, u32)>, f: impl FnMut(u32, u32)) {
        if !self.order.is_empty() {
            self.self_pairs_from(&[(0, 0)], stack, f);
        }
    }

    /// Pairs of nodes to start [`Bvh::self_pairs_from`] at, at least `want` of them where
    /// the tree has that many overlapping ones: together they give every pair once, so
    /// threads can share them.
    pub fn self_pair_tasks(&self, want: usize, out: &mut Vec<(u32, u32)>) {
        out.clear();
        if self.order.is_empty() {
            return;
        }
        let mut open = std::collections::VecDeque::from([(0u32, 0u32)]);
        while out.len() + open.len() < want {
            let Some((a, b)) = open.pop_front() else {
                break;
            };
            let (na, nb) = (&self.nodes[a as usize], &self.nodes[b as usize]);
            if !na.b.overlaps(&nb.b) {
                continue;
            }
            if na.count > 0 && nb.count > 0 {
                out.push((a, b));
            } else {
                self.children(a, b, |t| open.push_back(t));
            }
        }
        out.extend(open);
    }

    /// Calls `f(a, b)`, `a < b`, once for every two items under the node pairs `tasks`
    /// whose boxes overlap.
    pub fn self_pairs_from(
        &self,
        tasks: &[(u32, u32)],
        stack: &mut Vec<(u32, u32)>,
        mut f: impl FnMut(u32, u32),
    ) {
        stack.clear();
        stack.extend_from_slice(tasks);
        while let Some((a, b)) = stack.pop() {
            let (na, nb) = (&self.nodes[a as usize], &self.nodes[b as usize]);
            if !na.b.overlaps(&nb.b) {
                continue;
            }
            if na.count > 0 && nb.count > 0 {
                self.leaf_pairs(na, nb, a == b, &mut f);
            } else {
                self.children(a, b, |t| stack.push(t));
            }
        }
    }

    /// The node pairs that node pair `(a, b)`, not both leaves, opens into.
    fn children(&self, a: u32, b: u32, mut push: impl FnMut((u32, u32))) {
        let (na, nb) = (&self.nodes[a as usize], &self.nodes[b as usize]);
        match (na.count > 0, nb.count > 0) {
            _ if a == b => {
                let (l, r) = (na.first, na.first + 1);
                push((l, l));
                push((r, r));
                push((l, r));
            }
            // Open the inner node, or the larger of two inner nodes.
            (false, true) => {
                push((na.first, b));
                push((na.first + 1, b));
            }
            (true, false) => {
                push((a, nb.first));
                push((a, nb.first + 1));
            }
            _ => {
                if size(&na.b) >= size(&nb.b) {
                    push((na.first, b));
                    push((na.first + 1, b));
                } else {
                    push((a, nb.first));
                    push((a, nb.first + 1));
                }
            }
        }
    }

    fn leaf_pairs(&self, na: &Node, nb: &Node, same: bool, f: &mut impl FnMut(u32, u32)) {
        let ia = &self.order[na.first as usize..(na.first + na.count) as usize];
        let ib = &self.order[nb.first as usize..(nb.first + nb.count) as usize];
        for (x, &i) in ia.iter().enumerate() {
            let rest = if same { &ib[x + 1..] } else { ib };
            for &j in rest {
                if self.boxes[i as usize].overlaps(&self.boxes[j as usize]) {
                    f(i.min(j), i.max(j));
                }
            }
        }
    }
}

/// A box's size for choosing which node to open: the sum of its sides (a flat box,
/// as a flat cloth's, has no volume but still a size).
fn size(b: &Aabb) -> f32 {
    let e = (b.hi - b.lo).max(Vec3::ZERO);
    e.x + e.y + e.z
}

fn finite_or_zero(p: Vec3) -> Vec3 {
    if p.is_finite() { p } else { Vec3::ZERO }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A small deterministic generator (no dependency for a test).
    fn lcg(state: &mut u64) -> f32 {
        *state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        ((*state >> 40) as f32) / (1u64 << 24) as f32
    }

    fn random_boxes(n: usize, seed: u64) -> (Vec<Vec3>, Vec<Aabb>) {
        let mut s = seed;
        let mut centers = Vec::new();
        let mut boxes = Vec::new();
        for _ in 0..n {
            let c = Vec3::new(lcg(&mut s), lcg(&mut s), lcg(&mut s));
            let e = Vec3::new(lcg(&mut s), lcg(&mut s), lcg(&mut s)) * 0.1;
            centers.push(c);
            // Boxes drift from where the tree was built, as a cloth moves.
            let d = Vec3::new(lcg(&mut s), lcg(&mut s), lcg(&mut s)) * 0.2;
            boxes.push(Aabb {
                lo: c + d - e,
                hi: c + d + e,
            });
        }
        (centers, boxes)
    }

    #[test]
    fn self_pairs_are_every_overlapping_pair_once() {
        for (n, seed) in [(0, 1), (1, 2), (3, 3), (5, 4), (37, 5), (300, 6)] {
            let (centers, boxes) = random_boxes(n, seed);
            let mut t = Bvh::build(&centers);
            t.refit(boxes.iter().copied());
            let mut got = Vec::new();
            t.self_pairs(&mut Vec::new(), |a, b| got.push((a, b)));
            got.sort_unstable();
            let mut want = Vec::new();
            for a in 0..n {
                for b in a + 1..n {
                    if boxes[a].overlaps(&boxes[b]) {
                        want.push((a as u32, b as u32));
                    }
                }
            }
            assert_eq!(got, want, "{n} boxes");
            // Split into node pairs for threads, dealt out in turn: the same pairs.
            for want_tasks in [1, 4, 32] {
                let mut tasks = Vec::new();
                t.self_pair_tasks(want_tasks, &mut tasks);
                if n > 30 {
                    assert!(tasks.len() >= want_tasks, "{n} boxes, {want_tasks} tasks");
                }
                let mut split = Vec::new();
                for k in 0..3 {
                    let mine: Vec<_> = tasks.iter().skip(k).step_by(3).copied().collect();
                    t.self_pairs_from(&mine, &mut Vec::new(), |a, b| split.push((a, b)));
                }
                split.sort_unstable();
                assert_eq!(split, want, "{n} boxes in {} tasks", tasks.len());
            }
            if n > 30 {
                assert!(!want.is_empty(), "the test must see overlaps");
            }
        }
    }

    #[test]
    fn a_query_finds_every_overlapping_box() {
        let (centers, mut boxes) = random_boxes(200, 9);
        // A box that is not finite is never found.
        boxes[7].hi.x = f32::NAN;
        let mut t = Bvh::build(&centers);
        t.refit(boxes.iter().copied());
        let (_, queries) = random_boxes(50, 10);
        let mut stack = Vec::new();
        for q in &queries {
            let mut got = Vec::new();
            t.query(q, &mut stack, |i| got.push(i));
            got.sort_unstable();
            let want: Vec<u32> = (0..200u32)
                .filter(|&i| i != 7 && boxes[i as usize].overlaps(q))
                .collect();
            assert_eq!(got, want);
        }
    }
}
