//! `GridCells`: the grid's probe front end. From a box's keys it finds, in three registered
//! stages, the cells of its window and their banks, buckets and fingerprints, exactly as
//! `obb_model::fixed::grid::GridShape` defines them (checked against it in `tests/grid.rs`):
//!
//! | clock | stage |
//! | --- | --- |
//! | K | the keys |
//! | K+1 | per axis the window's cells first, first + 1, first + 2 (offset coordinates: the first is kmin >> g, the home cell first + 1), whether the third is in the window (kmax reaches the next cell), the box's width; each 6-bit chunk of the first cell's coordinate mod 3 |
//! | K+2 | each cell's H3 hash, the first cell's coordinate mod 3 (its chunks' residues summed), whether the box is small |
//! | K+3 | per bank (coordinates mod 3 on each axis) its cell's bucket, fingerprint, whether the window has a cell there, whether it is the home cell; the home cell's fingerprint |

use crate::projection::CENTER;
use obb_model::fixed::grid::{hash_row, GridShape, BANKS, FINGERPRINT_BITS, MAX_HASH_BITS};
use obb_model::fixed::HwConfig;
use rust_hdl::prelude::*;

/// Bits of an offset cell coordinate: keys shifted by the cell bits, plus 2, within the keys'
/// width (`generate::check_supported` keeps `key_bits` below it). Every value the stages
/// compute per axis has this width: rust-hdl cannot emit a width cast of a loop-indexed signal.
pub const COORD: usize = CENTER;
/// Bits of a cell's hash: the widest bucket, then the fingerprint.
pub const HASH: usize = (MAX_HASH_BITS + FINGERPRINT_BITS) as usize;
/// A bucket: the hash's width (only `grid_hash_bits` low bits are ever set).
pub const BUCKET: usize = HASH;
pub const FP: usize = FINGERPRINT_BITS as usize;
/// Clocks from the keys to the banks' cells.
pub const LATENCY: u64 = 3;
const _: () = assert!(BANKS == 27 && COORD == 23 && HASH == 20 && MAX_HASH_BITS == 12);

#[derive(LogicBlock)]
pub struct GridCells {
    pub clock: Signal<In, Clock>,
    pub key_valid: Signal<In, Bit>,
    pub key_min: [Signal<In, Bits<CENTER>>; 3],
    pub key_max: [Signal<In, Bits<CENTER>>; 3],
    /// The box's cells are on the outputs, `LATENCY` clocks after its keys.
    pub valid: Signal<Out, Bit>,
    /// The box's keys span at most one cell edge on every axis.
    pub small_box: Signal<Out, Bit>,
    /// Per bank: its cell's bucket.
    pub bucket: [Signal<Out, Bits<BUCKET>>; 27],
    /// Per bank: its cell's fingerprint.
    pub fp: [Signal<Out, Bits<FP>>; 27],
    /// Per bank: the window has a cell there.
    pub inside: [Signal<Out, Bit>; 27],
    /// Per bank: its cell is the home cell (the one holding the box's lower corner).
    pub home: [Signal<Out, Bit>; 27],
    /// The home cell's fingerprint.
    pub home_fp: Signal<Out, Bits<FP>>,
    // The cell edge in key units (a box at most this wide on every axis is small), its log2.
    cell_edge: Constant<Bits<CENTER>>,
    cell_bits: Constant<Bits<8>>,
    // Per axis and coordinate bit, the hash's column (`23 x + i`).
    column: Vec<Constant<Bits<HASH>>>,
    bucket_mask: Constant<Bits<HASH>>,
    // Per 6-bit chunk of a coordinate its shift, its mask, and per value of a chunk the
    // value and its residue mod 3; per pair of residues side by side (`4 a + b`, the shift
    // 2) their sum mod 3.
    chunk_at: Vec<Constant<Bits<8>>>,
    chunk_mask: Constant<Bits<COORD>>,
    chunk_value: Vec<Constant<Bits<COORD>>>,
    chunk_residue: Vec<Constant<Bits<COORD>>>,
    pair_at: Constant<Bits<8>>,
    pair_residue: Vec<Constant<Bits<COORD>>>,
    valid1: DFF<Bit>,
    valid2: DFF<Bit>,
    valid3: DFF<Bit>,
    // K+1: the box's width per axis; K+2: the box is small (the difference and the compare
    // on two clocks: two carry chains in one clock behind the injection's multiplexer were
    // over 4 ns).
    width1: [DFF<Bits<CENTER>>; 3],
    small2: DFF<Bit>,
    small3: DFF<Bit>,
    // Per axis the window's cells `3 x + d` (first + d), and whether the third is in it.
    cell1: [DFF<Bits<COORD>>; 9],
    third1: [DFF<Bit>; 3],
    hash2: [DFF<Bits<HASH>>; 9],
    third2: [DFF<Bit>; 3],
    // Per axis and 6-bit chunk of the first cell's coordinate (`4 x + c`), the chunk mod 3;
    // then the coordinate mod 3, per axis.
    res1: [DFF<Bits<COORD>>; 12],
    res2: [DFF<Bits<COORD>>; 3],
    bucket_r: [DFF<Bits<BUCKET>>; 27],
    fp_r: [DFF<Bits<FP>>; 27],
    inside_r: [DFF<Bit>; 27],
    home_r: [DFF<Bit>; 27],
    home_fp_r: DFF<Bits<FP>>,
    /// Per axis and cell: the hash accumulated over the coordinate's bits (`24 (3 x + d) + i`).
    hacc: Vec<Signal<Local, Bits<HASH>>>,
    // Per axis: the first cell; per 6-bit chunk of it its value; per axis and pair of
    // chunks (`2 x + p`) their residues side by side and summed mod 3; per axis those two
    // sums side by side.
    first: [Signal<Local, Bits<COORD>>; 3],
    chunk: [Signal<Local, Bits<COORD>>; 12],
    pair: [Signal<Local, Bits<COORD>>; 6],
    pair_sum: [Signal<Local, Bits<COORD>>; 6],
    pairs: [Signal<Local, Bits<COORD>>; 3],
    // Per axis and residue `3 x + r`: the window cell's hash, whether it is in the window,
    // whether it is the home cell.
    slot_hash: [Signal<Local, Bits<HASH>>; 9],
    slot_in: [Signal<Local, Bit>; 9],
    slot_home: [Signal<Local, Bit>; 9],
    bank_hash: [Signal<Local, Bits<HASH>>; 27],
    home_hash: Signal<Local, Bits<HASH>>,
}

