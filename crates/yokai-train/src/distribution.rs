//! The masked categorical policy: illegal actions get probability 0 before the softmax, so
//! log-probabilities and entropy are over legal actions only.

use burn::prelude::*;
use burn::tensor::activation::log_softmax;
use rand_chacha::rand_core::Rng;

/// A uniform draw in [0, 1) with 53 random bits: what [`sample_row`] takes as `u`.
pub fn unit_draw(rng: &mut impl Rng) -> f64 {
    unit_of(rng.next_u64())
}

/// The uniform in [0, 1) that 64 random `bits` give (their top 53): [`unit_draw`] of one
/// draw, or of a counter-based derivation (`derive_seed`) that needs no generator.
pub fn unit_of(bits: u64) -> f64 {
    (bits >> 11) as f64 / (1u64 << 53) as f64
}

/// The action index the acting seat of `game` samples from its row of `logits`, over its
/// legal actions only.
pub fn sample_legal(game: &yokai_engine::Game, logits: &[f32], rng: &mut impl Rng) -> usize {
    let mut mask = vec![0f32; logits.len()];
    game.write_legal_mask(game.current_seat(), &mut mask);
    sample_row(logits, &mask, unit_draw(rng), false).0
}

/// [`sample_legal`] for a seat that sees its game through a symmetry: `logits` are in its
/// view, so it samples over the view's legal actions (the true mask mapped) and returns the
/// action mapped back to the true game. Through the identity it is [`sample_legal`], draw
/// for draw.
pub fn sample_seen(view: &crate::seen::SeenSeat, logits: &[f32], rng: &mut impl Rng) -> usize {
    let sym = view.symmetry;
    if sym.is_identity() {
        return sample_legal(view.game, logits, rng);
    }
    let config = view.game.config();
    let mut truth = vec![0f32; logits.len()];
    view.game
        .write_legal_mask(view.game.current_seat(), &mut truth);
    let mut mask = vec![0f32; logits.len()];
    sym.apply_mask(config, &truth, &mut mask)
        .expect("a mask sized from the game's own config");
    let seen = sample_row(logits, &mask, unit_draw(rng), false).0;
    sym.inverse().apply_action_index(config, seen)
}

/// How far below the row's best legal logit an illegal action's logit is put: its
/// probability is then below e⁻⁶⁰ (with ~760 actions, a total leak under 10⁻²³, far below
/// f32 resolution), while `exp` stays in the normal range. Pushing illegal logits to
/// −10⁹ instead gives the same numbers but sends every illegal entry through libm's slow
/// underflow path, which measured as a fifth of the CPU training time.
pub(crate) const ILLEGAL_GAP: f32 = 60.0;

/// Log-probabilities `[B, N_a]` from logits and a 0/1 legal mask of the same shape.
pub fn masked_log_softmax(logits: Tensor<2>, mask: Tensor<2>) -> Tensor<2> {
    let best_legal = (logits.clone() + (mask.clone() - 1.0) * 1e9)
        .max_dim(1)
        .detach();
    let floor = best_legal - ILLEGAL_GAP;
    let illegal = mask.clone().neg() + 1.0;
    log_softmax(logits * mask + illegal * floor, 1)
}

/// Entropy `[B]` of each row's distribution over its legal actions.
pub fn entropy(log_probs: Tensor<2>, mask: Tensor<2>) -> Tensor<1> {
    let p = log_probs.clone().exp();
    (p * log_probs * mask).sum_dim(1).squeeze_dim::<1>(1).neg()
}

/// Entropy `[B]` of the binary choice "this action or another" in each row, from each
/// row's log-probability of the action: how undecided the row is about that one action.
pub fn binary_entropy(log_p: Tensor<1>) -> Tensor<1> {
    let p = log_p.clone().exp();
    let rest = (p.clone().neg() + 1.0).clamp_min(1e-7);
    (p * log_p + rest.clone() * rest.log()).neg()
}

/// Log-probability `[B]` of each row's chosen action, given as a one-hot `[B, N_a]`.
pub fn chosen_log_prob(log_probs: Tensor<2>, one_hot: Tensor<2>) -> Tensor<1> {
    (log_probs * one_hot).sum_dim(1).squeeze_dim::<1>(1)
}

/// Sample one action from a row of logits over the legal actions (mask 1), on the CPU,
/// with a uniform draw `u` in [0, 1). Returns the action, its log-probability and the
/// row's entropy. `greedy` takes the most likely legal action instead.
/// The index of the largest of `xs`, the first on a tie (0 for an empty slice): the
/// most likely class of a row of scores, as the colour layer's and the linear probes'
/// guesses name it.
pub fn first_max(xs: &[f32]) -> usize {
    (1..xs.len()).fold(0, |best, k| if xs[k] > xs[best] { k } else { best })
}

