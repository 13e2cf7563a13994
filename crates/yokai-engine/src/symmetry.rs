//! Symmetries of the game for Other-Play (RULES §6): colour permutations × the dihedral
//! group of the grid (rotations always, reflections optionally).
//!
//! A [`Symmetry`] maps the true game to the view one agent sees. Observations and legal masks
//! are mapped *to* the view with `apply_*`; the agent's chosen action is mapped *back* with
//! `inverse().apply_action`. Card ids and hint slots are not permuted (they are labels that
//! both views share), so only MOVE targets change under a symmetry.

use crate::action::Action;
use crate::bitboard::Cell;
use crate::config::Config;
use crate::observation::{BufferError, ImageLayout, Part, Scalar};
use crate::types::{Colour, ColourSet, MAX_COLOURS};

/// One element of (colour permutations) × (dihedral group of the square grid).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Symmetry {
    /// `colour_map[c]` is the colour the view shows for true colour `c`.
    colour_map: [u8; MAX_COLOURS],
    colours: u8,
    /// Rotations by 90° clockwise, applied after the optional reflection.
    rotation: u8,
    /// Mirror left↔right before rotating.
    reflect: bool,
}

/// A symmetry that does not fit the configuration.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum SymmetryError {
    #[error("colour permutation {perm:?} is not a permutation of 0..{colours}")]
    NotAPermutation { perm: Vec<u8>, colours: usize },
    #[error("rotation {0} is not one of 0, 1, 2, 3 quarter turns")]
    Rotation(u8),
}

fn permutations(n: usize) -> Vec<Vec<u8>> {
    if n == 0 {
        return vec![vec![]];
    }
    let mut out = Vec::new();
    for p in permutations(n - 1) {
        for i in 0..n {
            let mut q = p.clone();
            q.insert(i, (n - 1) as u8);
            out.push(q);
        }
    }
    out.sort();
    out
}

impl Symmetry {
    pub fn identity(config: &Config) -> Symmetry {
        Symmetry {
            colour_map: [0, 1, 2, 3],
            colours: config.colours() as u8,
            rotation: 0,
            reflect: false,
        }
    }

    /// `perm[c]` is the colour shown for true colour `c`; `rotation` in quarter turns
    /// clockwise; `reflect` mirrors left↔right first.
    pub fn new(
        config: &Config,
        perm: &[u8],
        rotation: u8,
        reflect: bool,
    ) -> Result<Symmetry, SymmetryError> {
        let c = config.colours();
        let mut seen = 0u8;
        for &p in perm {
            if (p as usize) < c {
                seen |= 1 << p;
            }
        }
        if perm.len() != c || seen.count_ones() as usize != c {
            return Err(SymmetryError::NotAPermutation {
                perm: perm.to_vec(),
                colours: c,
            });
        }
        if rotation > 3 {
            return Err(SymmetryError::Rotation(rotation));
        }
        let mut colour_map = [0, 1, 2, 3];
        colour_map[..c].copy_from_slice(perm);
        Ok(Symmetry {
            colour_map,
            colours: c as u8,
            rotation,
            reflect,
        })
    }

    /// Every symmetry: C! colour permutations × 4 rotations (× 2 with reflections), in a
    /// fixed order, so a trainer can sample one by index.
    pub fn all(config: &Config, reflections: bool) -> Vec<Symmetry> {
        Symmetry::enumerate(config, true, true, reflections)
    }

    /// The symmetries of a sub-group: colour permutations only, rotations only, or both
    /// (the paper's Φ_col, Φ_rot and Φ_col × Φ_rot).
    pub fn enumerate(
        config: &Config,
        colours: bool,
        rotations: bool,
        reflections: bool,
    ) -> Vec<Symmetry> {
        let perms = if colours {
            permutations(config.colours())
        } else {
            vec![(0..config.colours() as u8).collect()]
        };
        let mut out = Vec::new();
        for perm in &perms {
            for reflect in [false, true]
                .into_iter()
                .take(if reflections { 2 } else { 1 })
            {
                for rotation in 0..if rotations { 4 } else { 1 } {
                    out.push(
                        Symmetry::new(config, perm, rotation, reflect)
                            .expect("valid by construction"),
                    );
                }
            }
        }
        out
    }

