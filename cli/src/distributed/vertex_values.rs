//! Per-vertex arrays between the whole mesh, held by rank 0, and the ranks' parts: a value for
//! every local vertex of each part sent from rank 0 (the motion of a step), and the owned
//! vertices' values of every rank gathered on rank 0 in global order (the moved points).

use super::wire;
use meshmove::distributed::mpi::topology::SimpleCommunicator;
use meshmove::distributed::mpi::traits::*;

/// On rank 0 (`all`: the global ids of each rank's local vertices, and `per` values for every
/// vertex of the mesh): sends each rank its vertices' values and returns its own. On the other
/// ranks (`all` None): the values rank 0 sent. Collective.
pub fn scatter(world: &SimpleCommunicator, all: Option<(&[Vec<u64>], &[f64])>, per: usize) -> Vec<f64> {
    let Some((gids, values)) = all else { return wire::receive(world) };
    let of = |g: &[u64]| -> Vec<f64> {
        g.iter().flat_map(|&v| values[v as usize * per..(v as usize + 1) * per].iter().copied()).collect()
    };
    for (r, g) in gids.iter().enumerate().skip(1) {
        wire::send(world, r, &of(g));
    }
    of(&gids[0])
}

/// Every rank's values (`per` per local vertex, `gids` their global ids) on the vertices whose
/// `owned` flag is set, put in global order on rank 0 (`vertices`: of the whole mesh); None on
/// the other ranks. Collective.
pub fn gather(
    world: &SimpleCommunicator,
    (gids, owned): (&[u64], &[bool]),
    values: &[f64],
    per: usize,
    vertices: usize,
) -> Option<Vec<f64>> {
    let mine: Vec<u64> = gids.iter().zip(owned).filter(|(_, &o)| o).map(|(&g, _)| g).collect();
    let vals: Vec<f64> =
        values.chunks_exact(per).zip(owned).filter(|(_, &o)| o).flat_map(|(v, _)| v.iter().copied()).collect();
    if world.rank() != 0 {
        wire::send(world, 0, &mine);
        wire::send(world, 0, &vals);
        return None;
    }
    let mut out = vec![0.0; vertices * per];
    let mut put = |g: &[u64], v: &[f64]| {
        for (&g, x) in g.iter().zip(v.chunks_exact(per)) {
            if let Some(slot) = out.get_mut(g as usize * per..(g as usize + 1) * per) {
                slot.copy_from_slice(x);
            }
        }
    };
    put(&mine, &vals);
    for r in 1..world.size() as usize {
        let g: Vec<u64> = wire::receive_from(world, r);
        let v: Vec<f64> = wire::receive_from(world, r);
        put(&g, &v);
    }
    Some(out)
}
