//! Timing helpers: median of repeated runs, after a warm-up or not, and contenders timed in
//! turns.

use std::time::{Duration, Instant};

/// Runs `f` `repeat` times (at least once) and returns the median wall time in ms and the last
/// result.
pub fn median_ms<T>(repeat: usize, mut f: impl FnMut() -> T) -> (f64, T) {
    let mut times = Vec::with_capacity(repeat.max(1));
    let mut last = None;
    for _ in 0..repeat.max(1) {
        let t = Instant::now();
        let r = f();
        times.push(t.elapsed().as_secs_f64() * 1e3);
        last = Some(r);
    }
    (median(&mut times), last.expect("ran at least once"))
}

/// [`median_ms`] after running `f` untimed for `warmup` (and at least once): the steady state
/// of a loop that runs frame after frame. A fresh engine's first frames are slower: on this
/// machine kind the grid's first dozen frames of the surgical scene took 1.2 to 2.8 times its
/// later ones, so a median of 15 frames from a fresh engine could be one of the slow ones.
pub fn warm_median_ms<T>(warmup: Duration, repeat: usize, mut f: impl FnMut() -> T) -> (f64, T) {
    let start = Instant::now();
    f();
    while start.elapsed() < warmup {
        f();
    }
    median_ms(repeat, f)
}

/// One turn of [`race`]: one untimed run of `frame` (the turn before was another contender's,
/// whose data took this one's place in the caches), then timed runs until `length` has passed
/// (at least one), their wall times (ms) appended to `times`.
pub fn turn(length: Duration, times: &mut Vec<f64>, mut frame: impl FnMut()) {
    frame();
    let start = Instant::now();
    loop {
        let t = Instant::now();
        frame();
        times.push(t.elapsed().as_secs_f64() * 1e3);
        if start.elapsed() >= length {
            break;
        }
    }
}

/// A contender of [`race`]: called with a turn's length and its times, it runs one [`turn`].
pub type Contender<'a> = &'a mut dyn FnMut(Duration, &mut Vec<f64>);

/// Times contenders against each other in turns of `length` each, round after round, until
/// every one has at least `repeat` timed runs and `rounds` turns; returns each one's median
/// (ms). A first round of turns of `warmup` each is not timed.
///
/// Taking turns, the contenders' medians come from the same stretch of time. This machine kind
/// is shared: its speed changes over seconds, and timed one after the other, a fast
/// contender's few milliseconds of frames can fall wholly in a slow spell that a slow
/// contender's second of frames only partly meets. Each turn's first run is untimed, so the
/// other contenders' turns cost the caches nothing that a frame loop would not pay once.
pub fn race(
    contenders: &mut [Contender],
    warmup: Duration,
    repeat: usize,
    rounds: usize,
    length: Duration,
) -> Vec<f64> {
    for contender in contenders.iter_mut() {
        contender(warmup, &mut Vec::new());
    }
    let mut times = vec![Vec::new(); contenders.len()];
    let mut round = 0;
    while round < rounds.max(1) || times.iter().any(|t| t.len() < repeat.max(1)) {
        for (contender, t) in contenders.iter_mut().zip(&mut times) {
            contender(length, t);
        }
        round += 1;
    }
    times.iter_mut().map(|t| median(t)).collect()
}

/// The median of `times` (not empty), which it sorts.
pub fn median(times: &mut [f64]) -> f64 {
    times.sort_by(f64::total_cmp);
    times[times.len() / 2]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A turn runs one untimed frame, then timed ones until its length has passed.
    #[test]
    fn a_turn_times_all_its_frames_but_the_first() {
        let mut frames = 0;
        let mut times = vec![1.0];
        turn(Duration::from_millis(3), &mut times, || {
            frames += 1;
            std::thread::sleep(Duration::from_micros(500));
        });
        assert_eq!(times.len(), frames, "one earlier time, one untimed frame");
        assert!(frames >= 4, "{frames} frames");
        assert!(times[1..].iter().all(|&t| t >= 0.5), "{times:?}");
    }

    /// Every contender gets the same number of turns, at least `rounds` and enough for `repeat`
    /// timed runs of the slowest; the medians are each contender's own (a frame of 0.2 ms against
    /// one of 4 ms, twenty times apart).
    #[test]
    fn race_takes_turns_until_each_has_its_runs() {
        let (mut quick_turns, mut slow_turns) = (0, 0);
        let mut quick = |length, times: &mut Vec<f64>| {
            quick_turns += 1;
            turn(length, times, || {
                std::thread::sleep(Duration::from_micros(200))
            });
        };
        let mut slow = |length, times: &mut Vec<f64>| {
            slow_turns += 1;
            turn(length, times, || {
                std::thread::sleep(Duration::from_millis(4))
            });
        };
        let (warmup, length) = (Duration::from_millis(1), Duration::from_millis(5));
        let medians = race(&mut [&mut quick, &mut slow], warmup, 6, 2, length);
        // A turn of 5 ms times one or two 4 ms frames: six need three turns at least, after
        // the warm-up's.
        assert!(slow_turns >= 4, "{slow_turns} turns");
        assert_eq!(quick_turns, slow_turns);
        assert!(medians[0] >= 0.2 && medians[1] >= 4.0, "{medians:?}");
        assert!(medians[1] > 5.0 * medians[0], "{medians:?}");
    }
}