pub fn sample_row(logits: &[f32], mask: &[f32], u: f64, greedy: bool) -> (usize, f32, f32) {
    let max = logits
        .iter()
        .zip(mask)
        .filter(|(_, &m)| m > 0.5)
        .map(|(&l, _)| l as f64)
        .fold(f64::NEG_INFINITY, f64::max);
    assert!(max.is_finite(), "a row with no legal action or a NaN logit");
    let mut total = 0.0;
    for (&l, &m) in logits.iter().zip(mask) {
        if m > 0.5 {
            total += (l as f64 - max).exp();
        }
    }
    let log_total = total.ln();
    let mut entropy = 0.0;
    let mut drawn: Option<(usize, f64)> = None;
    let mut last = (0, 0.0);
    let mut best = (0, f64::NEG_INFINITY);
    let mut acc = 0.0;
    for (a, (&l, &m)) in logits.iter().zip(mask).enumerate() {
        if m <= 0.5 {
            continue;
        }
        let lp = l as f64 - max - log_total;
        let p = lp.exp();
        entropy -= p * lp;
        acc += p;
        if drawn.is_none() && u < acc {
            drawn = Some((a, lp));
        }
        if lp > best.1 {
            best = (a, lp);
        }
        last = (a, lp);
    }
    // A draw above the rounded total picks the last legal action.
    let (action, lp) = if greedy { best } else { drawn.unwrap_or(last) };
    (action, lp as f32, entropy as f32)
}

/// One move drawn from a row of logits at `temperature` (`act.temperature`): from
/// softmax(logits / T) over the legal actions, the most likely legal action at T = 0.
/// `scratch` holds the scaled row (reused between calls, so no row is allocated per move).
pub fn draw_row(
    logits: &[f32],
    mask: &[f32],
    u: f64,
    temperature: f32,
    scratch: &mut Vec<f32>,
) -> usize {
    if temperature == 0.0 {
        return sample_row(logits, mask, u, true).0;
    }
    if temperature == 1.0 {
        return sample_row(logits, mask, u, false).0;
    }
    scratch.clear();
    scratch.extend(logits.iter().map(|&l| l / temperature));
    sample_row(scratch, mask, u, false).0
}

/// P(END) over the legal actions of a row (`mask` 0/1, END at index `end`, legal), at
/// temperature 1: 1 / (1 + Σ_{a ≠ END} exp(l_a − l_END)), in f64 and without overflow; 1
/// where END is the only legal action.
pub fn end_probability(logits: &[f32], mask: &[f32], end: usize) -> f64 {
    let mut others = 0.0f64;
    for (a, (&l, &m)) in logits.iter().zip(mask.iter()).enumerate() {
        if m > 0.5 && a != end {
            others += (l as f64 - logits[end] as f64).min(700.0).exp();
        }
    }
    1.0 / (1.0 + others)
}

/// One move from a row of logits for a policy that decides END (`act.end_threshold`):
/// where END (index `end`) is legal and its probability over the legal actions exceeds
/// `threshold`, END; otherwise a draw (with `u`, at `temperature` as [`draw_row`]) over the
/// other legal actions, renormalised. P(END) is read at temperature 1, where the END term
/// calibrated it. Where END is illegal, or the only legal action, this is [`draw_row`]'s
/// draw. When END
/// is legal but not chosen, its entry of `mask` is cleared for that draw (the caller writes
/// a fresh mask for every row), so no second mask is built per move.
pub fn decide_end_row(
    logits: &[f32],
    mask: &mut [f32],
    u: f64,
    end: usize,
    threshold: f32,
    temperature: f32,
    scratch: &mut Vec<f32>,
) -> usize {
    if mask[end] > 0.5 {
        // Where END alone is legal its probability is 1: END.
        if end_probability(logits, mask, end) > threshold as f64 {
            return end;
        }
        mask[end] = 0.0;
    }
    draw_row(logits, mask, u, temperature, scratch)
}

#[cfg(test)]
mod tests {
    use super::*;
    use burn::tensor::TensorData;

    /// The first of the largest wins a tie; an empty row names 0.
    #[test]
    fn first_max_names_the_first_of_the_largest() {
        assert_eq!(first_max(&[1.0, 3.0, 3.0, 2.0]), 1);
        assert_eq!(first_max(&[-1.0, -5.0]), 0);
        assert_eq!(first_max(&[0.0, 0.0, 0.5]), 2);
        assert_eq!(first_max(&[]), 0);
    }

