//! Counting and selecting the set bytes of 0/1 action masks, eight bytes at a time (the
//! sampler of random legal actions and the action check run on them).

/// Number of nonzero bytes of a 0/1 mask; eight bytes at a time.
#[inline]
pub(crate) fn count_set(mask: &[u8]) -> u32 {
    const LOW: u64 = 0x0101_0101_0101_0101;
    let words = mask.chunks_exact(8);
    let tail: u32 = words.remainder().iter().map(|&m| m as u32).sum();
    words
        .map(|w| (u64::from_le_bytes(w.try_into().expect("8 bytes")) & LOW).count_ones())
        .sum::<u32>()
        + tail
}

/// Index of the `k`-th (0-based) nonzero byte of a 0/1 mask; eight bytes at a time, and
/// without a loop inside the word that holds it (its length would be a branch mispredicted
/// on most draws).
#[inline]
pub(crate) fn nth_set(mask: &[u8], mut k: u32) -> usize {
    const LOW: u64 = 0x0101_0101_0101_0101;
    const HIGH: u64 = 0x8080_8080_8080_8080;
    let mut words = mask.chunks_exact(8);
    let mut base = 0;
    for w in &mut words {
        let bits = u64::from_le_bytes(w.try_into().expect("8 bytes")) & LOW;
        let ones = bits.count_ones();
        if k < ones {
            // Byte i of `prefix` counts the set bytes 0..=i (at most 8, so no carries). The
            // k-th set byte is the first whose count exceeds k: its index is the number of
            // bytes whose count is at most k. `0x80 + k − count` keeps its top bit exactly
            // then, and never borrows from the next byte (it is at least 0x80 − 8).
            let prefix = bits.wrapping_mul(LOW);
            let at_most_k = ((HIGH | (k as u64).wrapping_mul(LOW)) - prefix) & HIGH;
            return base + at_most_k.count_ones() as usize;
        }
        k -= ones;
        base += 8;
    }
    for (i, &m) in words.remainder().iter().enumerate() {
        if m == 1 {
            if k == 0 {
                return base + i;
            }
            k -= 1;
        }
    }
    unreachable!("k is below the number of set bytes")
}

#[cfg(test)]
mod tests {
    use super::{count_set, nth_set};

    #[test]
    fn count_and_select_match_a_plain_scan_on_random_masks() {
        let mut x = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = move || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            x
        };
        for _ in 0..2000 {
            let len = (next() % 100) as usize;
            let density = next() % 4; // from sparse to full
            let mask: Vec<u8> = (0..len).map(|_| (next() % 4 < density + 1) as u8).collect();
            let set: Vec<usize> = (0..len).filter(|&i| mask[i] == 1).collect();
            assert_eq!(count_set(&mask) as usize, set.len(), "{mask:?}");
            for (k, &i) in set.iter().enumerate() {
                assert_eq!(nth_set(&mask, k as u32), i, "k = {k} of {mask:?}");
            }
        }
    }
}
