//! One test per rule of docs/spec/rules.md, each on a hand-built board.

mod common;

use common::{deal, layout};
use yokai_engine::*;

fn nine() -> Config {
    Config::from_name("9c-2p-perfect").unwrap()
}

/// Colours by rows of the start square (every colour clustered), hints {0}, {0,1}, {0,2}, {1,2}.
fn clustered_deal(config: &Config) -> Deal {
    deal(
        config,
        &[0, 0, 0, 1, 1, 1, 2, 2, 2],
        &[0b001, 0b011, 0b101, 0b110],
    )
}

fn obs(card: u8) -> Action {
    Action::Observe(Card(card))
}

fn mv(card: u8, row: usize, col: usize) -> Action {
    Action::Move(Card(card), Cell::new(row, col))
}

fn illegal(game: &mut Game, action: Action) -> Illegal {
    let before = game.clone();
    match game.apply(action) {
        Err(ActionError::Illegal { reason, .. }) => {
            assert_eq!(*game, before, "a rejected {action} changed the state");
            reason
        }
        other => panic!("{action} should be illegal, got {other:?}"),
    }
}

// --- §1 reset ----------------------------------------------------------------------------

#[test]
fn reset_places_card_k_on_start_square_cell_k_and_seat_0_moves_first() {
    for name in ["9c-2p", "16c-3p"] {
        let config = Config::from_name(name).unwrap();
        let game = Game::new(config, 7);
        let (r0, c0, side) = config.start_square();
        for k in 0..config.cards() {
            assert_eq!(
                game.cell_of(Card(k as u8)),
                Cell::new(r0 + k / side, c0 + k % side)
            );
        }
        assert_eq!(game.current_seat(), Seat(0));
        assert_eq!(game.substep(), Substep::FirstObserve);
        assert_eq!(game.face_down(), config.hints());
        assert_eq!(game.steps(), 0);
    }
}

#[test]
fn explicit_deal_sets_every_colour_and_hint() {
    let config = nine();
    let d = deal(
        &config,
        &[2, 1, 0, 0, 1, 2, 2, 1, 0],
        &[0b110, 0b001, 0b011, 0b101],
    );
    let game = Game::from_deal(config, &d).unwrap();
    assert_eq!(game.colour_of(Card(0)), Colour(2));
    assert_eq!(game.hint_colours(HintSlot(0)), ColourSet(0b110));
    assert_eq!(game.deal(), d);
}

// --- §2 turns ----------------------------------------------------------------------------

#[test]
fn substep_0_allows_end_or_observing_any_unhinted_card() {
    let game = Game::from_deal(nine(), &clustered_deal(&nine())).unwrap();
    let legal = game.legal_actions(Seat(0));
    let mut expected = vec![Action::End];
    expected.extend((0..9).map(obs));
    assert_eq!(legal, expected);
    assert_eq!(game.legal_actions(Seat(1)), vec![Action::Noop]);
}

#[test]
fn end_is_legal_only_at_substep_0() {
    let config = nine();
    let mut game = Game::from_deal(config, &clustered_deal(&config)).unwrap();
    game.apply(obs(0)).unwrap();
    assert!(matches!(
        illegal(&mut game, Action::End),
        Illegal::WrongSubstep { substep: 1, .. }
    ));
    game.apply(obs(1)).unwrap();
    assert!(matches!(
        illegal(&mut game, Action::End),
        Illegal::WrongSubstep { substep: 2, .. }
    ));
    game.apply(mv(2, 2, 4)).unwrap();
    assert!(matches!(
        illegal(&mut game, Action::End),
        Illegal::WrongSubstep { substep: 3, .. }
    ));
}

#[test]
fn second_observe_must_name_another_card() {
    let config = nine();
    let mut game = Game::from_deal(config, &clustered_deal(&config)).unwrap();
    game.apply(obs(4)).unwrap();
    assert_eq!(illegal(&mut game, obs(4)), Illegal::ObservedTwice);
    assert!(!game.legal_actions(Seat(0)).contains(&obs(4)));
    assert_eq!(game.legal_actions(Seat(0)).len(), 8);
    game.apply(obs(5)).unwrap();
    assert_eq!(game.substep(), Substep::Move);
}

