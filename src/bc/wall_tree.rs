//! A bounding-box tree over the simplices of a piecewise-linear SLIP wall, for its closest-point
//! queries (`slip_walls`). A wall's faces are as graded as the mesh next to it (a wall layer's
//! faces are orders of magnitude smaller than the far field's), so any uniform grid holds
//! thousands of faces in its cells near a body; the tree's boxes follow the faces' sizes, and a
//! query visits the boxes nearest first and skips every box farther than the best point found.

/// Simplices per leaf at most.
const LEAF: usize = 4;

/// A node: the box of its simplices and either its two children or its leaf's simplices.
#[derive(Clone, Debug)]
struct Node {
    lo: [f64; 3],
    hi: [f64; 3],
    /// Inner node: the children's indices; leaf: the range of `WallTree::order` it holds, as
    /// (start, end) with `leaf` set.
    a: u32,
    b: u32,
    leaf: bool,
}

/// The tree: nodes, the root first, and the simplices in leaf order.
#[derive(Clone, Debug)]
pub(super) struct WallTree {
    nodes: Vec<Node>,
    order: Vec<u32>,
}

/// The squared distance from `p` to the box `lo`–`hi` (zero inside).
fn box_d2(lo: &[f64; 3], hi: &[f64; 3], p: &[f64; 3]) -> f64 {
    (0..3).map(|c| (lo[c] - p[c]).max(p[c] - hi[c]).max(0.0)).map(|d| d * d).sum()
}

impl WallTree {
    /// The tree of simplices whose boxes are `boxes` (lower and upper corners; a simplex's box
    /// covers every point it can return as a closest point).
    pub(super) fn new(boxes: &[([f64; 3], [f64; 3])]) -> WallTree {
        let mut tree = WallTree { nodes: Vec::new(), order: (0..boxes.len() as u32).collect() };
        if !boxes.is_empty() {
            tree.split(boxes, 0, boxes.len());
        }
        tree
    }