    fn t2(v: Vec<f32>, shape: [usize; 2]) -> Tensor<2> {
        Tensor::from_data(TensorData::new(v, shape), &Device::flex())
    }

    /// A seat seeing its game through a symmetry samples in its view and plays the true
    /// game's action: with all its weight on one legal action of the view, it plays that
    /// action mapped back, which is legal in the true game. Over games at random points of
    /// random play (MOVE substeps among them, where a rotation moves the target cell), every
    /// one of the 24 symmetries of 9c-2p, each legal view action.
    #[test]
    fn a_seat_seeing_through_a_symmetry_plays_its_views_choice_in_the_true_game() {
        use crate::seen::SeenSeat;
        use rand_chacha::rand_core::SeedableRng;
        use yokai_engine::{Config, Game, Symmetry};
        let config = Config::from_name("9c-2p").unwrap();
        let symmetries = Symmetry::enumerate(&config, true, true, false);
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(4);
        let (mut moved, mut checked) = (0, 0);
        for d in 0..12u64 {
            let mut game = Game::new(config, d);
            for _ in 0..(d * 7 % 23) {
                let legal = game.legal_actions(game.current_seat());
                let pick = (rng.next_u64() % legal.len() as u64) as usize;
                if legal[pick] != yokai_engine::Action::End {
                    game.apply(legal[pick]).unwrap();
                }
            }
            let n = config.num_actions();
            let mut truth = vec![0f32; n];
            game.write_legal_mask(game.current_seat(), &mut truth);
            for &symmetry in &symmetries {
                let mut view = vec![0f32; n];
                symmetry.apply_mask(&config, &truth, &mut view).unwrap();
                let seat = SeenSeat {
                    game: &game,
                    seat: game.current_seat(),
                    symmetry,
                };
                for v in (0..n).filter(|&v| view[v] == 1.0).step_by(5) {
                    let mut logits = vec![0f32; n];
                    logits[v] = 100.0;
                    let played = sample_seen(&seat, &logits, &mut rng);
                    assert_eq!(truth[played], 1.0, "legal in the true game");
                    assert_eq!(symmetry.apply_action_index(&config, played), v);
                    moved += (played != v) as usize;
                    checked += 1;
                }
            }
        }
        assert!(
            checked > 800 && moved > 100,
            "{checked} checked, {moved} moved"
        );
    }

    /// The rollout gives rows with one legal action zero logits instead of running the
    /// actor on them: that is only sound if such a row's draw does not depend on its logits.
    #[test]
    fn a_single_legal_action_is_drawn_with_log_prob_and_entropy_zero_whatever_its_logit() {
        let mut mask = vec![0f32; 7];
        mask[4] = 1.0;
        for logit in [0.0f32, -31.5, 2.25, 1e4] {
            let mut logits: Vec<f32> = (0..7).map(|i| i as f32 * 3.0 - 9.0).collect();
            logits[4] = logit;
            for u in [0.0, 0.5, 0.999_999] {
                for greedy in [false, true] {
                    assert_eq!(sample_row(&logits, &mask, u, greedy), (4, 0.0, 0.0));
                }
            }
        }
    }

    #[test]
    fn binary_entropy_is_the_entropy_of_one_action_against_the_rest() {
        // p(action) = 1/4, 3/4 and 1 (the other actions illegal or impossible).
        let lp = Tensor::<1>::from_data(
            TensorData::new(vec![0.25f32.ln(), 0.75f32.ln(), 0.0], [3]),
            &Device::flex(),
        );
        let h: Vec<f32> = binary_entropy(lp)
            .into_data()
            .convert::<f32>()
            .try_into_vec()
            .unwrap();
        let expected = -(0.25f32 * 0.25f32.ln() + 0.75 * 0.75f32.ln());
        assert!((h[0] - expected).abs() < 1e-6, "{h:?}");
        assert!((h[1] - expected).abs() < 1e-6, "{h:?}");
        assert!(
            h[2].abs() < 1e-5 && h[2].is_finite(),
            "a sure action: {h:?}"
        );
    }

