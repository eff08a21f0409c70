//! A bounding-volume hierarchy over axis-aligned boxes: the candidates for the exact tests.
//!
//! Built by median splits along the longest axis of the boxes' centres, so its depth is about
//! `log₂ n` whatever the sizes: a far field hundreds of times larger than a finely triangulated
//! body costs no more than a uniform surface (a uniform grid sized by the mean box puts the
//! whole body in a few cells and goes quadratic). Queries report every box that overlaps a
//! closed query box; box comparisons are exact on the input, so the hierarchy only narrows the
//! candidates and never decides anything.

/// An axis-aligned box: lower and upper corners.
pub(crate) type Aabb = ([f64; 3], [f64; 3]);

/// Whether two closed boxes overlap (touching counts).
#[inline]
pub(crate) fn overlap(a: &Aabb, b: &Aabb) -> bool {
    (0..3).all(|k| a.0[k] <= b.1[k] && b.0[k] <= a.1[k])
}

/// Items per leaf, at most.
const LEAF: usize = 4;

#[derive(Clone, Copy, Debug)]
struct Node {
    bbox: Aabb,
    /// Leaf: `items[start..start + count]`; inner node: children `start` and `start + 1`.
    start: u32,
    /// Zero for an inner node.
    count: u32,
}

/// The hierarchy: nodes (the root first) and the item order of the leaves.
#[derive(Clone, Debug)]
pub(crate) struct Bvh {
    nodes: Vec<Node>,
    items: Vec<u32>,
}

fn union(a: &Aabb, b: &Aabb) -> Aabb {
    (
        std::array::from_fn(|k| a.0[k].min(b.0[k])),
        std::array::from_fn(|k| a.1[k].max(b.1[k])),
    )
}

const EMPTY: Aabb = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);

impl Bvh {
    /// The hierarchy of `boxes` (item `i` is `boxes[i]`).
    pub(crate) fn new(boxes: &[Aabb]) -> Bvh {
        let mut bvh = Bvh {
            nodes: Vec::with_capacity(2 * boxes.len() / LEAF + 1),
            items: (0..boxes.len() as u32).collect(),
        };
        let centres: Vec<[f64; 3]> = boxes
            .iter()
            .map(|b| std::array::from_fn(|k| b.0[k] / 2.0 + b.1[k] / 2.0))
            .collect();
        let centre = |i: u32, k: usize| centres[i as usize][k];
        bvh.nodes.push(Node {
            bbox: EMPTY,
            start: 0,
            count: 0,
        });
        // Explicit stack of (node, item range): no recursion depth to worry about.
        let mut todo = vec![(0usize, 0usize, boxes.len())];
        while let Some((node, lo, hi)) = todo.pop() {
            let bbox = bvh.items[lo..hi]
                .iter()
                .fold(EMPTY, |acc, &i| union(&acc, &boxes[i as usize]));
            bvh.nodes[node].bbox = bbox;
            if hi - lo <= LEAF {
                bvh.nodes[node].start = lo as u32;
                bvh.nodes[node].count = (hi - lo) as u32;
                continue;
            }
            let (mut clo, mut chi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
            for &i in &bvh.items[lo..hi] {
                for k in 0..3 {
                    clo[k] = clo[k].min(centre(i, k));
                    chi[k] = chi[k].max(centre(i, k));
                }
            }
            let axis = (0..3)
                .max_by(|&a, &b| (chi[a] - clo[a]).total_cmp(&(chi[b] - clo[b])))
                .unwrap_or(0);
            let mid = (hi - lo) / 2;
            bvh.items[lo..hi]
                .select_nth_unstable_by(mid, |&a, &b| centre(a, axis).total_cmp(&centre(b, axis)));
            let left = bvh.nodes.len();
            for _ in 0..2 {
                bvh.nodes.push(Node {
                    bbox: EMPTY,
                    start: 0,
                    count: 0,
                });
            }
            bvh.nodes[node].start = left as u32;
            todo.push((left, lo, lo + mid));
            todo.push((left + 1, lo + mid, hi));
        }
        bvh
    }

    /// The leaves: each one's box and items.
    pub(crate) fn leaves(&self) -> impl Iterator<Item = (&Aabb, &[u32])> + '_ {
        self.nodes.iter().filter(|n| n.count > 0).map(|n| {
            let s = n.start as usize;
            (&n.bbox, &self.items[s..s + n.count as usize])
        })
    }

    /// Calls `f` with every item whose box overlaps the closed box `q` (and possibly a few
    /// whose leaf box does: callers test the item boxes themselves). `stack` is scratch.
    #[inline]
    pub(crate) fn query(&self, q: &Aabb, stack: &mut Vec<u32>, mut f: impl FnMut(u32)) {
        if self.items.is_empty() {
            return;
        }
        stack.clear();
        stack.push(0);
        while let Some(n) = stack.pop() {
            let node = &self.nodes[n as usize];
            if !overlap(&node.bbox, q) {
                continue;
            }
            if node.count > 0 {
                let s = node.start as usize;
                for &i in &self.items[s..s + node.count as usize] {
                    f(i);
                }
            } else {
                stack.push(node.start);
                stack.push(node.start + 1);
            }
        }
    }
}

/// Boxes with their hierarchy: queries report exactly the items whose box overlaps.
#[derive(Clone, Debug)]
pub(crate) struct Boxes {
    /// Item `i`'s box.
    pub(crate) boxes: Vec<Aabb>,
    bvh: Bvh,
}

impl Boxes {
    pub(crate) fn new(boxes: Vec<Aabb>) -> Boxes {
        let bvh = Bvh::new(&boxes);
        Boxes { boxes, bvh }
    }

    /// The hierarchy.
    pub(crate) fn bvh(&self) -> &Bvh {
        &self.bvh
    }

    /// Calls `f` with every item whose closed box overlaps the closed box `q`, once each.
    #[inline]
    pub(crate) fn overlapping(&self, q: &Aabb, stack: &mut Vec<u32>, mut f: impl FnMut(u32)) {
        self.bvh.query(q, stack, |i| {
            if overlap(&self.boxes[i as usize], q) {
                f(i);
            }
        });
    }
}
