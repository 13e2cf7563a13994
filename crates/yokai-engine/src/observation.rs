//! Observations (RULES §5), written into caller-provided buffers so batched code never
//! allocates.
//!
//! # Image `[g, g+1, F]`, F = 2C + 8 (row-major: rows, then columns, then channels)
//!
//! Columns `0..g` are the board; column `g` holds one row per hint slot.
//!
//! The same values can also be written channels-first, `[F, g, g+1]`
//! ([`ImageLayout::Chw`]): the order convolution layers in PyTorch and burn take without a
//! transpose, and the order in which a batched environment updates images in place most
//! cheaply, because the two broadcast channels are then two contiguous planes instead of two
//! values on every pixel.
//!
//! | channel | board cell | hint column, row h |
//! |---|---|---|
//! | `0..C` known colour one-hot | colour of the card here, if this seat sees it | 0 |
//! | `C..2C` hint colours multi-hot | colours of the hint on the card here | colours of slot h once face up |
//! | `2C` row | r / (g−1), every cell | 0 |
//! | `2C+1` column | c / (g−1), every cell | 0 |
//! | `2C+2` present | a card is here | slot h is still face down |
//! | `2C+3` hinted | the card here carries a hint | slot h is placed |
//! | `2C+4` observed this turn | the acting seat observed this card this turn | 0 |
//! | `2C+5` card id | (id+1) / Y | 0 |
//! | `2C+6` my turn | 1 if this seat acts, on every pixel | same |
//! | `2C+7` substep | substep / 3, on every pixel | same |
//!
//! # Graph
//! Adjacency `[Y, Y]` (1 where two cards are 4-neighbours) and node features `[Y+H, F]` with
//! the same channels: card node k carries the board-cell channels of its cell; hint node h
//! carries its colours once face up, "present" while face down, "hinted" once placed, and —
//! once placed — the row, column and id channels of the card under it.
//!
//! # Public / private split (for OBL)
//! *Public* is the full encoding with the known-colour channels zeroed; *private* is the
//! known-colour channels alone: `[g, g+1, C]` for the image, `[Y, C]` for the graph.
//!
//! # Ground truth
//! `[Y]`: the true colour index of every card id (for belief models and probes only).
//!
//! # Element types
//! `f32` buffers get the scaled values above. `u8` buffers get the unscaled integers (row,
//! column, id+1, substep, 0/1), so `f32 = u8 / scale` with [`ImageChannels::scales`].

use crate::action::Action;
use crate::config::Config;
use crate::game::Game;
use crate::types::{Card, CardSet, HintSlot, Seat};

/// An element type an observation or mask can be written in.
pub trait Scalar: Copy + PartialEq + std::fmt::Debug + Send + Sync + 'static {
    const ZERO: Self;
    const ONE: Self;
    /// The value `num / den` (`f32`), or the integer `num` (`u8`).
    fn ratio(num: u32, den: u32) -> Self;
    /// The `num` this value was written from with denominator `den` (inverse of `ratio`).
    fn numerator(self, den: u32) -> u32;
    /// `ONE` if `on`, else `ZERO`.
    #[inline(always)]
    fn flag(on: bool) -> Self {
        if on {
            Self::ONE
        } else {
            Self::ZERO
        }
    }
}

impl Scalar for f32 {
    const ZERO: f32 = 0.0;
    const ONE: f32 = 1.0;
    #[inline(always)]
    fn ratio(num: u32, den: u32) -> f32 {
        if den == 0 {
            0.0
        } else {
            num as f32 / den as f32
        }
    }
    #[inline(always)]
    fn numerator(self, den: u32) -> u32 {
        (self * den as f32).round() as u32
    }
}

impl Scalar for u8 {
    const ZERO: u8 = 0;
    const ONE: u8 = 1;
    #[inline(always)]
    fn ratio(num: u32, _den: u32) -> u8 {
        num as u8
    }
    #[inline(always)]
    fn numerator(self, _den: u32) -> u32 {
        self as u32
    }
}

/// Channel offsets of the image and graph encodings of one configuration.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ImageChannels {
    pub known: usize,
    pub hint: usize,
    pub row: usize,
    pub col: usize,
    pub present: usize,
    pub hinted: usize,
    pub observed: usize,
    pub id: usize,
    pub my_turn: usize,
    pub substep: usize,
    /// F, channels per pixel (or features per graph node).
    pub len: usize,
}