    /// Adds the node of `order[start..end]` and its subtree; returns its index.
    fn split(&mut self, boxes: &[([f64; 3], [f64; 3])], start: usize, end: usize) -> u32 {
        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        let (mut clo, mut chi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        let centre = |s: u32, c: usize| 0.5 * (boxes[s as usize].0[c] + boxes[s as usize].1[c]);
        for &s in &self.order[start..end] {
            let (a, b) = &boxes[s as usize];
            for c in 0..3 {
                lo[c] = lo[c].min(a[c]);
                hi[c] = hi[c].max(b[c]);
                clo[c] = clo[c].min(centre(s, c));
                chi[c] = chi[c].max(centre(s, c));
            }
        }
        let k = self.nodes.len();
        self.nodes.push(Node { lo, hi, a: start as u32, b: end as u32, leaf: true });
        if end - start <= LEAF {
            return k as u32;
        }
        // Halved at the median of the box centres along their widest spread; ties by index, so
        // the tree does not depend on the sort's order.
        let axis = (0..3).max_by(|&x, &y| (chi[x] - clo[x]).total_cmp(&(chi[y] - clo[y]))).unwrap_or(0);
        let mid = start + (end - start) / 2;
        self.order[start..end]
            .select_nth_unstable_by(mid - start, |&s, &t| centre(s, axis).total_cmp(&centre(t, axis)).then(s.cmp(&t)));
        let a = self.split(boxes, start, mid);
        let b = self.split(boxes, mid, end);
        self.nodes[k] = Node { lo, hi, a, b, leaf: false };
        k as u32
    }

    /// The simplex whose point `closest_on(s)` is nearest to `p`, and that point (`p` itself when
    /// the tree is empty). Of equally near simplices the lowest index wins, whatever order the
    /// boxes were visited in.
    pub(super) fn closest(&self, p: &[f64; 3], closest_on: impl Fn(usize) -> [f64; 3]) -> [f64; 3] {
        let (mut best, mut best_d2, mut best_s) = (*p, f64::INFINITY, u32::MAX);
        if self.nodes.is_empty() {
            return best;
        }
        let mut stack: Vec<(f64, u32)> = vec![(box_d2(&self.nodes[0].lo, &self.nodes[0].hi, p), 0)];
        while let Some((d2, k)) = stack.pop() {
            if d2 > best_d2 {
                continue;
            }
            let node = &self.nodes[k as usize];
            if node.leaf {
                for &s in &self.order[node.a as usize..node.b as usize] {
                    let q = closest_on(s as usize);
                    let e2: f64 = (0..3).map(|c| (q[c] - p[c]) * (q[c] - p[c])).sum();
                    if e2 < best_d2 || (e2 == best_d2 && s < best_s) {
                        (best, best_d2, best_s) = (q, e2, s);
                    }
                }
                continue;
            }
            let da = box_d2(&self.nodes[node.a as usize].lo, &self.nodes[node.a as usize].hi, p);
            let db = box_d2(&self.nodes[node.b as usize].lo, &self.nodes[node.b as usize].hi, p);
            // The nearer child is popped first.
            if da <= db {
                stack.push((db, node.b));
                stack.push((da, node.a));
            } else {
                stack.push((da, node.a));
                stack.push((db, node.b));
            }
        }
        best
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::closest::closest_on_segment;
    use std::cell::Cell;

    /// A wall graded as a wall layer's edge is: 2 000 segments along y = 0 whose lengths grow
    /// geometrically from 1e-7 to 1 away from x = 0. The tree finds the brute force's closest
    /// point, and a query evaluates a few dozen segments, not the thousands a uniform grid's
    /// cell next to x = 0 holds.
    #[test]
    fn a_graded_wall_is_searched_in_few_evaluations() {
        let n = 2000;
        let ratio = (1e7f64).powf(1.0 / n as f64);
        let mut xs = vec![0.0];
        let mut h = 1e-7;
        for _ in 0..n {
            xs.push(xs.last().unwrap() + h);
            h *= ratio;
        }
        let segs: Vec<[[f64; 3]; 2]> = (0..n).map(|k| [[xs[k], 0.0, 0.0], [xs[k + 1], 0.0, 0.0]]).collect();
        let boxes: Vec<([f64; 3], [f64; 3])> = segs.iter().map(|s| (s[0], s[1])).collect();
        let tree = WallTree::new(&boxes);
        let d2 = |q: &[f64; 3], p: &[f64; 3]| (0..3).map(|c| (q[c] - p[c]).powi(2)).sum::<f64>();
        let mut most = 0;
        for k in (0..=n).step_by(7) {
            for dy in [0.0, 1e-9, 3e-3] {
                let p = [xs[k] * 0.999 + 1e-8, dy, 0.0];
                let calls = Cell::new(0usize);
                let got = tree.closest(&p, |s| {
                    calls.set(calls.get() + 1);
                    closest_on_segment(&segs[s][0], &segs[s][1], &p)
                });
                let want = segs
                    .iter()
                    .map(|s| closest_on_segment(&s[0], &s[1], &p))
                    .min_by(|a, b| d2(a, &p).total_cmp(&d2(b, &p)))
                    .unwrap();
                assert_eq!(d2(&got, &p), d2(&want, &p), "{p:?}: {got:?} vs {want:?}");
                most = most.max(calls.get());
            }
        }
        assert!(most <= 64, "a query evaluated {most} segments");
    }

    /// Of simplices equally near, the lowest index wins, though its box is visited last; an
    /// empty tree returns the point.
    #[test]
    fn ties_go_to_the_lowest_index() {
        let mut boxes = vec![([0.0, 0.0, 0.0], [1.0, 0.0, 0.0]); 9];
        boxes[0] = ([10.0, 0.0, 0.0], [11.0, 0.0, 0.0]);
        let tree = WallTree::new(&boxes);
        let order = std::cell::RefCell::new(Vec::new());
        // Every simplex's point is 10 from p; simplex 0's box is the farthest.
        let got = tree.closest(&[0.5, 1.0, 0.0], |s| {
            order.borrow_mut().push(s);
            if s == 0 {
                [0.5, 11.0, 0.0]
            } else {
                [0.5, -9.0, 0.0]
            }
        });
        assert_eq!(order.borrow().last(), Some(&0));
        assert_eq!(got, [0.5, 11.0, 0.0]);
        assert_eq!(WallTree::new(&[]).closest(&[1.0, 2.0, 3.0], |_| unreachable!()), [1.0, 2.0, 3.0]);
    }
}
