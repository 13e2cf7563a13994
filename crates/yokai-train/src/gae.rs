//! Generalised advantage estimation over a rollout stored time-major (`[T, B]`).

/// Advantages and returns (`advantage + value`) of `T` steps of `B` rows.
///
/// `done[t·B + b]` is 1 when row b's episode ended with the step at t: the value after it
/// belongs to a new episode and is not bootstrapped. `last_values` are the values of the
/// observations after the last step.
pub fn gae(
    rewards: &[f32],
    values: &[f32],
    dones: &[f32],
    last_values: &[f32],
    gamma: f32,
    lambda: f32,
) -> (Vec<f32>, Vec<f32>) {
    let b = last_values.len();
    let t = rewards.len() / b;
    assert_eq!(rewards.len(), t * b);
    assert_eq!(values.len(), t * b);
    assert_eq!(dones.len(), t * b);
    let mut adv = vec![0f32; t * b];
    let mut next_adv = vec![0f32; b];
    let mut next_value = last_values.to_vec();
    for s in (0..t).rev() {
        for r in 0..b {
            let i = s * b + r;
            let live = 1.0 - dones[i];
            let delta = rewards[i] + gamma * next_value[r] * live - values[i];
            next_adv[r] = delta + gamma * lambda * live * next_adv[r];
            adv[i] = next_adv[r];
            next_value[r] = values[i];
        }
    }
    let returns = adv.iter().zip(values).map(|(a, v)| a + v).collect();
    (adv, returns)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hand_computed_two_rows() {
        // Row 0: three steps, episode ends at t=1 (reward 1), then a new episode.
        // Row 1: no ending; bootstraps from last value 2.
        let (g, l) = (0.5f32, 0.5f32);
        let rewards = [0.0, 0.0, 1.0, 0.0, 0.0, 1.0];
        let values = [0.2, 0.1, 0.4, 0.3, 0.6, 0.5];
        let dones = [0.0, 0.0, 1.0, 0.0, 0.0, 0.0];
        let last = [0.8, 2.0];
        let (adv, ret) = gae(&rewards, &values, &dones, &last, g, l);
        // Row 0: δ2 = 0 + .5·.8 − .6 = −.2; A2 = −.2
        //        δ1 = 1 − .4 = .6 (done); A1 = .6
        //        δ0 = 0 + .5·.4 − .2 = 0; A0 = 0 + .25·.6 = .15
        // Row 1: δ2 = 1 + .5·2 − .5 = 1.5; A2 = 1.5
        //        δ1 = 0 + .5·.5 − .3 = −.05; A1 = −.05 + .25·1.5 = .325
        //        δ0 = 0 + .5·.3 − .1 = .05; A0 = .05 + .25·.325 = .13125
        let want = [0.15, 0.13125, 0.6, 0.325, -0.2, 1.5];
        assert_eq!((adv.len(), ret.len()), (6, 6));
        for (a, w) in adv.iter().zip(want) {
            assert!((a - w).abs() < 1e-6, "{adv:?}");
        }
        for i in 0..6 {
            assert!((ret[i] - (adv[i] + values[i])).abs() < 1e-6);
        }
    }
}