impl ImageChannels {
    pub fn new(colours: usize) -> ImageChannels {
        let c = colours;
        ImageChannels {
            known: 0,
            hint: c,
            row: 2 * c,
            col: 2 * c + 1,
            present: 2 * c + 2,
            hinted: 2 * c + 3,
            observed: 2 * c + 4,
            id: 2 * c + 5,
            my_turn: 2 * c + 6,
            substep: 2 * c + 7,
            len: 2 * c + 8,
        }
    }

    /// Per channel, the divisor that turns a `u8` observation into the `f32` one.
    pub fn scales(&self, config: &Config) -> Vec<u32> {
        let mut s = vec![1; self.len];
        s[self.row] = config.grid() as u32 - 1;
        s[self.col] = config.grid() as u32 - 1;
        s[self.id] = config.cards() as u32;
        s[self.substep] = 3;
        s
    }

    /// Human-readable channel names, for docs and debugging.
    pub fn names(&self) -> Vec<String> {
        let c = self.hint - self.known;
        let mut n: Vec<String> = (0..c).map(|i| format!("known_colour_{i}")).collect();
        n.extend((0..c).map(|i| format!("hint_colour_{i}")));
        n.extend(
            [
                "row",
                "col",
                "present",
                "hinted",
                "observed_this_turn",
                "card_id",
                "my_turn",
                "substep",
            ]
            .map(String::from),
        );
        n
    }
}

/// Which part of an observation to write (RULES §5, item 3).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Part {
    /// Everything the seat knows.
    Full,
    /// Everything but the seat's private colour knowledge (known-colour channels zero).
    Public,
    /// The private colour knowledge alone (C channels).
    Private,
}

/// Memory order of an image observation (see the module docs). Both hold the same values.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum ImageLayout {
    /// `[g, g+1, F]`: rows, columns, channels (RULES §5; the default).
    #[default]
    Hwc,
    /// `[F, g, g+1]`: channels, rows, columns.
    Chw,
}

/// Element offsets of one step along each image axis.
#[derive(Clone, Copy, Debug)]
struct Strides {
    row: usize,
    col: usize,
    channel: usize,
    /// g: board cell `i` of the bitboard is at row `i / g`, column `i % g`.
    grid: usize,
}

impl Strides {
    fn new(config: &Config, channels: usize, layout: ImageLayout) -> Strides {
        let (g, width) = (config.grid(), config.grid() + 1);
        match layout {
            ImageLayout::Hwc => Strides {
                row: width * channels,
                col: channels,
                channel: 1,
                grid: g,
            },
            ImageLayout::Chw => Strides {
                row: width,
                col: 1,
                channel: g * width,
                grid: g,
            },
        }
    }

    /// Offset of channel 0 of the pixel at (`row`, `col`).
    #[inline(always)]
    fn pixel(&self, row: usize, col: usize) -> usize {
        row * self.row + col * self.col
    }

    /// Offset of channel 0 of the pixel of board cell `cell` (a bitboard index).
    #[inline(always)]
    fn cell(&self, cell: usize) -> usize {
        self.pixel(cell / self.grid, cell % self.grid)
    }

    /// Offset of channel 0 of hint slot `slot`'s row of the hint column.
    #[inline(always)]
    fn slot(&self, slot: usize) -> usize {
        self.pixel(slot, self.grid)
    }
}

/// A buffer of the wrong length.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{what} buffer has length {got}, expected {expected} ({shape})")]
pub struct BufferError {
    pub what: &'static str,
    pub expected: usize,
    pub got: usize,
    pub shape: String,
}

fn check_len(what: &'static str, got: usize, shape: &[usize]) -> Result<(), BufferError> {
    let expected = shape.iter().product();
    if got == expected {
        Ok(())
    } else {
        Err(BufferError {
            what,
            expected,
            got,
            shape: format!("{shape:?}"),
        })
    }
}