    pub fn rotation(&self) -> u8 {
        self.rotation
    }
    pub fn reflects(&self) -> bool {
        self.reflect
    }
    pub fn is_identity(&self) -> bool {
        self.rotation == 0
            && !self.reflect
            && (0..self.colours).all(|c| self.colour_map[c as usize] == c)
    }

    /// The symmetry that undoes this one.
    pub fn inverse(&self) -> Symmetry {
        let mut colour_map = [0, 1, 2, 3];
        for c in 0..self.colours as usize {
            colour_map[self.colour_map[c] as usize] = c as u8;
        }
        // A reflection is its own inverse; (rotate ∘ reflect)⁻¹ = reflect ∘ rotate⁻¹, and
        // reflect ∘ rot^k = rot^(−k) ∘ reflect, so the inverse is again "reflect, then rot^k".
        let rotation = if self.reflect {
            self.rotation
        } else {
            (4 - self.rotation) % 4
        };
        Symmetry {
            colour_map,
            colours: self.colours,
            rotation,
            reflect: self.reflect,
        }
    }

    #[inline(always)]
    pub fn map_colour(&self, colour: Colour) -> Colour {
        Colour(self.colour_map[colour.index()])
    }

    pub fn map_colour_set(&self, set: ColourSet) -> ColourSet {
        ColourSet(set.colours().fold(0, |m, c| m | 1 << self.map_colour(c).0))
    }

    /// Where a cell of a `g × g` grid goes.
    #[inline(always)]
    pub fn map_cell(&self, grid: usize, cell: Cell) -> Cell {
        let last = grid as u8 - 1;
        let (mut r, mut c) = (cell.row, cell.col);
        if self.reflect {
            c = last - c;
        }
        for _ in 0..self.rotation {
            (r, c) = (c, last - r);
        }
        Cell { row: r, col: c }
    }

    /// The action as seen in the view (only MOVE targets change).
    pub fn apply_action(&self, config: &Config, action: Action) -> Action {
        match action {
            Action::Move(card, cell) => Action::Move(card, self.map_cell(config.grid(), cell)),
            other => other,
        }
    }

    /// Map an action index of the true game to the view's index.
    pub fn apply_action_index(&self, config: &Config, index: usize) -> usize {
        match config.decode(index) {
            Ok(a) => config.encode(self.apply_action(config, a)),
            Err(_) => index,
        }
    }

    /// Map a legal mask `[N_a]` of the true game to the view.
    pub fn apply_mask<T: Scalar>(
        &self,
        config: &Config,
        input: &[T],
        out: &mut [T],
    ) -> Result<(), BufferError> {
        let n = config.num_actions();
        check(n, input.len(), "legal mask (input)")?;
        check(n, out.len(), "legal mask (output)")?;
        let layout = config.action_layout();
        out[..layout.movement].copy_from_slice(&input[..layout.movement]);
        out[layout.reveal..].copy_from_slice(&input[layout.reveal..]);
        // Off the MOVE substep every MOVE is illegal, and at it most cards' blocks are: a
        // block of zeros maps to zeros, so only the others are permuted cell by cell (this
        // runs for every seat at every step of Other-Play training).
        let moves = layout.movement..layout.reveal;
        let zero = |block: &[T]| block.iter().all(|&v| v == T::ZERO);
        if zero(&input[moves.clone()]) {
            out[moves].fill(T::ZERO);
            return Ok(());
        }
        let geo = config.geometry();
        let cells = geo.cells();
        let map: Vec<usize> = (0..cells)
            .map(|i| geo.index(self.map_cell(config.grid(), geo.cell(i))))
            .collect();
        for card in 0..config.cards() {
            let base = layout.movement + card * cells;
            let (from, to) = (&input[base..][..cells], &mut out[base..][..cells]);
            if zero(from) {
                to.fill(T::ZERO);
                continue;
            }
            for (i, &j) in map.iter().enumerate() {
                to[j] = from[i];
            }
        }
        Ok(())
    }