#[test]
fn observing_is_private_but_which_card_is_public() {
    let config = nine();
    let mut game = Game::from_deal(config, &clustered_deal(&config)).unwrap();
    game.apply(obs(3)).unwrap();
    assert_eq!(game.view(Seat(0)).known_colour(Card(3)), Some(Colour(1)));
    assert_eq!(game.view(Seat(1)).known_colour(Card(3)), None);
    let ch = config.image_channels();
    let shape = config.image_shape(Part::Full);
    let mut img = vec![0f32; shape.iter().product()];
    let px = |cell: Cell| (cell.row as usize * (config.grid() + 1) + cell.col as usize) * ch.len;
    let at = px(game.cell_of(Card(3)));
    for seat in [Seat(0), Seat(1)] {
        game.write_image(seat, Part::Full, &mut img).unwrap();
        assert_eq!(
            img[at + ch.observed],
            1.0,
            "{seat} sees which card was observed"
        );
        let known: f32 = img[at + ch.known..at + ch.known + 3].iter().sum();
        assert_eq!(known, if seat == Seat(0) { 1.0 } else { 0.0 }, "{seat}");
    }
    assert_eq!(game.last_action(), Some((Seat(0), obs(3))));
}

#[test]
fn a_move_must_change_the_cell_land_on_an_empty_cell_and_stay_on_the_grid() {
    let config = nine();
    let mut game = Game::from_deal(config, &clustered_deal(&config)).unwrap();
    game.apply(obs(0)).unwrap();
    game.apply(obs(1)).unwrap();
    assert_eq!(illegal(&mut game, mv(2, 3, 5)), Illegal::SameCell);
    assert_eq!(illegal(&mut game, mv(2, 4, 4)), Illegal::CellOccupied);
    assert_eq!(
        illegal(&mut game, mv(2, 9, 0)),
        Illegal::OffGrid { side: 9 }
    );
    // (0, 0) is empty but far from every card.
    assert_eq!(illegal(&mut game, mv(2, 0, 0)), Illegal::Disconnects);
    assert!(matches!(
        illegal(&mut game, obs(2)),
        Illegal::WrongSubstep { substep: 2, .. }
    ));
    game.apply(mv(2, 2, 4)).unwrap();
    assert_eq!(game.cell_of(Card(2)), Cell::new(2, 4));
}

/// ```text
///      c3 c4 c5
/// r3:  0  .  1
/// r4:  2  3  4
/// r5:  5  .  6
/// r6:  7  .  8
/// ```
fn bridge_board() -> Game {
    let config = nine();
    let cells = layout(3, 3, &["0 . 1", "2 3 4", "5 . 6", "7 . 8"]);
    Game::from_layout(config, &clustered_deal(&config), &cells).unwrap()
}

fn targets(game: &Game, card: u8) -> Vec<Cell> {
    let g = game.config().geometry();
    game.move_targets(Card(card))
        .iter()
        .map(|i| g.cell(i))
        .collect()
}

#[test]
fn a_card_whose_removal_splits_the_group_has_only_the_bridging_targets() {
    let game = bridge_board();
    // Lifting card 3 splits column 3 from column 5: only the empty cells touching both.
    assert_eq!(
        targets(&game, 3),
        vec![Cell::new(3, 4), Cell::new(5, 4), Cell::new(6, 4)]
    );
    // Lifting card 2 leaves three groups ({0}, {5, 7}, the right side): no cell touches all.
    assert_eq!(targets(&game, 2), vec![]);
}

