//! The sections of a `.msh` file, read into the parser's state, and the mesh built from them.

use super::super::{line_of, IoError};
use super::parser::{Parser, Version};
use super::{GmshType, MshParts};
use crate::geometry::MAX_CORNERS;
use crate::mesh::MeshData;

impl<'a> Parser<'a> {
    pub(super) fn run(mut self) -> Result<MshParts, IoError> {
        match self.token() {
            Some(("$MeshFormat", _)) => self.mesh_format()?,
            Some((t, at)) => return Err(self.err_at(at, format!("expected `$MeshFormat`, found `{t}`"))),
            None => return Err(self.err_at(0, "empty file: expected `$MeshFormat`".into())),
        }
        while let Some((t, at)) = self.token() {
            match t {
                "$PhysicalNames" => self.physical_names()?,
                "$Entities" if self.version == Version::V41 => self.entities()?,
                "$Nodes" => self.nodes_section()?,
                "$Elements" => self.elements_section()?,
                _ if t.starts_with('$') && !t.starts_with("$End") => self.skip_section(&t[1..], at)?,
                _ => return Err(self.err_at(at, format!("expected a section header such as `$Nodes`, found `{t}`"))),
            }
        }
        if !self.seen_nodes {
            return Err(self.err_at(self.b.len(), "the file has no $Nodes section".into()));
        }
        if !self.seen_elements {
            return Err(self.err_at(self.b.len(), "the file has no $Elements section".into()));
        }
        self.finish()
    }

    pub(super) fn mesh_format(&mut self) -> Result<(), IoError> {
        let (v, at) =
            self.token().ok_or_else(|| self.err_at(self.b.len(), "expected the version in $MeshFormat".into()))?;
        self.version = match v {
            "2.2" => Version::V22,
            "4.1" => Version::V41,
            "1" | "1.0" | "2" | "2.0" | "2.1" | "3" | "3.0" | "4" | "4.0" => {
                return Err(IoError::Unsupported(format!(
                    "MSH version {v} (line {}); versions 2.2 and 4.1 are read",
                    line_of(self.b, at)
                )))
            }
            _ => {
                return Err(self.err_at(at, format!("expected a MSH version (2.2 or 4.1) in $MeshFormat, found `{v}`")))
            }
        };
        let file_type: i32 = self.num("file type (0 ASCII, 1 binary) in $MeshFormat")?;
        let data_size: usize = self.num("data size in $MeshFormat")?;
        match file_type {
            0 => {}
            1 => {
                self.binary = true;
                if data_size != 4 && data_size != 8 {
                    return Err(IoError::Unsupported(format!(
                        "binary MSH with data size {data_size} (4 or 8 expected)"
                    )));
                }
                self.size_t = data_size;
                // One newline, then the check integer 1 in the writer's byte order.
                self.skip_newline();
                let at = self.pos;
                let one = self.bytes::<4>("the integer 1 in $MeshFormat")?;
                if i32::from_le_bytes(one) == 1 {
                    self.swap = false;
                } else if i32::from_be_bytes(one) == 1 {
                    self.swap = true;
                } else {
                    return Err(self.err_bin(at, format!("expected the integer 1 in $MeshFormat, found bytes {one:?}")));
                }
            }
            _ => {
                return Err(
                    self.err_at(self.pos, format!("expected file type 0 or 1 in $MeshFormat, found {file_type}"))
                )
            }
        }
        self.expect_end("MeshFormat")
    }

    pub(super) fn skip_section(&mut self, name: &str, at: usize) -> Result<(), IoError> {
        let end = format!("$End{name}");
        let hay = &self.b[self.pos..];
        match hay.windows(end.len()).position(|w| w == end.as_bytes()) {
            Some(i) => {
                self.pos += i + end.len();
                Ok(())
            }
            None => Err(self.err_at(at, format!("section ${name} has no `{end}`"))),
        }
    }

    pub(super) fn physical_names(&mut self) -> Result<(), IoError> {
        let n: usize = self.num("the number of names in $PhysicalNames")?;
        for _ in 0..n {
            let dim: i32 = self.num("a dimension in $PhysicalNames")?;
            let tag: i32 = self.num("a physical tag in $PhysicalNames")?;
            let (rest, at) = self.rest_of_line();
            let name = rest
                .strip_prefix('"')
                .and_then(|r| r.strip_suffix('"'))
                .ok_or_else(|| self.err_at(at, format!("expected a quoted name in $PhysicalNames, found `{rest}`")))?;
            self.physical_names.push((dim, tag, name.to_string()));
        }
        self.expect_end("PhysicalNames")
    }