    /// Map one seat's image observation (`[g, g+1, F]`, or `[g, g+1, C]` for
    /// [`Part::Private`]) to the view: board pixels move, colour channels are relabelled,
    /// the positional channels describe the pixel's new place; hint-column rows stay.
    pub fn apply_image<T: Scalar>(
        &self,
        config: &Config,
        part: Part,
        input: &[T],
        out: &mut [T],
    ) -> Result<(), BufferError> {
        self.apply_image_in(config, part, ImageLayout::Hwc, input, out)
    }

    /// [`Symmetry::apply_image`] for an image in `layout` (channels-last or channels-first):
    /// the same map, so Other-Play works on either layout the environment writes.
    pub fn apply_image_in<T: Scalar>(
        &self,
        config: &Config,
        part: Part,
        layout: ImageLayout,
        input: &[T],
        out: &mut [T],
    ) -> Result<(), BufferError> {
        let shape = config.image_shape(part);
        let len: usize = shape.iter().product();
        check(len, input.len(), "image observation (input)")?;
        check(len, out.len(), "image observation (output)")?;
        let g = config.grid();
        let width = g + 1;
        let f = shape[2];
        let plane = g * width;
        // Where channel k of pixel p (= r·(g+1) + c) lies in the buffer.
        let at = |p: usize, k: usize| match layout {
            ImageLayout::Hwc => p * f + k,
            ImageLayout::Chw => k * plane + p,
        };
        let ch = config.image_channels();
        let scale = g as u32 - 1;
        // One pixel's channels on the stack (2C + 8 ≤ 16 with C ≤ MAX_COLOURS): this runs
        // for every seat at every step of Other-Play training.
        let mut buffers = [[T::ZERO; 2 * MAX_COLOURS + 8]; 2];
        let [src, dst] = &mut buffers;
        let (src, dst) = (&mut src[..f], &mut dst[..f]);
        for r in 0..g {
            for c in 0..width {
                let (tr, tc) = if c < g {
                    let t = self.map_cell(g, Cell::new(r, c));
                    (t.row as usize, t.col as usize)
                } else {
                    (r, c)
                };
                let (from, to) = (r * width + c, tr * width + tc);
                for (k, v) in src.iter_mut().enumerate() {
                    *v = input[at(from, k)];
                }
                if part == Part::Private {
                    self.permute_colours(src, dst, 0);
                } else {
                    dst.copy_from_slice(src);
                    self.permute_colours(src, dst, ch.known);
                    self.permute_colours(src, dst, ch.hint);
                    if c < g {
                        dst[ch.row] = T::ratio(tr as u32, scale);
                        dst[ch.col] = T::ratio(tc as u32, scale);
                    }
                }
                for (k, &v) in dst.iter().enumerate() {
                    out[at(to, k)] = v;
                }
            }
        }
        Ok(())
    }

    /// Map one seat's graph node features (`[Y+H, F]`, or `[Y, C]` for private) to the view.
    /// Adjacency needs no mapping: the dihedral group preserves 4-neighbourhoods.
    pub fn apply_nodes<T: Scalar>(
        &self,
        config: &Config,
        part: Part,
        input: &[T],
        out: &mut [T],
    ) -> Result<(), BufferError> {
        let shape = config.node_shape(part);
        let len: usize = shape.iter().product();
        check(len, input.len(), "graph node features (input)")?;
        check(len, out.len(), "graph node features (output)")?;
        let f = shape[1];
        let ch = config.image_channels();
        let g = config.grid();
        let scale = g as u32 - 1;
        for node in 0..shape[0] {
            let src = &input[node * f..][..f];
            let dst = &mut out[node * f..][..f];
            if part == Part::Private {
                self.permute_colours(src, dst, 0);
                continue;
            }
            dst.copy_from_slice(src);
            self.permute_colours(src, dst, ch.known);
            self.permute_colours(src, dst, ch.hint);
            // Card nodes always have a position; hint nodes once placed.
            if node < config.cards() || src[ch.hinted] == T::ONE {
                let cell = Cell::new(
                    src[ch.row].numerator(scale) as usize,
                    src[ch.col].numerator(scale) as usize,
                );
                let t = self.map_cell(g, cell);
                dst[ch.row] = T::ratio(t.row as u32, scale);
                dst[ch.col] = T::ratio(t.col as u32, scale);
            }
        }
        Ok(())
    }