#[test]
fn a_leaf_card_may_go_to_any_empty_cell_next_to_the_rest() {
    let game = bridge_board();
    let t = targets(&game, 7);
    // Card 7 at r6c3 has only card 5 as neighbour; every empty cell adjacent to the other
    // eight cards is a target, and its own cell is not.
    assert!(!t.contains(&Cell::new(6, 3)));
    assert!(
        t.contains(&Cell::new(5, 2))
            && t.contains(&Cell::new(7, 5))
            && t.contains(&Cell::new(2, 3))
    );
    assert!(
        !t.contains(&Cell::new(7, 3)),
        "r7c3 touches only card 7's old cell"
    );
    // (2,3) (3,2) (3,4) (2,5) (3,6) (4,2) (5,4) (4,6) (5,2) (5,6) (7,5) (6,6) (6,4)
    assert_eq!(t.len(), 13);
}

#[test]
fn no_legal_move_means_noop_is_the_only_move_substep_action() {
    // 4 cards fill a 2×2 grid: there is never an empty cell to move to.
    let config = Config::from_toml_str(
        "cards = 4\ncolours = 2\ngrid = 2\nplayers = 2\nhints = [2]\n",
        "t",
    )
    .unwrap();
    let d = deal(&config, &[0, 1, 0, 1], &[0b01, 0b10]);
    let mut game = Game::from_deal(config, &d).unwrap();
    game.apply(obs(0)).unwrap();
    game.apply(obs(1)).unwrap();
    assert_eq!(game.legal_actions(Seat(0)), vec![Action::Noop]);
    let mut mask = vec![0u8; config.num_actions()];
    game.write_legal_mask(Seat(0), &mut mask);
    assert_eq!(mask.iter().map(|&m| m as usize).sum::<usize>(), 1);
    assert_eq!(mask[0], 1);
    game.apply(Action::Noop).unwrap();
    assert_eq!(game.substep(), Substep::Hint);
}

#[test]
fn noop_is_refused_from_the_acting_seat_when_a_move_exists() {
    let config = nine();
    let mut game = Game::from_deal(config, &clustered_deal(&config)).unwrap();
    assert_eq!(illegal(&mut game, Action::Noop), Illegal::NoopNotAllowed);
    game.apply(obs(0)).unwrap();
    game.apply(obs(1)).unwrap();
    assert_eq!(illegal(&mut game, Action::Noop), Illegal::NoopNotAllowed);
}

#[test]
fn non_acting_seats_must_submit_noop() {
    let config = nine();
    let mut game = Game::from_deal(config, &clustered_deal(&config)).unwrap();
    let before = game.clone();
    let err = game.step_joint(&[obs(0), obs(1)]).unwrap_err();
    assert_eq!(
        err,
        ActionError::Illegal {
            seat: Seat(1),
            action: obs(1),
            reason: Illegal::NotYourTurn { acting: Seat(0) }
        }
    );
    assert_eq!(
        err.to_string(),
        "seat 1 cannot play `observe card 1`: it is seat 0's turn; other seats must submit NOOP"
    );
    assert_eq!(
        game.step_joint(&[obs(0)]).unwrap_err(),
        ActionError::WrongCount {
            expected: 2,
            got: 1
        }
    );
    assert_eq!(game, before);
    game.step_joint(&[obs(0), Action::Noop]).unwrap();
    assert_eq!(game.substep(), Substep::SecondObserve);
    let err = game.step_joint_indices(&[5, 10_000]).unwrap_err();
    assert!(
        err.to_string()
            .contains("action index 10000 is out of range"),
        "{err}"
    );
}

