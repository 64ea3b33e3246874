//! The radix sort is a stable sort by key.

use obb_model::radix::{bits_for, RadixSorter};
use proptest::prelude::*;

proptest! {
    #[test]
    fn equals_a_stable_sort(keys in prop::collection::vec(0u64..5000, 0..600), digit in 1u32..=16, wide in any::<bool>()) {
        let keys: Vec<u64> = keys.iter().map(|k| if wide { k.wrapping_mul(0x9E37_79B9_7F4A_7C15) } else { *k }).collect();
        let bits = bits_for(keys.iter().copied().max().unwrap_or(0));
        let mut k = keys.clone();
        let mut v: Vec<u32> = (0..keys.len() as u32).collect();
        let mut sorter = RadixSorter::new(digit);
        sorter.sort(&mut k, &mut v, bits);
        let mut expect: Vec<(u64, u32)> = keys.iter().copied().zip(0..).collect();
        expect.sort_by_key(|p| p.0);
        prop_assert_eq!(k.iter().copied().zip(v.iter().copied()).collect::<Vec<_>>(), expect);
        prop_assert_eq!(sorter.passes(bits), bits.div_ceil(digit));
        prop_assert!(sorter.digit_bits(bits) <= digit && sorter.digit_bits(bits) * sorter.passes(bits) >= bits);
    }
}
