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

/// An `initial` block that zeroes the registers `regs`: the Rust models start every register
/// at zero, and the Verilog must too in every simulator (Icarus starts one at `x`, which the
/// block harness treats as an error). Synthesis keeps them as init values; the DSP48E1's and
/// RAMB36E1's registers start at zero anyway, and their mapping is unchanged.
pub fn zeroed<S: AsRef<str>>(regs: impl IntoIterator<Item = S>) -> String {
    let mut v = String::from("initial begin\n");
    for r in regs {
        v.push_str(&format!("   {} = 0;\n", r.as_ref()));
    }
    v + "end\n"
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
{init}always @(posedge clock) begin
   t <= {{wide[{m2}:0], 1'b1}};
end
",
            init = zeroed(["t"]),
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
            zeroed(["a_r", "b_r", "m_r", "p"])
                + "\
always @(posedge clock) begin
   a_r <= a;
   b_r <= b;
   m_r <= a_r * b_r;
   p <= m_r;
end
",
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
{init}always @(posedge clock) begin
   d <= $signed({{{pad}'b0, b}}) - $signed({{{pad}'b0, a}});
end
",
            init = zeroed(["d"]),
            pad = M - N,
        ))
    }
}

/// Clocks from the operands of a dot product (`SDot3`, `SDot2`) to its sum. Each product is a
/// DSP48E1 with every pipeline register (AREG/BREG, MREG, PREG), and the products are summed in
/// the DSP48E1s' post-adders, one DSP after another, so no sum is left to the fabric: product k
/// enters its DSP k clocks after product 0 (AREG/BREG = 2, and a fabric register before that
/// for the third) and adds the previous DSP's P. Both shapes take the same number of clocks so
/// that the SAT's stages line up.
pub const DOT_LATENCY: u64 = 5;

/// Signed operands of `a` and `b` bits fit one DSP48E1 multiplier (25 x 18 bits).
const fn one_dsp(a: usize, b: usize) -> bool {
    (a <= 25 && b <= 18) || (a <= 18 && b <= 25)
}

/// The simulation model of a dot product: the sum of clock k's operands leaves after the rising
/// edge of clock k + DOT_LATENCY - 1 (registers start at zero, like the Verilog's).
#[derive(Clone, Debug, Default)]
struct DotPipe {
    sums: [i64; DOT_LATENCY as usize - 1],
}

impl DotPipe {
    /// One rising edge: takes this clock's sum, gives the one that is due.
    fn edge(&mut self, sum: i64) -> i64 {
        let due = self.sums[self.sums.len() - 1];
        self.sums.rotate_right(1);
        self.sums[0] = sum;
        due
    }
}

/// A signed dot product of three terms, `a0 b0 + a1 b1 + a2 b2`, as a cascade of three DSP48E1
/// (see `DOT_LATENCY`): `p` follows the operands by `DOT_LATENCY` clocks, one sum per clock.
/// (Scalar ports: an array port of a block in an array of blocks emits invalid Verilog in
/// rust-hdl.)
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
    _pipe: DotPipe,
}

impl<const A: usize, const B: usize, const P: usize> SDot3<A, B, P> {
    /// Clocks from operands to the dot product.
    pub const LATENCY: u64 = DOT_LATENCY;
    /// The sum fits P bits, and P the 48-bit post-adder.
    const FITS: () = assert!(A + B + 2 <= P && P <= 48 && one_dsp(A, B));
}

impl<const A: usize, const B: usize, const P: usize> Logic for SDot3<A, B, P> {
    fn update(&mut self) {
        let () = Self::FITS;
        if self.clock.pos_edge() {
            let term = |a: Signed<A>, b: Signed<B>| sval(a) * sval(b);
            let sum = term(self.a0.val(), self.b0.val())
                + term(self.a1.val(), self.b1.val())
                + term(self.a2.val(), self.b2.val());
            self.p.next = sbits(self._pipe.edge(sum));
        }
    }
    fn connect(&mut self) {
        self.p.connect();
    }
    fn hdl(&self) -> Verilog {
        // The products are declared at their exact width (A + B bits): wider, and yosys leaves
        // the post-adders and the P registers to the fabric once the core is flattened.
        Verilog::Custom(format!(
            "\
reg signed [{a}:0] a0_r, a1_r, a1_rr, a2_r, a2_rr, a2_rrr;
reg signed [{b}:0] b0_r, b1_r, b1_rr, b2_r, b2_rr, b2_rrr;
reg signed [{m}:0] m0, m1, m2;
reg signed [{p}:0] p0, p1;
{init}always @(posedge clock) begin
   // DSP 0: a0 b0 (AREG/BREG, MREG, PREG).
   a0_r <= a0;
   b0_r <= b0;
   m0 <= a0_r * b0_r;
   p0 <= m0;
   // DSP 1: a clock later (AREG/BREG = 2), plus DSP 0's P.
   a1_r <= a1;
   b1_r <= b1;
   a1_rr <= a1_r;
   b1_rr <= b1_r;
   m1 <= a1_rr * b1_rr;
   p1 <= m1 + p0;
   // DSP 2: two clocks later (a fabric register, then AREG/BREG = 2), plus DSP 1's P.
   a2_r <= a2;
   b2_r <= b2;
   a2_rr <= a2_r;
   b2_rr <= b2_r;
   a2_rrr <= a2_rr;
   b2_rrr <= b2_rr;
   m2 <= a2_rrr * b2_rrr;
   p <= m2 + p1;
end
",
            init = zeroed([
                "a0_r", "a1_r", "a1_rr", "a2_r", "a2_rr", "a2_rrr", "b0_r", "b1_r", "b1_rr",
                "b2_r", "b2_rr", "b2_rrr", "m0", "m1", "m2", "p0", "p1", "p",
            ]),
            a = A - 1,
            b = B - 1,
            m = A + B - 1,
            p = P - 1,
        ))
    }
}

