//! STUB replaced by the coarsening branch.
use crate::Mesh;
#[derive(Clone, Debug)]
pub struct CoarsenParams {
    pub min_vertices: usize,
    pub min_ratio: f64,
    pub corner_angle_deg: f64,
}
impl Default for CoarsenParams {
    fn default() -> Self {
        CoarsenParams {
            min_vertices: 40,
            min_ratio: 1.6,
            corner_angle_deg: 50.0,
        }
    }
}
pub struct CoarseMesh {
    pub mesh: Mesh,
    pub fine_vertex: Vec<u32>,
    pub links: Vec<[u32; 2]>,
}
pub fn coarsen(
    _fine: &Mesh,
    _links: &[[u32; 2]],
    _params: &CoarsenParams,
) -> crate::Result<Option<CoarseMesh>> {
    Ok(None)
}
