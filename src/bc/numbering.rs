//! The order of a level's unknowns: reverse Cuthill–McKee on the mesh graph.
//!
//! Every operator application gathers x over the neighbours of each row, so its speed on a large
//! mesh depends on how close neighbours are in memory. Mesh generators and refinement number
//! vertices in whatever order they were made (on the bench's refined meshes, edge midpoints in
//! cell order, scattered across the array), which makes the biharmonic operator 2.6× slower at
//! 1M vertices. Numbering the unknowns by breadth-first level sets keeps each row's neighbours
//! within a band about one mesh width wide, so the gathers hit cache whatever the caller's
//! numbering. Only the solver's unknowns are renumbered: meshes, coarsening and the results the
//! caller sees keep the caller's vertex numbers.

use crate::mesh::{Csr, VertexCells};
use crate::sparse::offset;

/// New-to-old order of `n` unknowns connected by the edges of `cells`, and where each connected
/// part of them starts in that order (ascending, the first 0; each part is numbered in one run).
/// Deterministic: ties break by index.
pub(crate) fn reverse_cuthill_mckee(n: usize, cells: &Csr) -> (Vec<u32>, Vec<u32>) {
    let (ptr, adj) = adjacency(n, cells);
    let degree = |v: u32| ptr[v as usize + 1] - ptr[v as usize];
    let neighbours = |v: u32| &adj[ptr[v as usize] as usize..ptr[v as usize + 1] as usize];
    let mut order: Vec<u32> = Vec::with_capacity(n);
    let mut seen = vec![false; n];
    // Scratch of the breadth-first search that looks for a far start vertex.
    let mut stamp = vec![u32::MAX; n];
    let mut queue: Vec<u32> = Vec::new();
    let mut next: Vec<u32> = Vec::new();
    // Where each part ends in `order` before it is reversed.
    let mut ends: Vec<usize> = Vec::new();
    for first in 0..n as u32 {
        if seen[first as usize] {
            continue;
        }
        // One George–Liu step: start from a minimum-degree vertex of the last level set of a
        // search from `first`, a vertex far out on this connected part.
        queue.clear();
        queue.push(first);
        stamp[first as usize] = first;
        let mut level_start = 0;
        let mut head = 0;
        while head < queue.len() {
            level_start = head;
            let end = queue.len();
            for q in head..end {
                for &w in neighbours(queue[q]) {
                    if stamp[w as usize] != first {
                        stamp[w as usize] = first;
                        queue.push(w);
                    }
                }
            }
            head = end;
        }
        let start = *queue[level_start..].iter().min_by_key(|&&v| (degree(v), v)).expect("a last level");
        // Cuthill–McKee from there: neighbours by increasing degree.
        let base = order.len();
        order.push(start);
        seen[start as usize] = true;
        let mut h = base;
        while h < order.len() {
            let v = order[h];
            h += 1;
            next.clear();
            next.extend(neighbours(v).iter().copied().filter(|&w| !seen[w as usize]));
            next.sort_unstable_by_key(|&w| (degree(w), w));
            for &w in &next {
                seen[w as usize] = true;
                order.push(w);
            }
        }
        ends.push(order.len());
    }
    order.reverse();
    let starts = ends.iter().rev().map(|&e| offset(n - e)).collect();
    (order, starts)
}

/// The graph of the cells' edges as CSR without the diagonal: each unknown's neighbours are the
/// other corners of its cells (`VertexCells`, linear in the mesh), each once, in order of first
/// appearance (a mark per unknown, no sort). The order within a row does not matter to the
/// numbering: its level sets do not depend on it, and both of its choices among neighbours
/// (the start vertex, the order of a vertex's new neighbours) are by (degree, index).
fn adjacency(n: usize, cells: &Csr) -> (Vec<u32>, Vec<u32>) {
    let around = VertexCells::build(n, cells);
    let mut ptr = vec![0u32; n + 1];
    let mut adj = Vec::with_capacity(cells.items().len());
    // mark[w] == v + 1: w is already in v's row (0 marks nothing, so no pass resets it).
    let mut mark = vec![0usize; n];
    for v in 0..n {
        mark[v] = v + 1;
        for &w in around.of(v).iter().flat_map(|&c| cells.get(c as usize)) {
            if mark[w as usize] != v + 1 {
                mark[w as usize] = v + 1;
                adj.push(w);
            }
        }
        ptr[v + 1] = offset(adj.len());
    }
    (ptr, adj)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn csr(cells: &[[u32; 3]]) -> Csr {
        let mut c = Csr::new();
        cells.iter().for_each(|t| c.push(t));
        c
    }

    /// A strip of 2×m squares numbered badly (even columns first, then odd): the order must be a
    /// permutation and bring the bandwidth down to a few columns.
    #[test]
    fn permutation_with_small_bandwidth() {
        let m = 200u32;
        // Vertex (i, j), i in 0..=m, j in 0..=1, numbered with odd i after all even i.
        let id = |i: u32, j: u32| if i % 2 == 0 { (i / 2) * 2 + j } else { (m / 2 + 1) * 2 + (i / 2) * 2 + j };
        let mut cells = Vec::new();
        for i in 0..m {
            cells.push([id(i, 0), id(i + 1, 0), id(i + 1, 1)]);
            cells.push([id(i, 0), id(i + 1, 1), id(i, 1)]);
        }
        let n = 2 * (m as usize + 1);
        let bw = |new_of: &dyn Fn(u32) -> i64| {
            cells
                .iter()
                .flat_map(|t| (0..3).map(move |k| (t[k], t[(k + 1) % 3])))
                .map(|(a, b)| (new_of(a) - new_of(b)).abs())
                .max()
                .unwrap()
        };
        assert!(bw(&|v| v as i64) > 100);
        let (order, parts) = reverse_cuthill_mckee(n, &csr(&cells));
        assert_eq!(parts, [0]);
        let mut new_of = vec![u32::MAX; n];
        for (k, &v) in order.iter().enumerate() {
            assert_eq!(new_of[v as usize], u32::MAX, "vertex {v} twice");
            new_of[v as usize] = k as u32;
        }
        assert!(bw(&|v| new_of[v as usize] as i64) <= 3);
    }

    /// Two disconnected triangles and an isolated index: every index appears once.
    #[test]
    fn disconnected_parts_and_isolated_unknowns() {
        let (order, parts) = reverse_cuthill_mckee(7, &csr(&[[0, 1, 2], [4, 5, 6]]));
        // Three parts, each a run of the order: {4, 5, 6}, the isolated 3, {0, 1, 2}.
        assert_eq!(parts, [0, 3, 4]);
        let part_of = |v: u32| parts.partition_point(|&s| s as usize <= order.iter().position(|&o| o == v).unwrap());
        assert!(part_of(0) == part_of(2) && part_of(4) == part_of(6) && part_of(0) != part_of(4) && part_of(3) != part_of(0));
        let mut sorted = order.clone();
        sorted.sort_unstable();
        assert_eq!(sorted, (0..7).collect::<Vec<u32>>());
    }
}
