//! A bounding-volume hierarchy over glyph boxes: median split on the longest axis. A leaf tests
//! each primitive's own box before the caller's exact test: thin glyphs at an angle (needles)
//! have boxes far larger than themselves, and a leaf's box is the union of four of them.

use glam::DVec3;

#[derive(Debug, Clone, Copy)]
pub struct Aabb {
    pub lo: DVec3,
    pub hi: DVec3,
}

impl Aabb {
    pub const EMPTY: Aabb = Aabb {
        lo: DVec3::splat(f64::INFINITY),
        hi: DVec3::splat(f64::NEG_INFINITY),
    };

    pub fn union(self, o: Aabb) -> Aabb {
        Aabb {
            lo: self.lo.min(o.lo),
            hi: self.hi.max(o.hi),
        }
    }

    /// Entry distance of the ray into the box if it enters before `t_max`.
    fn hit(&self, origin: DVec3, inv_dir: DVec3, t_max: f64) -> Option<f64> {
        let t1 = (self.lo - origin) * inv_dir;
        let t2 = (self.hi - origin) * inv_dir;
        // NaN (0 · inf on a face) must not reject: min/max of glam ignore the NaN side.
        let tmin = t1.min(t2).max_element().max(f64::NEG_INFINITY);
        let tmax = t1.max(t2).min_element().min(t_max);
        (tmin <= tmax && tmax >= 0.0).then_some(tmin)
    }
}

#[derive(Debug, Clone, Copy)]
struct Node {
    bounds: Aabb,
    /// Leaf: first primitive in `order`; inner: index of the left child (right = left + 1).
    start: u32,
    /// 0 for inner nodes.
    count: u32,
}

/// Primitives are referred to by their index in the slice the BVH was built from.
#[derive(Debug, Clone, Default)]
pub struct Bvh {
    nodes: Vec<Node>,
    order: Vec<u32>,
    /// `boxes[order[k]]` at k, grown by a billionth of its size so that rounding in the slab
    /// test cannot drop a ray that touches a glyph where the glyph touches its box.
    leaf_boxes: Vec<Aabb>,
}

const LEAF_SIZE: usize = 4;

impl Bvh {
    pub fn build(boxes: &[Aabb]) -> Self {
        let mut bvh = Bvh {
            nodes: Vec::with_capacity(boxes.len() * 2 / LEAF_SIZE + 1),
            order: (0..boxes.len() as u32).collect(),
            leaf_boxes: Vec::new(),
        };
        if boxes.is_empty() {
            return bvh;
        }
        bvh.nodes.push(Node {
            bounds: Aabb::EMPTY,
            start: 0,
            count: 0,
        });
        let mut stack = vec![(0usize, 0usize, boxes.len())];
        while let Some((node, start, end)) = stack.pop() {
            let bounds = bvh.order[start..end]
                .iter()
                .fold(Aabb::EMPTY, |b, &i| b.union(boxes[i as usize]));
            bvh.nodes[node].bounds = bounds;
            if end - start <= LEAF_SIZE {
                bvh.nodes[node].start = start as u32;
                bvh.nodes[node].count = (end - start) as u32;
                continue;
            }
            let centre = |i: u32| (boxes[i as usize].lo + boxes[i as usize].hi) * 0.5;
            let extent = bounds.hi - bounds.lo;
            let axis = if extent.x >= extent.y && extent.x >= extent.z {
                0
            } else if extent.y >= extent.z {
                1
            } else {
                2
            };
            let mid = (start + end) / 2;
            bvh.order[start..end].select_nth_unstable_by(mid - start, |&a, &b| {
                centre(a)[axis].total_cmp(&centre(b)[axis])
            });
            let left = bvh.nodes.len();
            for _ in 0..2 {
                bvh.nodes.push(Node {
                    bounds: Aabb::EMPTY,
                    start: 0,
                    count: 0,
                });
            }
            bvh.nodes[node].start = left as u32;
            stack.push((left, start, mid));
            stack.push((left + 1, mid, end));
        }
        bvh.leaf_boxes = bvh
            .order
            .iter()
            .map(|&i| {
                let b = boxes[i as usize];
                let pad = (b.hi - b.lo).abs().max_element() * 1e-9 + f64::MIN_POSITIVE;
                Aabb {
                    lo: b.lo - pad,
                    hi: b.hi + pad,
                }
            })
            .collect();
        bvh
    }

    /// Visit primitives whose boxes the ray may hit before the current best `t`; `test(i)` returns
    /// a hit distance to shrink the search.
    pub fn traverse(&self, origin: DVec3, dir: DVec3, mut test: impl FnMut(u32) -> Option<f64>) {
        if self.nodes.is_empty() {
            return;
        }
        let inv = dir.recip();
        let mut best = f64::INFINITY;
        let mut stack = Vec::with_capacity(64);
        stack.push(0u32);
        while let Some(n) = stack.pop() {
            let node = self.nodes[n as usize];
            if node.bounds.hit(origin, inv, best).is_none() {
                continue;
            }
            if node.count > 0 {
                let range = node.start as usize..(node.start + node.count) as usize;
                for (&i, b) in self.order[range.clone()]
                    .iter()
                    .zip(&self.leaf_boxes[range])
                {
                    if b.hit(origin, inv, best).is_none() {
                        continue;
                    }
                    if let Some(t) = test(i) {
                        best = best.min(t);
                    }
                }
            } else {
                // Near child last so it is popped first.
                let (a, b) = (node.start, node.start + 1);
                let da = self.nodes[a as usize].bounds.hit(origin, inv, best);
                let db = self.nodes[b as usize].bounds.hit(origin, inv, best);
                match (da, db) {
                    (Some(x), Some(y)) if x < y => stack.extend([b, a]),
                    (Some(_), Some(_)) => stack.extend([a, b]),
                    (Some(_), None) => stack.push(a),
                    (None, Some(_)) => stack.push(b),
                    (None, None) => {}
                }
            }
        }
    }
}
