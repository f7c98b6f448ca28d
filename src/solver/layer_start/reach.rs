//! Distances through a level's graph: from every unknown to the nearest of a set of sources,
//! along K's couplings measured between the unknowns' positions (`layer_start`'s blend).

use crate::sparse::CsrMatrix;
use std::cmp::Reverse;
use std::collections::BinaryHeap;

/// A distance and the unknown it belongs to, ordered by the distance and then the unknown (the
/// ties broken the same way on every run).
#[derive(Clone, Copy, PartialEq)]
struct Reached(f64, usize);

impl Eq for Reached {}

impl PartialOrd for Reached {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Reached {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.0.total_cmp(&other.0).then(self.1.cmp(&other.1))
    }
}

/// Per unknown of `k`'s graph (positions `points`, `dim` values each), the shortest distance
/// along its couplings to an unknown with `source` set and which source that is; infinite (and
/// None) where none is reached.
pub(super) fn nearest(k: &CsrMatrix, points: &[f64], dim: usize, source: &[bool]) -> (Vec<f64>, Vec<Option<usize>>) {
    let mut from = vec![None; source.len()];
    let dist = search(k, points, dim, source, Some(&mut from));
    (dist, from)
}

/// Per unknown, the shortest distance along `k`'s couplings to an unknown with `source` set, as
/// [`nearest`] without which source it is.
pub(super) fn distances(k: &CsrMatrix, points: &[f64], dim: usize, source: &[bool]) -> Vec<f64> {
    search(k, points, dim, source, None)
}

/// A multi-source Dijkstra from the unknowns with `source` set: the distances, and in `from`
/// (when asked for) the source each unknown is reached from.
fn search(
    k: &CsrMatrix,
    points: &[f64],
    dim: usize,
    source: &[bool],
    mut from: Option<&mut Vec<Option<usize>>>,
) -> Vec<f64> {
    let n = source.len();
    let at = |i: usize| &points[i * dim..(i + 1) * dim];
    let mut dist = vec![f64::INFINITY; n];
    let mut heap = BinaryHeap::new();
    for (i, _) in source.iter().enumerate().filter(|(_, &s)| s) {
        dist[i] = 0.0;
        if let Some(f) = from.as_deref_mut() {
            f[i] = Some(i);
        }
        heap.push(Reverse(Reached(0.0, i)));
    }
    while let Some(Reverse(Reached(d, i))) = heap.pop() {
        if d > dist[i] {
            continue;
        }
        for &j in &k.cols[k.row_ptr[i] as usize..k.row_ptr[i + 1] as usize] {
            let j = j as usize;
            let len: f64 = at(i).iter().zip(at(j)).map(|(a, b)| (a - b) * (a - b)).sum::<f64>().sqrt();
            let dj = d + len;
            if dj < dist[j] {
                dist[j] = dj;
                if let Some(f) = from.as_deref_mut() {
                    f[j] = f[i];
                }
                heap.push(Reverse(Reached(dj, j)));
            }
        }
    }
    dist
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A path of four unknowns on the x axis at 0, 1, 3 and 6: the distances along it to the
    /// sources, and which source each unknown reaches first.
    #[test]
    fn distances_along_a_path() {
        let pairs = vec![(0, 0), (0, 1), (1, 0), (1, 1), (1, 2), (2, 1), (2, 2), (2, 3), (3, 2), (3, 3)];
        let k = CsrMatrix::from_pattern(4, 4, pairs);
        let points = [0.0, 1.0, 3.0, 6.0];
        let (dist, from) = nearest(&k, &points, 1, &[true, false, false, true]);
        assert_eq!(dist, vec![0.0, 1.0, 3.0, 0.0]);
        assert_eq!(from, vec![Some(0), Some(0), Some(3), Some(3)]);
        assert_eq!(distances(&k, &points, 1, &[true, false, false, true]), dist);
        let (dist, from) = nearest(&k, &points, 1, &[false; 4]);
        assert!(dist.iter().all(|d| d.is_infinite()) && from.iter().all(Option::is_none));
    }
}
