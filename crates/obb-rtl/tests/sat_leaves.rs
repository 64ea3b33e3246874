//! The SAT back end's leaves, each alone, every output at every clock from reset, in rust-hdl
//! and in Verilog (Verilator), against references written here from the arithmetic each leaf
//! stands for, not from the model's stage functions (`SatRound` and `SatDecide` call those as
//! their Rust models): the dot products at the widths the SAT instantiates (`SDot3` for the
//! face radii; `SDot2` for `P` with its `~b1` subtraction, `r_A`, the minors and `r_B`),
//! `AbsShift` (`ceil(|x| / 2^s)`), `SatRound` and `SatDecide`. Operands are random, the
//! extremes (-2^(B-1), the largest positive, zero, ±1) and, where a leaf rounds or compares,
//! the values on either side of every tie.

use crate::common;

use common::{ceil_div, floor_div, in_verilator, nearest, ports, raw, run_rust_hdl, signed};
use obb_rtl::flow::verilator::Port;
use obb_rtl::leaf::{sbits, sval, uval, AbsShift, SDot2, SDot3, DOT_LATENCY};
use obb_rtl::sat_back::{SatDecide, FACE, HALF_S, MINOR, PAIR2, PAIR_MARGIN, P_BITS, RB};
use obb_rtl::sat_front::{RR, TU};
use obb_rtl::sat_round::{SatRound, ABS_TU, RT, R_UP, TH};
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use rust_hdl::prelude::*;

const CLOCKS: usize = 400;

/// A signed operand of `bits` bits: an extreme one time in two, else any value.
fn operand(rng: &mut StdRng, bits: usize) -> i64 {
    let lo = -(1i64 << (bits - 1));
    match rng.random_range(0..10) {
        0 => lo,
        1 => -lo - 1,
        2 => 0,
        3 => 1,
        4 => -1,
        _ => rng.random_range(lo..-lo),
    }
}

/// A non-negative value below 2^bits: the largest one time in five, else any.
fn magnitude(rng: &mut StdRng, bits: usize) -> i64 {
    if rng.random_bool(0.2) {
        (1i64 << bits) - 1
    } else {
        rng.random_range(0..1i64 << bits)
    }
}

/// What a leaf of latency `lat` shows after each rising edge: the result of clock k's
/// operands after the edge of clock k + lat - 1, zeros before the first (every register starts
/// at zero).
fn delayed(results: Vec<Vec<u64>>, lat: u64) -> Vec<Vec<u64>> {
    let zeros = vec![0; results[0].len()];
    delayed_from(results, lat, zeros)
}

/// The same with `reset` shown before the first result.
fn delayed_from(results: Vec<Vec<u64>>, lat: u64, reset: Vec<u64>) -> Vec<Vec<u64>> {
    let n = results.len();
    std::iter::repeat_n(reset, lat as usize - 1)
        .chain(results)
        .take(n)
        .collect()
}

/// The block's rust-hdl simulation and its Verilog in Verilator both give `want`.
fn both_give<B: Block>(
    mut make: impl FnMut() -> B,
    (name, inputs, outputs): (&str, &[Port], &[Port]),
    v: &[Vec<u64>],
    want: &[Vec<u64>],
    apply: impl Fn(&mut B, &[u64]),
    clock: impl Fn(&mut B, bool),
    read: impl Fn(&B) -> Vec<u64>,
) {
    let got = run_rust_hdl(&mut make(), v, apply, clock, read);
    assert_eq!(got, want, "{name}: rust-hdl");
    let got = in_verilator(&mut make(), name, inputs, outputs, v);
    assert_eq!(got, want, "{name}: Verilog");
}

