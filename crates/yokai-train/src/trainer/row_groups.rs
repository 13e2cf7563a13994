//! The choosing rows of a shard cut into groups by the actions that can be legal in them,
//! so the learner's masked softmax, entropy and their gradients run over those columns
//! only.
//!
//! Why: MOVE (Y·g² = 729 of the 777 actions on 9c) is legal only at the MOVE substep, a
//! quarter of a seat's decisions. With the pointer head ([`ActionLogits::Split`]) the rows
//! off that substep form a group over the other 48 columns, the rows at it a group over
//! all of them; the dense head's logits ([`ActionLogits::Every`]) are one group over every
//! column. The groups' per-row terms are put back in the rows' own order
//! ([`RowGroups::terms`]), so everything after the softmax reads them as it read
//! the whole softmax's.

use super::choice_terms::choice_terms;
use crate::network::ActionLogits;
use crate::tensor::rows_tensor;
use burn::prelude::*;
use std::ops::Range;
use yokai_engine::{Action, Config};

/// One group: its rows' logits, legal masks and chosen actions over the group's columns,
/// and where END is among those columns.
pub(super) struct RowGroup {
    /// `[k, w]`.
    pub logits: Tensor<2>,
    /// `k × w`, 1 where legal.
    pub mask: Vec<f32>,
    /// Each row's chosen column.
    pub chosen: Vec<usize>,
    /// END's column.
    pub end: usize,
}

/// The choosing rows' legal masks where they already lie: row `k`'s mask is
/// `all[rows[k]·N_a..][..N_a]`. The learner reads the rollout's buffer in place: copying
/// each choosing row's 777 floats into the minibatch, only for the groups to copy the
/// columns they need again, was 2 % of a `cpu-fast` update's CPU samples.
#[derive(Clone, Copy)]
pub(super) struct MaskRows<'a> {
    /// Masks `[· × N_a]`, 1 where legal.
    pub all: &'a [f32],
    /// Each choosing row's row in `all`.
    pub rows: &'a [usize],
    /// N_a.
    pub na: usize,
}

impl MaskRows<'_> {
    /// Choosing row `k`'s mask over every action.
    fn row(&self, k: usize) -> &[f32] {
        &self.all[self.rows[k] * self.na..][..self.na]
    }
}

/// A shard's choosing rows as groups (none empty).
pub(super) struct RowGroups {
    pub groups: Vec<RowGroup>,
    /// Where each choosing row sits among the groups' rows (the groups one after
    /// another); `None` when that is the rows' own order.
    back: Option<Tensor<1, Int>>,
}

impl RowGroups {
    /// The groups of `n` choosing rows from the head's logits, the positions `moving` of
    /// the rows at the MOVE substep (ascending, as the head was given them), the rows'
    /// legal masks and the actions they took, in the game's action order.
    ///
    /// A row off the MOVE substep with a MOVE legal or chosen would lose it here; the head
    /// relies on the same rule (MOVE legal only at the MOVE substep), which the engine's
    /// property tests hold (`network::board`).
    pub fn new(
        logits: ActionLogits,
        moving: &[usize],
        masks: MaskRows,
        actions: &[usize],
        game: &Config,
        d: &Device,
    ) -> RowGroups {
        let na = game.num_actions();
        let n = actions.len();
        debug_assert_eq!((masks.rows.len(), masks.na), (n, na));
        let end = game.encode(Action::End);
        // The group's masks over its columns, given as ranges of the action order.
        let gather = |rows: &[usize], ranges: &[Range<usize>]| {
            let width: usize = ranges.iter().map(|r| r.len()).sum();
            let mut out = Vec::with_capacity(rows.len() * width);
            for &k in rows {
                let row = masks.row(k);
                for range in ranges {
                    out.extend_from_slice(&row[range.clone()]);
                }
            }
            out
        };
        let (others, moves) = match logits {
            ActionLogits::Every(logits) => {
                let all: Vec<usize> = (0..n).collect();
                let group = RowGroup {
                    logits,
                    mask: gather(&all, std::slice::from_ref(&(0..na))),
                    chosen: actions.to_vec(),
                    end,
                };
                return RowGroups {
                    groups: vec![group],
                    back: None,
                };
            }
            ActionLogits::Split { others, moves } => (others, moves),
        };
        let layout = game.action_layout();
        // The columns off the MOVE block, in action order (what `others` holds), then for
        // the moving rows the MOVE block after them.
        let moves_block = layout.movement..layout.reveal;
        let still_columns = [0..layout.movement, layout.reveal..na];
        let moving_columns = [0..layout.movement, layout.reveal..na, moves_block.clone()];
        let mut at_move = vec![false; n];
        for &k in moving {
            at_move[k] = true;
        }
        let still: Vec<usize> = (0..n).filter(|&k| !at_move[k]).collect();
        debug_assert!(
            still.iter().all(|&k| !moves_block.contains(&actions[k])
                && masks.row(k)[moves_block.clone()].iter().all(|&m| m == 0.0)),
            "a row off the MOVE substep with a MOVE legal or chosen"
        );
        let group = |rows: &[usize], columns: &[Range<usize>], logits: Tensor<2>| {
            // Where each action sits among the group's columns.
            let mut column_of = vec![usize::MAX; na];
            for (j, a) in columns.iter().cloned().flatten().enumerate() {
                column_of[a] = j;
            }
            RowGroup {
                logits,
                mask: gather(rows, columns),
                chosen: rows.iter().map(|&k| column_of[actions[k]]).collect(),
                end: column_of[end],
            }
        };
        let select = |rows: &[usize]| {
            if rows.len() == n {
                others.clone()
            } else {
                others
                    .clone()
                    .select(0, rows_tensor(rows.iter().map(|&k| k as i64).collect(), d))
            }
        };
        let mut groups = Vec::with_capacity(2);
        if !still.is_empty() {
            groups.push(group(&still, &still_columns, select(&still)));
        }
        if !moving.is_empty() {
            let logits = Tensor::cat(vec![select(moving), moves], 1);
            groups.push(group(moving, &moving_columns, logits));
        }
        let order = still.iter().chain(moving);
        let mut back = vec![0i64; n];
        for (i, &k) in order.enumerate() {
            back[k] = i as i64;
        }
        let in_order = back.iter().enumerate().all(|(k, &i)| i == k as i64);
        RowGroups {
            groups,
            back: (!in_order).then(|| rows_tensor(back, d)),
        }
    }