    pub(super) fn entities(&mut self) -> Result<(), IoError> {
        if self.binary {
            self.skip_newline();
        }
        let mut counts = [0usize; 4];
        for (d, c) in counts.iter_mut().enumerate() {
            *c = self.size41(&format!("the number of {d}-dimensional entities in $Entities"))?;
        }
        for (dim, &count) in counts.iter().enumerate() {
            for _ in 0..count {
                let tag = self.int41("an entity tag in $Entities")?;
                let nbox = if dim == 0 { 3 } else { 6 };
                for _ in 0..nbox {
                    self.f64_41("a bounding-box coordinate in $Entities")?;
                }
                let nphys = self.size41("the number of physical tags in $Entities")?;
                for k in 0..nphys {
                    let p = self.int41("a physical tag in $Entities")?;
                    if k == 0 {
                        self.entity_phys.insert((dim as i32, tag), p);
                    }
                }
                if dim > 0 {
                    let nb = self.size41("the number of bounding entities in $Entities")?;
                    for _ in 0..nb {
                        self.int41("a bounding entity tag in $Entities")?;
                    }
                }
            }
        }
        self.expect_end("Entities")
    }

    pub(super) fn add_node(&mut self, tag: usize, xyz: [f64; 3], at: usize) -> Result<(), IoError> {
        if !self.node_index.insert(tag, self.nodes.len()) {
            let msg = format!("node tag {tag} appears twice in $Nodes");
            return Err(if self.binary { self.err_bin(at, msg) } else { self.err_at(at, msg) });
        }
        self.nodes.push((tag, xyz));
        Ok(())
    }

    pub(super) fn nodes_section(&mut self) -> Result<(), IoError> {
        if self.seen_nodes {
            return Err(self.err_at(self.pos, "a second $Nodes section".into()));
        }
        self.seen_nodes = true;
        match self.version {
            Version::V22 => {
                let n: usize = self.num("the number of nodes in $Nodes")?;
                self.node_index.size_for(n, self.b.len());
                if self.binary {
                    self.skip_newline();
                }
                for i in 0..n {
                    if !self.binary {
                        self.skip_ws();
                    }
                    let at = self.pos;
                    let (tag, xyz) = if self.binary {
                        let tag = self.bin_tag("a node tag in $Nodes")?;
                        let x = self.bin_f64("a node coordinate in $Nodes")?;
                        let y = self.bin_f64("a node coordinate in $Nodes")?;
                        let z = self.bin_f64("a node coordinate in $Nodes")?;
                        (tag, [x, y, z])
                    } else {
                        let tag: usize = self.num_named(|| format!("node {} of {n}: tag in $Nodes", i + 1))?;
                        let x: f64 = self.num("a node x coordinate in $Nodes")?;
                        let y: f64 = self.num("a node y coordinate in $Nodes")?;
                        let z: f64 = self.num("a node z coordinate in $Nodes")?;
                        (tag, [x, y, z])
                    };
                    self.add_node(tag, xyz, at)?;
                }
            }
            Version::V41 => {
                if self.binary {
                    self.skip_newline();
                }
                let blocks = self.size41("the number of entity blocks in $Nodes")?;
                let total = self.size41("the number of nodes in $Nodes")?;
                self.node_index.size_for(total, self.b.len());
                self.size41("the smallest node tag in $Nodes")?;
                self.size41("the largest node tag in $Nodes")?;
                let mut read = 0usize;
                for _ in 0..blocks {
                    let _dim = self.int41("an entity dimension in a $Nodes block")?;
                    let _tag = self.int41("an entity tag in a $Nodes block")?;
                    let parametric = self.int41("the parametric flag in a $Nodes block")?;
                    let n = self.size41("the number of nodes in a $Nodes block")?;
                    let mut tags = Vec::with_capacity(n.min(1 << 20));
                    for _ in 0..n {
                        tags.push((self.size41("a node tag in $Nodes")?, self.pos));
                    }
                    let extra = if parametric != 0 { 3 } else { 0 };
                    for (tag, at) in tags {
                        let x = self.f64_41("a node x coordinate in $Nodes")?;
                        let y = self.f64_41("a node y coordinate in $Nodes")?;
                        let z = self.f64_41("a node z coordinate in $Nodes")?;
                        for _ in 0..extra {
                            self.f64_41("a parametric node coordinate in $Nodes")?;
                        }
                        self.add_node(tag, [x, y, z], at)?;
                    }
                    read += n;
                }
                if read != total {
                    return Err(
                        self.err_at(self.pos, format!("$Nodes announces {total} nodes but its blocks hold {read}"))
                    );
                }
            }
        }
        self.expect_end("Nodes")
    }

