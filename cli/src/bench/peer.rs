//! The 3D peer case for scripts/peer-openfoam.sh: the bench's hexahedral box as a Gmsh file
//! (physical groups = patches), the top's displacement as the CSV `meshmove deform` reads, the
//! case file that holds the box as the bench does (bottom fixed, top clamped, sides sliding),
//! and the same mesh and motion as an OpenFOAM case for `moveMesh` with `displacementLaplacian`.

use super::cases::{box_top_dz, A_3D};
use meshmove_cases::boxes::{structured_box, BoxCells, BOX_BOTTOM, BOX_SIDES, BOX_TOP};
use std::fmt::Write as _;
use std::path::Path;

/// Writes box.msh, top.csv, case.toml and the OpenFOAM case foam/ for the `n`³ hexahedral box
/// to `dir`.
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
    write_foam_case(&dir.join("foam"), n)?;
    println!(
        "wrote {} ({} vertices), top.csv, case.toml, foam/ (the OpenFOAM case)",
        msh.display(),
        mesh.num_vertices()
    );
    Ok(())
}

/// A FoamFile header of class `class` for object `object`.
fn foam_header(class: &str, location: &str, object: &str) -> String {
    format!(
        "FoamFile\n{{\n    version     2.0;\n    format      ascii;\n    class       {class};\n    location    \"{location}\";\n    object      {object};\n}}\n\n"
    )
}

