//! Arithmetic leaves that rust-hdl cannot express (its multiply stops at 16 x 16 bits): each is
//! a Rust simulation model plus hand-written Verilog, registered as a DSP48E1 wants, and each is
//! co-simulated against its own Verilog (tests/leaves.rs).

use rust_hdl::prelude::*;

/// The value of an unsigned signal.
pub fn uval<const N: usize>(b: Bits<N>) -> u64 {
    b.to_u64()
}

/// The value of a signed signal.
pub fn sval<const N: usize>(s: Signed<N>) -> i64 {
    let raw = s.inner().to_u64();
    if N < 64 && raw >> (N - 1) & 1 == 1 {
        raw as i64 - (1i64 << N)
    } else {
        raw as i64
    }
}

/// A signed signal from a value that fits it.
pub fn sbits<const N: usize>(v: i64) -> Signed<N> {
    debug_assert!(N == 64 || (-(1i64 << (N - 1))..(1i64 << (N - 1))).contains(&v));
    Signed::from(v)
}

/// `2|r| + 1`, registered: the projection's multiplier operand for a rotation entry `r` (the
/// `+1` covers the entry's rounding, docs/numerics.md).
#[derive(Clone, Debug, Default, LogicBlock)]
pub struct AbsTwice<const N: usize, const M: usize> {
    pub r: Signal<In, Signed<N>>,
    pub t: Signal<Out, Bits<M>>,
    pub clock: Signal<In, Clock>,
}

impl<const N: usize, const M: usize> AbsTwice<N, M> {
    /// `2|r| + 1` must fit M bits.
    const FITS: () = assert!(M > N);
}