/// `SDot2<A, B, P, SUB>`: `a0 b0 + a1 b1`, or `a0 b0 - a1 b1` (which the leaf computes as
/// `a0 b0 + a1 ~b1 + a1`), `DOT_LATENCY` clocks after its operands.
fn sdot2<const A: usize, const B: usize, const P: usize, const SUB: bool>(seed: u64) {
    let mut rng = StdRng::seed_from_u64(seed);
    let v: Vec<Vec<u64>> = (0..CLOCKS)
        .map(|_| {
            let a = [operand(&mut rng, A), operand(&mut rng, A)];
            let b = [operand(&mut rng, B), operand(&mut rng, B)];
            vec![raw(a[0], A), raw(a[1], A), raw(b[0], B), raw(b[1], B)]
        })
        .collect();
    let results = v
        .iter()
        .map(|x| {
            let (a0, a1) = (signed(x[0], A), signed(x[1], A));
            let (b0, b1) = (signed(x[2], B), signed(x[3], B));
            let p = if SUB {
                a0 * b0 - a1 * b1
            } else {
                a0 * b0 + a1 * b1
            };
            vec![raw(p, P)]
        })
        .collect();
    let name = format!("sdot2_{A}_{B}_{P}_{}", if SUB { "sub" } else { "add" });
    let inputs = [
        Port::new("a0", A),
        Port::new("a1", A),
        Port::new("b0", B),
        Port::new("b1", B),
    ];
    both_give(
        SDot2::<A, B, P, SUB>::default,
        (&name, &inputs, &[Port::new("p", P)]),
        &v,
        &delayed(results, DOT_LATENCY),
        |u, x| {
            u.a0.next = sbits(signed(x[0], A));
            u.a1.next = sbits(signed(x[1], A));
            u.b0.next = sbits(signed(x[2], B));
            u.b1.next = sbits(signed(x[3], B));
        },
        |u, c| u.clock.next = Clock::from(c),
        |u| vec![raw(sval(u.p.val()), P)],
    );
}

/// Every two-term dot product the SAT instantiates: `P` (a difference), `r_A` (a sum), the
/// minors (a difference) and `r_B` (a sum).
#[test]
fn two_term_dot_products_match_their_sums() {
    sdot2::<TH, RT, P_BITS, true>(1);
    sdot2::<HALF_S, RT, PAIR2, false>(2);
    sdot2::<RT, RT, PAIR2, true>(3);
    sdot2::<MINOR, HALF_S, RB, false>(4);
}

/// `SDot3` at the face radii's widths: `a0 b0 + a1 b1 + a2 b2`.
#[test]
fn three_term_dot_product_matches_its_sum() {
    const A: usize = R_UP;
    const B: usize = HALF_S;
    let mut rng = StdRng::seed_from_u64(5);
    let v: Vec<Vec<u64>> = (0..CLOCKS)
        .map(|_| {
            let a: Vec<u64> = (0..3).map(|_| raw(operand(&mut rng, A), A)).collect();
            let b: Vec<u64> = (0..3).map(|_| raw(operand(&mut rng, B), B)).collect();
            [a, b].concat()
        })
        .collect();
    let results = v
        .iter()
        .map(|x| {
            let p: i64 = (0..3).map(|k| signed(x[k], A) * signed(x[3 + k], B)).sum();
            vec![raw(p, FACE)]
        })
        .collect();
    // Scalar ports a0..a2, b0..b2 (not arrays: `SDot3` says why).
    let inputs: Vec<Port> = [("a", A), ("b", B)]
        .iter()
        .flat_map(|&(name, bits)| (0..3).map(move |k| Port::new(format!("{name}{k}"), bits)))
        .collect();
    both_give(
        SDot3::<A, B, FACE>::default,
        ("sdot3_face", &inputs, &[Port::new("p", FACE)]),
        &v,
        &delayed(results, DOT_LATENCY),
        |u, x| {
            u.a0.next = sbits(signed(x[0], A));
            u.a1.next = sbits(signed(x[1], A));
            u.a2.next = sbits(signed(x[2], A));
            u.b0.next = sbits(signed(x[3], B));
            u.b1.next = sbits(signed(x[4], B));
            u.b2.next = sbits(signed(x[5], B));
        },
        |u, c| u.clock.next = Clock::from(c),
        |u| vec![raw(sval(u.p.val()), FACE)],
    );
}

