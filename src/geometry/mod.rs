//! The geometry of cells: everything that knows the dimension and the cell type lives here.

mod cell_type;

pub use cell_type::{CellType, MAX_CORNERS};
