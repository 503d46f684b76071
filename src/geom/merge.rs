//! `polyfill3 --merge`: runs of whole, same-coloured cells along a row become
//! one polygon covering exactly the same region ([`RunMerger`]); with
//! `--merge=blocks`, runs of consecutive rows over the same columns become
//! one rectangle of cells ([`BlockMerger`]).
//!
//! The merged polygon keeps every grid corner along its sides (collinear
//! vertices): the cells of the rows above and below, and the clipped cells at
//! the ends, still meet it vertex to vertex, so there are no T-junctions and a
//! rasterizer leaves no cracks. A run gets fewer polygons but not fewer
//! vertices (a run of k cells has 2k + 2); a block of r rows of k cells has
//! 2k + 2r against r(2k + 2) as runs, so it is where the bytes go down.

use glam::DVec3;
use std::collections::VecDeque;

/// How `polyfill3 --merge` joins whole cells of one colour: [`RunMerger`]
/// for both, then [`BlockMerger`] for blocks. (The variants' comments are
/// `polyfill3 --help`'s.)
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[cfg_attr(feature = "cli", derive(clap::ValueEnum))]
pub enum Merge {
    /// Runs of cells along a row.
    #[default]
    Rows,
    /// Rectangles of cells: runs of consecutive rows over the same columns
    /// joined.
    Blocks,
}

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

/// Runs of consecutive rows joined into rectangles of cells: a run that
/// covers the same columns in the same colour as a block ending on the row
/// below, and whose bottom side is that block's top side to the bit (the
/// grid's corners, computed once per corner), extends the block; anything
/// else starts a block. Runs come row by row, columns ascending (as the
/// partition gives its cells), so the blocks of the row below are met in
/// the order they lie: each run looks at the next of them only, and a block
/// passed by is closed. At most two rows' blocks are open. Closed blocks are
/// taken in the order they closed.
#[derive(Default)]
pub struct BlockMerger {
    /// Blocks ending on the row below the current one that no run has
    /// continued yet, columns ascending.
    below: VecDeque<OpenBlock>,
    /// Blocks the current row has continued or started, columns ascending.
    current: VecDeque<OpenBlock>,
    /// Closed blocks, oldest first.
    closed: VecDeque<OpenBlock>,
    /// The row of the last run added.
    row: i64,
    /// Vertex lists of blocks taken, for the next ones.
    spare: Vec<Vec<DVec3>>,
    out: Vec<DVec3>,
}

/// A rectangle of cells being joined, by its four sides.
struct OpenBlock {
    /// Column k of its cells' first (leftmost) column.
    first: i64,
    /// Rows j of its first and last rows.
    first_row: i64,
    last_row: i64,
    /// The colour key of its cells.
    key: u32,
    /// Cells per row.
    cols: usize,
    /// The first row's bottom side, left to right.
    bottom: Vec<DVec3>,
    /// The ends of each boundary between two of its rows, bottom to top:
    /// the right ones and the left ones.
    right: Vec<DVec3>,
    left: Vec<DVec3>,
    /// The last row's top side, left to right.
    top: Vec<DVec3>,
}

impl BlockMerger {
    /// A merger with no block open.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds a finished run (from [`RunMerger::take`]): it extends the block
    /// it continues, or starts one.
    pub fn add(&mut self, run: &Run) {
        if run.row != self.row || self.current.back().is_some_and(|b| b.first >= run.first) {
            // A new row: what is left of the row below cannot be continued.
            self.closed.append(&mut self.below);
            if run.row == self.row + 1 {
                std::mem::swap(&mut self.below, &mut self.current);
            } else {
                // Not the next row, or (never from the partition) columns
                // not ascending: start afresh, which keeps the queues in
                // column order whatever the order of the runs.
                self.closed.append(&mut self.current);
            }
            self.row = run.row;
        }
        while self.below.front().is_some_and(|b| b.first < run.first) {
            self.closed.extend(self.below.pop_front());
        }
        let (bottom, top) = run.vertices.split_at(run.cells + 1);
        // For a partition's runs the side check alone decides (a block of
        // other columns, or of a row that is not the one below, has other
        // corners). The column test also keeps apart runs whose corners
        // meet though their columns differ (squares given, not a grid's:
        // `corners_that_meet_join_no_rows_that_do_not_follow_nor_other_columns`),
        // and with the count test it settles most misses first.
        let continues = |b: &OpenBlock| {
            b.first == run.first
                && b.cols == run.cells
                && b.key == run.key
                && b.top.iter().eq(bottom.iter())
        };
        if self.below.front().is_some_and(continues) {
            let mut b = self.below.pop_front().expect("a block below");
            b.left.push(b.top[0]);
            b.right.push(b.top[run.cells]);
            b.top.clear();
            b.top.extend(top.iter().rev());
            b.last_row = run.row;
            self.current.push_back(b);
            return;
        }
        let mut list = || self.spare.pop().unwrap_or_default();
        let (mut b_side, mut t_side, right, left) = (list(), list(), list(), list());
        b_side.extend_from_slice(bottom);
        t_side.extend(top.iter().rev());
        self.current.push_back(OpenBlock {
            first: run.first,
            first_row: run.row,
            last_row: run.row,
            key: run.key,
            cols: run.cells,
            bottom: b_side,
            right,
            left,
            top: t_side,
        });
    }