/// `a0 b0 + a1 b1` (or `a0 b0 - a1 b1` when `SUB`), signed, as a cascade of two DSP48E1 (see
/// `DOT_LATENCY`): `p` follows the operands by `DOT_LATENCY` clocks. A DSP48E1 post-adder that
/// yosys infers only adds, so `SUB` adds `a1 ~b1 + a1` (= `-a1 b1`, and `~b1` cannot overflow
/// where `-b1` could): `a1` enters DSP 0's post-adder through its C port. Scalar ports (see
/// `SDot3`).
#[derive(Clone, Debug, Default, LogicBlock)]
pub struct SDot2<const A: usize, const B: usize, const P: usize, const SUB: bool> {
    pub a0: Signal<In, Signed<A>>,
    pub a1: Signal<In, Signed<A>>,
    pub b0: Signal<In, Signed<B>>,
    pub b1: Signal<In, Signed<B>>,
    pub p: Signal<Out, Signed<P>>,
    pub clock: Signal<In, Clock>,
    _pipe: DotPipe,
}

impl<const A: usize, const B: usize, const P: usize, const SUB: bool> SDot2<A, B, P, SUB> {
    /// Clocks from operands to result.
    pub const LATENCY: u64 = DOT_LATENCY;
    /// As `SDot3`'s.
    const FITS: () = assert!(A + B < P && P <= 48 && one_dsp(A, B));
}

impl<const A: usize, const B: usize, const P: usize, const SUB: bool> Logic
    for SDot2<A, B, P, SUB>
{
    fn update(&mut self) {
        let () = Self::FITS;
        if self.clock.pos_edge() {
            let (a0, b0) = (sval(self.a0.val()), sval(self.b0.val()));
            let (a1, b1) = (sval(self.a1.val()), sval(self.b1.val()));
            let sum = if SUB {
                a0 * b0 - a1 * b1
            } else {
                a0 * b0 + a1 * b1
            };
            self.p.next = sbits(self._pipe.edge(sum));
        }
    }
    fn connect(&mut self) {
        self.p.connect();
    }
    fn hdl(&self) -> Verilog {
        // Every operand first passes a fabric register (where `SUB` inverts b1), so that the
        // sum takes as long as `SDot3`'s. (Products are declared at their exact width, as in
        // `SDot3`.)
        let (b1, c) = if SUB { ("~b1", "a1") } else { ("b1", "0") };
        Verilog::Custom(format!(
            "\
reg signed [{a}:0] a0_f, a1_f, c_f, a0_r, a1_r, a1_rr, c_r, c_rr;
reg signed [{b}:0] b0_f, b1_f, b0_r, b1_r, b1_rr;
reg signed [{m}:0] m0, m1;
reg signed [{p}:0] p0;
{init}always @(posedge clock) begin
   a0_f <= a0;
   b0_f <= b0;
   a1_f <= a1;
   b1_f <= {b1};
   c_f <= {c};
   // DSP 0: a0 b0 (AREG/BREG, MREG, PREG), plus C.
   a0_r <= a0_f;
   b0_r <= b0_f;
   c_r <= c_f;
   c_rr <= c_r;
   m0 <= a0_r * b0_r;
   p0 <= m0 + c_rr;
   // DSP 1: a clock later (AREG/BREG = 2), plus DSP 0's P.
   a1_r <= a1_f;
   b1_r <= b1_f;
   a1_rr <= a1_r;
   b1_rr <= b1_r;
   m1 <= a1_rr * b1_rr;
   p <= m1 + p0;
end
",
            init = zeroed([
                "a0_f", "a1_f", "c_f", "a0_r", "a1_r", "a1_rr", "c_r", "c_rr", "b0_f", "b1_f",
                "b0_r", "b1_r", "b1_rr", "m0", "m1", "p0", "p",
            ]),
            a = A - 1,
            b = B - 1,
            m = A + B - 1,
            p = P - 1,
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
{init}always @(posedge clock) begin
   y <= total >> s;
end
",
            init = zeroed(["y"]),
            n1 = N - 1,
            n = N,
        ))
    }
}