    #[test]
    fn log_probs_and_entropy_cover_legal_actions_only() {
        // Row 0: logits [ln 1, ln 3, 5 (illegal)] → p = [1/4, 3/4, 0].
        // Row 1: one legal action → p = 1, entropy 0.
        let logits = t2(vec![0.0, 3f32.ln(), 5.0, 1.0, 2.0, 3.0], [2, 3]);
        let mask = t2(vec![1.0, 1.0, 0.0, 0.0, 0.0, 1.0], [2, 3]);
        let lp = masked_log_softmax(logits, mask.clone());
        let v = lp.to_data().try_into_vec::<f32>().unwrap();
        assert!((v[0] - 0.25f32.ln()).abs() < 1e-5);
        assert!((v[1] - 0.75f32.ln()).abs() < 1e-5);
        assert!(v[2] < -50.0);
        assert!(v[5].abs() < 1e-6);
        let h = entropy(lp.clone(), mask)
            .into_data()
            .try_into_vec::<f32>()
            .unwrap();
        let want = -(0.25f32 * 0.25f32.ln() + 0.75 * 0.75f32.ln());
        assert!((h[0] - want).abs() < 1e-5, "{h:?}");
        assert!(h[1].abs() < 1e-6);
        let chosen = chosen_log_prob(lp, t2(vec![0.0, 1.0, 0.0, 0.0, 0.0, 1.0], [2, 3]));
        let c = chosen.into_data().try_into_vec::<f32>().unwrap();
        assert!((c[0] - 0.75f32.ln()).abs() < 1e-5 && c[1].abs() < 1e-6);
    }

    #[test]
    fn sampling_follows_the_masked_distribution() {
        let logits = [0.0, 3f32.ln(), 9.0];
        let mask = [1.0, 1.0, 0.0];
        assert_eq!(sample_row(&logits, &mask, 0.1, false).0, 0);
        assert_eq!(sample_row(&logits, &mask, 0.3, false).0, 1);
        assert_eq!(sample_row(&logits, &mask, 0.999_999_9, false).0, 1);
        assert_eq!(sample_row(&logits, &mask, 0.1, true).0, 1);
        let (_, lp, h) = sample_row(&logits, &mask, 0.1, false);
        assert!((lp - 0.25f32.ln()).abs() < 1e-6);
        assert!((h - 0.562_335_1).abs() < 1e-5);
    }

    /// On random rows (777 logits, random masks, some with a single legal action) the
    /// draw, its log-probability and the entropy are the softmax's over the legal actions,
    /// computed here by the definition: the draw is the first legal action whose cumulative
    /// probability passes u (away from the boundaries, where rounding may decide).
    #[test]
    fn sample_row_follows_the_definition_on_random_rows() {
        use rand_chacha::rand_core::SeedableRng;
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(17);
        for row in 0..200 {
            let n = 777;
            let logits: Vec<f32> = (0..n)
                .map(|_| (unit_draw(&mut rng) * 24.0 - 12.0) as f32)
                .collect();
            let keep = if row % 10 == 0 {
                0.0
            } else {
                unit_draw(&mut rng)
            };
            let mut mask: Vec<f32> = (0..n)
                .map(|_| (unit_draw(&mut rng) < keep) as u8 as f32)
                .collect();
            mask[row % n] = 1.0;
            let legal: Vec<usize> = (0..n).filter(|&a| mask[a] > 0.5).collect();
            let max = legal
                .iter()
                .map(|&a| logits[a] as f64)
                .fold(f64::MIN, f64::max);
            let z: f64 = legal.iter().map(|&a| (logits[a] as f64 - max).exp()).sum();
            let p = |a: usize| (logits[a] as f64 - max).exp() / z;
            let h: f64 = legal.iter().map(|&a| -p(a) * p(a).ln()).sum();
            let best = *legal
                .iter()
                .max_by(|&&a, &&b| logits[a].total_cmp(&logits[b]).then(b.cmp(&a)))
                .unwrap();
            assert_eq!(sample_row(&logits, &mask, 0.5, true).0, best);
            for _ in 0..20 {
                let u = unit_draw(&mut rng);
                let (a, lp, entropy) = sample_row(&logits, &mask, u, false);
                assert!(mask[a] > 0.5, "row {row}: illegal {a}");
                assert!((lp as f64 - p(a).ln()).abs() < 1e-5, "row {row}: log p");
                assert!(
                    (entropy as f64 - h).abs() < 1e-5 * (1.0 + h),
                    "row {row}: H"
                );
                let below: f64 = legal.iter().take_while(|&&b| b < a).map(|&b| p(b)).sum();
                assert!(
                    below <= u + 1e-12 && u < below + p(a) + 1e-12,
                    "row {row}: u {u} drew {a} with cumulative [{below}, {})",
                    below + p(a)
                );
            }
        }
    }

