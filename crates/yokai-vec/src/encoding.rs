//! Which observation the environment writes for every seat, and how to write one.

use crate::VecError;
use yokai_engine::{Config, Game, ImageLayout, Part, Scalar, Seat};

/// Which observation the environment writes for every seat.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Encoding {
    /// Image `[g, g+1, F]` (or `[g, g+1, C]` for the private part), or channels-first
    /// `[F, g, g+1]` with [`ImageLayout::Chw`].
    Image(Part, ImageLayout),
    /// Graph node features `[Y+H, F]` (or `[Y, C]` for private), plus the adjacency buffer.
    Graph(Part),
    /// No observation (masks and rewards only), e.g. for scripted policies.
    None,
}

impl Encoding {
    /// Shape of one seat's observation.
    pub fn shape(&self, config: &Config) -> Vec<usize> {
        match self {
            Encoding::Image(part, layout) => config.image_shape_in(*part, *layout).to_vec(),
            Encoding::Graph(part) => config.node_shape(*part).to_vec(),
            Encoding::None => vec![0],
        }
    }

    pub(crate) fn len(&self, config: &Config) -> usize {
        self.shape(config).iter().product()
    }

    /// Write `seat`'s observation of `game` in this encoding: the values the batched
    /// environment writes for that seat, for a game stepped outside it (Off-Belief
    /// Learning's fictitious games). Builds the image background on the fly.
    pub fn write<T: Scalar>(
        &self,
        game: &Game,
        seat: Seat,
        out: &mut [T],
    ) -> Result<(), yokai_engine::BufferError> {
        match *self {
            Encoding::Image(part, layout) => game.write_image_in(seat, part, layout, out),
            Encoding::Graph(part) => game.write_nodes(seat, part, out),
            Encoding::None => Ok(()),
        }
    }

    /// Parse `image`, `image-public`, `image-private` (each with an optional `-chw` for the
    /// channels-first layout, e.g. `image-public-chw`), `graph`, `graph-public`,
    /// `graph-private` or `none`.
    pub fn parse(name: &str) -> Result<Encoding, VecError> {
        let unknown = || VecError::Encoding(name.to_string());
        let (rest, layout) = match name.strip_suffix("-chw") {
            Some(rest) => (rest, ImageLayout::Chw),
            None => (name, ImageLayout::Hwc),
        };
        let (kind, part) = match rest.split_once('-') {
            Some((k, "public")) => (k, Part::Public),
            Some((k, "private")) => (k, Part::Private),
            Some(_) => return Err(unknown()),
            None => (rest, Part::Full),
        };
        match (kind, part, layout) {
            ("image", _, _) => Ok(Encoding::Image(part, layout)),
            ("graph", _, ImageLayout::Hwc) => Ok(Encoding::Graph(part)),
            ("none", Part::Full, ImageLayout::Hwc) => Ok(Encoding::None),
            _ => Err(unknown()),
        }
    }
}
