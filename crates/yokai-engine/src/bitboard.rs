//! The grid as a set of cells packed into one `u128`.
//!
//! Cell `(row, col)` of a `g × g` grid is bit `row·g + col`. With `g ≤ 11` the 121 cells fit
//! in one `u128`, so "which cells are occupied", "the neighbours of a group" and "is this group
//! connected" are a handful of shifts and masks instead of loops over an array. The shifts
//! that move a set one column left or right would wrap around the row ends, so
//! [`Geometry`] keeps the column masks that cut the wrapped bits off.

use serde::{Deserialize, Serialize};
use std::fmt;

/// The largest grid side the bitboard supports (11 × 11 = 121 ≤ 128 bits).
pub const MAX_GRID: usize = 11;

/// A set of grid cells.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct Bitboard(pub u128);

impl Bitboard {
    pub const EMPTY: Bitboard = Bitboard(0);

    #[inline(always)]
    pub fn from_index(index: usize) -> Bitboard {
        Bitboard(1u128 << index)
    }

    #[inline(always)]
    pub fn contains(self, index: usize) -> bool {
        self.0 >> index & 1 == 1
    }

    #[inline(always)]
    pub fn is_empty(self) -> bool {
        self.0 == 0
    }

    #[inline(always)]
    pub fn count(self) -> u32 {
        self.0.count_ones()
    }

    /// The lowest cell of the set as a one-cell set (empty for an empty set).
    #[inline(always)]
    pub fn lowest(self) -> Bitboard {
        Bitboard(self.0 & self.0.wrapping_neg())
    }

    /// The set's bit indices in increasing order: a grid's cell indices
    /// ([`Geometry::index`]), which is what move generation, action indices and per-cell
    /// tables are computed from. A bitboard does not know its grid's side, so the cells
    /// themselves come from [`Geometry::cells_in`].
    #[inline]
    pub fn iter(self) -> BitIter {
        BitIter {
            low: self.0 as u64,
            high: (self.0 >> 64) as u64,
        }
    }
}

crate::types::bit_set_ops!(Bitboard);

impl fmt::Debug for Bitboard {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "Bitboard(")?;
        f.debug_list().entries(self.iter()).finish()?;
        write!(f, ")")
    }
}

/// Iterator over the set bits of a bitboard, lowest first. It walks the two 64-bit halves
/// one after the other: a u128 `trailing_zeros` and `x & (x - 1)` cost a select and a
/// borrow across the halves on every bit, and move generation calls this once per target.
pub struct BitIter {
    low: u64,
    high: u64,
}

impl Iterator for BitIter {
    type Item = usize;
    #[inline(always)]
    fn next(&mut self) -> Option<usize> {
        if self.low != 0 {
            let i = self.low.trailing_zeros() as usize;
            self.low &= self.low - 1;
            return Some(i);
        }
        if self.high != 0 {
            let i = self.high.trailing_zeros() as usize;
            self.high &= self.high - 1;
            return Some(64 + i);
        }
        None
    }
}

/// A cell of the grid, addressed the way people and the action codec name it.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug, Serialize, Deserialize, PartialOrd, Ord)]
pub struct Cell {
    pub row: u8,
    pub col: u8,
}

impl Cell {
    pub fn new(row: usize, col: usize) -> Cell {
        Cell {
            row: row as u8,
            col: col as u8,
        }
    }
}

impl fmt::Display for Cell {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "r{}c{}", self.row, self.col)
    }
}

/// The masks of one grid size, precomputed once per configuration.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub struct Geometry {
    side: u8,
    board: Bitboard,
    /// Cells not in column 0: where a set shifted one column right may land.
    not_first_col: Bitboard,
    /// Cells not in the last column: where a set shifted one column left may land.
    not_last_col: Bitboard,
}