/// `AbsShift<N, M>`: `ceil(|x| / 2^s)`, registered, for the shifts and magnitudes whose result
/// fits M bits: `|x| = q 2^s + r` with the remainder r at 0, 1 and 2^s - 1 (the rounding's
/// edges), either sign, and x = -2^(N-1) where its magnitude fits.
fn abs_shift<const N: usize, const M: usize>(seed: u64, shifts: std::ops::RangeInclusive<u32>) {
    let mut rng = StdRng::seed_from_u64(seed);
    let v: Vec<Vec<u64>> = (0..CLOCKS)
        .map(|_| {
            let s = rng.random_range(shifts.clone());
            // The largest |x| whose result fits M bits and that N signed bits hold.
            let most = (((1i64 << M) - 1) << s).min(1i64 << (N - 1));
            let mag = match rng.random_range(0..6) {
                0 => most,
                1 => 0,
                2..=4 => {
                    let q = rng.random_range(0..=most >> s);
                    let r = [0, 1, (1 << s) - 1][rng.random_range(0..3)];
                    (q << s | r).min(most)
                }
                _ => rng.random_range(0..=most),
            };
            let x = if rng.random_bool(0.5) || mag == 1i64 << (N - 1) {
                -mag
            } else {
                mag
            };
            vec![raw(x, N), u64::from(s)]
        })
        .collect();
    let results = v
        .iter()
        .map(|x| vec![ceil_div(signed(x[0], N).abs(), x[1] as u32) as u64])
        .collect();
    both_give(
        AbsShift::<N, M>::default,
        (
            &format!("abs_shift_{N}_{M}"),
            &[Port::new("x", N), Port::new("s", 8)],
            &[Port::new("y", M)],
        ),
        &v,
        &delayed(results, 1),
        |u, x| {
            u.x.next = sbits(signed(x[0], N));
            u.s.next = x[1].into();
        },
        |u, c| u.clock.next = Clock::from(c),
        |u| vec![uval(u.y.val())],
    );
}

/// Both shapes the SAT uses: the minors' `ceil(|minor| / 2^f)` and `|P|` (no shift).
#[test]
fn abs_shift_rounds_magnitudes_up() {
    abs_shift::<PAIR2, MINOR>(6, 0..=18);
    abs_shift::<P_BITS, P_BITS>(7, 0..=0);
}

/// `SatRound`, one clock: `|t|`, `|u|`, `floor(t / 2^f)`; per R entry `ceil(|R| / 2^f)`,
/// `R / 2^f` to the nearest (ties up) and that value's magnitude; for f = 2, 9 and 16, on random
/// values and on every rounding edge (`±2^(f-1)` and its neighbours, `±3·2^(f-1)`) and the
/// largest.
#[test]
fn sat_round_matches_its_rounding_rules() {
    let mut rng = StdRng::seed_from_u64(8);
    let mut v = Vec::new();
    for f in [2u32, 9, 16] {
        let r_max = 1i64 << (2 * f);
        let t_max = (1i64 << (23 + f)) - 1;
        let h = 1i64 << (f - 1);
        let edges = [0, 1, h - 1, h, h + 1, 3 * h, 2 * h - 1, 2 * h, r_max];
        let value = |rng: &mut StdRng, most: i64| {
            let x = if rng.random_bool(0.5) {
                edges[rng.random_range(0..edges.len())].min(most)
            } else {
                rng.random_range(0..=most)
            };
            if rng.random_bool(0.5) {
                -x
            } else {
                x
            }
        };
        for _ in 0..150 {
            let mut x: Vec<u64> = (0..6).map(|_| raw(value(&mut rng, t_max), TU)).collect();
            x.extend((0..9).map(|_| raw(value(&mut rng, r_max), RR)));
            x.push(u64::from(f));
            v.push(x);
        }
    }
    let results = v
        .iter()
        .map(|x| {
            let f = x[15] as u32;
            let mut out = Vec::new();
            for i in 0..3 {
                let (t, u) = (signed(x[i], TU), signed(x[3 + i], TU));
                out.extend([t.unsigned_abs(), u.unsigned_abs(), raw(floor_div(t, f), TH)]);
            }
            for k in 0..9 {
                let r = signed(x[6 + k], RR);
                let rt = nearest(r, f);
                out.extend([
                    raw(ceil_div(r.abs(), f), R_UP),
                    raw(rt, RT),
                    raw(rt.abs(), RT),
                ]);
            }
            out
        })
        .collect();
    let mut inputs = [ports("t", 3, TU), ports("u", 3, TU), ports("r", 9, RR)].concat();
    inputs.push(Port::new("f", 8));
    let mut outputs = Vec::new();
    for i in 0..3 {
        outputs.push(Port::new(format!("abs_t${i}"), ABS_TU));
        outputs.push(Port::new(format!("abs_u${i}"), ABS_TU));
        outputs.push(Port::new(format!("th${i}"), TH));
    }
    for k in 0..9 {
        outputs.push(Port::new(format!("r_up${k}"), R_UP));
        outputs.push(Port::new(format!("rt${k}"), RT));
        outputs.push(Port::new(format!("art${k}"), RT));
    }
    both_give(
        SatRound::default,
        ("sat_round", &inputs, &outputs),
        &v,
        &delayed(results, 1),
        |u, x| {
            for i in 0..3 {
                u.t[i].next = sbits(signed(x[i], TU));
                u.u[i].next = sbits(signed(x[3 + i], TU));
            }
            for k in 0..9 {
                u.r[k].next = sbits(signed(x[6 + k], RR));
            }
            u.f.next = x[15].into();
        },
        |u, c| u.clock.next = Clock::from(c),
        |u| {
            let mut out = Vec::new();
            for i in 0..3 {
                out.push(uval(u.abs_t[i].val()));
                out.push(uval(u.abs_u[i].val()));
                out.push(raw(sval(u.th[i].val()), TH));
            }
            for k in 0..9 {
                out.push(raw(sval(u.r_up[k].val()), R_UP));
                out.push(raw(sval(u.rt[k].val()), RT));
                out.push(raw(sval(u.art[k].val()), RT));
            }
            out
        },
    );
}

