//! Helpers of the C ABI's tests.

use obb_model::{detect, EngineKind, GroupMask, Obb, Prepared};
use obbcd_c::ObbcdPair;
use std::collections::BTreeMap;
use std::process::{Command, Output};

/// Runs `cmd`; panics with its output if it cannot start or fails.
#[allow(dead_code)] // not every test binary runs a program
pub fn run(cmd: &mut Command) -> Output {
    let out = cmd
        .output()
        .unwrap_or_else(|e| panic!("cannot run {cmd:?}: {e} (is a C compiler installed?)"));
    assert!(
        out.status.success(),
        "{cmd:?} failed: {}\n{}{}",
        out.status,
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

/// Brute force's pairs on the groups' boxes, in the engine's order (the static groups first,
/// then the others, groups ascending), as (group, index) pairs, each with its two boxes.
#[allow(dead_code)] // not every test binary compares pairs
pub fn brute(
    groups: &BTreeMap<u32, Vec<Obb>>,
    statics: &[u32],
    mask: &GroupMask,
) -> Vec<(ObbcdPair, Obb, Obb)> {
    let order: Vec<(&u32, &Vec<Obb>)> = groups
        .iter()
        .filter(|(g, _)| statics.contains(g))
        .chain(groups.iter().filter(|(g, _)| !statics.contains(g)))
        .collect();
    let all: Vec<Obb> = order.iter().flat_map(|(_, b)| b.iter().cloned()).collect();
    let at: Vec<(u32, u32)> = order
        .iter()
        .flat_map(|(&g, b)| (0..b.len() as u32).map(move |i| (g, i)))
        .collect();
    let mut prepared = Prepared::default();
    let (pairs, _) = detect(EngineKind::Brute, &prepared.update(&all), mask);
    pairs
        .iter()
        .map(|&[i, j]| {
            let (i, j) = (i as usize, j as usize);
            let ((group_a, index_a), (group_b, index_b)) = (at[i], at[j]);
            let pair = ObbcdPair {
                group_a,
                index_a,
                group_b,
                index_b,
            };
            (pair, all[i].clone(), all[j].clone())
        })
        .collect()
}