    /// Records one element; `nodes` are Gmsh node tags. `at` is the element's offset.
    pub(super) fn add_element(&mut self, ty: GmshType, phys: i32, nodes: &[usize], at: usize) -> Result<(), IoError> {
        let start = self.element_nodes.len();
        for &t in nodes {
            match self.node_index.get(t) {
                Some(i) => self.element_nodes.push(i),
                None => {
                    let msg = format!("an element of $Elements refers to node {t}, which $Nodes does not define");
                    return Err(if self.binary { self.err_bin(at, msg) } else { self.err_at(at, msg) });
                }
            }
        }
        if ty.dim == 0 {
            self.element_nodes.truncate(start);
        } else {
            self.elements.push((ty, phys, start));
        }
        Ok(())
    }

    pub(super) fn elements_section(&mut self) -> Result<(), IoError> {
        if !self.seen_nodes {
            return Err(self.err_at(self.pos, "$Elements comes before $Nodes".into()));
        }
        if self.seen_elements {
            return Err(self.err_at(self.pos, "a second $Elements section".into()));
        }
        self.seen_elements = true;
        match self.version {
            Version::V22 if self.binary => self.elements22_binary()?,
            Version::V22 => self.elements22_ascii()?,
            Version::V41 => self.elements41()?,
        }
        self.expect_end("Elements")
    }

    pub(super) fn elements22_ascii(&mut self) -> Result<(), IoError> {
        let n: usize = self.num("the number of elements in $Elements")?;
        for i in 0..n {
            self.skip_ws();
            let at = self.pos;
            let _id: usize = self.num_named(|| format!("element {} of {n}: tag in $Elements", i + 1))?;
            let ty: i32 = self.num("an element type in $Elements")?;
            let ntags: usize = self.num("the number of tags in $Elements")?;
            let mut phys = 0;
            for k in 0..ntags {
                let t: i32 = self.num("an element tag in $Elements")?;
                if k == 0 {
                    phys = t;
                }
            }
            let gt = gmsh_type(ty, at, self)?;
            let mut nodes = [0usize; MAX_CORNERS];
            for v in nodes.iter_mut().take(gt.nodes) {
                *v = self.num("an element node tag in $Elements")?;
            }
            self.add_element(gt, phys, &nodes[..gt.nodes], at)?;
        }
        Ok(())
    }

    pub(super) fn elements22_binary(&mut self) -> Result<(), IoError> {
        let n: usize = self.num("the number of elements in $Elements")?;
        self.skip_newline();
        let mut read = 0usize;
        while read < n {
            let at = self.pos;
            let ty = self.bin_i32("an element type in $Elements")?;
            let count = self.bin_tag("an element count in $Elements")?;
            let ntags = self.bin_tag("the number of tags in $Elements")?;
            let gt = gmsh_type(ty, at, self)?;
            if count == 0 || read + count > n {
                return Err(
                    self.err_bin(at, format!("element block of {count} exceeds the {n} elements $Elements announces"))
                );
            }
            for _ in 0..count {
                let at = self.pos;
                self.bin_i32("an element tag in $Elements")?;
                let mut phys = 0;
                for k in 0..ntags {
                    let t = self.bin_i32("an element tag in $Elements")?;
                    if k == 0 {
                        phys = t;
                    }
                }
                let mut nodes = [0usize; MAX_CORNERS];
                for v in nodes.iter_mut().take(gt.nodes) {
                    *v = self.bin_tag("an element node tag in $Elements")?;
                }
                self.add_element(gt, phys, &nodes[..gt.nodes], at)?;
            }
            read += count;
        }
        Ok(())
    }