/// `SatDecide`'s inputs in port order: |t| (3), |u| (3), face_a (3), face_b (3), |P| (9), r_A
/// (9), r_B (9), half_a (3), half_b (3), the pair's margin, f, k, the face and cross margins.
fn decide_ports() -> Vec<Port> {
    let mut p = [
        ports("abs_t", 3, ABS_TU),
        ports("abs_u", 3, ABS_TU),
        ports("face_a", 3, FACE),
        ports("face_b", 3, FACE),
        ports("abs_p", 9, P_BITS),
        ports("r_a", 9, PAIR2),
        ports("r_b", 9, RB),
        ports("half_a", 3, HALF_S),
        ports("half_b", 3, HALF_S),
    ]
    .concat();
    p.push(Port::new("pair_margin", PAIR_MARGIN));
    p.extend(["f", "k"].map(|n| Port::new(n, 8)));
    p.extend(["face_margin", "cross_margin"].map(|n| Port::new(n, 24)));
    p
}

/// Index of each input group in a `decide_ports` vector.
const T: usize = 0;
const U: usize = 3;
const FA: usize = 6;
const FB: usize = 9;
const AP: usize = 12;
const RA: usize = 21;
const RBI: usize = 30;
const HA: usize = 39;
const HB: usize = 42;
const PM: usize = 45;
const F: usize = 46;
const K: usize = 47;
const FM: usize = 48;
const CM: usize = 49;

/// Per axis (x < 6 the faces, A's then B's; then the 9 cross axes) the compared pair: the
/// projected distance, and the radii with the margins.
fn sides(x: &[u64], axis: usize) -> (i64, i64) {
    let v = |k: usize| x[k] as i64;
    let f = x[F] as u32;
    let face = v(FM) + v(PM);
    let cross = v(CM) + v(PM);
    match axis {
        0..3 => (v(T + axis), (v(HA + axis) << f) + v(FA + axis) + face),
        3..6 => {
            let j = axis - 3;
            (v(U + j), (v(HB + j) << f) + v(FB + j) + face)
        }
        _ => {
            let c = axis - 6;
            (v(AP + c), v(RA + c) + v(RBI + c) + cross)
        }
    }
}