impl<const N: usize, const M: usize> Logic for AbsTwice<N, M> {
    fn update(&mut self) {
        let () = Self::FITS;
        if self.clock.pos_edge() {
            let r = sval(self.r.val());
            self.t.next = Bits::from(2 * r.unsigned_abs() + 1);
        }
    }
    fn connect(&mut self) {
        self.t.connect();
    }
    fn hdl(&self) -> Verilog {
        // |r| as an unsigned N-bit number (-2^(N-1) gives 2^(N-1)), widened to M bits.
        Verilog::Custom(format!(
            "\
wire [{n1}:0] mag = r[{n1}] ? -r : r;
wire [{m1}:0] wide = {{{{{pad}{{1'b0}}}}, mag}};
always @(posedge clock) begin
   t <= {{wide[{m2}:0], 1'b1}};
end
",
            n1 = N - 1,
            m1 = M - 1,
            m2 = M - 2,
            pad = M - N,
        ))
    }
}

/// An unsigned multiplier mapped to one DSP48E1: inputs, product and output registered
/// (AREG/BREG, MREG, PREG), so `p` follows `a` and `b` by three clocks, one product per clock.
#[derive(Clone, Debug, Default, LogicBlock)]
pub struct UMul<const A: usize, const B: usize, const P: usize> {
    pub a: Signal<In, Bits<A>>,
    pub b: Signal<In, Bits<B>>,
    pub p: Signal<Out, Bits<P>>,
    pub clock: Signal<In, Clock>,
    a_r: Signal<Local, Bits<A>>,
    b_r: Signal<Local, Bits<B>>,
    m_r: Signal<Local, Bits<P>>,
}

impl<const A: usize, const B: usize, const P: usize> UMul<A, B, P> {
    /// Clocks from operands to product.
    pub const LATENCY: u64 = 3;
    /// Products must fit the 64-bit simulation model (and P must hold them).
    const FITS: () = assert!(A + B <= 64 && A + B <= P);
}

impl<const A: usize, const B: usize, const P: usize> Logic for UMul<A, B, P> {
    fn update(&mut self) {
        if self.clock.pos_edge() {
            // A block's own Local and Out signals read back their `next` value in rust-hdl:
            // read every stage before writing any, so that each moves one stage per edge.
            let (a, b, m) = (uval(self.a_r.val()), uval(self.b_r.val()), self.m_r.val());
            self.a_r.next = self.a.val();
            self.b_r.next = self.b.val();
            self.m_r.next = Bits::from(a * b);
            self.p.next = m;
        }
    }
    fn connect(&mut self) {
        let () = Self::FITS;
        self.a_r.connect();
        self.b_r.connect();
        self.m_r.connect();
        self.p.connect();
    }
    fn hdl(&self) -> Verilog {
        Verilog::Custom(
            "\
always @(posedge clock) begin
   a_r <= a;
   b_r <= b;
   m_r <= a_r * b_r;
   p <= m_r;
end
"
            .into(),
        )
    }
}

/// `b - a` of two unsigned N-bit values as a signed M-bit value, registered: the center
/// difference `T` of two offset-binary centers (the offsets cancel).
#[derive(Clone, Debug, Default, LogicBlock)]
pub struct Diff<const N: usize, const M: usize> {
    pub a: Signal<In, Bits<N>>,
    pub b: Signal<In, Bits<N>>,
    pub d: Signal<Out, Signed<M>>,
    pub clock: Signal<In, Clock>,
}

impl<const N: usize, const M: usize> Diff<N, M> {
    const FITS: () = assert!(M > N && M <= 64);
}

impl<const N: usize, const M: usize> Logic for Diff<N, M> {
    fn update(&mut self) {
        let () = Self::FITS;
        if self.clock.pos_edge() {
            self.d.next = sbits(uval(self.b.val()) as i64 - uval(self.a.val()) as i64);
        }
    }
    fn connect(&mut self) {
        self.d.connect();
    }
    fn hdl(&self) -> Verilog {
        Verilog::Custom(format!(
            "\
always @(posedge clock) begin
   d <= $signed({{{pad}'b0, b}}) - $signed({{{pad}'b0, a}});
end
",
            pad = M - N,
        ))
    }
}

/// A signed dot product of three terms, `a0 b0 + a1 b1 + a2 b2`, three DSP48E1: inputs,
/// products and sum registered, so `p` follows the operands by three clocks. (Scalar ports: an
/// array port of a block in an array of blocks emits invalid Verilog in rust-hdl.)
#[derive(Clone, Debug, Default, LogicBlock)]
pub struct SDot3<const A: usize, const B: usize, const P: usize> {
    pub a0: Signal<In, Signed<A>>,
    pub a1: Signal<In, Signed<A>>,
    pub a2: Signal<In, Signed<A>>,
    pub b0: Signal<In, Signed<B>>,
    pub b1: Signal<In, Signed<B>>,
    pub b2: Signal<In, Signed<B>>,
    pub p: Signal<Out, Signed<P>>,
    pub clock: Signal<In, Clock>,
    a0_r: Signal<Local, Signed<A>>,
    a1_r: Signal<Local, Signed<A>>,
    a2_r: Signal<Local, Signed<A>>,
    b0_r: Signal<Local, Signed<B>>,
    b1_r: Signal<Local, Signed<B>>,
    b2_r: Signal<Local, Signed<B>>,
    m0: Signal<Local, Signed<P>>,
    m1: Signal<Local, Signed<P>>,
    m2: Signal<Local, Signed<P>>,
}

impl<const A: usize, const B: usize, const P: usize> SDot3<A, B, P> {
    /// Clocks from operands to the dot product.
    pub const LATENCY: u64 = 3;
    const FITS: () = assert!(A + B + 2 <= P && P <= 64);
}

impl<const A: usize, const B: usize, const P: usize> Logic for SDot3<A, B, P> {
    fn update(&mut self) {
        let () = Self::FITS;
        if self.clock.pos_edge() {
            // Read every stage before writing any (see `UMul`).
            let (a0, a1, a2) = (
                sval(self.a0_r.val()),
                sval(self.a1_r.val()),
                sval(self.a2_r.val()),
            );
            let (b0, b1, b2) = (
                sval(self.b0_r.val()),
                sval(self.b1_r.val()),
                sval(self.b2_r.val()),
            );
            let sum = sval(self.m0.val()) + sval(self.m1.val()) + sval(self.m2.val());
            self.a0_r.next = self.a0.val();
            self.a1_r.next = self.a1.val();
            self.a2_r.next = self.a2.val();
            self.b0_r.next = self.b0.val();
            self.b1_r.next = self.b1.val();
            self.b2_r.next = self.b2.val();
            self.m0.next = sbits(a0 * b0);
            self.m1.next = sbits(a1 * b1);
            self.m2.next = sbits(a2 * b2);
            self.p.next = sbits(sum);
        }
    }
    fn connect(&mut self) {
        self.a0_r.connect();
        self.a1_r.connect();
        self.a2_r.connect();
        self.b0_r.connect();
        self.b1_r.connect();
        self.b2_r.connect();
        self.m0.connect();
        self.m1.connect();
        self.m2.connect();
        self.p.connect();
    }
    fn hdl(&self) -> Verilog {
        Verilog::Custom(
            "\
always @(posedge clock) begin
   a0_r <= a0;
   a1_r <= a1;
   a2_r <= a2;
   b0_r <= b0;
   b1_r <= b1;
   b2_r <= b2;
   m0 <= a0_r * b0_r;
   m1 <= a1_r * b1_r;
   m2 <= a2_r * b2_r;
   p <= m0 + m1 + m2;
end
"
            .into(),
        )
    }
}

/// `a0 b0 + a1 b1` (or `a0 b0 - a1 b1` when `SUB`), signed, two DSP48E1: inputs, products and
/// result registered, so `p` follows the operands by three clocks. Scalar ports (see `SDot3`).
#[derive(Clone, Debug, Default, LogicBlock)]
pub struct SDot2<const A: usize, const B: usize, const P: usize, const SUB: bool> {
    pub a0: Signal<In, Signed<A>>,
    pub a1: Signal<In, Signed<A>>,
    pub b0: Signal<In, Signed<B>>,
    pub b1: Signal<In, Signed<B>>,
    pub p: Signal<Out, Signed<P>>,
    pub clock: Signal<In, Clock>,
    a0_r: Signal<Local, Signed<A>>,
    a1_r: Signal<Local, Signed<A>>,
    b0_r: Signal<Local, Signed<B>>,
    b1_r: Signal<Local, Signed<B>>,
    m0: Signal<Local, Signed<P>>,
    m1: Signal<Local, Signed<P>>,
}

impl<const A: usize, const B: usize, const P: usize, const SUB: bool> SDot2<A, B, P, SUB> {
    /// Clocks from operands to result.
    pub const LATENCY: u64 = 3;
    const FITS: () = assert!(A + B < P && P <= 64);
}

impl<const A: usize, const B: usize, const P: usize, const SUB: bool> Logic
    for SDot2<A, B, P, SUB>
{
    fn update(&mut self) {
        let () = Self::FITS;
        if self.clock.pos_edge() {
            // Read every stage before writing any (see `UMul`).
            let (a0, a1) = (sval(self.a0_r.val()), sval(self.a1_r.val()));
            let (b0, b1) = (sval(self.b0_r.val()), sval(self.b1_r.val()));
            let (m0, m1) = (sval(self.m0.val()), sval(self.m1.val()));
            self.a0_r.next = self.a0.val();
            self.a1_r.next = self.a1.val();
            self.b0_r.next = self.b0.val();
            self.b1_r.next = self.b1.val();
            self.m0.next = sbits(a0 * b0);
            self.m1.next = sbits(a1 * b1);
            self.p.next = sbits(if SUB { m0 - m1 } else { m0 + m1 });
        }
    }
    fn connect(&mut self) {
        self.a0_r.connect();
        self.a1_r.connect();
        self.b0_r.connect();
        self.b1_r.connect();
        self.m0.connect();
        self.m1.connect();
        self.p.connect();
    }
    fn hdl(&self) -> Verilog {
        Verilog::Custom(format!(
            "\
always @(posedge clock) begin
   a0_r <= a0;
   a1_r <= a1;
   b0_r <= b0;
   b1_r <= b1;
   m0 <= a0_r * b0_r;
   m1 <= a1_r * b1_r;
   p <= m0 {} m1;
end
",
            if SUB { "-" } else { "+" }
        ))
    }
}

/// `ceil(|x| / 2^s)`, registered, for a signed N-bit `x` and a shift `s` that is a constant of
/// the configuration (`s = 0` gives `|x|`).
#[derive(Clone, Debug, Default, LogicBlock)]
pub struct AbsShift<const N: usize, const M: usize> {
    pub x: Signal<In, Signed<N>>,
    pub s: Signal<In, Bits<8>>,
    pub y: Signal<Out, Bits<M>>,
    pub clock: Signal<In, Clock>,
}

impl<const N: usize, const M: usize> Logic for AbsShift<N, M> {
    fn update(&mut self) {
        if self.clock.pos_edge() {
            let (x, s) = (sval(self.x.val()).unsigned_abs(), uval(self.s.val()));
            self.y.next = Bits::from((x + (1 << s) - 1) >> s);
        }
    }
    fn connect(&mut self) {
        self.y.connect();
    }
    fn hdl(&self) -> Verilog {
        // |x| needs N bits as an unsigned number (-2^(N-1) gives 2^(N-1)); one more bit holds
        // the rounding addend.
        Verilog::Custom(format!(
            "\
wire [{n1}:0] mag = x[{n1}] ? -x : x;
wire [{n}:0] round = ({{{{{n}{{1'b0}}}}, 1'b1}} << s) - 1;
wire [{n}:0] total = {{1'b0, mag}} + round;
always @(posedge clock) begin
   y <= total >> s;
end
",
            n1 = N - 1,
            n = N,
        ))
    }
}
