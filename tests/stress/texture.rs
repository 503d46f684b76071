//! Patterns of every size the format allows, sampled far from the origin.

use patkit::texture::Texels;
use patkit::{Pattern, Rgb8};
use proptest::prelude::*;

/// A SIZE x SIZE two-colour checker: colour `(col ^ row) & 1`.
fn pattern(size: u32) -> Pattern {
    let texels = (0..size * size)
        .map(|i| (((i % size) ^ (i / size)) & 1) as u16)
        .collect();
    Pattern::new(size, vec![Rgb8([250, 10, 10]), Rgb8([10, 10, 250])], texels).unwrap()
}

#[test]
fn patterns_of_size_16_to_4096_round_trip_through_the_text_format() {
    for size in [16, 32, 256, 1024, 4096] {
        let p = pattern(size);
        let text = p.to_canonical();
        let q = Pattern::parse(text.as_bytes(), "p.pat").unwrap();
        assert_eq!(p, q, "size {size}");
    }
}

proptest! {
    #![proptest_config(crate::config())]

    #[test]
    fn screen_pattern_tiles_are_periodic_and_finite_up_to_1e7_repeats(
        size_log in 4u32..13, k in -10_000_000i64..10_000_000, j in -10_000_000i64..10_000_000,
        col in 0i64..4096, row in 0i64..4096,
    ) {
        // Texel (k*SIZE + col, j*SIZE + row) of the infinite tiling is texel
        // (col, row): no drift, however many repeats away.
        let size = 1u32 << size_log;
        let s = Texels::new(&pattern(size));
        let (col, row) = (col % size as i64, row % size as i64);
        let far = s.texel(k * size as i64 + col, j * size as i64 + row, [0.0; 3]);
        prop_assert_eq!(far, s.texel(col, row, [0.0; 3]));
        let c = far.unwrap();
        prop_assert!(c.iter().all(|v| v.is_finite() && (0.0..=1.0).contains(v)));
    }
}