/// The `n`³ hexahedral box as an OpenFOAM case in `dir`: constant/polyMesh written here (the
/// same points in the same order as box.msh, cell (i, j, k) numbered i + n (j + n k)), the
/// top's displacement as the nonuniform value of `0/pointDisplacement` (in the order OpenFOAM
/// numbers a patch's points: first appearance in its faces), and `displacementLaplacian`
/// solved by GAMG to a 1e-8 residual with relTol 0 (converged, not one sweep per step).
pub fn write_foam_case(dir: &Path, n: usize) -> Result<(), String> {
    let n1 = n + 1;
    let pid = |g: [usize; 3]| (g[2] * n1 + g[1]) * n1 + g[0];
    let cid = |i: usize, j: usize, k: usize| i + n * (j + n * k);
    // The face of the grid square with lower corner `g` normal to `axis`, its normal along
    // +axis (`positive`) or −axis (right-hand rule over the point order).
    let face = |axis: usize, g: [usize; 3], positive: bool| {
        let (u, w) = ((axis + 1) % 3, (axis + 2) % 3);
        let at = |du: usize, dw: usize| {
            let mut p = g;
            p[u] += du;
            p[w] += dw;
            pid(p)
        };
        if positive {
            [at(0, 0), at(1, 0), at(1, 1), at(0, 1)]
        } else {
            [at(0, 0), at(0, 1), at(1, 1), at(1, 0)]
        }
    };
    let mut faces: Vec<[usize; 4]> = Vec::new();
    let mut owner: Vec<usize> = Vec::new();
    let mut neighbour: Vec<usize> = Vec::new();
    // Internal faces in upper-triangular order: by owner, then by neighbour (+x, +y, +z).
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                let c = cid(i, j, k);
                let g = [i, j, k];
                for axis in 0..3 {
                    if g[axis] + 1 < n {
                        let mut q = g;
                        q[axis] += 1;
                        faces.push(face(axis, q, true));
                        owner.push(c);
                        neighbour.push(cid(q[0], q[1], q[2]));
                    }
                }
            }
        }
    }
    let n_internal = faces.len();
    // Boundary faces, one patch after another, normals outward.
    let patches: [(&str, usize, bool); 6] =
        [("bottom", 2, false), ("top", 2, true), ("x0", 0, false), ("x1", 0, true), ("y0", 1, false), ("y1", 1, true)];
    let mut bounds = String::new();
    let mut top_points: Vec<usize> = Vec::new();
    let mut seen = vec![false; n1 * n1 * n1];
    for (name, axis, high) in patches {
        let start = faces.len();
        let (u, w) = ((axis + 1) % 3, (axis + 2) % 3);
        for b in 0..n {
            for a in 0..n {
                let mut g = [0; 3];
                g[u] = a;
                g[w] = b;
                let mut cell = g;
                if high {
                    g[axis] = n;
                    cell[axis] = n - 1;
                }
                let f = face(axis, g, high);
                if name == "top" {
                    for p in f {
                        if !seen[p] {
                            seen[p] = true;
                            top_points.push(p);
                        }
                    }
                }
                faces.push(f);
                owner.push(cid(cell[0], cell[1], cell[2]));
            }
        }
        let _ = write!(
            bounds,
            "    {name}\n    {{\n        type            patch;\n        nFaces          {};\n        startFace       {start};\n    }}\n",
            faces.len() - start
        );
    }
    let (np, nc, nf) = (n1 * n1 * n1, n * n * n, faces.len());
    let note = format!("nPoints:{np}  nCells:{nc}  nFaces:{nf}  nInternalFaces:{n_internal}");
    let mesh_dir = dir.join("constant/polyMesh");
    for sub in ["constant/polyMesh", "system", "0"] {
        std::fs::create_dir_all(dir.join(sub)).map_err(|e| format!("{}: {e}", dir.join(sub).display()))?;
    }
    let mut points = foam_header("vectorField", "constant/polyMesh", "points");
    let _ = write!(points, "{np}\n(\n");
    let step = 1.0 / n as f64;
    for k in 0..n1 {
        for j in 0..n1 {
            for i in 0..n1 {
                let x = |a: usize| if a == n { 1.0 } else { a as f64 * step };
                let _ = writeln!(points, "({:?} {:?} {:?})", x(i), x(j), x(k));
            }
        }
    }
    points.push_str(")\n");
    let mut fs = foam_header("faceList", "constant/polyMesh", "faces");
    let _ = write!(fs, "{nf}\n(\n");
    for f in &faces {
        let _ = writeln!(fs, "4({} {} {} {})", f[0], f[1], f[2], f[3]);
    }
    fs.push_str(")\n");
    let list = |object: &str, v: &[usize]| {
        let mut s = foam_header("labelList", "constant/polyMesh", object).replace(
            &format!("    object      {object};\n"),
            &format!("    note        \"{note}\";\n    object      {object};\n"),
        );
        let _ = write!(s, "{}\n(\n", v.len());
        for x in v {
            let _ = writeln!(s, "{x}");
        }
        s.push_str(")\n");
        s
    };
    let mut boundary = foam_header("polyBoundaryMesh", "constant/polyMesh", "boundary");
    let _ = write!(boundary, "6\n(\n{bounds})\n");
    // The top's displacement, in its points' order of first appearance.
    let mut disp = foam_header("pointVectorField", "0", "pointDisplacement");
    disp.push_str("dimensions      [0 1 0 0 0 0 0];\n\ninternalField   uniform (0 0 0);\n\nboundaryField\n{\n");
    disp.push_str(
        "    bottom\n    {\n        type            fixedValue;\n        value           uniform (0 0 0);\n    }\n",
    );
    let _ = write!(disp, "    top\n    {{\n        type            fixedValue;\n        value           nonuniform List<vector>\n{}\n(\n", top_points.len());
    for &p in &top_points {
        let (i, j) = (p % n1, (p / n1) % n1);
        let x = |a: usize| if a == n { 1.0 } else { a as f64 * step };
        let _ = writeln!(disp, "(0 0 {:?})", box_top_dz(x(i), x(j)));
    }
    disp.push_str(")\n;\n    }\n");
    for side in ["x0", "x1", "y0", "y1"] {
        // Sliding: the normal component held, the tangential ones free.
        let _ = write!(disp, "    {side}\n    {{\n        type            slip;\n    }}\n");
    }
    disp.push_str("}\n");
    let control = foam_header("dictionary", "system", "controlDict")
        + "application     moveMesh;\nstartFrom       startTime;\nstartTime       0;\nstopAt          endTime;\n\
           endTime         1;\ndeltaT          1;\nwriteControl    timeStep;\nwriteInterval   1;\n\
           writeFormat     ascii;\nwritePrecision  12;\nwriteCompression off;\ntimeFormat      general;\n\
           timePrecision   6;\nrunTimeModifiable false;\n\nprofiling\n{\n    active      true;\n    cpuInfo     false;\n\
           memInfo     false;\n    sysInfo     false;\n}\n";
    let schemes = foam_header("dictionary", "system", "fvSchemes")
        + "ddtSchemes\n{\n    default         Euler;\n}\ngradSchemes\n{\n    default         Gauss linear;\n}\n\
           divSchemes\n{\n    default         none;\n}\nlaplacianSchemes\n{\n    default         Gauss linear corrected;\n}\n\
           interpolationSchemes\n{\n    default         linear;\n}\nsnGradSchemes\n{\n    default         corrected;\n}\n";
    let solution = foam_header("dictionary", "system", "fvSolution")
        + "solvers\n{\n    cellDisplacement\n    {\n        solver          GAMG;\n        smoother        GaussSeidel;\n\
           tolerance       1e-8;\n        relTol          0;\n        maxIter         1000;\n    }\n}\n";
    let dynamic = foam_header("dictionary", "constant", "dynamicMeshDict")
        + "dynamicFvMesh   dynamicMotionSolverFvMesh;\nmotionSolverLibs (\"libfvMotionSolvers.so\");\n\
           motionSolver    displacementLaplacian;\nsolver          displacementLaplacian;\n\
           displacementLaplacianCoeffs\n{\n    diffusivity     uniform;\n}\n";
    let files = [
        (mesh_dir.join("points"), points),
        (mesh_dir.join("faces"), fs),
        (mesh_dir.join("owner"), list("owner", &owner)),
        (mesh_dir.join("neighbour"), list("neighbour", &neighbour)),
        (mesh_dir.join("boundary"), boundary),
        (dir.join("0/pointDisplacement"), disp),
        (dir.join("system/controlDict"), control),
        (dir.join("system/fvSchemes"), schemes),
        (dir.join("system/fvSolution"), solution),
        (dir.join("constant/dynamicMeshDict"), dynamic),
    ];
    for (path, text) in files {
        std::fs::write(&path, text).map_err(|e| format!("{}: {e}", path.display()))?;
    }
    Ok(())
}