impl Geometry {
    /// Geometry of a `side × side` grid; `side` must be in `1..=MAX_GRID` (the config
    /// validates that before building one).
    pub fn new(side: usize) -> Geometry {
        assert!(
            (1..=MAX_GRID).contains(&side),
            "grid side {side} out of range"
        );
        let cells = side * side;
        let board = Bitboard(if cells == 128 {
            u128::MAX
        } else {
            (1u128 << cells) - 1
        });
        let mut first_col = 0u128;
        let mut last_col = 0u128;
        for r in 0..side {
            first_col |= 1u128 << (r * side);
            last_col |= 1u128 << (r * side + side - 1);
        }
        Geometry {
            side: side as u8,
            board,
            not_first_col: Bitboard(board.0 & !first_col),
            not_last_col: Bitboard(board.0 & !last_col),
        }
    }

    #[inline(always)]
    pub fn side(&self) -> usize {
        self.side as usize
    }

    #[inline(always)]
    pub fn cells(&self) -> usize {
        self.side() * self.side()
    }

    #[inline(always)]
    pub fn board(&self) -> Bitboard {
        self.board
    }

    #[inline(always)]
    pub fn index(&self, cell: Cell) -> usize {
        cell.row as usize * self.side() + cell.col as usize
    }

    #[inline(always)]
    pub fn cell(&self, index: usize) -> Cell {
        Cell::new(index / self.side(), index % self.side())
    }

    /// The cells of a set on this grid, in increasing index order (row by row).
    pub fn cells_in(&self, set: Bitboard) -> impl Iterator<Item = Cell> + '_ {
        set.iter().map(|index| self.cell(index))
    }

    pub fn contains(&self, cell: Cell) -> bool {
        (cell.row as usize) < self.side() && (cell.col as usize) < self.side()
    }

    /// The cells 4-adjacent to some cell of `set` (may include cells of `set` itself).
    #[inline(always)]
    pub fn neighbours(&self, set: Bitboard) -> Bitboard {
        let g = self.side as u32;
        let b = set.0;
        Bitboard(
            ((b << 1) & self.not_first_col.0)
                | ((b >> 1) & self.not_last_col.0)
                | (shl_small(b, g) & self.board.0)
                | shr_small(b, g),
        )
    }

    /// The 4-connected component of `within` that contains `seed` (`seed ⊆ within`).
    #[inline(always)]
    pub fn flood(&self, seed: Bitboard, within: Bitboard) -> Bitboard {
        let mut filled = seed;
        loop {
            let next = Bitboard((filled.0 | self.neighbours(filled).0) & within.0);
            if next == filled {
                return filled;
            }
            filled = next;
        }
    }

    /// The 3×3 block of `set` centred on `index`, as 9 bits: the cell `dr` rows and `dc`
    /// columns away is bit `3·(dr+1) + (dc+1)`. Cells off the grid are out. Move generation
    /// asks this once per card, so it is two shifts and two column tests rather than a
    /// division and eight bounds checks.
    #[inline(always)]
    pub fn block(&self, index: usize, set: Bitboard) -> u16 {
        let g = self.side();
        // Bring the block's top-left cell (index − g − 1) to bit 0. Near the top edge it lies
        // before the first cell, so shift the other way and let zeros (off the grid) in.
        let s = if index > g {
            (set.0 >> (index - g - 1)) as u64
        } else {
            (set.0 as u64) << (g + 1 - index)
        };
        let mut block = (s & 7) | ((s >> g) & 7) << 3 | ((s >> (2 * g)) & 7) << 6;
        // Rows run on into each other in the bitboard: cut the column that wrapped around.
        if !self.not_first_col.contains(index) {
            block &= !0b001_001_001;
        }
        if !self.not_last_col.contains(index) {
            block &= !0b100_100_100;
        }
        block as u16
    }

    /// Whether `set` is one 4-connected group (the empty set counts as connected).
    #[inline]
    pub fn is_connected(&self, set: Bitboard) -> bool {
        set.is_empty() || self.flood(set.lowest(), set) == set
    }
}

/// `b << s` for a shift known to lie in `1..64` (a grid side), as two 64-bit halves: the
/// general u128 shift by a runtime amount must also handle shifts of 64 or more, which costs
/// a branch or a select on every call of the move generator's inner loop.
#[inline(always)]
fn shl_small(b: u128, s: u32) -> u128 {
    debug_assert!((1..64).contains(&s));
    let (lo, hi) = (b as u64, (b >> 64) as u64);
    let hi = (hi << s) | (lo >> (64 - s));
    ((hi as u128) << 64) | (lo << s) as u128
}