/// `k` blocks of a kind.
pub fn vec<T: Default>(k: usize) -> Vec<T> {
    (0..k).map(|_| T::default()).collect()
}

impl GridCells {
    pub fn new(cfg: &HwConfig) -> GridCells {
        let shape = GridShape::new(cfg);
        let a = shape.coord_bits as usize;
        assert!(a < COORD, "cell coordinates fit the stages");
        let mut column = Vec::with_capacity(3 * COORD);
        for x in 0..3 {
            for i in 0..COORD {
                // Hash bit k is matrix row k: the bucket's rows, then the fingerprint's.
                let mut col = 0u64;
                for k in 0..HASH as u32 {
                    if i < a && hash_row(k) >> (x * a + i) & 1 == 1 {
                        col |= 1 << k;
                    }
                }
                column.push(Constant::new(col.into()));
            }
        }
        GridCells {
            clock: Default::default(),
            key_valid: Default::default(),
            key_min: Default::default(),
            key_max: Default::default(),
            valid: Default::default(),
            small_box: Default::default(),
            bucket: Default::default(),
            fp: Default::default(),
            inside: Default::default(),
            home: Default::default(),
            home_fp: Default::default(),
            cell_edge: Constant::new((1u64 << shape.cell_bits).into()),
            cell_bits: Constant::new(u64::from(shape.cell_bits).into()),
            column,
            bucket_mask: Constant::new(((1u64 << shape.hash_bits) - 1).into()),
            chunk_at: (0..4u64).map(|c| Constant::new((6 * c).into())).collect(),
            chunk_mask: Constant::new(63u64.into()),
            chunk_value: (0..64u64).map(|v| Constant::new(v.into())).collect(),
            chunk_residue: (0..64u64).map(|v| Constant::new((v % 3).into())).collect(),
            pair_at: Constant::new(2u64.into()),
            pair_residue: (0..16u64)
                .map(|v| Constant::new((((v >> 2) + (v & 3)) % 3).into()))
                .collect(),
            valid1: Default::default(),
            valid2: Default::default(),
            valid3: Default::default(),
            width1: Default::default(),
            small2: Default::default(),
            small3: Default::default(),
            cell1: Default::default(),
            third1: Default::default(),
            hash2: Default::default(),
            third2: Default::default(),
            res1: Default::default(),
            res2: Default::default(),
            bucket_r: Default::default(),
            fp_r: Default::default(),
            inside_r: Default::default(),
            home_r: Default::default(),
            home_fp_r: Default::default(),
            hacc: vec(9 * (COORD + 1)),
            first: Default::default(),
            chunk: Default::default(),
            pair: Default::default(),
            pair_sum: Default::default(),
            pairs: Default::default(),
            slot_hash: Default::default(),
            slot_in: Default::default(),
            slot_home: Default::default(),
            bank_hash: Default::default(),
            home_hash: Default::default(),
        }
    }
}

