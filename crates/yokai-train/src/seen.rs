//! What one seat sees: its observation of a game mapped through the symmetry it sees the
//! game through (Other-Play draws one per seat and episode; the identity elsewhere), and
//! its chosen action mapped back to the true game.
//!
//! The batched rollout (`Actor::view`) and every place that steps a network
//! on game states outside it (OBL's fictitious continuations, a partner's replayed memory)
//! use these, so that a seat sees a fictitious world through the same symmetry as the real
//! one it plays in.

use yokai_engine::{Config, Game, Seat, Symmetry};
use yokai_vec::Encoding;

/// One seat of one game, seen through `symmetry`.
#[derive(Clone, Copy, Debug)]
pub struct SeenSeat<'a> {
    pub game: &'a Game,
    pub seat: Seat,
    pub symmetry: Symmetry,
}

impl<'a> SeenSeat<'a> {
    /// The seat as it is, without a symmetry.
    pub fn plain(game: &'a Game, seat: Seat) -> SeenSeat<'a> {
        SeenSeat {
            game,
            seat,
            symmetry: Symmetry::identity(game.config()),
        }
    }

    /// The seat's observation in `encoding`, through its symmetry, written to `out` (sized
    /// `encoding.shape(config)`).
    pub fn write(&self, encoding: Encoding, out: &mut [f32]) {
        if self.symmetry.is_identity() {
            encoding
                .write(self.game, self.seat, out)
                .expect("a buffer sized from the game's own config");
            return;
        }
        let mut truth = vec![0f32; out.len()];
        encoding
            .write(self.game, self.seat, &mut truth)
            .expect("a buffer sized from the game's own config");
        see_through(&self.symmetry, self.game.config(), encoding, &truth, out);
    }

    /// Whether the seat is the one to act.
    pub fn acts(&self) -> bool {
        self.game.current_seat() == self.seat
    }
}

/// `truth`, one seat's observation of the true game in `encoding`, as a seat seeing the
/// game through `symmetry` sees it, written to `out`.
pub fn see_through(
    symmetry: &Symmetry,
    config: &Config,
    encoding: Encoding,
    truth: &[f32],
    out: &mut [f32],
) {
    match encoding {
        Encoding::Image(part, layout) => symmetry.apply_image_in(config, part, layout, truth, out),
        Encoding::Graph(part) => symmetry.apply_nodes(config, part, truth, out),
        Encoding::None => Ok(()),
    }
    .expect("buffers sized from the same config");
}

#[cfg(test)]
mod tests {
    use super::*;
    use yokai_engine::Action;

    /// A seat's view through a symmetry is the true observation mapped by it, and through
    /// the identity it is the true observation, in each encoding a network reads: over the
    /// states of a game played with its first legal non-END action, every symmetry of the
    /// 9c-2p game, both seats.
    #[test]
    fn a_seats_view_is_its_observation_mapped_by_its_symmetry() {
        let config = Config::from_name("9c-2p").unwrap();
        let encodings = [
            Encoding::Graph(yokai_engine::Part::Public),
            Encoding::Image(yokai_engine::Part::Full, yokai_engine::ImageLayout::Hwc),
        ];
        let symmetries = Symmetry::enumerate(&config, true, true, false);
        assert_eq!(symmetries.len(), 24, "3! colour maps × 4 rotations");
        let mut game = Game::new(config, 11);
        let mut changed = 0;
        for _ in 0..12 {
            for encoding in encodings {
                let l: usize = encoding.shape(&config).iter().product();
                for s in 0..2 {
                    let seat = Seat(s);
                    let mut truth = vec![0f32; l];
                    encoding.write(&game, seat, &mut truth).unwrap();
                    let mut plain = vec![0f32; l];
                    SeenSeat::plain(&game, seat).write(encoding, &mut plain);
                    assert_eq!(plain, truth);
                    for &symmetry in &symmetries {
                        let mut want = vec![0f32; l];
                        see_through(&symmetry, &config, encoding, &truth, &mut want);
                        let mut got = vec![0f32; l];
                        let view = SeenSeat {
                            game: &game,
                            seat,
                            symmetry,
                        };
                        view.write(encoding, &mut got);
                        assert_eq!(got, want);
                        changed += (got != truth) as usize;
                    }
                }
            }
            let a = game
                .legal_actions(game.current_seat())
                .into_iter()
                .find(|&a| a != Action::End)
                .unwrap();
            game.apply(a).unwrap();
        }
        assert!(changed > 1000, "most symmetries change the view: {changed}");
    }
}