#[test]
fn reveal_turns_over_the_lowest_face_down_slot_even_with_unplaced_hints() {
    let config = nine();
    let mut game = Game::from_deal(config, &clustered_deal(&config)).unwrap();
    // seat 0: reveals slot 0
    for a in [obs(0), obs(1), mv(2, 2, 4), Action::Reveal] {
        game.apply(a).unwrap();
    }
    assert_eq!(game.revealed_hint(HintSlot(0)), Some(ColourSet(0b001)));
    assert_eq!(game.revealed_hint(HintSlot(1)), None);
    assert_eq!(game.current_seat(), Seat(1));
    // seat 1: slot 0 is revealed and unplaced, REVEAL is still legal and turns over slot 1.
    for a in [obs(0), obs(1), mv(2, 3, 5)] {
        game.apply(a).unwrap();
    }
    let legal = game.legal_actions(Seat(1));
    assert!(legal.contains(&Action::Reveal));
    assert!(legal.contains(&Action::Place(HintSlot(0), Card(8))));
    assert!(
        !legal.contains(&Action::Place(HintSlot(1), Card(8))),
        "slot 1 is still face down"
    );
    assert_eq!(
        illegal(&mut game, Action::Place(HintSlot(1), Card(8))),
        Illegal::HintFaceDown
    );
    assert_eq!(
        illegal(&mut game, Action::Place(HintSlot(7), Card(8))),
        Illegal::NoSuchHint { slot: 7 }
    );
    game.apply(Action::Reveal).unwrap();
    assert_eq!(game.revealed_hint(HintSlot(1)), Some(ColourSet(0b011)));
    assert_eq!((game.face_down(), game.revealed_unplaced()), (2, 2));
}

/// Plays seat's turn: observe `a`, `b`, move per `m`, then the hint action.
fn turn(game: &mut Game, a: u8, b: u8, m: Action, hint: Action) {
    for action in [obs(a), obs(b), m, hint] {
        game.apply(action)
            .unwrap_or_else(|e| panic!("{e}\n{game:?}"));
    }
}

#[test]
fn a_hint_may_go_on_a_card_observed_this_turn_and_then_locks_it() {
    let config = nine();
    let mut game = Game::from_deal(config, &clustered_deal(&config)).unwrap();
    turn(&mut game, 0, 1, mv(2, 2, 4), Action::Reveal);
    // seat 1 observes card 4 and hints it in the same turn.
    turn(
        &mut game,
        4,
        5,
        mv(2, 3, 5),
        Action::Place(HintSlot(0), Card(4)),
    );
    assert!(game.is_hinted(Card(4)));
    assert_eq!(game.hint_on(Card(4)), Some(HintSlot(0)));
    // The hinted card cannot be observed, moved, or hinted again.
    assert_eq!(illegal(&mut game, obs(4)), Illegal::CardHinted);
    game.apply(obs(0)).unwrap();
    game.apply(obs(1)).unwrap();
    assert!(game.move_targets(Card(3)).count() > 0);
    assert_eq!(
        illegal(&mut game, Action::Move(Card(4), Cell::new(5, 6))),
        Illegal::CardHinted
    );
    assert!(!game
        .legal_actions(Seat(0))
        .iter()
        .any(|a| matches!(a, Action::Move(Card(4), _))));
    game.apply(mv(8, 6, 4)).unwrap();
    game.apply(Action::Reveal).unwrap();
    game.apply(obs(0)).unwrap();
    game.apply(obs(1)).unwrap();
    game.apply(mv(8, 5, 5)).unwrap();
    assert_eq!(
        illegal(&mut game, Action::Place(HintSlot(1), Card(4))),
        Illegal::CardHinted
    );
    assert_eq!(
        illegal(&mut game, Action::Place(HintSlot(0), Card(3))),
        Illegal::HintPlaced
    );
    assert_eq!(
        game.cell_of(Card(4)),
        Cell::new(4, 4),
        "hinted cards never move"
    );
}

