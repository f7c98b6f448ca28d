//! What can be wrong with a mesh a caller hands us; each variant names the offending item.

use thiserror::Error;

#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum MeshError {
    #[error("the mesh has no vertices or no cells")]
    Empty,
    #[error("vertex {vertex} has a non-finite coordinate ({x}, {y})")]
    NonFiniteCoordinate { vertex: usize, x: f64, y: f64 },
    #[error("cell {cell} refers to vertex index {index}, outside {base}..{end} (index base {base})")]
    IndexOutOfRange { cell: usize, index: i64, base: i64, end: i64 },
    #[error("cell {cell} repeats vertex {vertex}")]
    RepeatedVertex { cell: usize, vertex: usize },
    #[error("vertex {vertex} is not used by any cell")]
    UnusedVertex { vertex: usize },
    #[error("cell {cell} has zero area ({area:e})")]
    DegenerateCell { cell: usize, area: f64 },
    #[error(
        "cell {cell} is oriented against the rest of the mesh ({clockwise} cells clockwise, {counter_clockwise} \
         counter-clockwise): a cell is inverted or the mesh folds over itself"
    )]
    InconsistentOrientation { cell: usize, clockwise: usize, counter_clockwise: usize },
    #[error(
        "cells {first} and {second} lie on the same side of their shared edge ({a}, {b}): the mesh overlaps itself"
    )]
    Overlap { first: usize, second: usize, a: usize, b: usize },
    #[error("cells {first} and {second} have the same vertices")]
    RepeatedCell { first: usize, second: usize },
    #[error("edge ({a}, {b}) is shared by {cells} cells; at most two may share an edge")]
    NonManifoldEdge { a: usize, b: usize, cells: usize },
    #[error("tagged edge {edge} refers to vertex index {index}, outside {base}..{end}")]
    TaggedIndexOutOfRange { edge: usize, index: i64, base: i64, end: i64 },
    #[error("tagged edge {edge} ({a}, {b}) is not an edge of any cell")]
    TaggedEdgeNotAnEdge { edge: usize, a: usize, b: usize },
    #[error("tagged edge {edge} ({a}, {b}) is tagged twice, with patches {first} and {second}")]
    TaggedEdgeTwice { edge: usize, a: usize, b: usize, first: i32, second: i32 },
    #[error("{regions} region ids given for {cells} cells")]
    RegionCount { regions: usize, cells: usize },
    #[error("a mesh of dimension {dim}: meshmove handles 2 and 3")]
    Dimension { dim: usize },
    #[error("cell {cell} is a {cell_type}, which is not a cell of a {dim}D mesh")]
    CellTypeNotInDimension { cell: usize, cell_type: crate::geometry::CellType, dim: usize },
    #[error("the mesh has {vertices} vertices; at most {max} are supported")]
    TooLarge { vertices: usize, max: usize },
}
