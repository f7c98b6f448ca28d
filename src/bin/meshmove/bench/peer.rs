//! The 3D peer case for scripts/peer-openfoam.sh: the bench's hexahedral box as a Gmsh file
//! (physical groups = patches, which `gmshToFoam` turns into OpenFOAM patches), the top's
//! displacement as the CSV `meshmove deform` reads, and the case file that holds the box as the
//! bench does (bottom fixed, top clamped, sides sliding).

use super::cases::{box_top_dz, A_3D};
use meshmove::cases::boxes::{structured_box, BoxCells, BOX_BOTTOM, BOX_SIDES, BOX_TOP};
use std::fmt::Write as _;
use std::path::Path;

/// Writes box.msh, top.csv and case.toml for the `n`³ hexahedral box to `dir`.
pub fn write_case(dir: &Path, n: usize) -> Result<(), String> {
    let mesh = structured_box(n, BoxCells::Hexes);
    let msh = dir.join("box.msh");
    meshmove::io::write_msh22(&mesh, &msh).map_err(|e| format!("{}: {e}", msh.display()))?;
    let mut csv = String::from("vertex,dx,dy,dz\n");
    for v in mesh.patch_vertices(BOX_TOP) {
        let p = mesh.point(v as usize);
        let _ = writeln!(csv, "{v},0,0,{:?}", box_top_dz(p[0], p[1]));
    }
    let mut toml = format!(
        "# The bench's 3D free-surface box ({n}^3 hexahedra): top moved by {A_3D} cos 2πx cos 2πy in z.\n\
         method = \"biharmonic\"\ntolerance = 1e-8\nthreads = 1\n\n\
         [[patch]]\npatch = {BOX_BOTTOM}\nkind = \"fixed\"\n\n\
         [[patch]]\npatch = {BOX_TOP}\nkind = \"clamped\"\n"
    );
    for (p, normal) in BOX_SIDES {
        let kinds: Vec<&str> = (0..3).map(|c| if c == normal { "\"fixed\"" } else { "\"free\"" }).collect();
        let _ = write!(toml, "\n[[patch]]\npatch = {p}\nkind = [{}]\n", kinds.join(", "));
    }
    let _ = write!(toml, "\n[[motion]]\nfile = \"top.csv\"\npatch = {BOX_TOP}\n");
    for (name, text) in [("top.csv", csv), ("case.toml", toml)] {
        let path = dir.join(name);
        std::fs::write(&path, text).map_err(|e| format!("{}: {e}", path.display()))?;
    }
    println!("wrote {} ({} vertices), top.csv, case.toml", msh.display(), mesh.num_vertices());
    Ok(())
}