#[test]
fn the_game_ends_exactly_when_the_last_hint_is_placed() {
    let config = nine();
    let mut game = Game::from_deal(config, &clustered_deal(&config)).unwrap();
    // Reveal all four hints, then place them one per turn; moves shuttle card 2 up and back.
    let shuttle = [mv(2, 2, 4), mv(2, 3, 5)];
    let mut t = 0;
    for _ in 0..4 {
        turn(&mut game, 0, 1, shuttle[t % 2], Action::Reveal);
        t += 1;
    }
    assert_eq!(game.face_down(), 0);
    // Place slot 0 ({R}) on card 0 (R), slot 1 ({R,G}) on 3 (G), slot 2 ({R,B}) on 6 (B),
    // slot 3 ({G,B}) on 7 (B): all correct.
    let placements = [(0, 0), (1, 3), (2, 6), (3, 7)];
    for (i, &(slot, card)) in placements.iter().enumerate() {
        assert!(!game.is_over(), "over before the last placement");
        let (a, b) = if card == 1 { (4, 5) } else { (1, 5) };
        let step_before = game.steps();
        for action in [obs(a), obs(b), shuttle[t % 2]] {
            game.apply(action).unwrap();
        }
        let step = game
            .apply(Action::Place(HintSlot(slot), Card(card)))
            .unwrap();
        t += 1;
        assert_eq!(game.steps(), step_before + 4);
        assert_eq!(step.done, i == 3);
        if i == 3 {
            // Won (the shuttle returns card 2 home on even turns: 8 turns in all), every hint
            // correct: R = S = correct − wrong = 4.
            assert_eq!(game.cell_of(Card(2)), Cell::new(3, 5));
            assert_eq!(step.reward, 4);
            assert_eq!(game.phase(), Phase::Finished);
        } else {
            assert_eq!(step.reward, 0);
        }
    }
    assert_eq!(game.steps(), config.max_episode_len());
    assert!(game.legal_actions(Seat(0)).is_empty() && game.legal_actions(Seat(1)).is_empty());
    assert_eq!(illegal(&mut game, Action::Noop), Illegal::GameOver);
    let o = game.outcome().unwrap();
    assert_eq!(
        (o.correct_hints, o.wrong_hints, o.won, o.early_end, o.length),
        (4, 0, true, false, 32)
    );
}

// --- §4 scoring --------------------------------------------------------------------------

#[test]
fn a_won_early_end_with_four_face_down_hints_scores_20() {
    let config = nine();
    let mut game = Game::from_deal(config, &clustered_deal(&config)).unwrap();
    let step = game.apply(Action::End).unwrap();
    assert_eq!(
        step,
        Step {
            reward: 20,
            shaping: 0,
            done: true
        }
    );
    assert_eq!(config.max_reward(), 20);
    let o = game.outcome().unwrap();
    assert!(o.won && o.early_end && o.length == 1 && o.score == 20);
}

#[test]
fn a_lost_early_end_with_two_of_three_clustered_and_one_wrong_hint_gives_minus_3() {
    let config = nine();
    // Start square colours:  R R R / G B G / G B B  → R and B clustered, G split.
    let d = deal(
        &config,
        &[0, 0, 0, 1, 2, 1, 1, 2, 2],
        &[0b001, 0b011, 0b101, 0b110],
    );
    let mut game = Game::from_deal(config, &d).unwrap();
    turn(&mut game, 0, 1, mv(2, 2, 4), Action::Reveal);
    // Slot 0 shows {R}; card 3 is G: a wrong hint. Card 2 goes back home.
    turn(
        &mut game,
        0,
        1,
        mv(2, 3, 5),
        Action::Place(HintSlot(0), Card(3)),
    );
    assert_eq!(game.clustered_colours(), 2);
    let step = game.apply(Action::End).unwrap();
    assert_eq!(step.reward, -3);
    let o = game.outcome().unwrap();
    assert_eq!(
        (o.won, o.clustered, o.wrong_hints, o.correct_hints),
        (false, 2, 1, 0)
    );
    // S would have been 5·3 + 2·0 + 0 − 1 = 14, but a lost game does not score S.
    assert_eq!(o.score, 14);
}

