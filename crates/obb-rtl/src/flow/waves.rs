//! Waveforms of a co-simulation: a file of the format its extension names (VCD, or FST, which
//! Verilator writes natively and GTKWave reads, many times smaller), a window of clocks and a
//! hierarchy depth, so that a waveform of an interesting moment of a large scene stays small.
//!
//! The test bench opens the file at the start (`$dumpfile`), starts dumping at the window's
//! first clock (`$dumpvars`) and ends the run at its last: Verilator 5.006 ignores `$dumpoff`
//! and `$dumpvars`' depth, so the window's end is the run's end and the depth is a build option
//! there (`--trace-depth`), a run option in Icarus. A run that records waves is therefore not
//! the compared run: `obbcd cosim` compares an untraced run, then records.

use anyhow::{bail, Result};
use std::path::{Path, PathBuf};

/// A waveform file's format.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WaveFormat {
    Vcd,
    Fst,
}

/// What a traced build needs to know: the format and, for Verilator, the depth.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Trace {
    pub format: WaveFormat,
    /// Levels of hierarchy from the test bench (0: all).
    pub depth: u32,
}

/// A waveform to record.
#[derive(Clone, Debug)]
pub struct Waves {
    /// The file, `.vcd` or `.fst`.
    pub path: PathBuf,
    /// The format its extension names.
    pub format: WaveFormat,
    /// The first clock dumped, counted from the run's first clock over all its frames.
    pub from: u64,
    /// The clock at which the run ends (exclusive); `None`: the run's end.
    pub to: Option<u64>,
    /// Levels of hierarchy from the test bench: 1 the test bench's own signals, 2 also
    /// `obb_core`'s, and so on; 0 all.
    pub depth: u32,
}

impl Waves {
    /// Checks the extension and the window.
    pub fn new(path: &Path, from: u64, to: Option<u64>, depth: u32) -> Result<Waves> {
        let format = match path.extension().and_then(|e| e.to_str()) {
            Some("vcd") => WaveFormat::Vcd,
            Some("fst") => WaveFormat::Fst,
            _ => bail!(
                "waveform file {}: the extension names the format, .vcd or .fst",
                path.display()
            ),
        };
        if let Some(to) = to {
            if to <= from {
                bail!("the waveform window is empty: it ends at clock {to}, not after {from}");
            }
        }
        Ok(Waves {
            path: path.to_path_buf(),
            format,
            from,
            to,
            depth,
        })
    }

    /// What the build needs.
    pub fn trace(&self) -> Trace {
        Trace {
            format: self.format,
            depth: self.depth,
        }
    }

    /// The test bench's plusargs for the recording (the file made absolute: the simulator runs
    /// in the cache).
    pub fn plusargs(&self) -> Result<Vec<String>> {
        let mut args = vec![
            format!("+waves={}", std::path::absolute(&self.path)?.display()),
            format!("+waves_from={}", self.from),
            format!("+waves_depth={}", self.depth),
        ];
        if let Some(to) = self.to {
            args.push(format!("+waves_to={to}"));
        }
        Ok(args)
    }
}
