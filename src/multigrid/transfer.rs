//! STUB replaced by the coarsening branch.
use crate::Mesh;
use glam::DVec2;
#[derive(Clone, Copy, Debug)]
pub struct Location {
    pub cell: u32,
    pub weights: [f64; 3],
}
pub fn locate(_coarse: &Mesh, _points: &[DVec2], _regions: &[Option<i32>]) -> Vec<Location> {
    unimplemented!()
}
pub fn update_weights(_coarse: &Mesh, _points: &[DVec2], _locs: &mut [Location]) {
    unimplemented!()
}