#[test]
fn lost_without_an_early_end_pays_no_early_end_penalty() {
    let config = Config::from_toml_str(
        "cards = 4\ncolours = 2\ngrid = 2\nplayers = 2\nhints = [2]\n",
        "t",
    )
    .unwrap();
    // 2×2 grid, colours R G / G R: neither colour is connected, and nothing can ever move.
    let d = deal(&config, &[0, 1, 1, 0], &[0b01, 0b10]);
    let mut game = Game::from_deal(config, &d).unwrap();
    for a in [
        obs(0),
        obs(1),
        Action::Noop,
        Action::Reveal,
        obs(0),
        obs(1),
        Action::Noop,
    ] {
        game.apply(a).unwrap();
    }
    // slot 0 {R} on card 1 (G): wrong. Then slot 1 {G} on card 0 (R): wrong, game over.
    game.apply(Action::Place(HintSlot(0), Card(1))).unwrap();
    for a in [obs(0), obs(2), Action::Noop] {
        game.apply(a).unwrap();
    }
    let step = game.apply(Action::Reveal).unwrap();
    assert!(!step.done);
    for a in [obs(0), obs(2), Action::Noop] {
        game.apply(a).unwrap();
    }
    let step = game.apply(Action::Place(HintSlot(1), Card(0))).unwrap();
    // R = −0 − (2 − 0) − 2 = −4
    assert_eq!(
        step,
        Step {
            reward: -4,
            shaping: 0,
            done: true
        }
    );
    assert_eq!(config.min_reward(), -5);
}

#[test]
fn shaping_rewards_first_observations_and_correct_hints_only() {
    let config = nine();
    let mut game = Game::from_deal(config, &clustered_deal(&config)).unwrap();
    let shaping: Vec<i32> = [obs(0), obs(1), mv(2, 2, 4), Action::Reveal]
        .into_iter()
        .map(|a| game.apply(a).unwrap().shaping)
        .collect();
    assert_eq!(shaping, [1, 1, 0, 0]);
    // seat 1 observes card 0 for the first time (seat 0 did, but that does not count).
    assert_eq!(game.apply(obs(0)).unwrap().shaping, 1);
    assert_eq!(game.apply(obs(3)).unwrap().shaping, 1);
    game.apply(mv(2, 3, 5)).unwrap();
    // slot 0 {R} on card 1 (R): correct.
    assert_eq!(
        game.apply(Action::Place(HintSlot(0), Card(1)))
            .unwrap()
            .shaping,
        1
    );
    // seat 0 again: card 0 was already observed by seat 0 → no shaping; card 5 is new.
    assert_eq!(game.apply(obs(0)).unwrap().shaping, 0);
    assert_eq!(game.apply(obs(5)).unwrap().shaping, 1);
    game.apply(mv(2, 2, 4)).unwrap();
    game.apply(Action::Reveal).unwrap();
    game.apply(obs(0)).unwrap();
    game.apply(obs(2)).unwrap();
    game.apply(mv(2, 3, 5)).unwrap();
    // slot 1 {R,G} on card 6 (B): wrong, no shaping.
    assert_eq!(
        game.apply(Action::Place(HintSlot(1), Card(6)))
            .unwrap()
            .shaping,
        0
    );
}

// --- §5 memory -----------------------------------------------------------------------------

#[test]
fn perfect_memory_keeps_colours_and_imperfect_forgets_them_when_the_turn_ends() {
    for memory in [Memory::Perfect, Memory::Imperfect] {
        let config = nine().with_memory(memory);
        let mut game = Game::from_deal(config, &clustered_deal(&config)).unwrap();
        for a in [obs(0), obs(8), mv(2, 2, 4)] {
            game.apply(a).unwrap();
        }
        assert_eq!(
            game.known_cards(Seat(0)),
            CardSet::from_iter([Card(0), Card(8)]),
            "{memory}: during the turn"
        );
        game.apply(Action::Reveal).unwrap();
        let after = game.known_cards(Seat(0));
        match memory {
            Memory::Perfect => assert_eq!(after, CardSet::from_iter([Card(0), Card(8)])),
            Memory::Imperfect => assert_eq!(after, CardSet::EMPTY),
        }
        // Seat 1 plays a turn; seat 0's memory of card 0 outlives it only with perfect memory.
        game.apply(obs(4)).unwrap();
        game.apply(obs(5)).unwrap();
        game.apply(mv(2, 3, 5)).unwrap();
        let view = game.view(Seat(0));
        assert_eq!(view.known_colour(Card(2)), None);
        assert_eq!(
            view.known_colour(Card(0)).is_some(),
            memory == Memory::Perfect
        );
    }
}

