//! Diagnostic: train the given config and print, after every update, the policy's mean
//! probability of END at the very first step of a game (a state where ending at once is
//! worth −2.5 against about −4.3 for playing on).
use burn::prelude::*;
use burn::tensor::TensorData;
use yokai_engine::{Action, Config, Game, Part, Seat};
use yokai_train::{MlpEncoder, TrainConfig, Trainer};

fn main() {
    let path = std::env::args().nth(1).expect("config path");
    let updates: u64 = std::env::args().nth(2).map_or(50, |s| s.parse().unwrap());
    let config = TrainConfig::from_file(std::path::Path::new(&path)).unwrap();
    let game_config: Config = config.game_config().unwrap();
    let mut t = Trainer::<MlpEncoder>::new(config, 0).unwrap();
    let l: usize = game_config.node_shape(Part::Full).iter().product();
    let na = game_config.num_actions();
    let end = game_config.encode(Action::End);
    let n = 64;
    let mut obs = vec![0f32; n * l];
    let mut masks = vec![0f32; n * na];
    for i in 0..n {
        let g = Game::new(game_config, 1000 + i as u64);
        g.view(Seat(0))
            .write_nodes(Part::Full, &mut obs[i * l..][..l])
            .unwrap();
        g.view(Seat(0)).write_legal_mask(&mut masks[i * na..][..na]);
    }
    let dev = Device::flex();
    for _ in 0..updates {
        let s = t.update().unwrap();
        let net = t.model().valid();
        let h = net.hidden_size();
        let (logits, state) = net.step(
            Tensor::from_data(TensorData::new(obs.clone(), [n, l]), &dev),
            Tensor::zeros([n, h], &dev),
            Tensor::zeros([n, 1], &dev),
        );
        let lp = yokai_train::distribution::masked_log_softmax(
            logits,
            Tensor::from_data(TensorData::new(masks.clone(), [n, na]), &dev),
        );
        let v: Vec<f32> = lp.into_data().convert::<f32>().try_into_vec().unwrap();
        let p_end: f32 = (0..n).map(|i| v[i * na + end].exp()).sum::<f32>() / n as f32;
        let val: Vec<f32> = net
            .values(state, None)
            .into_data()
            .convert::<f32>()
            .try_into_vec()
            .unwrap();
        println!(
            "update {:>4} R {:>6.2} EE {:.2} P(END|s0) {:.3} V(s0) {:.2}",
            s.update,
            s.games.map_or(f64::NAN, |m| m.reward),
            s.games.map_or(f64::NAN, |m| m.early_end),
            p_end,
            val.iter().sum::<f32>() / n as f32
        );
    }
}
