//! `--neighbour-mb` of `bench` and `replay`: a neighbour on another core that keeps its own
//! lines in the shared last-level cache, as another tenant of the CPU does.
//!
//! On a shared machine (a Zen 3 EPYC of this machine kind) the grid's frame slowed in spells,
//! by up to 1.7 times where parry3d's slowed by 1.1 to 1.3: the frame's data (some 6.5 MB on
//! the surgical scene) live in the L3, and a tenant that reads lines of its own there at random
//! takes part of it. A stream through a large buffer keeps nothing there and slowed the frame
//! little; random reads over some 12 MB brought the spells about (docs/engines.md, "The spells
//! reproduced"). This neighbour is those reads: eight chains of dependent loads, each following
//! one random cycle through every 64-byte line of its buffer, on a thread of its own until it
//! is stopped.

use anyhow::{anyhow, Result};
use rand::seq::SliceRandom;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// Words of a 64-byte line: each line's first word holds the offset of the next line's.
const WORDS_PER_LINE: usize = 64 / std::mem::size_of::<usize>();

/// Independent chains of loads: a core keeps several misses in flight, as a busy tenant does.
const CHAINS: usize = 8;

/// Rounds (one load in each chain) between looks at the stop flag.
const ROUNDS_PER_LOOK: u64 = 1024;

/// The largest buffer taken (MB): far past any L3, and well within this machine kind's memory.
const MAX_MB: usize = 4096;

/// The neighbour's thread, reading until it is stopped (or dropped).
pub struct Neighbour {
    mb: usize,
    stop: Arc<AtomicBool>,
    started: Instant,
    thread: Option<JoinHandle<u64>>,
}

/// What the neighbour did: `rounds` loads in each chain over `elapsed`.
pub struct Chased {
    pub mb: usize,
    pub rounds: u64,
    pub elapsed: Duration,
}

impl Chased {
    /// Nanoseconds between two loads of one chain: the latency of its reads (the chains'
    /// loads overlap), about the L3's when its lines stay there and memory's when they do not.
    pub fn ns_per_load(&self) -> f64 {
        self.elapsed.as_secs_f64() * 1e9 / self.rounds.max(1) as f64
    }
}

impl Neighbour {
    /// Lays out a buffer of `mb` MB as one random cycle (before it starts, so that laying it out
    /// is not in what is timed beside it) and starts reading it. Callers take
    /// [`Neighbour::beside_workers`], which first checks for a free core.
    fn start(mb: usize) -> Result<Self> {
        anyhow::ensure!(
            (1..=MAX_MB).contains(&mb),
            "--neighbour-mb must be from 1 to {MAX_MB}, not {mb}"
        );
        let words = cycle((mb << 20) / 64, 1);
        let stop = Arc::new(AtomicBool::new(false));
        let flag = Arc::clone(&stop);
        let thread = std::thread::Builder::new()
            .name("neighbour".into())
            .spawn(move || chase(&words, &flag))?;
        Ok(Neighbour {
            mb,
            stop,
            started: Instant::now(),
            thread: Some(thread),
        })
    }

    /// [`Neighbour::start`] on a core that the worker threads leave free: on a core of theirs it
    /// would take their time, not their cache.
    pub fn beside_workers(mb: usize) -> Result<Self> {
        let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
        let threads = rayon::current_num_threads();
        anyhow::ensure!(
            threads < cores,
            "--neighbour-mb needs a core of its own beside the {threads} worker threads, on {cores} cores: give fewer (`obbcd --threads N ...`, N below {cores})"
        );
        Self::start(mb)
    }

    /// Stops the reads and says what they did.
    pub fn finish(mut self) -> Result<Chased> {
        let rounds = self.halt()?;
        Ok(Chased {
            mb: self.mb,
            rounds,
            elapsed: self.started.elapsed(),
        })
    }

    fn halt(&mut self) -> Result<u64> {
        self.stop.store(true, Ordering::Relaxed);
        match self.thread.take() {
            Some(t) => t
                .join()
                .map_err(|_| anyhow!("the neighbour's reads panicked")),
            None => Ok(0),
        }
    }
}

