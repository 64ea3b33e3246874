//! Runs emitted Verilog in a real simulator (Verilator, or Icarus as a second opinion) on
//! vectors: a generated test bench reads one packed input word per clock (`$fscanf`, until the
//! file ends: a build serves any number of vectors), applies it, clocks the design and writes
//! the packed outputs after the edge. The same vectors drive the rust-hdl simulation, and both are
//! compared with the model, because rust-hdl's simulation and its Verilog can disagree.

use super::cache;
use anyhow::{bail, Context, Result};
use std::fmt::Write as _;
use std::path::Path;
use std::process::Command;

/// A port of the design under test: its Verilog name and width (at most 64 bits).
#[derive(Clone, Debug)]
pub struct Port {
    pub name: String,
    pub bits: usize,
}

impl Port {
    pub fn new(name: impl Into<String>, bits: usize) -> Port {
        assert!((1..=64).contains(&bits), "ports of 1 to 64 bits");
        Port {
            name: name.into(),
            bits,
        }
    }
}

/// Packs values (the first port in the lowest bits) into a hex word.
fn pack(ports: &[Port], values: &[u64]) -> String {
    let fields: Vec<(u64, usize)> = values
        .iter()
        .zip(ports)
        .map(|(&v, p)| (v, p.bits))
        .collect();
    hex_word(&fields)
}

/// Packs (value, bits) fields, the first in the lowest bits, into a hex word of whole digits.
pub fn hex_word(fields: &[(u64, usize)]) -> String {
    let mut bits = Vec::new();
    for &(v, n) in fields {
        bits.extend((0..n).map(|b| v >> b & 1 == 1));
    }
    bits.resize(bits.len().div_ceil(4) * 4, false);
    bits.chunks(4)
        .rev()
        .map(|c| {
            let d = c.iter().rev().fold(0, |acc, &b| acc << 1 | u32::from(b));
            char::from_digit(d, 16).expect("a hex digit")
        })
        .collect()
}

/// Unpacks a hex word into one value per port; an `x` or `z` digit is an error.
fn unpack(ports: &[Port], word: &str) -> Result<Vec<u64>> {
    let mut bits = Vec::with_capacity(word.len() * 4);
    for c in word.trim().chars().rev() {
        // An unknown (x) or floating (z) bit is a failure, not a zero: it hides X propagation.
        if matches!(c, 'x' | 'X' | 'z' | 'Z') {
            bail!("output word `{word}` has unknown or floating bits");
        }
        let d = c
            .to_digit(16)
            .with_context(|| format!("bad output word `{word}`"))?;
        bits.extend((0..4).map(|b| d >> b & 1 == 1));
    }
    let mut at = 0;
    let mut out = Vec::with_capacity(ports.len());
    for p in ports {
        let v = (0..p.bits).fold(0u64, |acc, b| {
            acc | u64::from(bits.get(at + b).copied().unwrap_or(false)) << b
        });
        out.push(v);
        at += p.bits;
    }
    Ok(out)
}

