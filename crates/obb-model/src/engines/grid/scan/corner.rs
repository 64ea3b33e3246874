//! The pair work of the corner layout (`super::super::corner`): each entry of a cell meets the
//! five stretches of sorted entries its cell meets, `W` at a time with AVX-512 or AVX2, one at
//! a time otherwise. Every pair met is wanted, so there is no class test; the forms meet, count
//! and keep the same pairs in the same order.

#[cfg(target_arch = "x86_64")]
use super::step::ColumnPtrs;
use super::Emitter;
use crate::engines::grid::corner::{Corner, CornerCell};
use crate::engines::{Counters, Pair};
use crate::prepared::Frame;
use crate::simd::Vectors;
#[cfg(target_arch = "x86_64")]
use crate::simd::{compile_for_each_isa, Isa};

/// The stretches an entry meets: its own (after it, through the next cell on x), and its
/// cell's four rows.
const STRETCHES: usize = 5;

/// The pairs of the cells `cells` of `corner` whose AABBs overlap, through the SAT into `out`,
/// on the instruction set `vectors` (one this CPU has).
pub(in crate::engines::grid) fn scan_corner(
    vectors: Vectors,
    corner: &Corner,
    cells: &[CornerCell],
    boxes: &Frame,
    out: &mut Vec<Pair>,
) -> Counters {
    #[cfg(target_arch = "x86_64")]
    if let Some(c) = on(vectors, corner, cells, boxes, out) {
        return c;
    }
    let _ = vectors;
    let mut emit = Emitter::new(out);
    let ids = corner.columns.ids();
    for cell in cells {
        for p in cell.start as usize..cell.end as usize {
            let i = (ids[p] >> 32) as usize;
            emit.reserve(reach(cell, p));
            for (a, b) in stretches(cell, p) {
                for &id in &ids[a..b] {
                    emit.pair(boxes, i, (id >> 32) as usize);
                }
            }
        }
    }
    emit.finish(boxes)
}

/// The stretches of sorted entries that entry `p` of `cell` meets.
#[inline(always)]
fn stretches(cell: &CornerCell, p: usize) -> [(usize, usize); STRETCHES] {
    let r = cell.rows.map(|(a, b)| (a as usize, b as usize));
    [(p + 1, cell.next_end as usize), r[0], r[1], r[2], r[3]]
}

/// Pairs entry `p` of `cell` meets.
#[inline(always)]
fn reach(cell: &CornerCell, p: usize) -> usize {
    stretches(cell, p).iter().map(|&(a, b)| b - a).sum()
}

#[cfg(target_arch = "x86_64")]
compile_for_each_isa!(scan_vector(
    corner: &Corner,
    cells: &[CornerCell],
    boxes: &Frame,
    out: &mut Vec<Pair>,
) -> Counters);

/// [`scan_corner`], `W` entries of a stretch a step (`ColumnPtrs::keep`).
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn scan_vector<I: Isa<W>, const W: usize>(
    isa: I,
    corner: &Corner,
    cells: &[CornerCell],
    boxes: &Frame,
    out: &mut Vec<Pair>,
) -> Counters {
    let mut emit = Emitter::new(out);
    let columns = ColumnPtrs::new(corner.columns.bounds(), corner.columns.ids());
    let mut visits = 0;
    for cell in cells {
        for p in cell.start as usize..cell.end as usize {
            let meets = reach(cell, p);
            // Each step stores `W` pairs whole, of which those kept come first.
            emit.reserve(meets + STRETCHES * W);
            visits += meets as u64;
            let (out, mut kept) = (emit.out.as_mut_ptr(), emit.kept);
            // SAFETY: `p` is a sorted entry, inside the columns.
            let own = unsafe { columns.own(isa, p) };
            for (a, b) in stretches(cell, p) {
                // (A counted loop: through `step_by`, the surgical scene's scan took 0.9 million
                // instructions a frame more.)
                let mut q = a;
                while q < b {
                    // SAFETY: the columns hold every entry and their padding, so the `W` from
                    // `q` below the entries' count are inside them; the step writes `W` pairs
                    // at `kept`, and `reserve` made room for every pair of the entry and `W`
                    // more per stretch.
                    kept += unsafe { columns.keep(isa, &own, isa.first(b - q), q, out.add(kept)) };
                    q += W;
                }
            }
            emit.kept = kept;
        }
    }
    emit.counters.visits = visits;
    emit.finish(boxes)
}