/// `SatDecide`: the pair collides unless on some axis `floor(distance / 2^k)` exceeds
/// `floor(radii and margins / 2^k)`; before its first result (from reset) `hit` is high. Half
/// the clocks set one axis's distance on either side of that comparison's tie (its own floor
/// equal, or one more) with every other axis's distance zero, so the verdict is that axis's
/// comparison alone; the rest draw every value. `f` and `k`, constants of a configuration, are
/// drawn anew every 50 clocks, and the 2 clocks before are compared (in the Verilog, two clocks
/// later) with the new `k`: their distances are all zero, so that no verdict depends on which
/// `k` it meets.
#[test]
fn sat_decide_matches_its_comparisons() {
    const SEGMENT: usize = 50;
    let mut rng = StdRng::seed_from_u64(9);
    let widths = decide_ports();
    let mut v: Vec<Vec<u64>> = Vec::new();
    let (mut f, mut k) = (0, 0);
    for clock in 0..CLOCKS {
        if clock % SEGMENT == 0 {
            (f, k) = (rng.random_range(2..=16), rng.random_range(0..=24));
        }
        // Every operand is non-negative (the leaf adds unsigned); signed ports keep their sign
        // bit clear.
        let mut x: Vec<u64> = widths
            .iter()
            .map(|p| {
                let bits = if p.name.starts_with("abs_") || p.bits == 24 {
                    p.bits
                } else {
                    p.bits - 1
                };
                magnitude(&mut rng, bits) as u64
            })
            .collect();
        x[F] = f;
        x[K] = k;
        // Keep `h << f` within the half-length's range of the configurations (17 bits).
        for h in &mut x[HA..HB + 3] {
            *h &= (1 << 17) - 1;
        }
        if clock % SEGMENT >= SEGMENT - 2 {
            for a in (T..U + 3).chain(AP..AP + 9) {
                x[a] = 0;
            }
        } else if rng.random_bool(0.5) {
            let axis = rng.random_range(0..15);
            for a in (T..U + 3).chain(AP..AP + 9) {
                x[a] = 0;
            }
            let k = x[K] as u32;
            let (_, rhs) = sides(&x, axis);
            let cut = floor_div(rhs, k) << k;
            let lhs = match rng.random_range(0..4) {
                0 => cut,
                1 => cut + (1 << k) - 1,
                2 => cut + (1 << k),
                _ => cut - 1,
            }
            .max(0);
            let at = match axis {
                0..3 => T + axis,
                3..6 => U + axis - 3,
                _ => AP + axis - 6,
            };
            x[at] = lhs.min((1 << widths[at].bits) - 1) as u64;
        }
        v.push(x);
    }
    let results: Vec<Vec<u64>> = v
        .iter()
        .map(|x| {
            let k = x[K] as u32;
            let apart = (0..15).any(|axis| {
                let (lhs, rhs) = sides(x, axis);
                floor_div(lhs, k) > floor_div(rhs, k)
            });
            vec![u64::from(!apart)]
        })
        .collect();
    let hits = results.iter().filter(|r| r[0] == 1).count();
    assert!(
        hits > CLOCKS / 10 && hits < CLOCKS * 9 / 10,
        "both verdicts come often: {hits} hits of {CLOCKS}"
    );
    both_give(
        SatDecide::default,
        ("sat_decide", &widths, &[Port::new("hit", 1)]),
        &v,
        &delayed_from(results, SatDecide::LATENCY, vec![1]),
        |u, x| {
            for i in 0..3 {
                u.abs_t[i].next = x[T + i].into();
                u.abs_u[i].next = x[U + i].into();
                u.face_a[i].next = sbits(x[FA + i] as i64);
                u.face_b[i].next = sbits(x[FB + i] as i64);
                u.half_a[i].next = sbits(x[HA + i] as i64);
                u.half_b[i].next = sbits(x[HB + i] as i64);
            }
            for c in 0..9 {
                u.abs_p[c].next = x[AP + c].into();
                u.r_a[c].next = sbits(x[RA + c] as i64);
                u.r_b[c].next = sbits(x[RBI + c] as i64);
            }
            u.pair_margin.next = x[PM].into();
            u.f.next = x[F].into();
            u.k.next = x[K].into();
            u.face_margin.next = x[FM].into();
            u.cross_margin.next = x[CM].into();
        },
        |u, c| u.clock.next = Clock::from(c),
        |u| vec![u64::from(u.hit.val())],
    );
}