impl Config {
    pub fn image_channels(&self) -> ImageChannels {
        ImageChannels::new(self.colours())
    }
    /// Shape of the image observation of one seat: `[g, g+1, F]`, or `[g, g+1, C]` for the
    /// private part.
    pub fn image_shape(&self, part: Part) -> [usize; 3] {
        let f = match part {
            Part::Private => self.colours(),
            _ => self.image_channels().len,
        };
        [self.grid(), self.grid() + 1, f]
    }
    /// Shape of the image observation of one seat in `layout`: `[g, g+1, F]` or `[F, g, g+1]`
    /// (`F` = C for the private part).
    pub fn image_shape_in(&self, part: Part, layout: ImageLayout) -> [usize; 3] {
        let [h, w, f] = self.image_shape(part);
        match layout {
            ImageLayout::Hwc => [h, w, f],
            ImageLayout::Chw => [f, h, w],
        }
    }
    /// Shape of the graph node features: `[Y+H, F]`, or `[Y, C]` for the private part.
    pub fn node_shape(&self, part: Part) -> [usize; 2] {
        match part {
            Part::Private => [self.cards(), self.colours()],
            _ => [self.cards() + self.hints(), self.image_channels().len],
        }
    }
    /// Shape of the graph adjacency: `[Y, Y]`.
    pub fn adjacency_shape(&self) -> [usize; 2] {
        [self.cards(), self.cards()]
    }
}

/// The image of an empty board: positional channels on every board cell and the two
/// broadcast channels on every pixel; everything else zero.
fn write_background<T: Scalar>(
    config: &Config,
    layout: ImageLayout,
    my_turn: bool,
    substep: u8,
    out: &mut [T],
) {
    let ch = config.image_channels();
    let s = Strides::new(config, ch.len, layout);
    let g = config.grid();
    let scale = g as u32 - 1;
    let my_turn = T::flag(my_turn);
    let substep = T::ratio(substep as u32, 3);
    out.fill(T::ZERO);
    for r in 0..g {
        for c in 0..=g {
            let px = s.pixel(r, c);
            if c < g {
                out[px + ch.row * s.channel] = T::ratio(r as u32, scale);
                out[px + ch.col * s.channel] = T::ratio(c as u32, scale);
            }
            out[px + ch.my_turn * s.channel] = my_turn;
            out[px + ch.substep * s.channel] = substep;
        }
    }
}

/// What an action changes in every seat's image, besides the two broadcast channels:
/// computed by [`Game::image_changes`] *before* the action is applied and handed to
/// [`ImageEncoder::update`] after it, so that a batched environment writes the few values
/// that change instead of whole images. Each store into an image that is not in cache costs
/// a cache line, so the update writes exactly the channels that change.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ImageChanges {
    /// A card observed: "observed this turn" for everyone, its colour for the actor.
    observed: Option<Card>,
    /// A card moved, and the bit index of the cell it left.
    moved: Option<(Card, u8)>,
    /// A hint slot turned face up.
    revealed: Option<HintSlot>,
    /// A hint placed on a card.
    placed: Option<(HintSlot, Card)>,
    /// The action ends the turn: "my turn" changes, and these cards (observed in the turn
    /// that ends) lose their "observed this turn" mark and, with imperfect memory, the
    /// colour the actor saw.
    turn_end: Option<CardSet>,
}

/// Writes image observations fast. The background (everything that does not depend on
/// where the cards are) is precomputed for each (is-my-turn, substep) pair, so a full write
/// is one `memcpy` plus the card and hint pixels; [`ImageEncoder::update`] goes further and
/// writes only the channels an action changed. Same output as [`Game::write_image_in`]
/// (tested).
#[derive(Clone, Debug)]
pub struct ImageEncoder<T: Scalar> {
    config: Config,
    layout: ImageLayout,
    len: usize,
    /// `[my_turn 0/1][substep 0..4]` backgrounds, each `len` long.
    backgrounds: Vec<T>,
}

impl<T: Scalar> ImageEncoder<T> {
    pub fn new(config: &Config, layout: ImageLayout) -> ImageEncoder<T> {
        let len: usize = config.image_shape(Part::Full).iter().product();
        let mut backgrounds = vec![T::ZERO; 8 * len];
        for my_turn in 0..2 {
            for substep in 0..4 {
                let out = &mut backgrounds[(my_turn * 4 + substep) * len..][..len];
                write_background(config, layout, my_turn == 1, substep as u8, out);
            }
        }
        ImageEncoder {
            config: *config,
            layout,
            len,
            backgrounds,
        }
    }

