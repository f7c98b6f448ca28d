//! What every rank needs of a case beside its part, sent from rank 0, which read it: the boundary
//! conditions (a kind per patch and component, what the distributed solver takes) and each
//! step's motion (the prescribed displacement of the rank's vertices, every rigid motion).

use super::{vertex_values, wire};
use meshmove::distributed::mpi::topology::SimpleCommunicator;
use meshmove::{BoundaryConditions, Kind, Motion, RigidMotion};

const KINDS: [Kind; 4] = [Kind::Fixed, Kind::Clamped, Kind::Free, Kind::Slip];

/// The index of `x` in `list` as a message value.
pub fn code<T: PartialEq>(list: &[T], x: &T) -> f64 {
    list.iter().position(|y| y == x).unwrap_or(0) as f64
}

/// The entry of `list` a message value names.
pub fn decode<T: Copy>(list: &[T], x: f64) -> Result<T, String> {
    list.get(x as usize).copied().ok_or_else(|| format!("rank 0 sent an unknown code {x}"))
}

/// Rank 0's conditions (`given`: them and the patches whose kinds count, every patch of the
/// mesh) on every rank: the default kinds and each patch's kinds (links, interfaces and slip
/// surfaces are not carried: the distributed solver does not take them). Collective.
pub fn broadcast_conditions(
    world: &SimpleCommunicator,
    given: Option<(&BoundaryConditions, &[i32])>,
) -> Result<BoundaryConditions, String> {
    let mut m: Vec<f64> = Vec::new();
    if let Some((bcs, patches)) = given {
        m.extend(bcs.default_kind.iter().map(|k| code(&KINDS, k)));
        for &p in patches {
            m.push(p as f64);
            m.extend((0..3).map(|c| code(&KINDS, &bcs.kind(p, c))));
        }
    }
    wire::broadcast(world, &mut m);
    let short = || "rank 0 sent short boundary conditions".to_string();
    let mut bcs = BoundaryConditions::new();
    for c in 0..3 {
        bcs.default_kind[c] = decode(&KINDS, *m.get(c).ok_or_else(short)?)?;
    }
    for p in m[3..].chunks(4) {
        let [id, k @ ..] = p else { return Err(short()) };
        for (c, &k) in k.iter().enumerate() {
            bcs.set_kind(*id as i32, c, decode(&KINDS, k)?).map_err(|e| e.to_string())?;
        }
    }
    Ok(bcs)
}

/// Rank 0's `motion` of the whole mesh (`given`: with the global ids of each rank's vertices)
/// on this rank's `dim`-dimensional part: its vertices' displacements and every rigid motion.
/// Collective.
pub fn scatter_motion(
    world: &SimpleCommunicator,
    given: Option<(&[Vec<u64>], &Motion)>,
    dim: usize,
) -> Result<Motion, String> {
    let displacement = vertex_values::scatter(world, given.map(|(g, m)| (g, &m.displacement[..])), dim);
    let mut m: Vec<f64> = given
        .map(|(_, m)| &m.rigid[..])
        .unwrap_or_default()
        .iter()
        .flat_map(|(p, r)| [*p as f64].into_iter().chain(r.translation).chain(r.rotation).chain(r.center))
        .collect();
    wire::broadcast(world, &mut m);
    let rigid = m
        .chunks(10)
        .map(|c| match c {
            [p, x @ ..] if x.len() == 9 => Ok((
                *p as i32,
                RigidMotion {
                    translation: [x[0], x[1], x[2]],
                    rotation: [x[3], x[4], x[5]],
                    center: [x[6], x[7], x[8]],
                },
            )),
            _ => Err("rank 0 sent a short rigid motion".to_string()),
        })
        .collect::<Result<_, String>>()?;
    Ok(Motion { displacement, rigid })
}

/// The patches whose kinds [`broadcast_conditions`] carries for `mesh`: each patch of the mesh,
/// and 0 (the untagged boundary).
pub fn patches_of(mesh: &meshmove::Mesh) -> Vec<i32> {
    let mut ids = mesh.patch_ids();
    if !ids.contains(&0) {
        ids.insert(0, 0);
    }
    ids
}
