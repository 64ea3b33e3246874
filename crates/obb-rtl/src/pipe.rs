//! `Pipe<T, D>`: a value carried alongside a pipeline, `D` clocks later, one register a clock.
//! The pipelines' timing is in the types (`Pipe<_, 6>` from clock 6 to clock 12) rather than in
//! hand-counted arrays of registers with strided taps. Where a value is used at several
//! clocks, one pipe a segment, each fed by the one before (as rust-hdl-widgets' `DelayLine`,
//! without its run-time tap).

use rust_hdl::prelude::*;

#[derive(Clone, Debug, LogicBlock)]
pub struct Pipe<T: Synth, const D: usize> {
    pub clock: Signal<In, Clock>,
    /// The value entering the pipe.
    pub d: Signal<In, T>,
    /// `d` from `D` clocks before.
    pub q: Signal<Out, T>,
    /// `stage[s]` holds `d` from `s + 1` clocks before.
    stage: [DFF<T>; D],
}

impl<T: Synth, const D: usize> Default for Pipe<T, D> {
    fn default() -> Self {
        const { assert!(D >= 1, "a pipe delays by one clock at least") };
        Pipe {
            clock: Default::default(),
            d: Default::default(),
            q: Default::default(),
            // `derive(Default)` stops at arrays of 32.
            stage: std::array::from_fn(|_| Default::default()),
        }
    }
}

impl<T: Synth, const D: usize> Logic for Pipe<T, D> {
    #[hdl_gen]
    fn update(&mut self) {
        for s in 0..D {
            self.stage[s].clock.next = self.clock.val();
        }
        self.stage[0].d.next = self.d.val();
        for s in 1..D {
            self.stage[s].d.next = self.stage[s - 1].q.val();
        }
        // A loop of one: `hdl_gen` cannot emit `stage[D - 1]` with a named constant.
        for s in (D - 1)..D {
            self.q.next = self.stage[s].q.val();
        }
    }
}