    /// Write `seat`'s image of `game` (which must have this encoder's config).
    #[inline]
    pub fn write(
        &self,
        game: &Game,
        seat: Seat,
        part: Part,
        out: &mut [T],
    ) -> Result<(), BufferError> {
        debug_assert_eq!(game.config, self.config);
        game.write_image_over(seat, part, self.layout, out, |my_turn, substep, out| {
            let index = my_turn as usize * 4 + substep as usize;
            out.copy_from_slice(&self.backgrounds[index * self.len..][..self.len]);
        })
    }

    /// Bring `out`, which holds `seat`'s image of the game one action ago, up to date with
    /// `game`, given that action's [`ImageChanges`]. The private part is small and is
    /// rewritten whole, and so is the image of a game that just ended (nobody's turn).
    #[inline]
    pub fn update(
        &self,
        game: &Game,
        seat: Seat,
        part: Part,
        changes: ImageChanges,
        out: &mut [T],
    ) -> Result<(), BufferError> {
        if part == Part::Private || game.is_over() {
            return self.write(game, seat, part, out);
        }
        if out.len() != self.len {
            return check_len(
                "image observation",
                out.len(),
                &self.config.image_shape(part),
            );
        }
        let config = &self.config;
        let ch = config.image_channels();
        let s = Strides::new(config, ch.len, self.layout);
        let substep = T::ratio(game.substep as u32, 3);
        let broadcast = |out: &mut [T], channel: usize, value: T| match self.layout {
            ImageLayout::Chw => out[channel * s.channel..][..s.channel].fill(value),
            ImageLayout::Hwc => out[channel..]
                .iter_mut()
                .step_by(ch.len)
                .for_each(|v| *v = value),
        };
        broadcast(out, ch.substep, substep);
        let known = game.known_in(seat, part);
        let card_pixel = |card: Card| game.card_pixel(card, &s);
        let colour_channel = |card: Card| ch.known + game.colour_of[card.index()].index();
        if let Some(card) = changes.observed {
            let px = card_pixel(card);
            out[px + ch.observed * s.channel] = T::ONE;
            if known.contains(card) {
                out[px + colour_channel(card) * s.channel] = T::ONE;
            }
        }
        if let Some((card, from)) = changes.moved {
            // A moving card is unhinted: only these channels are set on the cell it left.
            let from = s.cell(from as usize);
            for channel in [ch.present, ch.id, ch.observed, colour_channel(card)] {
                out[from + channel * s.channel] = T::ZERO;
            }
            game.write_card_pixel(card.index(), known, &ch, &s, out);
        }
        // Hints change once a turn at most: their pixels are rewritten by the full writers,
        // whose only zero-to-one change here is the revealed slot's "face down" mark.
        if let Some(slot) = changes.revealed {
            out[s.slot(slot.index()) + ch.present * s.channel] = T::ZERO;
            game.write_slot_pixel(slot.index(), &ch, &s, out);
        }
        if let Some((slot, card)) = changes.placed {
            game.write_slot_pixel(slot.index(), &ch, &s, out);
            game.write_card_pixel(card.index(), known, &ch, &s, out);
        }
        if let Some(cards) = changes.turn_end {
            broadcast(out, ch.my_turn, T::flag(game.is_turn_of(seat)));
            for card in cards.iter() {
                let px = card_pixel(card);
                out[px + ch.observed * s.channel] = T::ZERO;
                out[px + colour_channel(card) * s.channel] = T::flag(known.contains(card));
            }
        }
        Ok(())
    }
}

impl Game {
    /// Write `seat`'s image observation `[g, g+1, F]` (see the module docs for the layout).
    /// Builds the background on the fly; batched code uses [`ImageEncoder`], which copies a
    /// precomputed one.
    pub fn write_image<T: Scalar>(
        &self,
        seat: Seat,
        part: Part,
        out: &mut [T],
    ) -> Result<(), BufferError> {
        self.write_image_in(seat, part, ImageLayout::Hwc, out)
    }

    /// Write `seat`'s image observation in `layout`.
    pub fn write_image_in<T: Scalar>(
        &self,
        seat: Seat,
        part: Part,
        layout: ImageLayout,
        out: &mut [T],
    ) -> Result<(), BufferError> {
        let config = self.config;
        self.write_image_over(seat, part, layout, out, |my_turn, substep, out| {
            write_background(&config, layout, my_turn, substep, out)
        })
    }

