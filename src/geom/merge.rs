//! `polyfill3 --merge`: runs of whole, same-coloured cells along a row become
//! one polygon covering exactly the same region.
//!
//! The merged polygon keeps every grid corner along its long sides (collinear
//! vertices): the cells of the rows above and below, and the clipped cells at
//! the ends, still meet it vertex to vertex, so there are no T-junctions and a
//! rasterizer leaves no cracks. The renderer gets fewer polygons; the number
//! of vertices does not shrink.

use glam::DVec3;

/// A run of whole cells in one row being joined.
#[derive(Default)]
pub struct RunMerger {
    active: bool,
    row: i64,
    first: i64,
    next: i64,
    key: u32,
    bottom: Vec<DVec3>,
    top: Vec<DVec3>,
    out: Vec<DVec3>,
}

/// A finished run.
pub struct Run<'a> {
    /// Column k of the run's first (leftmost) cell.
    pub first: i64,
    /// Row j of every cell of the run.
    pub row: i64,
    /// The colour key the run was built with.
    pub key: u32,
    /// Number of cells joined.
    pub cells: usize,
    /// Counter-clockwise: the bottom side left to right, the top right to left.
    pub vertices: &'a [DVec3],
}

impl RunMerger {
    /// A merger with no run open.
    pub fn new() -> Self {
        Self::default()
    }

    /// Whether the whole cell (k, j) of colour `key` continues the current run.
    pub fn continues(&self, k: i64, j: i64, key: u32) -> bool {
        self.active && j == self.row && k == self.next && key == self.key
    }

    /// Adds whole cell (k, j) with corners `[c(k,j), c(k+1,j), c(k+1,j+1),
    /// c(k,j+1)]`. Call [`RunMerger::take`] first unless [`RunMerger::continues`].
    pub fn push(&mut self, k: i64, j: i64, key: u32, sq: &[DVec3]) {
        if self.continues(k, j, key) {
            self.bottom.push(sq[1]);
            self.top.push(sq[2]);
        } else {
            debug_assert!(!self.active, "take the run before starting another");
            self.active = true;
            self.row = j;
            self.first = k;
            self.key = key;
            self.bottom.clear();
            self.top.clear();
            self.bottom.extend([sq[0], sq[1]]);
            self.top.extend([sq[3], sq[2]]);
        }
        self.next = k + 1;
    }

    /// Ends the current run and returns it, if there is one.
    pub fn take(&mut self) -> Option<Run<'_>> {
        if !self.active {
            return None;
        }
        self.active = false;
        self.out.clear();
        self.out.extend_from_slice(&self.bottom);
        self.out.extend(self.top.iter().rev());
        Some(Run {
            first: self.first,
            row: self.row,
            key: self.key,
            cells: self.bottom.len() - 1,
            vertices: &self.out,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sq(k: f64) -> [DVec3; 4] {
        [
            DVec3::new(k, 0.0, 0.0),
            DVec3::new(k + 1.0, 0.0, 0.0),
            DVec3::new(k + 1.0, 1.0, 0.0),
            DVec3::new(k, 1.0, 0.0),
        ]
    }

    #[test]
    fn three_cells_make_one_ccw_polygon_with_all_corners() {
        let mut m = RunMerger::new();
        m.push(0, 0, 7, &sq(0.0));
        assert!(m.continues(1, 0, 7));
        assert!(!m.continues(1, 0, 8));
        m.push(1, 0, 7, &sq(1.0));
        m.push(2, 0, 7, &sq(2.0));
        let r = m.take().unwrap();
        assert_eq!(r.cells, 3);
        assert_eq!(r.vertices.len(), 8);
        assert_eq!(r.vertices[3], DVec3::new(3.0, 0.0, 0.0));
        assert_eq!(r.vertices[4], DVec3::new(3.0, 1.0, 0.0));
        assert_eq!(r.vertices[7], DVec3::new(0.0, 1.0, 0.0));
        assert!(m.take().is_none());
    }
}