/// Writes the points of `vtu` as `foam/2/polyMesh/points`: `checkMesh -time 2` then measures
/// our moved mesh as it measures OpenFOAM's (time 1). The .vtu must be the peer box moved (same
/// points, same order as the case's polyMesh).
pub fn write_points(vtu: &Path, foam: &Path) -> Result<(), String> {
    let data = meshmove::io::read_vtu(vtu).map_err(|e| format!("{}: {e}", vtu.display()))?;
    let m = &data.mesh;
    let owner = std::fs::read_to_string(foam.join("constant/polyMesh/owner"))
        .map_err(|e| format!("{}: {e} (write the case with --peer-case first)", foam.display()))?;
    let expected = owner
        .split("nPoints:")
        .nth(1)
        .and_then(|t| t.split_whitespace().next())
        .and_then(|t| t.parse::<usize>().ok())
        .ok_or_else(|| format!("{}: no nPoints in constant/polyMesh/owner", foam.display()))?;
    if m.dim != 3 || m.num_vertices() != expected {
        return Err(format!(
            "{}: {} points in {}D; the OpenFOAM case has {expected} in 3D",
            vtu.display(),
            m.num_vertices(),
            m.dim
        ));
    }
    let dir = foam.join("2/polyMesh");
    std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let mut points = foam_header("vectorField", "2/polyMesh", "points");
    let _ = write!(points, "{}\n(\n", m.num_vertices());
    for p in m.coords.chunks_exact(3) {
        let _ = writeln!(points, "({:?} {:?} {:?})", p[0], p[1], p[2]);
    }
    points.push_str(")\n");
    let path = dir.join("points");
    std::fs::write(&path, points).map_err(|e| format!("{}: {e}", path.display()))?;
    println!("wrote {}", path.display());
    Ok(())
}