    /// What `action`, about to be applied, changes in the images (see [`ImageChanges`]).
    pub fn image_changes(&self, action: Action) -> ImageChanges {
        let mut changes = ImageChanges::default();
        match action {
            Action::Observe(card) => changes.observed = Some(card),
            Action::Move(card, _) => changes.moved = Some((card, self.cell_of[card.index()])),
            Action::Reveal => changes.revealed = Some(HintSlot(self.revealed)),
            Action::Place(slot, card) => changes.placed = Some((slot, card)),
            Action::Noop | Action::End => {}
        }
        if self.substep == 3 {
            changes.turn_end = Some(self.turn_observed);
        }
        changes
    }

    /// The one image writer: checks the buffer, lets `background(my_turn, substep, out)`
    /// fill in what does not depend on the cards, then writes the card and hint pixels.
    fn write_image_over<T: Scalar>(
        &self,
        seat: Seat,
        part: Part,
        layout: ImageLayout,
        out: &mut [T],
        background: impl FnOnce(bool, u8, &mut [T]),
    ) -> Result<(), BufferError> {
        check_len(
            "image observation",
            out.len(),
            &self.config.image_shape(part),
        )?;
        if part == Part::Private {
            self.write_image_private(seat, layout, out);
            return Ok(());
        }
        background(self.is_turn_of(seat), self.substep, out);
        let ch = self.config.image_channels();
        let s = Strides::new(&self.config, ch.len, layout);
        let known = self.known_in(seat, part);
        for k in 0..self.config.cards() {
            self.write_card_pixel(k, known, &ch, &s, out);
        }
        for slot in 0..self.config.hints() {
            self.write_slot_pixel(slot, &ch, &s, out);
        }
        Ok(())
    }

    fn write_image_private<T: Scalar>(&self, seat: Seat, layout: ImageLayout, out: &mut [T]) {
        let s = Strides::new(&self.config, self.config.colours(), layout);
        out.fill(T::ZERO);
        for card in self.known_cards(seat).iter() {
            let colour = self.colour_of[card.index()].index();
            out[self.card_pixel(card, &s) + colour * s.channel] = T::ONE;
        }
    }

    /// Whether `seat` acts now ("my turn": nobody's once the game is over).
    #[inline]
    fn is_turn_of(&self, seat: Seat) -> bool {
        seat.0 == self.current && !self.is_over()
    }

    /// The cards whose colour `part` of `seat`'s observation shows.
    #[inline]
    fn known_in(&self, seat: Seat, part: Part) -> CardSet {
        if part == Part::Full {
            self.known_cards(seat)
        } else {
            CardSet::EMPTY
        }
    }

    /// Offset of channel 0 of `card`'s pixel.
    #[inline(always)]
    fn card_pixel(&self, card: Card, s: &Strides) -> usize {
        s.cell(self.cell_of[card.index()] as usize)
    }

    /// Write card `k`'s pixel over one whose card channels are zero (or already hold it).
    #[inline(always)]
    fn write_card_pixel<T: Scalar>(
        &self,
        k: usize,
        known: CardSet,
        ch: &ImageChannels,
        s: &Strides,
        out: &mut [T],
    ) {
        let card = Card(k as u8);
        let px = self.card_pixel(card, s);
        let mut set = |channel: usize, value: T| out[px + channel * s.channel] = value;
        set(ch.present, T::ONE);
        set(ch.id, T::ratio(k as u32 + 1, self.config.cards() as u32));
        if known.contains(card) {
            set(ch.known + self.colour_of[k].index(), T::ONE);
        }
        if self.hinted.contains(card) {
            set(ch.hinted, T::ONE);
            for colour in self.hint_colours[self.card_hint[k] as usize].colours() {
                set(ch.hint + colour.index(), T::ONE);
            }
        }
        if self.turn_observed.contains(card) {
            set(ch.observed, T::ONE);
        }
    }