impl Logic for GridCells {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clock, valid1, valid2, valid3, small2, small3, home_fp_r);
        for x in 0..3 {
            self.width1[x].clock.next = self.clock.val();
            self.third1[x].clock.next = self.clock.val();
            self.third2[x].clock.next = self.clock.val();
            self.res2[x].clock.next = self.clock.val();
        }
        for c in 0..12 {
            self.res1[c].clock.next = self.clock.val();
        }
        for c in 0..9 {
            self.cell1[c].clock.next = self.clock.val();
            self.hash2[c].clock.next = self.clock.val();
        }
        for b in 0..27 {
            self.bucket_r[b].clock.next = self.clock.val();
            self.fp_r[b].clock.next = self.clock.val();
            self.inside_r[b].clock.next = self.clock.val();
            self.home_r[b].clock.next = self.clock.val();
        }
        self.valid1.d.next = self.key_valid.val();
        self.valid2.d.next = self.valid1.q.val();
        self.valid3.d.next = self.valid2.q.val();
        self.small3.d.next = self.small2.q.val();
        // K+1: the window's cells per axis, first to first + 2 (offset coordinates: the first
        // is kmin >> g, the home cell first + 1); the third is in the window when kmax reaches
        // the next cell. The box's width per axis (a small box spans at most one cell edge on
        // every axis: decided at K+2).
        for x in 0..3 {
            self.width1[x].d.next = self.key_max[x].val() - self.key_min[x].val();
            self.cell1[3 * x].d.next = self.key_min[x].val() >> self.cell_bits.val();
            self.cell1[3 * x + 1].d.next = (self.key_min[x].val() >> self.cell_bits.val()) + 1;
            self.cell1[3 * x + 2].d.next = (self.key_min[x].val() >> self.cell_bits.val()) + 2;
            self.third1[x].d.next = (self.key_max[x].val() >> self.cell_bits.val())
                != (self.key_min[x].val() >> self.cell_bits.val());
            // The first cell mod 3, in two steps: 64 = 1 mod 3, so a number's residue is the
            // sum of its 6-bit chunks' residues, and a chunk's residue is a function of its six
            // bits, stated as a table so that synthesis makes it one LUT per bit (sums of the
            // chunk's base-4 digits went through carry chains: 9 LUT levels). (Each residue is
            // masked to its two bits, so that synthesis sees the rest of the register is zero.)
            self.first[x].next = self.key_min[x].val() >> self.cell_bits.val();
            for c in 0..4 {
                self.chunk[4 * x + c].next =
                    (self.first[x].val() >> self.chunk_at[c].val()) & self.chunk_mask.val();
                self.res1[4 * x + c].d.next = 0.into();
                for v in 0..64 {
                    if self.chunk[4 * x + c].val() == self.chunk_value[v].val() {
                        self.res1[4 * x + c].d.next = self.chunk_residue[v].val();
                    }
                }
            }
        }

        // K+2: each cell's hash (bit k the parity of the coordinate bits row k selects: the
        // XOR of the columns of its set bits), and the first cell's residue mod 3 (its chunks'
        // residues summed, reduced).
        self.small2.d.next = (self.width1[0].q.val() <= self.cell_edge.val())
            & (self.width1[1].q.val() <= self.cell_edge.val())
            & (self.width1[2].q.val() <= self.cell_edge.val());
        for x in 0..3 {
            self.third2[x].d.next = self.third1[x].q.val();
            for d in 0..3 {
                self.hacc[24 * (3 * x + d)].next = 0.into();
                for i in 0..23 {
                    self.hacc[24 * (3 * x + d) + i + 1].next =
                        self.hacc[24 * (3 * x + d) + i].val();
                    if self.cell1[3 * x + d].q.val().get_bit(i) {
                        self.hacc[24 * (3 * x + d) + i + 1].next =
                            self.hacc[24 * (3 * x + d) + i].val() ^ self.column[23 * x + i].val();
                    }
                }
                self.hash2[3 * x + d].d.next = self.hacc[24 * (3 * x + d) + 23].val();
            }
            // The four residues summed mod 3 in two steps, each a table of two residues side
            // by side, so that each is one LUT per bit (summed and reduced by compares, they
            // went through two carry chains and four LUT levels).
            for p in 0..2 {
                self.pair[2 * x + p].next = (self.res1[4 * x + 2 * p].q.val()
                    << self.pair_at.val())
                    | self.res1[4 * x + 2 * p + 1].q.val();
                self.pair_sum[2 * x + p].next = 0.into();
                for v in 0..16 {
                    if self.pair[2 * x + p].val() == self.chunk_value[v].val() {
                        self.pair_sum[2 * x + p].next = self.pair_residue[v].val();
                    }
                }
            }
            self.pairs[x].next =
                (self.pair_sum[2 * x].val() << self.pair_at.val()) | self.pair_sum[2 * x + 1].val();
            self.res2[x].d.next = 0.into();
            for v in 0..16 {
                if self.pairs[x].val() == self.chunk_value[v].val() {
                    self.res2[x].d.next = self.pair_residue[v].val();
                }
            }
        }

        // K+3: per axis, the window's cell with each residue (`3 x + r`): first + d has residue
        // (res + d) mod 3; the home cell is first + 1. A bank's cell is the one with its
        // residues on the three axes; its hash is the XOR of theirs (the hash is linear).
        for x in 0..3 {
            self.slot_hash[3 * x].next = self.hash2[3 * x].q.val();
            self.slot_hash[3 * x + 1].next = self.hash2[3 * x + 1].q.val();
            self.slot_hash[3 * x + 2].next = self.hash2[3 * x + 2].q.val();
            self.slot_in[3 * x].next = true;
            self.slot_in[3 * x + 1].next = true;
            self.slot_in[3 * x + 2].next = self.third2[x].q.val();
            self.slot_home[3 * x].next = false;
            self.slot_home[3 * x + 1].next = true;
            self.slot_home[3 * x + 2].next = false;
            if self.res2[x].q.val() == 1 {
                self.slot_hash[3 * x + 1].next = self.hash2[3 * x].q.val();
                self.slot_hash[3 * x + 2].next = self.hash2[3 * x + 1].q.val();
                self.slot_hash[3 * x].next = self.hash2[3 * x + 2].q.val();
                self.slot_in[3 * x + 1].next = true;
                self.slot_in[3 * x + 2].next = true;
                self.slot_in[3 * x].next = self.third2[x].q.val();
                self.slot_home[3 * x + 1].next = false;
                self.slot_home[3 * x + 2].next = true;
            }
            if self.res2[x].q.val() == 2 {
                self.slot_hash[3 * x + 2].next = self.hash2[3 * x].q.val();
                self.slot_hash[3 * x].next = self.hash2[3 * x + 1].q.val();
                self.slot_hash[3 * x + 1].next = self.hash2[3 * x + 2].q.val();
                self.slot_in[3 * x + 2].next = true;
                self.slot_in[3 * x].next = true;
                self.slot_in[3 * x + 1].next = self.third2[x].q.val();
                self.slot_home[3 * x + 1].next = false;
                self.slot_home[3 * x].next = true;
            }
        }
        for z in 0..3 {
            for y in 0..3 {
                for x in 0..3 {
                    self.bank_hash[x + 3 * y + 9 * z].next = self.slot_hash[x].val()
                        ^ self.slot_hash[3 + y].val()
                        ^ self.slot_hash[6 + z].val();
                    self.bucket_r[x + 3 * y + 9 * z].d.next =
                        self.bank_hash[x + 3 * y + 9 * z].val() & self.bucket_mask.val();
                    self.fp_r[x + 3 * y + 9 * z].d.next =
                        self.bank_hash[x + 3 * y + 9 * z].val().get_bits::<FP>(12);
                    self.inside_r[x + 3 * y + 9 * z].d.next = self.slot_in[x].val()
                        & self.slot_in[3 + y].val()
                        & self.slot_in[6 + z].val();
                    self.home_r[x + 3 * y + 9 * z].d.next = self.slot_home[x].val()
                        & self.slot_home[3 + y].val()
                        & self.slot_home[6 + z].val();
                }
            }
        }
        self.home_hash.next = self.hash2[1].q.val() ^ self.hash2[4].q.val() ^ self.hash2[7].q.val();
        self.home_fp_r.d.next = self.home_hash.val().get_bits::<FP>(12);

        self.valid.next = self.valid3.q.val();
        self.small_box.next = self.small3.q.val();
        self.home_fp.next = self.home_fp_r.q.val();
        for b in 0..27 {
            self.bucket[b].next = self.bucket_r[b].q.val();
            self.fp[b].next = self.fp_r[b].q.val();
            self.inside[b].next = self.inside_r[b].q.val();
            self.home[b].next = self.home_r[b].q.val();
        }
    }
}
