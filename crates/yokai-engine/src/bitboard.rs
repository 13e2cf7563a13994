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

    /// Cell indices in increasing order.
    #[inline]
    pub fn iter(self) -> BitIter {
        BitIter(self.0)
    }
}

impl std::ops::BitOr for Bitboard {
    type Output = Bitboard;
    #[inline(always)]
    fn bitor(self, rhs: Bitboard) -> Bitboard {
        Bitboard(self.0 | rhs.0)
    }
}
impl std::ops::BitAnd for Bitboard {
    type Output = Bitboard;
    #[inline(always)]
    fn bitand(self, rhs: Bitboard) -> Bitboard {
        Bitboard(self.0 & rhs.0)
    }
}
impl std::ops::BitXor for Bitboard {
    type Output = Bitboard;
    #[inline(always)]
    fn bitxor(self, rhs: Bitboard) -> Bitboard {
        Bitboard(self.0 ^ rhs.0)
    }
}
impl std::ops::Not for Bitboard {
    type Output = Bitboard;
    #[inline(always)]
    fn not(self) -> Bitboard {
        Bitboard(!self.0)
    }
}
impl std::ops::BitOrAssign for Bitboard {
    #[inline(always)]
    fn bitor_assign(&mut self, rhs: Bitboard) {
        self.0 |= rhs.0;
    }
}
impl std::ops::BitAndAssign for Bitboard {
    #[inline(always)]
    fn bitand_assign(&mut self, rhs: Bitboard) {
        self.0 &= rhs.0;
    }
}
impl std::ops::BitXorAssign for Bitboard {
    #[inline(always)]
    fn bitxor_assign(&mut self, rhs: Bitboard) {
        self.0 ^= rhs.0;
    }
}

impl fmt::Debug for Bitboard {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "Bitboard(")?;
        f.debug_list().entries(self.iter()).finish()?;
        write!(f, ")")
    }
}

/// Iterator over the set bits of a bitboard, lowest first.
pub struct BitIter(u128);

impl Iterator for BitIter {
    type Item = usize;
    #[inline(always)]
    fn next(&mut self) -> Option<usize> {
        if self.0 == 0 {
            return None;
        }
        let i = self.0.trailing_zeros() as usize;
        self.0 &= self.0 - 1;
        Some(i)
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
                | ((b << g) & self.board.0)
                | (b >> g),
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

    /// Whether `set` is one 4-connected group (the empty set counts as connected).
    #[inline]
    pub fn is_connected(&self, set: Bitboard) -> bool {
        set.is_empty() || self.flood(set.lowest(), set) == set
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn neighbours_do_not_wrap_around_rows() {
        let geo = Geometry::new(9);
        // r0c8 is at the end of row 0; its right neighbour would be r1c0 if shifts wrapped.
        let end_of_row = Bitboard::from_index(geo.index(Cell::new(0, 8)));
        let n: Vec<Cell> = geo
            .neighbours(end_of_row)
            .iter()
            .map(|i| geo.cell(i))
            .collect();
        assert_eq!(n, vec![Cell::new(0, 7), Cell::new(1, 8)]);
        let start_of_row = Bitboard::from_index(geo.index(Cell::new(4, 0)));
        let n: Vec<Cell> = geo
            .neighbours(start_of_row)
            .iter()
            .map(|i| geo.cell(i))
            .collect();
        assert_eq!(n, vec![Cell::new(3, 0), Cell::new(4, 1), Cell::new(5, 0)]);
    }

    #[test]
    fn neighbours_stay_on_the_largest_board() {
        let geo = Geometry::new(MAX_GRID);
        let corner = Bitboard::from_index(geo.index(Cell::new(10, 10)));
        let n: Vec<Cell> = geo.neighbours(corner).iter().map(|i| geo.cell(i)).collect();
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