    /// Per choosing row, in the rows' own order: log π(chosen), the entropy and log π(END),
    /// from each group's softmax over its columns ([`choice_terms`]).
    pub fn terms(self) -> [Tensor<1>; 3] {
        let mut per_group: [Vec<Tensor<1>>; 3] = Default::default();
        for g in self.groups {
            let terms = choice_terms(g.logits, g.mask, g.chosen, g.end);
            for (list, term) in per_group.iter_mut().zip(terms) {
                list.push(term);
            }
        }
        per_group.map(|list| in_row_order(self.back.as_ref(), list))
    }
}

/// Per-row tensors of the groups (one per group, in the order of the groups) as one `[n]`
/// tensor in the choosing rows' own order, `back` giving where each row sits among the
/// groups' rows (`None`: in order already).
fn in_row_order(back: Option<&Tensor<1, Int>>, mut per_group: Vec<Tensor<1>>) -> Tensor<1> {
    let joined = if per_group.len() == 1 {
        per_group.pop().expect("one group")
    } else {
        Tensor::cat(per_group, 0)
    };
    match back {
        None => joined,
        Some(back) => joined.select(0, back.clone()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::distribution::{chosen_log_prob, entropy, masked_log_softmax};
    use crate::tensor::{tensor1, tensor2, to_vec};
    use rand_chacha::rand_core::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;
    use yokai_engine::{Game, Substep};

    /// Rows of random play: each row's legal mask and a legal action, and the positions
    /// of the rows at the MOVE substep.
    fn rows_of_play(game: Config, n: usize, seed: u64) -> (Vec<f32>, Vec<usize>, Vec<usize>) {
        let na = game.num_actions();
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let (mut masks, mut actions, mut moving) = (vec![0f32; n * na], vec![], vec![]);
        let mut g = Game::new(game, rng.next_u64());
        for k in 0..n {
            if g.is_over() {
                g = Game::new(game, rng.next_u64());
            }
            let seat = g.current_seat();
            g.write_legal_mask(seat, &mut masks[k * na..][..na]);
            if g.substep() == Substep::Move {
                moving.push(k);
            }
            let legal = g.legal_actions(seat);
            let a = legal[(rng.next_u64() % legal.len() as u64) as usize];
            actions.push(game.encode(a));
            g.apply(a).unwrap();
        }
        (masks, actions, moving)
    }

    /// On rows of random play (9c-2p and 16c-3p) the split groups give every row the
    /// log-probability of its action, its entropy and its log-probability of END that the
    /// softmax over all N_a columns gives, and a loss weighing them row by row has the same
    /// gradient with respect to every logit that can be legal (0 for the others, which the
    /// split never reads).
    #[test]
    fn split_groups_give_the_full_softmax_terms_and_gradients() {
        for (name, seed) in [("9c-2p-perfect", 3), ("16c-3p-perfect", 4)] {
            let game = Config::from_name(name).unwrap();
            let (na, n) = (game.num_actions(), 40);
            let layout = game.action_layout();
            let d = Device::flex().autodiff();
            let (masks, actions, moving) = rows_of_play(game, n, seed);
            let one_hot: Vec<f32> = (0..n * na)
                .map(|i| (actions[i / na] == i % na) as u8 as f32)
                .collect();
            assert!(!moving.is_empty() && moving.len() < n, "{name}: {moving:?}");
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            let values: Vec<f32> = (0..n * na)
                .map(|_| (rng.next_u32() % 2000) as f32 / 250.0 - 4.0)
                .collect();
            let weights: Vec<f32> = (0..n).map(|k| (k % 5) as f32 - 2.0).collect();
            let leaf = || tensor2(values.clone(), [n, na], &d).require_grad();

            // The full softmax over every column, rows in their own order.
            let full = leaf();
            let lp = masked_log_softmax(full.clone(), tensor2(masks.clone(), [n, na], &d));
            let logp = chosen_log_prob(lp.clone(), tensor2(one_hot.clone(), [n, na], &d));
            let h = entropy(lp.clone(), tensor2(masks.clone(), [n, na], &d));
            let end = lp.narrow(1, 1, 1).squeeze_dim::<1>(1);
            let w = tensor1(weights.clone(), &d);
            let loss = (logp.clone() * w.clone()).sum() + h.clone().sum() + end.clone().sum();
            let full_grad = to_vec(full.grad(&loss.backward()).unwrap());

            // The split: the MOVE block cut out of every row, kept for the moving rows.
            let split = leaf();
            let others = Tensor::cat(
                vec![
                    split.clone().narrow(1, 0, layout.movement),
                    split.clone().narrow(1, layout.reveal, na - layout.reveal),
                ],
                1,
            );
            let idx = rows_tensor(moving.iter().map(|&k| k as i64).collect(), &d);
            let moves = split
                .clone()
                .narrow(1, layout.movement, layout.reveal - layout.movement)
                .select(0, idx);
            let logits = ActionLogits::Split { others, moves };
            // The masks read where they lie: row k at row n + 1 − k of a larger buffer
            // whose first two rows (every action legal) no choosing row names.
            let mut all = vec![1f32; (n + 2) * na];
            let at: Vec<usize> = (0..n).map(|k| n + 1 - k).collect();
            for (k, &r) in at.iter().enumerate() {
                all[r * na..][..na].copy_from_slice(&masks[k * na..][..na]);
            }
            let rows = MaskRows {
                all: &all,
                rows: &at,
                na,
            };
            let groups = RowGroups::new(logits, &moving, rows, &actions, &game, &d);
            assert_eq!(groups.groups.len(), 2);
            assert!(
                groups.back.is_some(),
                "the moving rows go last among the groups'"
            );
            let [g_logp, g_h, g_end] = groups.terms();
            let g_w = tensor1(weights.clone(), &d);
            let g_loss = (g_logp.clone() * g_w).sum() + g_h.clone().sum() + g_end.clone().sum();
            let split_grad = to_vec(split.grad(&g_loss.backward()).unwrap());

            let close = |a: f32, b: f32| (a - b).abs() <= 2e-5 * (1.0 + a.abs());
            for (what, a, b) in [
                ("log π", logp, g_logp),
                ("H", h, g_h),
                ("log π(END)", end, g_end),
            ] {
                let (a, b) = (to_vec(a), to_vec(b));
                for k in 0..n {
                    assert!(
                        close(a[k], b[k]),
                        "{name} {what} row {k}: {} vs {}",
                        a[k],
                        b[k]
                    );
                }
            }
            for (i, (&a, &b)) in full_grad.iter().zip(&split_grad).enumerate() {
                let (k, col) = (i / na, i % na);
                let can_be_legal =
                    moving.contains(&k) || !(layout.movement..layout.reveal).contains(&col);
                if can_be_legal {
                    assert!(close(a, b), "{name} d/d logit ({k}, {col}): {a} vs {b}");
                } else {
                    assert!(a.abs() < 1e-20 && b == 0.0, "{name} ({k}, {col}): {a} {b}");
                }
            }
        }
    }

    /// The dense head's logits are one group over every column, rows in their own order.
    #[test]
    fn every_logit_is_one_group_in_the_rows_order() {
        let game = Config::from_name("9c-2p-perfect").unwrap();
        let (na, n) = (game.num_actions(), 12);
        let d = Device::flex();
        let (masks, actions, moving) = rows_of_play(game, n, 5);
        let logits = ActionLogits::Every(Tensor::zeros([n, na], &d));
        let at: Vec<usize> = (0..n).collect();
        let rows = MaskRows {
            all: &masks,
            rows: &at,
            na,
        };
        let groups = RowGroups::new(logits, &moving, rows, &actions, &game, &d);
        assert_eq!(groups.groups.len(), 1);
        assert!(groups.back.is_none());
        assert_eq!(groups.groups[0].mask, masks);
        assert_eq!(groups.groups[0].chosen, actions);
        let per_row = Tensor::<1>::from_data(TensorData::new(vec![3.0f32, 1.0], [2]), &d);
        assert_eq!(
            to_vec(in_row_order(groups.back.as_ref(), vec![per_row])),
            [3.0, 1.0]
        );
    }
}