#[test]
fn the_last_place_ends_the_placers_turn_so_imperfect_memory_forgets() {
    // 9c-2p has 4 hints: turns alternate REVEAL and PLACE, and the game ends on the PLACE of
    // the 8th turn (seat 1's), right after seat 1 observed two cards in it.
    for memory in [Memory::Perfect, Memory::Imperfect] {
        let config = nine().with_memory(memory);
        let mut game = Game::from_deal(config, &clustered_deal(&config)).unwrap();
        let mut placed = 0;
        for t in 0..8 {
            game.apply(obs(0)).unwrap();
            game.apply(obs(1)).unwrap();
            let mover = game.legal_actions(game.current_seat())[0];
            game.apply(mover).unwrap();
            if t % 2 == 0 {
                game.apply(Action::Reveal).unwrap();
            } else {
                // Hint the last unhinted cards, which no turn observes.
                let step = game
                    .apply(Action::Place(HintSlot(placed), Card(8 - placed)))
                    .unwrap();
                placed += 1;
                assert_eq!(step.done, t == 7);
            }
        }
        assert!(game.is_over());
        let placer = Seat(1);
        let view = game.view(placer);
        match memory {
            Memory::Imperfect => {
                assert_eq!(game.known_cards(placer), CardSet::EMPTY);
                assert_eq!(view.known_colour(Card(0)), None);
                assert_eq!(view.known_colour(Card(1)), None);
            }
            Memory::Perfect => {
                let first_two = CardSet::first(2);
                assert_eq!(game.known_cards(placer) & first_two, first_two);
                assert!(view.known_colour(Card(1)).is_some());
            }
        }
    }
}

#[test]
fn perfect_memory_follows_a_moved_card() {
    let config = nine();
    let mut game = Game::from_deal(config, &clustered_deal(&config)).unwrap();
    turn(&mut game, 2, 0, mv(2, 2, 4), Action::Reveal);
    let ch = config.image_channels();
    let mut img = vec![0u8; config.image_shape(Part::Full).iter().product()];
    game.write_image(Seat(0), Part::Full, &mut img).unwrap();
    let px = (2 * (config.grid() + 1) + 4) * ch.len;
    assert_eq!(
        &img[px..px + 3],
        &[1, 0, 0],
        "card 2 (R) seen at its new cell r2c4"
    );
    assert_eq!(img[px + ch.id], 3, "u8 id channel holds id + 1");
    let old = (3 * (config.grid() + 1) + 5) * ch.len;
    assert_eq!(img[old + ch.present], 0);
}

#[test]
fn hand_made_layouts_are_validated() {
    let config = nine();
    let d = clustered_deal(&config);
    let mut cells = layout(3, 3, &["0 1 2", "3 4 5", "6 7 8"]);
    assert!(Game::from_layout(config, &d, &cells).is_ok());
    cells[8] = Cell::new(0, 0);
    assert_eq!(
        Game::from_layout(config, &d, &cells).unwrap_err(),
        LayoutError::NotConnected
    );
    cells[8] = Cell::new(3, 3);
    assert!(matches!(
        Game::from_layout(config, &d, &cells),
        Err(LayoutError::Overlap {
            card: 8,
            other: 0,
            ..
        })
    ));
    cells[8] = Cell::new(9, 3);
    assert!(matches!(
        Game::from_layout(config, &d, &cells),
        Err(LayoutError::OffGrid { card: 8, .. })
    ));
    assert!(matches!(
        Game::from_layout(config, &d, &cells[..5]),
        Err(LayoutError::CardCount { .. })
    ));
}
