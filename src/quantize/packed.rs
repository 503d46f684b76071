//! Colours packed in a `u32` (`r << 16 | g << 8 | b`, ordered as the colours
//! are) and the one open-addressing slot search that the histogram's count
//! ([`super::palette`]) and the remap's nearest-colour table
//! ([`super::remap`]) share.

/// `c` packed: `r << 16 | g << 8 | b`.
#[inline]
pub(super) fn pack([r, g, b]: [u8; 3]) -> u32 {
    (r as u32) << 16 | (g as u32) << 8 | b as u32
}

/// The colour [`pack`] packed.
#[inline]
pub(super) fn unpack(p: u32) -> [u8; 3] {
    [(p >> 16) as u8, (p >> 8) as u8, p as u8]
}

/// A free slot of a table of packed colours: no 24-bit colour packs to it.
pub(super) const EMPTY: u32 = u32::MAX;

/// The slot of `key` in `keys` (a power of two long, at least 2, never
/// full): where it is, or the free one where it would go. Fibonacci hashing
/// (the top bits of the product, which mix all of the key's), then linear
/// probing; the tables are kept at most half full, so a probe rarely goes
/// past its first slot.
#[inline]
pub(super) fn slot(keys: &[u32], key: u32) -> usize {
    let mask = keys.len() - 1;
    let mut s = (key.wrapping_mul(0x9e37_79b1) >> (32 - keys.len().trailing_zeros())) as usize;
    while keys[s] != key && keys[s] != EMPTY {
        s = (s + 1) & mask;
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn packing_keeps_the_colour_and_its_order_and_slots_find_their_keys() {
        assert_eq!(unpack(pack([1, 2, 3])), [1, 2, 3]);
        assert!(pack([0, 255, 255]) < pack([1, 0, 0]));
        assert_eq!(pack([255; 3]), 0xff_ffff);
        assert_ne!(pack([255; 3]), EMPTY);
        // Every key of a half-full table is found where it was put, and a
        // missing one lands on a free slot.
        let mut keys = vec![EMPTY; 64];
        for k in 0..32u32 {
            let key = pack([k as u8, 7, 9]);
            let s = slot(&keys, key);
            assert_eq!(keys[s], EMPTY);
            keys[s] = key;
        }
        for k in 0..32u32 {
            assert_eq!(
                keys[slot(&keys, pack([k as u8, 7, 9]))],
                pack([k as u8, 7, 9])
            );
        }
        assert_eq!(keys[slot(&keys, pack([200, 7, 9]))], EMPTY);
    }
}
