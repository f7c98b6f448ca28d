//! The cells of a mesh split into parts by METIS: a k-way partition of the cells' dual graph
//! (two cells are neighbours when they share a face: `dim` vertices), balanced in cell count
//! and with few cut faces, so that each rank's halo is small. METIS is the partitioner
//! finite-volume codes already use (ParMETIS's serial core); its partition is deterministic for a
//! given mesh and part count (a fixed seed), so a run's parts, and with them its results, repeat.

use meshmove::MeshData;

/// The seed of METIS's random choices: fixed, so the same mesh gives the same parts.
const SEED: metis::Idx = 1;

/// The part (0..parts) of each cell of `data`. Every part gets at least one cell; an error when
/// the mesh has fewer cells than parts, is too large for METIS's 32-bit indices, or METIS fails.
pub fn partition(data: &MeshData, parts: usize) -> Result<Vec<usize>, String> {
    let cells = data.num_cells();
    if parts == 0 || cells < parts {
        return Err(format!("{cells} cells cannot be split into {parts} parts (one rank needs a cell at least)"));
    }
    if parts == 1 {
        return Ok(vec![0; cells]);
    }
    let idx = |x: usize| metis::Idx::try_from(x).map_err(|_| format!("{x} is too large for METIS's 32-bit indices"));
    let eptr = data.cell_offsets.iter().map(|&o| idx(o as usize)).collect::<Result<Vec<_>, _>>()?;
    let eind = data.cell_vertices.iter().map(|&v| idx(v as usize)).collect::<Result<Vec<_>, _>>()?;
    let dual = metis::mesh_to_dual(&eptr, &eind, idx(data.dim)?).map_err(|e| format!("METIS: {e}"))?;
    let (xadj, adjncy) = (dual.xadj().to_vec(), dual.adjncy().to_vec());
    let mut part = vec![0; cells];
    metis::Graph::new(1, idx(parts)?, &xadj, &adjncy)
        .map_err(|e| format!("METIS: {e}"))?
        .set_option(metis::option::Seed(SEED))
        .part_kway(&mut part)
        .map_err(|e| format!("METIS: {e}"))?;
    let part: Vec<usize> = part.into_iter().map(|p| usize::try_from(p).unwrap_or(usize::MAX)).collect();
    let mut count = vec![0usize; parts];
    for &p in &part {
        match count.get_mut(p) {
            Some(n) => *n += 1,
            None => return Err(format!("METIS returned part {p} of {parts}")),
        }
    }
    match count.iter().position(|&n| n == 0) {
        Some(p) => Err(format!("METIS left part {p} of {parts} empty: the mesh is too small for {parts} ranks")),
        None => Ok(part),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use meshmove::CellType;

    /// nx × ny unit squares.
    fn grid(nx: usize, ny: usize) -> MeshData {
        let mut d = MeshData::new(2);
        for j in 0..=ny {
            for i in 0..=nx {
                d.push_vertex(&[i as f64, j as f64]);
            }
        }
        let v = |i: usize, j: usize| (j * (nx + 1) + i) as u32;
        for j in 0..ny {
            for i in 0..nx {
                d.push_cell(CellType::Quad, &[v(i, j), v(i + 1, j), v(i + 1, j + 1), v(i, j + 1)], 0);
            }
        }
        d
    }

    #[test]
    fn parts_are_balanced_repeatable_and_compact() {
        let d = grid(32, 32);
        let part = partition(&d, 4).unwrap();
        assert_eq!(part, partition(&d, 4).unwrap());
        let mut count = [0usize; 4];
        part.iter().for_each(|&p| count[p] += 1);
        // Balanced within METIS's default imbalance of 3 %.
        assert!(count.iter().all(|&n| (248..=264).contains(&n)), "{count:?}");
        // Few cut faces: four quarters cut 64 of the 1984 interior faces; a scattered split cuts
        // most of them.
        let cut = (0..32 * 32)
            .filter(|&c| c % 32 < 31)
            .filter(|&c| part[c] != part[c + 1])
            .chain((0..32 * 31).filter(|&c| part[c] != part[c + 32]))
            .count();
        assert!(cut <= 128, "{cut} cut faces");
    }

    #[test]
    fn too_few_cells_is_an_error() {
        assert_eq!(partition(&grid(2, 1), 1).unwrap(), vec![0, 0]);
        let e = partition(&grid(2, 1), 3).unwrap_err();
        assert!(e.contains("2 cells cannot be split into 3 parts"), "{e}");
    }
}