/// `b >> s` for a shift in `1..64` (see [`shl_small`]).
#[inline(always)]
fn shr_small(b: u128, s: u32) -> u128 {
    debug_assert!((1..64).contains(&s));
    let (lo, hi) = (b as u64, (b >> 64) as u64);
    let lo = (lo >> s) | (hi << (64 - s));
    ((hi >> s) as u128) << 64 | lo as u128
}

/// For each [`Geometry::block`] around a cell (the centre bit is ignored): whether the
/// cell's side neighbours (N, E, S, W) are linked to each other through the 8 cells around
/// it. If they are, taking the cell away cannot split a connected set that contains it,
/// since any path through the cell can go around it instead; so move generation needs no
/// flood fill for such a card.
pub const BLOCK_KEEPS_CONNECTED: [bool; 512] = block_table();

/// The block bit of each ring position N, NE, E, SE, S, SW, W, NW (consecutive positions
/// share a side, so links are runs of set bits on the cyclic ring).
const RING_IN_BLOCK: [u16; 8] = [1, 2, 5, 8, 7, 6, 3, 0];

/// The 8 cells around the centre of a 3×3 block, as bits in ring order.
const fn ring_of_block(block: u16) -> u8 {
    let mut ring = 0u8;
    let mut i = 0;
    while i < 8 {
        ring |= ((block >> RING_IN_BLOCK[i] & 1) as u8) << i;
        i += 1;
    }
    ring
}

const fn block_table() -> [bool; 512] {
    let ring = ring_table();
    let mut table = [false; 512];
    let mut block = 0;
    while block < 512 {
        table[block] = ring[ring_of_block(block as u16) as usize];
        block += 1;
    }
    table
}