/// The test bench: clock low, apply word k, rising edge, write the outputs (ports, and probes
/// named `dut.<signal>`), falling edge. Its
/// own names start with `tb_` or end with `_file`, apart from any port's (a port `f` once met
/// the bench's file handle `f`).
fn testbench(top: &str, clock: &str, inputs: &[Port], outputs: &[Port]) -> String {
    let iw: usize = inputs.iter().map(|p| p.bits).sum();
    let mut v = String::new();
    let _ = writeln!(v, "`timescale 1ns/1ps\nmodule tb;");
    let _ = writeln!(v, "reg {clock} = 0;\nreg [{}:0] cur, tb_word;", iw - 1);
    let mut at = 0;
    for p in inputs {
        let _ = writeln!(
            v,
            "wire [{}:0] {} = cur[{}:{}];",
            p.bits - 1,
            p.name,
            at + p.bits - 1,
            at
        );
        at += p.bits;
    }
    // An output named with a dot is a probe: a signal inside the design, read by its
    // hierarchical name below `dut` (e.g. `decide$abs_t$0`, an input of the child `decide`).
    let mut packed = Vec::new();
    for (k, p) in outputs.iter().enumerate() {
        match p.name.strip_prefix("dut.") {
            Some(path) => {
                let _ = writeln!(v, "wire [{}:0] tb_probe_{k} = dut.{path};", p.bits - 1);
                packed.push(format!("tb_probe_{k}"));
            }
            None => {
                let _ = writeln!(v, "wire [{}:0] {};", p.bits - 1, p.name);
                packed.push(p.name.clone());
            }
        }
    }
    let conns: Vec<String> = std::iter::once(clock.to_string())
        .chain(
            inputs
                .iter()
                .chain(outputs)
                .filter(|p| !p.name.starts_with("dut."))
                .map(|p| p.name.clone()),
        )
        .map(|n| format!(".{n}({n})"))
        .collect();
    let _ = writeln!(v, "{top} dut({});", conns.join(", "));
    packed.reverse();
    let _ = writeln!(
        v,
        "integer tb_fd, tb_in;
reg [1023:0] stim_file, out_file;
initial begin
  if (!$value$plusargs(\"stim=%s\", stim_file)) $fatal(1, \"no +stim\");
  if (!$value$plusargs(\"out=%s\", out_file)) $fatal(1, \"no +out\");
  tb_in = $fopen(stim_file, \"r\");
  if (tb_in == 0) $fatal(1, \"cannot open the stimulus\");
  tb_fd = $fopen(out_file, \"w\");
  // (Read into a word of its own, then assigned: Verilator does not see `$fscanf`'s write
  // as a change that the port wires must follow.)
  while ($fscanf(tb_in, \"%h\\n\", tb_word) == 1) begin
    cur = tb_word;
    #1 {clock} = 1;
    #1 $fwrite(tb_fd, \"%h\\n\", {{{}}});
    #1 {clock} = 0;
  end
  $fclose(tb_in);
  $fclose(tb_fd);
  $finish;
end
endmodule",
        packed.join(", ")
    );
    v
}

/// A scratch directory for one simulation, below the system's temporary directory, its own for
/// every call (tests run in parallel threads of one process); removed with everything in it when
/// dropped. It derefs to its path.
pub fn scratch_dir(name: &str) -> Result<Scratch> {
    tempfile::Builder::new()
        .prefix(&format!("obb-rtl-{name}-"))
        .tempdir()
        .map(Scratch)
        .with_context(|| format!("cannot create a scratch directory for {name}"))
}

/// See [`scratch_dir`].
#[derive(Debug)]
pub struct Scratch(tempfile::TempDir);

impl std::ops::Deref for Scratch {
    type Target = Path;
    fn deref(&self) -> &Path {
        self.0.path()
    }
}

impl AsRef<Path> for Scratch {
    fn as_ref(&self) -> &Path {
        self.0.path()
    }
}

/// Runs a tool to completion; its stdout, or an error with all it said.
pub fn output(cmd: &mut Command, what: &str) -> Result<String> {
    let out = cmd.output().with_context(|| {
        format!("cannot run {what}: is it installed? (scripts/test.sh installs it)")
    })?;
    if !out.status.success() {
        bail!(
            "{what} failed:\n{}{}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        );
    }
    Ok(String::from_utf8_lossy(&out.stdout).into_owned())
}

fn run(cmd: &mut Command, what: &str) -> Result<()> {
    output(cmd, what).map(drop)
}

/// How long the simulations of a Verilator build run, which decides how much its C++ is
/// optimised: compiling that C++ is most of a short test's time.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Runs {
    /// Whole scenes, up to millions of clocks: the C++ at `-O1`. Not Verilator's default `-Os`:
    /// GCC's `-Os` is superlinear on the one large evaluation function a grid core becomes (one
    /// 1.2 MB file took more than seven minutes; `-O1` takes ten seconds), while the simulation
    /// runs about 1.4 times slower.
    Long,
    /// A block's vectors or a few small frames (thousands of clocks): the C++ at `-O0`, which
    /// compiled a grid block in 26 s of CPU where `-O1` took 43.
    Short,
}

/// What a Verilator build does with the warnings of its Verilog.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Warnings {
    /// Printed, and the build goes on: a core with its hand-written test bench (`sim/`), which
    /// `lint` checks on its own where the tests need it.
    Printed,
    /// Every warning [`lint`] reports fails the build, and the build is the lint: Verilator
    /// parses and checks a large design once instead of twice (a grid block's lint took 5 to
    /// 12 s of CPU, as long as its translation to C++). The generated test bench's
    /// own warnings (the ports a test leaves unconnected) are off (`BENCH_LINT_OFF`).
    Fatal,
}

/// A Verilator configuration file that turns every warning off in the generated test bench
/// (`tb.v`), so that a [`Warnings::Fatal`] build reports only the design's.
const BENCH_LINT_OFF: &str = "`verilator_config\nlint_off -file \"*tb.v\"\n";

/// Warnings neither the lint nor a build reports: WIDTH (rust-hdl writes 32-bit literals),
/// DECLFILENAME and UNUSED.
const QUIET: [&str; 3] = ["-Wno-WIDTH", "-Wno-DECLFILENAME", "-Wno-UNUSED"];

/// The flags of a Verilator build of a test bench (top module `tb`) into the executable
/// `obj/Vtb` of its directory, for simulations that run `runs` (a build's cache key holds the
/// flags). Where `ccache` is on the PATH the C++ compiler runs through it: Verilator's own
/// runtime, the same in every build, is then compiled once (about 11 s of CPU a build).
pub fn binary_flags(runs: Runs, warnings: Warnings) -> Vec<String> {
    let opt = match runs {
        Runs::Long => "-O1",
        Runs::Short => "-O0",
    };
    let mut make = format!("OPT_FAST={opt} OPT_SLOW={opt} OPT_GLOBAL=-O1");
    if has_ccache() {
        make.push_str(" OBJCACHE=ccache");
    }
    let flags = [
        "--binary",
        "-j",
        "2",
        "-O3",
        "--top-module",
        "tb",
        "-MAKEFLAGS",
        &make,
        "--Mdir",
        "obj",
    ];
    let policy: &[&str] = match warnings {
        Warnings::Printed => &["-Wno-fatal"],
        Warnings::Fatal => &["-Wall"],
    };
    flags
        .iter()
        .chain(policy)
        .chain(&QUIET)
        .map(|f| f.to_string())
        .collect()
}

/// Whether `ccache` runs here (asked once).
fn has_ccache() -> bool {
    static HAS: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
    *HAS.get_or_init(|| Command::new("ccache").arg("--version").output().is_ok())
}

/// A Verilog simulator: Verilator for speed, Icarus as a second opinion.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Simulator {
    Verilator,
    Icarus,
}

/// Simulates `verilog` (top module `top`, clocked by `clock`) in `sim` on one input vector per
/// clock and returns the outputs after each rising edge. The files of the run are written in
/// `dir`; a Verilator build is taken from `cache` (`cache::entry`, keyed by the test bench, the
/// design, the flags and Verilator's version) when one is given, else built in `dir`. The
/// Verilator build lints the design as [`lint`] does ([`Warnings::Fatal`]): a design with a
/// warning is an error, and a cached build passed the lint.
#[allow(clippy::too_many_arguments)]
pub fn simulate(
    sim: Simulator,
    dir: &Path,
    cache: Option<&Path>,
    verilog: &str,
    top: &str,
    clock: &str,
    inputs: &[Port],
    outputs: &[Port],
    vectors: &[Vec<u64>],
) -> Result<Vec<Vec<u64>>> {
    assert!(!vectors.is_empty() && !inputs.is_empty());
    let bench = testbench(top, clock, inputs, outputs);
    let stim: String = vectors.iter().map(|v| pack(inputs, v) + "\n").collect();
    std::fs::write(dir.join("stim.hex"), stim)?;
    let plusargs = ["+stim=stim.hex", "+out=out.hex"];
    let sources = |at: &Path| -> Result<()> {
        std::fs::write(at.join("dut.v"), verilog)?;
        std::fs::write(at.join("tb.v"), &bench)?;
        Ok(())
    };
    match sim {
        Simulator::Verilator => {
            let flags = binary_flags(Runs::Short, Warnings::Fatal);
            let build = |at: &Path| {
                sources(at)?;
                std::fs::write(at.join("bench.vlt"), BENCH_LINT_OFF)?;
                let mut cmd = Command::new("verilator");
                cmd.current_dir(at)
                    .args(&flags)
                    .args(["bench.vlt", "tb.v", "dut.v"]);
                run(&mut cmd, "verilator (lint and build)")
            };
            let built = match cache {
                Some(cache) => {
                    let version = output(Command::new("verilator").arg("--version"), "verilator")?;
                    let flags = flags.join(" ");
                    let parts =
                        [&bench, verilog, &flags, BENCH_LINT_OFF, &version].map(str::as_bytes);
                    let name = format!("block-{top}-{}", cache::key(&parts));
                    cache::entry(cache, &name, build)?.0
                }
                None => {
                    build(dir)?;
                    dir.to_path_buf()
                }
            };
            run(
                Command::new(built.join("obj/Vtb"))
                    .current_dir(dir)
                    .args(plusargs),
                "the Verilator simulation",
            )?;
        }
        Simulator::Icarus => {
            sources(dir)?;
            run(
                Command::new("iverilog")
                    .current_dir(dir)
                    .args(["-g2012", "-s", "tb", "-o", "tb.vvp", "tb.v", "dut.v"]),
                "iverilog (build)",
            )?;
            run(
                Command::new("vvp")
                    .current_dir(dir)
                    .args(["-n", "tb.vvp"])
                    .args(plusargs),
                "the Icarus simulation",
            )?;
        }
    }
    let text = std::fs::read_to_string(dir.join("out.hex"))?;
    text.lines().map(|l| unpack(outputs, l)).collect()
}

/// Lints `verilog` with Verilator: all warnings on, except WIDTH (rust-hdl writes 32-bit
/// literals), DECLFILENAME and UNUSED; LATCH and everything else is an error.
pub fn lint(dir: &Path, verilog: &str, top: &str) -> Result<()> {
    std::fs::write(dir.join("lint.v"), verilog)?;
    run(
        Command::new("verilator")
            .current_dir(dir)
            .args(["--lint-only", "-Wall"])
            .args(QUIET)
            .args(["--top-module", top, "lint.v"]),
        "verilator --lint-only",
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pack_and_unpack_round_trip() {
        let ports = [Port::new("a", 3), Port::new("b", 64), Port::new("c", 1)];
        let values = vec![5, 0xdead_beef_1234_5678, 1];
        let word = pack(&ports, &values);
        assert_eq!(word.len(), 17);
        assert_eq!(unpack(&ports, &word).unwrap(), values);
    }

    /// A block's build is its lint: a latch fails it as it fails `lint`, while the test
    /// bench's own warnings (here an output it leaves unconnected) do not.
    #[test]
    fn a_block_build_lints_the_design_and_not_the_bench() {
        let block = |body: &str| {
            format!(
                "module m(input clock, input [3:0] a, output reg [3:0] q, output [3:0] r);\n\
                 {body}\nalways @(posedge clock) q <= a;\nendmodule\n"
            )
        };
        let clean = block("assign r = ~a;");
        let latch = block("reg [3:0] l;\nalways @(*) if (a[0]) l = a;\nassign r = l;");
        let (inputs, outputs) = ([Port::new("a", 4)], [Port::new("q", 4)]);
        let vectors = vec![vec![5], vec![9]];
        let run = |verilog: &str| {
            let dir = scratch_dir("m").unwrap();
            simulate(
                Simulator::Verilator,
                &dir,
                None,
                verilog,
                "m",
                "clock",
                &inputs,
                &outputs,
                &vectors,
            )
        };
        assert_eq!(run(&clean).unwrap(), [[5], [9]]);
        let dir = scratch_dir("m").unwrap();
        lint(&dir, &clean, "m").unwrap();
        for e in [
            lint(&dir, &latch, "m").unwrap_err(),
            run(&latch).unwrap_err(),
        ] {
            assert!(format!("{e:#}").contains("%Warning-LATCH"), "{e:#}");
        }
    }

    #[test]
    fn unknown_or_floating_bits_are_errors() {
        let ports = [Port::new("a", 8)];
        for word in ["x0", "0X", "z1", "Z0"] {
            assert!(unpack(&ports, word).is_err(), "{word}");
        }
    }
}