    /// Map a ground-truth colour vector `[Y]` to the view.
    pub fn apply_ground_truth<T: Scalar>(&self, input: &[T], out: &mut [T]) {
        for (o, &i) in out.iter_mut().zip(input) {
            *o = T::ratio(self.colour_map[i.numerator(1) as usize] as u32, 1);
        }
    }

    #[inline(always)]
    fn permute_colours<T: Scalar>(&self, src: &[T], dst: &mut [T], offset: usize) {
        for c in 0..self.colours as usize {
            dst[offset + self.colour_map[c] as usize] = src[offset + c];
        }
    }
}

fn check(expected: usize, got: usize, what: &'static str) -> Result<(), BufferError> {
    if expected == got {
        Ok(())
    } else {
        Err(BufferError {
            what,
            expected,
            got,
            shape: format!("[{expected}]"),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn group_sizes() {
        let c9 = Config::from_name("9c").unwrap();
        let c16 = Config::from_name("16c").unwrap();
        assert_eq!(Symmetry::all(&c9, false).len(), 6 * 4);
        assert_eq!(Symmetry::all(&c9, true).len(), 6 * 8);
        assert_eq!(Symmetry::all(&c16, false).len(), 24 * 4);
        assert_eq!(Symmetry::enumerate(&c9, true, false, false).len(), 6);
        assert_eq!(Symmetry::enumerate(&c9, false, true, false).len(), 4);
    }

    #[test]
    fn quarter_turn_is_clockwise() {
        let c = Config::from_name("9c").unwrap();
        let s = Symmetry::new(&c, &[0, 1, 2], 1, false).unwrap();
        // top-left corner goes to top-right under a clockwise quarter turn
        assert_eq!(s.map_cell(9, Cell::new(0, 0)), Cell::new(0, 8));
        assert_eq!(s.map_cell(9, Cell::new(0, 8)), Cell::new(8, 8));
        let m = Symmetry::new(&c, &[0, 1, 2], 0, true).unwrap();
        assert_eq!(m.map_cell(9, Cell::new(2, 1)), Cell::new(2, 7));
    }

    #[test]
    fn inverse_undoes_every_element_on_every_cell() {
        let c = Config::from_name("16c").unwrap();
        for s in Symmetry::all(&c, true) {
            let inv = s.inverse();
            for r in 0..10 {
                for col in 0..10 {
                    let cell = Cell::new(r, col);
                    assert_eq!(inv.map_cell(10, s.map_cell(10, cell)), cell, "{s:?}");
                }
            }
            for colour in 0..4 {
                assert_eq!(inv.map_colour(s.map_colour(Colour(colour))), Colour(colour));
            }
        }
    }

    #[test]
    fn bad_symmetries_are_errors() {
        let c = Config::from_name("9c").unwrap();
        assert!(Symmetry::new(&c, &[0, 0, 1], 0, false).is_err());
        assert!(Symmetry::new(&c, &[0, 1], 0, false).is_err());
        assert!(Symmetry::new(&c, &[0, 1, 3], 0, false).is_err());
        assert_eq!(
            Symmetry::new(&c, &[0, 1, 2], 4, false),
            Err(SymmetryError::Rotation(4))
        );
    }
}