/// A bench or replay that ends early (an error) still stops its neighbour.
impl Drop for Neighbour {
    fn drop(&mut self) {
        let _ = self.halt();
    }
}

/// `lines` 64-byte lines, each line's first word the offset (in words) of the next line's
/// first word, the lines in one random cycle through them all (from `seed`): a chain that
/// follows it reads every line once per lap, in an order no prefetcher can guess.
fn cycle(lines: usize, seed: u64) -> Vec<usize> {
    let mut order: Vec<usize> = (0..lines).collect();
    order.shuffle(&mut ChaCha8Rng::seed_from_u64(seed));
    let mut words = vec![0; lines * WORDS_PER_LINE];
    for (k, &line) in order.iter().enumerate() {
        words[line * WORDS_PER_LINE] = order[(k + 1) % lines] * WORDS_PER_LINE;
    }
    words
}

/// Follows [`CHAINS`] chains through `words` until `stop`; returns the rounds taken (a load in
/// each chain a round). The chains start at lines spread over the buffer, so at places far
/// apart along the cycle, and do not read each other's lines just after one another.
fn chase(words: &[usize], stop: &AtomicBool) -> u64 {
    let lines = words.len() / WORDS_PER_LINE;
    let mut at: [usize; CHAINS] = std::array::from_fn(|k| k * lines / CHAINS * WORDS_PER_LINE);
    let mut rounds = 0;
    while !stop.load(Ordering::Relaxed) {
        for _ in 0..ROUNDS_PER_LOOK {
            for p in &mut at {
                *p = words[*p];
            }
        }
        rounds += ROUNDS_PER_LOOK;
    }
    // The chains' ends are the loads' only use: without this they could be left out.
    std::hint::black_box(at);
    rounds
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The buffer is one cycle through every line: from any line, `lines` steps visit each line
    /// once and come back (a shuffled list of next lines would form several shorter cycles).
    #[test]
    fn the_buffer_is_one_cycle_through_every_line() {
        for lines in [1, 2, 3, 1000, 4099] {
            let words = cycle(lines, 7);
            assert_eq!(words.len(), lines * WORDS_PER_LINE);
            let mut seen = vec![false; lines];
            let mut at = 0;
            for _ in 0..lines {
                assert_eq!(at % WORDS_PER_LINE, 0, "an offset inside a line");
                let line = at / WORDS_PER_LINE;
                assert!(!seen[line], "line {line} visited twice in {lines}");
                seen[line] = true;
                at = words[at];
            }
            assert_eq!(at, 0, "{lines} steps do not come back");
            // Not the lines in memory order, which a prefetcher would follow.
            if lines >= 1000 {
                let in_order = (0..lines)
                    .filter(|&l| words[l * WORDS_PER_LINE] == (l + 1) * WORDS_PER_LINE)
                    .count();
                assert!(in_order < lines / 100, "{in_order} of {lines} in order");
            }
        }
    }

    /// The neighbour reads until it is told to stop, and a dropped one stops too.
    #[test]
    fn the_neighbour_reads_until_stopped() {
        let n = Neighbour::start(1).unwrap();
        std::thread::sleep(Duration::from_millis(50));
        let chased = n.finish().unwrap();
        assert_eq!(chased.mb, 1);
        assert!(chased.rounds >= ROUNDS_PER_LOOK, "{} rounds", chased.rounds);
        assert!(chased.elapsed >= Duration::from_millis(50));
        let ns = chased.ns_per_load();
        assert!(ns > 0.1 && ns < 1e6, "{ns} ns a load");
        let dropped = Neighbour::start(1).unwrap();
        let stop = Arc::clone(&dropped.stop);
        drop(dropped);
        assert!(stop.load(Ordering::Relaxed));
    }

    #[test]
    fn sizes_out_of_range_are_refused() {
        for mb in [0, MAX_MB + 1] {
            let e = Neighbour::start(mb).err().expect("refused");
            assert!(
                e.to_string().contains("--neighbour-mb must be from 1"),
                "{e}"
            );
        }
    }
}
