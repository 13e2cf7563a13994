//! The device inference runs on when nobody chose one.

use burn::prelude::*;

/// The device of inference outside training (evaluation, play, Python): burn's `flex` CPU
/// backend, whatever GPU features are built in. Training picks its device with
/// [`crate::Trainer::new_on`] ([`crate::Backend`]).
pub fn default_device() -> Device {
    Device::flex()
}
