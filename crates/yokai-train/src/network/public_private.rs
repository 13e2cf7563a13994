//! The public–private encoder of Off-Belief Learning (Hu et al. 2021; the paper's §5: "the
//! standard public–private architecture with separate CNN encoders for private and public
//! observations"): the paper's CNN twice, one over the public channels of the image, one
//! over the private ones (the colours the seat knows first-hand, RULES §5 "public/private
//! split"), their features side by side.
//!
//! Why two encoders: what a seat knows privately is exactly what OBL's fictitious worlds
//! redraw, so the network keeps it apart from what every seat sees alike until the memory.

use super::{conv_layers, conv_stack, Encoder};
use crate::config::{EncoderKind, TrainConfig};
use crate::init::Init;
use burn::module::Module;
use burn::nn::conv::Conv2d;
use burn::prelude::*;
use yokai_engine::{Config, ImageLayout, Part};
use yokai_vec::Encoding;

#[derive(Module, Debug)]
pub struct PublicPrivateEncoder {
    /// Four 3×3 convolutions over the public channels.
    public: Vec<Conv2d>,
    /// Four 3×3 convolutions over the private channels.
    private: Vec<Conv2d>,
    /// Image rows, columns and channels.
    #[module(skip)]
    shape: [usize; 3],
    /// The private channels: the first `colours` of the image (known colour one-hot).
    #[module(skip)]
    colours: usize,
    #[module(skip)]
    out: usize,
}

impl Encoder for PublicPrivateEncoder {
    const KINDS: &'static [EncoderKind] = &[EncoderKind::PublicPrivate];
    fn encoding() -> Encoding {
        Encoding::Image(Part::Full, ImageLayout::Hwc)
    }
    fn new(config: &TrainConfig, game: &Config, init: &mut Init, device: &Device) -> Self {
        let shape = game.image_shape(Part::Full);
        let colours = game.image_shape(Part::Private)[2];
        let f = config.network.filters;
        let public = conv_layers(init, shape[2] - colours, f, device);
        let private = conv_layers(init, colours, f, device);
        let out = 2 * (shape[0] - 8) * (shape[1] - 8) * f;
        PublicPrivateEncoder {
            public,
            private,
            shape,
            colours,
            out,
        }
    }
    fn output_size(&self) -> usize {
        self.out
    }
    fn forward(&self, obs: Tensor<2>) -> Tensor<2> {
        let [b, _] = obs.dims();
        let [h, w, c] = self.shape;
        let x: Tensor<4> = obs.reshape([b, h, w, c]);
        let private = x.clone().narrow(3, 0, self.colours);
        let public = x.narrow(3, self.colours, c - self.colours);
        Tensor::cat(
            vec![
                conv_stack(&self.public, public),
                conv_stack(&self.private, private),
            ],
            1,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::network::board::tests::to_vec;

    /// Each half of the features reads its own part of the observation only: changing a
    /// colour the seat knows changes the private half alone, and changing a public channel
    /// (a card's hint colours) the public half alone. 9c and 16c.
    #[test]
    fn each_half_reads_its_own_channels() {
        for name in ["9c-2p-perfect", "16c-2p-perfect"] {
            let game = Config::from_name(name).unwrap();
            let mut config = TrainConfig::from_toml_str("", "test").unwrap();
            config.network.filters = 8;
            let enc = PublicPrivateEncoder::new(&config, &game, &mut Init::new(3), &Device::flex());
            let [h, w, c] = game.image_shape(Part::Full);
            let colours = game.colours();
            let base: Vec<f32> = (0..h * w * c)
                .map(|i| ((i * 7919) % 13) as f32 / 13.0)
                .collect();
            let features = |obs: &[f32]| {
                let x = Tensor::from_data(
                    TensorData::new(obs.to_vec(), [1, obs.len()]),
                    &Device::flex(),
                );
                to_vec(enc.forward(x))
            };
            let at = |row: usize, col: usize, ch: usize| (row * w + col) * c + ch;
            let half = enc.output_size() / 2;
            let before = features(&base);
            assert_eq!(before.len(), 2 * half);
            let (mut private, mut public) = (base.clone(), base.clone());
            private[at(4, 4, colours - 1)] += 1.0;
            public[at(4, 4, colours)] += 1.0;
            let (p, q) = (features(&private), features(&public));
            assert_eq!(
                p[..half],
                before[..half],
                "{name}: a private channel moved the public half"
            );
            assert_ne!(
                p[half..],
                before[half..],
                "{name}: the private half ignores known colours"
            );
            assert_eq!(
                q[half..],
                before[half..],
                "{name}: a public channel moved the private half"
            );
            assert_ne!(
                q[..half],
                before[..half],
                "{name}: the public half ignores hint colours"
            );
        }
    }
}