    pub(super) fn elements41(&mut self) -> Result<(), IoError> {
        if self.binary {
            self.skip_newline();
        }
        let blocks = self.size41("the number of entity blocks in $Elements")?;
        let total = self.size41("the number of elements in $Elements")?;
        self.size41("the smallest element tag in $Elements")?;
        self.size41("the largest element tag in $Elements")?;
        let mut read = 0usize;
        for _ in 0..blocks {
            let at = self.pos;
            let dim = self.int41("an entity dimension in an $Elements block")?;
            let etag = self.int41("an entity tag in an $Elements block")?;
            let ty = self.int41("an element type in an $Elements block")?;
            let n = self.size41("the number of elements in an $Elements block")?;
            let gt = gmsh_type(ty, at, self)?;
            let phys = self.entity_phys.get(&(dim, etag)).copied().unwrap_or(0);
            for _ in 0..n {
                // ASCII: point at the element's line, not at the end of the previous one.
                if !self.binary {
                    self.skip_ws();
                }
                let at = self.pos;
                self.size41("an element tag in $Elements")?;
                let mut nodes = [0usize; MAX_CORNERS];
                for v in nodes.iter_mut().take(gt.nodes) {
                    *v = self.size41("an element node tag in $Elements")?;
                }
                self.add_element(gt, phys, &nodes[..gt.nodes], at)?;
            }
            read += n;
        }
        if read != total {
            return Err(
                self.err_at(self.pos, format!("$Elements announces {total} elements but its blocks hold {read}"))
            );
        }
        Ok(())
    }

    /// The mesh of the elements read: see the module documentation.
    pub(super) fn finish(self) -> Result<MshParts, IoError> {
        let dim = self.elements.iter().map(|e| e.0.dim).max().unwrap_or(0);
        if dim < 2 {
            return Err(IoError::Unsupported("the file has no 2D or 3D elements (Gmsh element types 2 to 7)".into()));
        }
        let element = |&(ty, _, start): &(GmshType, i32, usize)| &self.element_nodes[start..start + ty.nodes];
        // The nodes of the cells are kept, in file order.
        let mut new_index = vec![u32::MAX; self.nodes.len()];
        for e in self.elements.iter().filter(|e| e.0.dim == dim) {
            element(e).iter().for_each(|&v| new_index[v] = 0);
        }
        if dim == 2 {
            crate::io::check_planar(self.nodes.iter().zip(&new_index).filter(|(_, &k)| k == 0).map(|((_, p), _)| *p))?;
        }
        let mut data = MeshData::new(dim);
        let mut node_tags = Vec::new();
        for ((tag, xyz), k) in self.nodes.iter().zip(new_index.iter_mut()) {
            if *k == 0 {
                *k = data.push_vertex(&xyz[..dim]);
                node_tags.push(*tag);
            }
        }
        for e @ &(ty, phys, _) in &self.elements {
            let nodes = element(e);
            let mut corners = [0u32; MAX_CORNERS];
            for (c, &k) in corners.iter_mut().zip(ty.vtk_order()) {
                *c = new_index[nodes[k]];
            }
            let corners = &corners[..ty.nodes];
            if ty.dim == dim {
                data.push_cell(ty.cell.expect("the element types of dimension 2 and 3 are cell types"), corners, phys);
            } else if ty.dim + 1 == dim {
                if corners.contains(&u32::MAX) {
                    return Err(IoError::Unsupported(format!(
                        "a {} element of physical tag {phys} has a node that is on no cell",
                        ty.name
                    )));
                }
                data.push_face(corners, phys);
            }
        }
        Ok((data, self.physical_names, node_tags))
    }
}

/// The element type `ty` if it is one that is read; `Unsupported` for the rest.
pub(super) fn gmsh_type(ty: i32, at: usize, p: &Parser) -> Result<GmshType, IoError> {
    GmshType::from_id(ty).ok_or_else(|| {
        let name = match ty {
            8 => " (3-node line)",
            9 => " (6-node triangle)",
            10 => " (9-node quadrangle)",
            11 => " (10-node tetrahedron)",
            12 => " (27-node hexahedron)",
            16 => " (8-node quadrangle)",
            17 => " (20-node hexahedron)",
            _ => "",
        };
        let place = if p.binary { format!("byte {at}") } else { format!("line {}", line_of(p.b, at)) };
        IoError::Unsupported(format!(
            "Gmsh element type {ty}{name} at {place}; the types read are lines (1), triangles (2), quadrangles (3), \
             tetrahedra (4), hexahedra (5), prisms (6), pyramids (7) and points (15)"
        ))
    })
}
