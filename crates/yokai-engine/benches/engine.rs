//! Micro-benchmarks of the hot paths: legal-move generation, one engine step, observation
//! and mask writing. `cargo bench -p yokai-engine`.

use criterion::{criterion_group, criterion_main, BatchSize, Criterion};
use std::hint::black_box;
use yokai_engine::{Config, Game, ImageEncoder, ImageLayout, Part, Scalar, Seat, Substep};

/// Mid-game states at the MOVE substep, reached by deterministic pseudo-random play.
fn move_states(config: Config, count: usize) -> Vec<Game> {
    let mut out = Vec::new();
    let mut seed = 0u64;
    while out.len() < count {
        let mut game = Game::new(config, seed);
        let mut t = seed as usize;
        while !game.is_over() {
            if game.substep() == Substep::Move && game.steps() > 8 {
                out.push(game.clone());
                break;
            }
            let legal = game.legal_actions(game.current_seat());
            let mut a = legal[(t * 7919) % legal.len()];
            if a == yokai_engine::Action::End && legal.len() > 1 {
                a = legal[1];
            }
            game.apply(a).unwrap();
            t += 1;
        }
        seed += 1;
    }
    out
}

fn bench_image<T: Scalar>(c: &mut Criterion, id: &str, states: &[Game]) {
    let config = *states[0].config();
    let encoder = ImageEncoder::<T>::new(&config, ImageLayout::Hwc);
    let mut out = vec![T::ZERO; config.image_shape(Part::Full).iter().product()];
    let mut i = 0;
    c.bench_function(id, |b| {
        b.iter(|| {
            encoder
                .write(
                    &states[i % states.len()],
                    Seat(0),
                    Part::Full,
                    black_box(&mut out),
                )
                .unwrap();
            i += 1;
        })
    });
}

fn benches(c: &mut Criterion) {
    for name in ["9c-2p", "16c-2p"] {
        let config = Config::from_name(name).unwrap();
        let states = move_states(config, 64);
        c.bench_function(&format!("{name}/legal_mask_at_move_substep"), |b| {
            let mut mask = vec![0u8; config.num_actions()];
            let mut i = 0;
            b.iter(|| {
                let g = &states[i % states.len()];
                g.write_legal_mask(g.current_seat(), black_box(&mut mask));
                i += 1;
            })
        });
        c.bench_function(&format!("{name}/move_targets_all_cards"), |b| {
            let mut i = 0;
            b.iter(|| {
                let g = &states[i % states.len()];
                let mut total = 0;
                for k in 0..config.cards() {
                    total += g.move_targets(yokai_engine::Card(k as u8)).count();
                }
                i += 1;
                black_box(total)
            })
        });
        c.bench_function(&format!("{name}/apply_one_move"), |b| {
            let mut i = 0;
            b.iter_batched(
                || {
                    let g = states[i % states.len()].clone();
                    let a = g.legal_actions(g.current_seat())[i % 3];
                    i += 1;
                    (g, a)
                },
                |(mut g, a)| black_box(g.apply(a).unwrap()),
                BatchSize::SmallInput,
            )
        });
        bench_image::<f32>(c, &format!("{name}/image_f32_one_seat"), &states);
        bench_image::<u8>(c, &format!("{name}/image_u8_one_seat"), &states);
    }
}

criterion_group!(engine, benches);
criterion_main!(engine);
