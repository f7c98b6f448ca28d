//! Upper bounds on every count and option a caller can pass, checked before anything is
//! allocated or spawned: by the solver's `Options` checks (which publish the bounds a Rust caller
//! meets as `solver::MAX_*`) and by the C layer, which names them in the header as
//! `MESHMOVE_MAX_*` (a compile-time assertion keeps the two equal). Each bound is far above any
//! real use and low enough that a call at the bound still returns in reasonable time and memory.

/// Equal steps of one `move_in_steps` call.
pub(crate) const MAX_STEPS: usize = 1_000_000;
/// Cycles (or CG iterations) of one solve.
pub(crate) const MAX_CYCLES: usize = 1_000_000;
/// Chebyshev smoother degree (the cost of a cycle grows linearly with it).
pub(crate) const MAX_CHEB_DEGREE: usize = 64;
/// Worker threads of one solver. Fixed (not a multiple of the cores) so that the bound is the
/// same on every machine; far above the cores of one node.
pub(crate) const MAX_THREADS: usize = 1024;
/// Automatic sub-steps of one step.
pub(crate) const MAX_SUBSTEPS: usize = 1 << 20;
/// Vertices of a mesh given through the C ABI: 2 × vertices must fit an `int32_t` length.
pub(crate) const MAX_VERTICES: usize = (i32::MAX / 2) as usize;
/// Cells of a mesh given through the C ABI: 3 × cells must fit an `int32_t` length.
pub(crate) const MAX_CELLS: usize = (i32::MAX / 3) as usize;