/// For each ring pattern: whether its side cells are linked within the ring.
const fn ring_table() -> [bool; 256] {
    let mut table = [false; 256];
    let mut pattern = 0;
    while pattern < 256 {
        // Label the runs of consecutive set bits on the cyclic ring of 8.
        let mut run_of = [0u8; 8];
        let mut run = 0u8;
        let mut start = 0;
        // Start just after an unset bit so that no run wraps across the start (if all 8
        // bits are set there is one run).
        while start < 8 && pattern >> start & 1 == 1 {
            start += 1;
        }
        let mut i = 0;
        while i < 8 {
            let bit = (start + 1 + i) % 8;
            if pattern >> bit & 1 == 1 {
                if i == 0 || pattern >> ((bit + 7) % 8) & 1 == 0 {
                    run += 1;
                }
                run_of[bit] = run;
            }
            i += 1;
        }
        let mut side_run = 0u8;
        let mut linked = true;
        let mut side = 0;
        while side < 8 {
            if pattern >> side & 1 == 1 {
                if side_run == 0 {
                    side_run = run_of[side];
                } else if run_of[side] != side_run {
                    linked = false;
                }
            }
            side += 2;
        }
        table[pattern] = linked;
        pattern += 1;
    }
    table
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn small_shifts_equal_the_general_u128_shifts() {
        let mut b: u128 = 0x9e37_79b9_7f4a_7c15_f39c_c060_5ced_c834;
        for _ in 0..200 {
            b = b.rotate_left(17) ^ b.wrapping_mul(0x2545_f491_4f6c_dd1d);
            for s in 1..64 {
                assert_eq!(shl_small(b, s), b << s, "{b:#x} << {s}");
                assert_eq!(shr_small(b, s), b >> s, "{b:#x} >> {s}");
            }
        }
    }

    #[test]
    fn a_cell_whose_ring_links_its_neighbours_never_splits_a_group() {
        // Exhaustive over the 3×3 block around a centre cell on a 5×5 grid: for every
        // connected set in the block that contains the centre, the rest stays connected
        // exactly when the table says the ring links the side neighbours (inside the block
        // there is no other way around).
        let geo = Geometry::new(5);
        let centre = geo.index(Cell::new(2, 2));
        let ring_cells = [
            (1, 2),
            (1, 3),
            (2, 3),
            (3, 3),
            (3, 2),
            (3, 1),
            (2, 1),
            (1, 1),
        ];
        let (mut kept, mut refused) = (0, 0);
        for pattern in 0..256usize {
            let mut set = Bitboard::from_index(centre);
            for (i, &(r, c)) in ring_cells.iter().enumerate() {
                if pattern >> i & 1 == 1 {
                    set |= Bitboard::from_index(geo.index(Cell::new(r, c)));
                }
            }
            let block = geo.block(centre, set);
            assert_eq!(ring_of_block(block) as usize, pattern);
            if !geo.is_connected(set) {
                continue;
            }
            let rest = set ^ Bitboard::from_index(centre);
            if BLOCK_KEEPS_CONNECTED[block as usize] {
                assert!(geo.is_connected(rest), "pattern {pattern:08b}");
                kept += 1;
            } else {
                assert!(!geo.is_connected(rest), "pattern {pattern:08b}");
                refused += 1;
            }
        }
        assert!(kept > 0 && refused > 0);
        // Off-grid cells are out of the ring.
        assert_eq!(ring_of_block(geo.block(0, geo.board())), 0b0001_1100);
    }

    #[test]
    fn block_is_the_3x3_neighbourhood_at_every_cell_of_every_grid() {
        let mut x: u128 = 0x2545_f491_4f6c_dd1d_9e37_79b9_7f4a_7c15;
        for side in 1..=MAX_GRID {
            let geo = Geometry::new(side);
            for _ in 0..50 {
                x = x.rotate_left(23) ^ x.wrapping_mul(0x9e37_79b9_7f4a_7c15);
                let set = Bitboard(x & geo.board().0);
                for index in 0..geo.cells() {
                    let (r, c) = (index / side, index % side);
                    let mut expected = 0u16;
                    for dr in 0..3 {
                        for dc in 0..3 {
                            let (rr, cc) = ((r + dr).wrapping_sub(1), (c + dc).wrapping_sub(1));
                            if rr < side && cc < side && set.contains(rr * side + cc) {
                                expected |= 1 << (3 * dr + dc);
                            }
                        }
                    }
                    assert_eq!(geo.block(index, set), expected, "side {side}, cell {index}");
                }
            }
        }
    }

    #[test]
    fn neighbours_do_not_wrap_around_rows() {
        let geo = Geometry::new(9);
        // r0c8 is at the end of row 0; its right neighbour would be r1c0 if shifts wrapped.
        let end_of_row = Bitboard::from_index(geo.index(Cell::new(0, 8)));
        let n: Vec<Cell> = geo.cells_in(geo.neighbours(end_of_row)).collect();
        assert_eq!(n, vec![Cell::new(0, 7), Cell::new(1, 8)]);
        let start_of_row = Bitboard::from_index(geo.index(Cell::new(4, 0)));
        let n: Vec<Cell> = geo.cells_in(geo.neighbours(start_of_row)).collect();
        assert_eq!(n, vec![Cell::new(3, 0), Cell::new(4, 1), Cell::new(5, 0)]);
    }

    #[test]
    fn neighbours_stay_on_the_largest_board() {
        let geo = Geometry::new(MAX_GRID);
        let corner = Bitboard::from_index(geo.index(Cell::new(10, 10)));
        let n: Vec<Cell> = geo.cells_in(geo.neighbours(corner)).collect();
        assert_eq!(n, vec![Cell::new(9, 10), Cell::new(10, 9)]);
    }

    #[test]
    fn diagonal_cells_are_not_connected() {
        let geo = Geometry::new(9);
        let a = Bitboard::from_index(geo.index(Cell::new(2, 2)));
        let b = Bitboard::from_index(geo.index(Cell::new(3, 3)));
        assert!(!geo.is_connected(a | b));
        let c = Bitboard::from_index(geo.index(Cell::new(2, 3)));
        assert!(geo.is_connected(a | b | c));
    }
}