    /// Closes every open block (the end of a polygon's cells): the merger
    /// is then ready for another polygon.
    pub fn close_all(&mut self) {
        self.closed.append(&mut self.below);
        self.closed.append(&mut self.current);
    }

    /// The oldest closed block.
    pub fn take_closed(&mut self) -> Option<Block<'_>> {
        let b = self.closed.pop_front()?;
        self.out.clear();
        self.out.extend_from_slice(&b.bottom);
        self.out.extend_from_slice(&b.right);
        self.out.extend(b.top.iter().rev());
        self.out.extend(b.left.iter().rev());
        let rows = (b.last_row - b.first_row + 1) as usize;
        for mut v in [b.bottom, b.right, b.left, b.top] {
            v.clear();
            self.spare.push(v);
        }
        Some(Block {
            first: b.first,
            row: b.first_row,
            key: b.key,
            cells: b.cols * rows,
            vertices: &self.out,
        })
    }
}

/// A finished block: one or more runs of consecutive rows.
pub struct Block<'a> {
    /// Column k of its first (leftmost) column.
    pub first: i64,
    /// Row j of its first (lowest) row.
    pub row: i64,
    /// The colour key of its cells.
    pub key: u32,
    /// Number of cells joined, all rows.
    pub cells: usize,
    /// Counter-clockwise: the bottom side left to right, the right side up,
    /// the top right to left, the left side down.
    pub vertices: &'a [DVec3],
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

    /// Whole cell (k, j) of a unit grid.
    fn cell(k: i64, j: i64) -> [DVec3; 4] {
        let c = |k: i64, j: i64| DVec3::new(k as f64, j as f64, 0.0);
        [c(k, j), c(k + 1, j), c(k + 1, j + 1), c(k, j + 1)]
    }

    /// What the two mergers make of a grid of colour keys (`None`:
    /// transparent), fed as polyfill3 feeds them: row by row, columns
    /// ascending.
    fn blocks_of(grid: &[Vec<Option<u32>>]) -> Vec<(i64, i64, u32, usize, Vec<DVec3>)> {
        let (mut runs, mut blocks, mut out) = (RunMerger::new(), BlockMerger::new(), Vec::new());
        let mut take = |runs: &mut RunMerger, blocks: &mut BlockMerger| {
            if let Some(run) = runs.take() {
                blocks.add(&run);
            }
            while let Some(b) = blocks.take_closed() {
                out.push((b.first, b.row, b.key, b.cells, b.vertices.to_vec()));
            }
        };
        for (j, row) in grid.iter().enumerate() {
            for (k, key) in row.iter().enumerate() {
                let (k, j) = (k as i64, j as i64);
                match key {
                    Some(key) => {
                        if !runs.continues(k, j, *key) {
                            take(&mut runs, &mut blocks);
                        }
                        runs.push(k, j, *key, &cell(k, j));
                    }
                    None => take(&mut runs, &mut blocks),
                }
            }
        }
        take(&mut runs, &mut blocks);
        blocks.close_all();
        take(&mut runs, &mut blocks);
        out
    }

    #[test]
    fn two_rows_over_the_same_columns_make_one_block_with_every_corner() {
        let out = blocks_of(&[vec![Some(1); 3], vec![Some(1); 3]]);
        assert_eq!(out.len(), 1);
        let (first, row, key, cells, v) = &out[0];
        assert_eq!((*first, *row, *key, *cells), (0, 0, 1, 6));
        let c = |x: f64, y: f64| DVec3::new(x, y, 0.0);
        let want = [
            c(0.0, 0.0),
            c(1.0, 0.0),
            c(2.0, 0.0),
            c(3.0, 0.0),
            c(3.0, 1.0),
            c(3.0, 2.0),
            c(2.0, 2.0),
            c(1.0, 2.0),
            c(0.0, 2.0),
            c(0.0, 1.0),
        ];
        assert_eq!(v[..], want[..]);
    }

    #[test]
    fn a_run_over_other_columns_or_of_another_colour_starts_a_block() {
        // Row 1 is one cell shorter; row 2 has row 1's columns in another
        // colour: three blocks, each one run.
        let out = blocks_of(&[
            vec![Some(1); 3],
            vec![Some(1), Some(1), None],
            vec![Some(2), Some(2), None],
        ]);
        let cells: Vec<_> = out.iter().map(|b| (b.1, b.3)).collect();
        assert_eq!(cells, [(0, 3), (1, 2), (2, 2)]);
    }

    #[test]
    fn a_run_whose_bottom_is_not_the_top_below_to_the_bit_starts_a_block() {
        let (mut runs, mut blocks) = (RunMerger::new(), BlockMerger::new());
        runs.push(0, 0, 1, &cell(0, 0));
        blocks.add(&runs.take().unwrap());
        let mut shifted = cell(0, 1);
        shifted[0].x += f64::EPSILON;
        runs.push(0, 1, 1, &shifted);
        blocks.add(&runs.take().unwrap());
        blocks.close_all();
        let mut n = 0;
        while let Some(b) = blocks.take_closed() {
            assert_eq!(b.cells, 1);
            n += 1;
        }
        assert_eq!(n, 2);
    }

    /// Runs built from given cell squares, not a grid's: the row and column
    /// tests must hold even where the corners alone would join them.
    fn joined(cells: &[(i64, i64, [DVec3; 4])]) -> Vec<usize> {
        let (mut runs, mut blocks) = (RunMerger::new(), BlockMerger::new());
        for (k, j, square) in cells {
            runs.push(*k, *j, 1, square);
            blocks.add(&runs.take().unwrap());
        }
        blocks.close_all();
        std::iter::from_fn(|| blocks.take_closed().map(|b| b.cells)).collect()
    }

    #[test]
    fn corners_that_meet_join_no_rows_that_do_not_follow_nor_other_columns() {
        let lower = cell(0, 0);
        // Bottom side on `lower`'s top, as if one row up.
        let upper = cell(0, 1);
        assert_eq!(joined(&[(0, 0, lower), (0, 1, upper)]), [2]);
        // Two rows up, or one column left, with the same corners.
        assert_eq!(joined(&[(0, 0, lower), (0, 2, upper)]), [1, 1]);
        assert_eq!(joined(&[(1, 0, lower), (0, 1, upper)]), [1, 1]);
    }

    /// The blocks the mergers should make, found another way: the grid's
    /// maximal runs of one key in each row, each joined to the run of the
    /// row below over the same columns and key; as (first column, first
    /// row, key, columns, rows).
    fn expected_blocks(grid: &[Vec<Option<u32>>]) -> Vec<(i64, i64, u32, i64, i64)> {
        let mut done = Vec::new();
        let mut below: Vec<(i64, i64, u32, i64, i64)> = Vec::new();
        for (j, row) in grid.iter().enumerate() {
            let mut here = Vec::new();
            let mut k = 0;
            while k < row.len() {
                let Some(key) = row[k] else {
                    k += 1;
                    continue;
                };
                let start = k;
                while k < row.len() && row[k] == Some(key) {
                    k += 1;
                }
                let (first, cols) = (start as i64, (k - start) as i64);
                match below
                    .iter()
                    .position(|b| b.0 == first && b.2 == key && b.3 == cols)
                {
                    Some(i) => {
                        let b = below.remove(i);
                        here.push((b.0, b.1, b.2, b.3, b.4 + 1));
                    }
                    None => here.push((first, j as i64, key, cols, 1)),
                }
            }
            done.append(&mut below);
            below = here;
        }
        done.append(&mut below);
        done.sort();
        done
    }

    proptest::proptest! {
        /// On random grids of a few colours with transparent holes, the
        /// blocks are the expected rectangles, each outlined counter-clockwise
        /// through every grid corner on its sides (so its neighbours meet it
        /// vertex to vertex), and together they hold every cell once.
        #[test]
        fn blocks_are_the_rectangles_of_equal_runs_through_every_corner(
            grid in proptest::collection::vec(
                proptest::collection::vec(proptest::option::weighted(0.8, 0u32..3), 1..9),
                1..9,
            )
        ) {
            let out = blocks_of(&grid);
            let mut got: Vec<_> = out
                .iter()
                .map(|(first, row, key, cells, v)| {
                    let cols = v.iter().map(|p| p.x as i64).max().unwrap() - first;
                    let rows = v.iter().map(|p| p.y as i64).max().unwrap() - row;
                    proptest::prop_assert_eq!(*cells as i64, cols * rows);
                    // The outline: bottom left to right, right side up, top
                    // right to left, left side down.
                    let mut ring = Vec::new();
                    let c = |k: i64, j: i64| DVec3::new(k as f64, j as f64, 0.0);
                    ring.extend((0..=cols).map(|k| c(first + k, *row)));
                    ring.extend((1..rows).map(|j| c(first + cols, row + j)));
                    ring.extend((0..=cols).rev().map(|k| c(first + k, row + rows)));
                    ring.extend((1..rows).rev().map(|j| c(*first, row + j)));
                    proptest::prop_assert_eq!(&ring[..], &v[..]);
                    Ok((*first, *row, *key, cols, rows))
                })
                .collect::<Result<_, _>>()?;
            got.sort();
            proptest::prop_assert_eq!(got, expected_blocks(&grid));
        }
    }
}