    /// Write hint slot `slot`'s row of the hint column over one whose card channels are zero
    /// (or hold it as it was, up to the "face down" mark, which it only sets).
    #[inline(always)]
    fn write_slot_pixel<T: Scalar>(
        &self,
        slot: usize,
        ch: &ImageChannels,
        s: &Strides,
        out: &mut [T],
    ) {
        let px = s.slot(slot);
        let mut set = |channel: usize| out[px + channel * s.channel] = T::ONE;
        if slot < self.revealed as usize {
            for colour in self.hint_colours[slot].colours() {
                set(ch.hint + colour.index());
            }
        } else {
            set(ch.present);
        }
        if self.hint_card(HintSlot(slot as u8)).is_some() {
            set(ch.hinted);
        }
    }

    /// Write the graph adjacency `[Y, Y]`: 1 where two cards are 4-neighbours (public).
    pub fn write_adjacency<T: Scalar>(&self, out: &mut [T]) -> Result<(), BufferError> {
        let config = &self.config;
        check_len("adjacency", out.len(), &config.adjacency_shape())?;
        let y = config.cards();
        let geo = config.geometry();
        // Read only at occupied cells, each of which holds a card.
        let mut card_at = [0u8; 128];
        for k in 0..y {
            card_at[self.cell_of[k] as usize] = k as u8;
        }
        out.fill(T::ZERO);
        for k in 0..y {
            let own = crate::bitboard::Bitboard::from_index(self.cell_of[k] as usize);
            for cell in (geo.neighbours(own) & self.occupied).iter() {
                out[k * y + card_at[cell] as usize] = T::ONE;
            }
        }
        Ok(())
    }

    /// Write `seat`'s graph node features (see the module docs).
    pub fn write_nodes<T: Scalar>(
        &self,
        seat: Seat,
        part: Part,
        out: &mut [T],
    ) -> Result<(), BufferError> {
        let config = &self.config;
        check_len("graph node features", out.len(), &config.node_shape(part))?;
        let known = self.known_cards(seat);
        out.fill(T::ZERO);
        if part == Part::Private {
            let c = config.colours();
            for card in known.iter() {
                out[card.index() * c + self.colour_of[card.index()].index()] = T::ONE;
            }
            return Ok(());
        }
        let ch = config.image_channels();
        let f = ch.len;
        let g = config.grid();
        let y = config.cards();
        let scale = g as u32 - 1;
        let my_turn = T::flag(self.is_turn_of(seat));
        let substep = T::ratio(self.substep as u32, 3);
        let place = |px: &mut [T], card: usize| {
            let cell = self.cell_of[card] as usize;
            px[ch.row] = T::ratio((cell / g) as u32, scale);
            px[ch.col] = T::ratio((cell % g) as u32, scale);
            px[ch.id] = T::ratio(card as u32 + 1, y as u32);
        };
        for k in 0..y {
            let card = Card(k as u8);
            let px = &mut out[k * f..][..f];
            place(px, k);
            px[ch.present] = T::ONE;
            if part == Part::Full && known.contains(card) {
                px[ch.known + self.colour_of[k].index()] = T::ONE;
            }
            if self.hinted.contains(card) {
                px[ch.hinted] = T::ONE;
                for colour in self.hint_colours[self.card_hint[k] as usize].colours() {
                    px[ch.hint + colour.index()] = T::ONE;
                }
            }
            if self.turn_observed.contains(card) {
                px[ch.observed] = T::ONE;
            }
            px[ch.my_turn] = my_turn;
            px[ch.substep] = substep;
        }
        for slot in 0..config.hints() {
            let px = &mut out[(y + slot) * f..][..f];
            if slot < self.revealed as usize {
                for colour in self.hint_colours[slot].colours() {
                    px[ch.hint + colour.index()] = T::ONE;
                }
            } else {
                px[ch.present] = T::ONE;
            }
            if let Some(card) = self.hint_card(HintSlot(slot as u8)) {
                px[ch.hinted] = T::ONE;
                place(px, card.index());
            }
            px[ch.my_turn] = my_turn;
            px[ch.substep] = substep;
        }
        Ok(())
    }

    /// Write the true colour index of every card id (`[Y]`). Hidden information.
    pub fn write_ground_truth<T: Scalar>(&self, out: &mut [T]) -> Result<(), BufferError> {
        check_len("ground truth", out.len(), &[self.config.cards()])?;
        for (k, v) in out.iter_mut().enumerate() {
            *v = T::ratio(self.colour_of[k].0 as u32, 1);
        }
        Ok(())
    }
}
