//! The grid's scratch space: the buffers the dilation, the observation's row
//! passes, the shift and the place cap compute in, kept apart from the belief
//! (the planes of [`super::FuzzyGrid`]) so that what the grid believes and
//! what it computes with are different things. The grid owns one and hands it
//! to the passes ([`super::dilate`] takes the plane and the workspace as
//! arguments).
//!
//! Sized once per grid, so that stepping allocates nothing. Depends on
//! [`super::dilate`] for the sizes its passes need.
//!
//! # Complexity
//!
//! Construction is O(cells).

/// Scratch buffers sized for one `nx × ny` grid.
#[derive(Debug, Clone)]
pub(crate) struct Workspace {
    /// A plane the size of the belief's: the dilation's ring of rows and
    /// window maxima, the shift's target, the place cap's marks.
    pub(super) plane: Vec<f32>,
    /// One line of values (room for a padded row of dilation blocks).
    pub(super) line: Vec<f32>,
    /// A second line, with a block of slack past a padded row.
    pub(super) line_out: Vec<f32>,
    /// The deque of the 1-D passes.
    pub(super) deque: Vec<u32>,
    /// Chunk maxima, minima and bounds of the dilation's offset passes.
    pub(super) cm: Vec<f32>,
    /// The plane before a blur, for the heading sets of the cells it raises
    /// ([`super::RaisedHeadings`]): empty until the first such blur, so that a grid that does
    /// not use it does not pay a plane for it.
    pub(super) before: Vec<f32>,
    /// The cells a heading-class motion moves ([`super::CellMotion`]): empty until the first
    /// such motion, then never more than the grid's cells.
    pub(super) movers: Vec<super::classes::Mover>,
}

impl Workspace {
    /// Buffers for an `nx × ny` grid.
    pub(super) fn for_grid(nx: usize, ny: usize) -> Self {
        let longest = nx.max(ny) + nx.min(ny); // a diagonal is never longer
        Workspace {
            plane: vec![0.0; nx * ny],
            line: vec![0.0; longest.max(super::dilate::padded_row(nx))],
            line_out: vec![0.0; longest.max(super::dilate::padded_row(nx) + 32)],
            deque: vec![0; longest],
            cm: vec![0.0; super::dilate::chunk_len(nx, ny)],
            before: Vec::new(),
            movers: Vec::new(),
        }
    }
}
