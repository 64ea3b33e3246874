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

    /// Sorting by the bits above `low` only is a stable sort by `key >> low`: keys equal there
    /// keep their order, whatever their low bits; also when `low` covers every bit.
    #[test]
    fn sorts_by_the_bits_above_low_only(
        keys in prop::collection::vec(0u64..1 << 20, 0..600),
        low in 0u32..24,
        digit in 1u32..=16,
    ) {
        let bits = bits_for(keys.iter().copied().max().unwrap_or(0));
        let mut k = keys.clone();
        let mut v: Vec<u32> = (0..keys.len() as u32).collect();
        let mut sorter = RadixSorter::new(16);
        sorter.set_max_digit_bits(digit);
        sorter.sort_bits(&mut k, &mut v, low, bits);
        let mut expect: Vec<(u64, u32)> = keys.iter().copied().zip(0..).collect();
        expect.sort_by_key(|p| p.0.checked_shr(low).unwrap_or(0));
        prop_assert_eq!(k.iter().copied().zip(v.iter().copied()).collect::<Vec<_>>(), expect);
    }
}