    #[test]
    fn deciding_end_takes_it_above_the_threshold_and_never_below() {
        // Legal: NOOP (0), END (1), action 2; action 3 illegal. END is index 1, drawn at
        // temperature 1.
        let mask = [1.0, 1.0, 1.0, 0.0];
        let decide = |logits: &[f32], mask: &[f32], u: f64, threshold: f32| {
            decide_end_row(
                logits,
                &mut mask.to_vec(),
                u,
                1,
                threshold,
                1.0,
                &mut Vec::new(),
            )
        };
        let draws: Vec<f64> = (0..1000).map(|i| (i as f64 + 0.5) / 1000.0).collect();
        // P = [0.1, 0.6, 0.3]: END on every draw.
        let likely = [0.1f32.ln(), 0.6f32.ln(), 0.3f32.ln(), 50.0];
        assert!(draws.iter().all(|&u| decide(&likely, &mask, u, 0.5) == 1));
        // P = [0.1, 0.4, 0.5]: never END; NOOP and action 2 as 1 : 5, as renormalised.
        let unlikely = [0.1f32.ln(), 0.4f32.ln(), 0.5f32.ln(), 50.0];
        let chosen: Vec<usize> = draws
            .iter()
            .map(|&u| decide(&unlikely, &mask, u, 0.5))
            .collect();
        assert!(!chosen.contains(&1) && !chosen.contains(&3));
        let noops = chosen.iter().filter(|&&a| a == 0).count();
        assert!(
            (160..=173).contains(&noops),
            "{noops} NOOPs of 1000, want about 167"
        );
        // The threshold is the rule's: 0.7 refuses the P(END) = 0.6 row.
        assert!(draws.iter().all(|&u| decide(&likely, &mask, u, 0.7) != 1));
        // END illegal: the plain draw. END alone legal: END.
        let no_end = [1.0, 0.0, 1.0, 0.0];
        for &u in &draws {
            assert_eq!(
                decide(&likely, &no_end, u, 0.5),
                sample_row(&likely, &no_end, u, false).0
            );
        }
        assert_eq!(decide(&unlikely, &[0.0, 1.0, 0.0, 0.0], 0.3, 0.5), 1);
    }

    #[test]
    fn a_temperature_sharpens_or_flattens_the_draw_and_zero_takes_the_best() {
        // Legal: actions 0, 1, 2 with P = [0.2, 0.3, 0.5]; action 3 illegal (and best).
        let logits = [0.2f32.ln(), 0.3f32.ln(), 0.5f32.ln(), 9.0];
        let mask = [1.0, 1.0, 1.0, 0.0];
        let draws: Vec<f64> = (0..10_000).map(|i| (i as f64 + 0.5) / 10_000.0).collect();
        let mut scratch = Vec::new();
        let share = |t: f32, scratch: &mut Vec<f32>| {
            let best = draws
                .iter()
                .filter(|&&u| draw_row(&logits, &mask, u, t, scratch) == 2)
                .count();
            best as f64 / draws.len() as f64
        };
        // T = 1: the trained distribution, drawn exactly as sample_row draws it.
        for &u in &draws[..100] {
            assert_eq!(
                draw_row(&logits, &mask, u, 1.0, &mut scratch),
                sample_row(&logits, &mask, u, false).0
            );
        }
        assert!((share(1.0, &mut scratch) - 0.5).abs() < 0.001);
        // T = 0.5 squares the probabilities: 0.25 / (0.04 + 0.09 + 0.25).
        assert!((share(0.5, &mut scratch) - 0.25 / 0.38).abs() < 0.001);
        // T = 2: square roots; T = 0: always the best legal action, never the illegal one.
        let roots = 0.5f64.sqrt() / (0.2f64.sqrt() + 0.3f64.sqrt() + 0.5f64.sqrt());
        assert!((share(2.0, &mut scratch) - roots).abs() < 0.001);
        assert_eq!(share(0.0, &mut scratch), 1.0);
        // Deciding END reads P(END) at temperature 1 whatever the draw's temperature: END
        // (index 1) at P = 0.6 is taken, at P = 0.3 refused, and then the best other move.
        let end_mask = [1.0, 1.0, 1.0, 0.0];
        let end_likely = [0.1f32.ln(), 0.6f32.ln(), 0.3f32.ln(), 9.0];
        for &u in &draws[..100] {
            let mut m = end_mask;
            assert_eq!(
                decide_end_row(&end_likely, &mut m, u, 1, 0.5, 0.0, &mut scratch),
                1
            );
            let mut m = end_mask;
            // P(END) = 0.3 < 0.5: the best of the others (action 2) at T = 0.
            assert_eq!(
                decide_end_row(&logits, &mut m, u, 1, 0.5, 0.0, &mut scratch),
                2
            );
        }
    }
}
