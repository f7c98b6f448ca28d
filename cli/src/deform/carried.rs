//! The parts of a case's boundary conditions that `BoundaryConditions` holds as closures or keeps
//! to itself — the analytic shapes of SLIP walls, the links, the interfaces — kept as plain data
//! as the case file gives them, so that `deform` under mpirun can send them to every rank, which
//! puts them into its own conditions (`Carried::apply`).

use meshmove::bc::SlipSurface;
use meshmove::{BoundaryConditions, InterfaceVariant, Link};

/// The analytic wall of a `[[patch]]` with a `shape` (2D: the z components 0).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum WallShape {
    Sphere { center: [f64; 3], radius: f64 },
    Cylinder { center: [f64; 3], axis: [f64; 3], radius: f64 },
    Plane { point: [f64; 3], normal: [f64; 3] },
}

impl WallShape {
    /// The wall's closest-point surface.
    pub fn surface(&self) -> SlipSurface {
        match *self {
            WallShape::Sphere { center, radius } => SlipSurface::sphere(center, radius),
            WallShape::Cylinder { center, axis, radius } => SlipSurface::cylinder(center, axis, radius),
            WallShape::Plane { point, normal } => SlipSurface::plane(point, normal),
        }
    }
}

/// What a case's conditions hold beside the kinds of its patches.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Carried {
    /// The SLIP patches with an analytic wall, and their walls.
    pub walls: Vec<(i32, WallShape)>,
    /// The `[[link]]`s (by offset).
    pub links: Vec<Link>,
    /// The `[[interface]]`s: a patch and its variant.
    pub interfaces: Vec<(i32, InterfaceVariant)>,
}

impl Carried {
    /// Puts the walls, links and interfaces into `bcs`.
    pub fn apply(&self, bcs: &mut BoundaryConditions) {
        for (p, w) in &self.walls {
            bcs.set_slip_surface(*p, w.surface());
        }
        for l in &self.links {
            bcs.add_link(l.clone());
        }
        for (p, v) in &self.interfaces {
            bcs.set_interface(*p, *v);
        }
    }
}

#[cfg(feature = "mpi")]
pub use message::broadcast;

/// `Carried` as messages from rank 0 to every rank.
#[cfg(feature = "mpi")]
mod message {
    use super::{Carried, WallShape};
    use crate::distributed::case::{code, decode};
    use crate::distributed::wire;
    use meshmove::distributed::mpi::topology::SimpleCommunicator;
    use meshmove::{InterfaceVariant, Link};

    const VARIANTS: [InterfaceVariant; 2] = [InterfaceVariant::Separate, InterfaceVariant::Continuous];

    /// Values per wall: the patch, the shape (0 sphere, 1 cylinder, 2 plane), three vectors and
    /// a radius.
    const WALL: usize = 12;
    /// Values per link: the patches, the offset and the tolerance.
    const LINK: usize = 6;

    fn wall_values(p: i32, w: &WallShape) -> [f64; WALL] {
        let (shape, a, b, r) = match *w {
            WallShape::Sphere { center, radius } => (0.0, center, [0.0; 3], radius),
            WallShape::Cylinder { center, axis, radius } => (1.0, center, axis, radius),
            WallShape::Plane { point, normal } => (2.0, point, normal, 0.0),
        };
        let mut m = [0.0; WALL];
        m[0] = p as f64;
        m[1] = shape;
        m[2..5].copy_from_slice(&a);
        m[5..8].copy_from_slice(&b);
        m[8] = r;
        m
    }

    fn wall_of(m: &[f64]) -> Result<(i32, WallShape), String> {
        let v = |i: usize| [m[i], m[i + 1], m[i + 2]];
        let shape = match m[1] as usize {
            0 => WallShape::Sphere { center: v(2), radius: m[8] },
            1 => WallShape::Cylinder { center: v(2), axis: v(5), radius: m[8] },
            2 => WallShape::Plane { point: v(2), normal: v(5) },
            s => return Err(format!("rank 0 sent an unknown wall shape {s}")),
        };
        Ok((m[0] as i32, shape))
    }

    /// Rank 0's `carried` on every rank (the other ranks pass None). Collective.
    pub fn broadcast(world: &SimpleCommunicator, carried: Option<&Carried>) -> Result<Carried, String> {
        let (mut walls, mut links, mut interfaces) = (Vec::new(), Vec::new(), Vec::new());
        if let Some(c) = carried {
            walls.extend(c.walls.iter().flat_map(|(p, w)| wall_values(*p, w)));
            // A case file gives links by offset only.
            for l in &c.links {
                if let Link::ByOffset { a, b, offset, tol } = l {
                    links.extend([*a as f64, *b as f64].into_iter().chain(*offset).chain([*tol]));
                }
            }
            interfaces.extend(c.interfaces.iter().flat_map(|(p, v)| [*p as f64, code(&VARIANTS, v)]));
        }
        for m in [&mut walls, &mut links, &mut interfaces] {
            wire::broadcast(world, m);
        }
        let short = |what: &str, m: &[f64], n: usize| match m.len() % n {
            0 => Ok(()),
            _ => Err(format!("rank 0 sent short {what}")),
        };
        short("walls", &walls, WALL)?;
        short("links", &links, LINK)?;
        short("interfaces", &interfaces, 2)?;
        Ok(Carried {
            walls: walls.chunks(WALL).map(wall_of).collect::<Result<_, _>>()?,
            links: links
                .chunks(LINK)
                .map(|l| Link::ByOffset { a: l[0] as i32, b: l[1] as i32, offset: [l[2], l[3], l[4]], tol: l[5] })
                .collect(),
            interfaces: interfaces
                .chunks(2)
                .map(|i| Ok((i[0] as i32, decode(&VARIANTS, i[1])?)))
                .collect::<Result<_, String>>()?,
        })
    }
}
