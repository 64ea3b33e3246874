//! `obbcd synth`: the synthesis estimate of the core for a configuration (yosys for the
//! XC6VHX565T): resources beside the paper's tables, logic depth, pipelining, and an estimated
//! period, written as a Markdown report.

use crate::detect::load_config;
use anyhow::{Context, Result};
use clap::Args;
use indicatif::ProgressBar;
use obb_model::fixed::HwConfig;
use obb_rtl::flow::synth::{
    self, DelayModel, PathGroup, Report, Resources, AIM_NS, PAPER, XC6VHX565T,
};
use obb_rtl::flow::{cache, generate};
use std::fmt::Write as _;
use std::path::PathBuf;
use std::time::Duration;

/// Rows of the report's table of deep paths.
const GROUP_ROWS: usize = 25;

#[derive(Args)]
pub struct SynthArgs {
    /// Hardware configuration (TOML); default: the built-in one.
    #[arg(long)]
    config: Option<PathBuf>,
    /// Markdown report to write.
    #[arg(short = 'o', long = "output", default_value = "reports/synth.md")]
    output: PathBuf,
    /// Cache of netlists (default: $OBBCD_CACHE, else ~/.cache/obbcd).
    #[arg(long)]
    cache: Option<PathBuf>,
    /// One block alone, as `gen-rtl` writes it to `blocks/` (minutes, not the whole core's
    /// quarter of an hour): its resources and its logic depth.
    #[arg(long, value_enum)]
    block: Option<Block>,
}

/// The blocks `gen-rtl` writes on their own (`rtl-out/blocks/`).
#[derive(Clone, Copy, clap::ValueEnum)]
enum Block {
    Projection,
    Sat,
    RadixSort,
    /// The grid broad phase (`broad_phase = "grid"`).
    GridPhase,
}

impl Block {
    fn module(self) -> &'static str {
        match self {
            Block::Projection => "projection",
            Block::Sat => "sat",
            Block::RadixSort => "radix_sort",
            Block::GridPhase => "grid_phase",
        }
    }
}

/// The line of the report that names the RTL it was made from (a test compares it with
/// `rtl-out/obb_core.v`).
pub fn rtl_line(file: &str, verilog: &str) -> String {
    format!(
        "RTL: `{file}` with SHA-256 prefix `{}`.",
        cache::key(&[verilog.as_bytes()])
    )
}

pub fn run(a: SynthArgs) -> Result<()> {
    let cfg = load_config(a.config.as_deref())?;
    let (top, file, verilog) = match a.block {
        None => ("obb_core", "obb_core.v".to_string(), generate::core(&cfg)?),
        Some(b) => (
            b.module(),
            format!("blocks/{}.v", b.module()),
            generate::block(&cfg, b.module())?,
        ),
    };
    let cache = a.cache.clone().unwrap_or_else(cache::default_dir);
    let bar = ProgressBar::new_spinner().with_message(
        "yosys synth_xilinx -family xc6v (on 2 cores: the default grid core about 30 \
             minutes, the sweep core 4, one block 1 to 5)",
    );
    bar.enable_steady_tick(Duration::from_millis(200));
    let netlist = synth::netlist(&verilog, top, synth::Mapping::Report, &cache.join("synth"));
    bar.finish_and_clear();
    let (dir, cached) = netlist?;
    eprintln!(
        "netlist in {} ({})",
        dir.display(),
        if cached { "cached" } else { "new" }
    );
    let report = synth::analyze(&dir.join("net.json"), top)?;
    let text = markdown(&cfg, top, &rtl_line(&file, &verilog), &report);
    if let Some(parent) = a.output.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(parent)
            .with_context(|| format!("cannot create {}", parent.display()))?;
    }
    std::fs::write(&a.output, &text)
        .with_context(|| format!("cannot write {}", a.output.display()))?;
    print!("{text}");
    eprintln!("wrote {}", a.output.display());
    Ok(())
}

/// A table of path groups under `title` (nothing when there are none).
fn groups(s: &mut String, title: &str, groups: &[PathGroup]) {
    if groups.is_empty() {
        return;
    }
    let _ = writeln!(
        s,
        "{title}:\n\n| from | to | LUT levels | ns | endpoints |\n| --- | --- | --- | --- | --- |"
    );
    for g in groups.iter().take(GROUP_ROWS) {
        let _ = writeln!(
            s,
            "| `{}` | `{}` | {} | {:.2} | {} |",
            g.from, g.to, g.luts, g.ns, g.endpoints
        );
    }
    let _ = writeln!(s);
}

fn pct(used: f64, of: u64) -> String {
    format!("{:.1} %", 100.0 * used / of as f64)
}

/// The report: the configuration, the resources beside the paper's, the pipelining and logic
/// depth, the targets met or not, and the delay model.
fn markdown(cfg: &HwConfig, top: &str, rtl: &str, r: &Report) -> String {
    let mut s = String::new();
    header(&mut s, cfg, top, rtl);
    resources(&mut s, top, &r.resources);
    depth(&mut s, r);
    targets(&mut s, r);
    delay_model(&mut s, &r.delays);
    s
}

/// The title, what wrote the report, the configuration, and that the period is an estimate.
fn header(s: &mut String, cfg: &HwConfig, top: &str, rtl: &str) {
    let _ = writeln!(
        s,
        "# Synthesis estimate: `{top}` on the {}\n\n\
         Written by `obbcd synth` (yosys `synth_xilinx -family xc6v -flatten -noiopad`, which \
         stands in for ISE's XST). {}\n\
         Configuration: capacity {}, broad phase `{}`, groups `{}`, center/half/rot/key bits \
         {}/{}/{}/{}, target clock {} ns.\n\n\
         **The period is an estimate, not a sign-off**: yosys has no Virtex-6 timing and places \
         nothing; the delay model below turns logic depth into nanoseconds. ISE's timing report \
         (`scripts/ise/build.tcl`) is the authority.\n",
        XC6VHX565T.name,
        rtl,
        cfg.capacity,
        cfg.broad_phase,
        cfg.groups,
        cfg.center_bits,
        cfg.half_bits,
        cfg.rot_bits,
        cfg.key_bits,
        cfg.clock_ns,
    );
}

/// The resources against the device and the paper's two designs.
fn resources(s: &mut String, top: &str, res: &Resources) {
    let _ = writeln!(
        s,
        "## Resources\n\n\
         | resource | {top} | of the device | {} | {} |\n| --- | --- | --- | --- | --- |",
        PAPER[0].what, PAPER[1].what
    );
    let ram = res.ramb36_equivalent();
    let paper_ram = |k: usize| PAPER[k].ramb36.map_or("-".into(), |v| v.to_string());
    let rows = [
        (
            "LUTs (logic)".to_string(),
            res.luts.to_string(),
            pct(res.luts as f64, XC6VHX565T.luts),
            PAPER[0].luts.to_string(),
            PAPER[1].luts.to_string(),
        ),
        (
            "LUTs as memory (distributed RAM, shift registers)".into(),
            res.lutram.to_string(),
            pct(res.lutram as f64, XC6VHX565T.luts),
            "-".into(),
            "-".into(),
        ),
        (
            "registers".into(),
            res.registers.to_string(),
            pct(res.registers as f64, XC6VHX565T.registers),
            PAPER[0].registers.to_string(),
            PAPER[1].registers.to_string(),
        ),
        (
            "DSP48E1".into(),
            res.dsp.to_string(),
            pct(res.dsp as f64, XC6VHX565T.dsp),
            PAPER[0].dsp.to_string(),
            PAPER[1].dsp.to_string(),
        ),
        (
            "block RAM (36 Kb units)".into(),
            format!("{ram} ({} RAMB36E1, {} RAMB18E1)", res.ramb36, res.ramb18),
            pct(ram, XC6VHX565T.ramb36),
            paper_ram(0),
            paper_ram(1),
        ),
        (
            "CARRY4".into(),
            res.carry4.to_string(),
            "-".into(),
            "-".into(),
            "-".into(),
        ),
        (
            "MUXF7/MUXF8".into(),
            res.muxf.to_string(),
            "-".into(),
            "-".into(),
            "-".into(),
        ),
    ];
    for (a, b, c, e, f) in rows {
        let _ = writeln!(s, "| {a} | {b} | {c} | {e} | {f} |");
    }
}

/// DSP and block RAM pipelining, the slowest and the deepest paths, the estimated period, and
/// the paths deeper than 3 LUT levels or slower than the aim, by register families.
fn depth(s: &mut String, r: &Report) {
    let res = &r.resources;
    let w = &r.worst;
    let period = w.delay_ns;
    let _ = writeln!(
        s,
        "\n## Pipelining and logic depth\n\n\
         - DSP48E1 multiplying without MREG: {} of {}; without PREG: {}.\n\
         - Block RAMs with a used read port without its output register (DO_REG): {} of {}.\n\
         - Slowest register-to-register path under the model: **{:.2} ns**, {} LUT levels and \
         {} CARRY4, from `{}` to `{}`.\n\
         - Most LUT levels on any path: {}, from `{}` to `{}`; path endpoints (bits) behind \
         more than 3 LUT levels: {}.\n\
         - **Estimated period {:.2} ns ({:.0} MHz)**; the paper's ISE figures: {:.3} ns (SAT), \
         {:.3} ns (whole).\n",
        r.dsp_without_mreg,
        res.dsp,
        r.dsp_without_preg,
        r.bram_without_output_register,
        res.ramb36 + res.ramb18,
        period,
        w.luts,
        w.carry4,
        w.from,
        w.to,
        r.deepest.luts,
        r.deepest.from,
        r.deepest.to,
        r.endpoints_over_3_luts,
        period,
        1000.0 / period,
        PAPER[0].period_ns,
        PAPER[1].period_ns,
    );
    groups(
        s,
        &format!(
            "Endpoints behind more than 3 LUT levels, by the register families they run \
             between (deepest first; {} of {} groups)",
            r.deep_groups.len().min(GROUP_ROWS),
            r.deep_groups.len()
        ),
        &r.deep_groups,
    );
    groups(
        s,
        &format!(
            "Endpoints slower than {AIM_NS} ns under the model: {}. By the register families \
             they run between (slowest first; {} of {} groups)",
            r.endpoints_over_aim,
            r.slow_groups.len().min(GROUP_ROWS),
            r.slow_groups.len()
        ),
        &r.slow_groups,
    );
}

/// Each target, what was measured, and whether it is met.
fn targets(s: &mut String, r: &Report) {
    let res = &r.resources;
    let ram = res.ramb36_equivalent();
    let period = r.worst.delay_ns;
    let met = |ok: bool| if ok { "met" } else { "**not met**" };
    let paper = &PAPER[1];
    let _ = writeln!(
        s,
        "## Targets\n\n| target | measured | |\n| --- | --- | --- |\n\
         | every DSP48E1 with MREG and PREG | {} without MREG, {} without PREG | {} |\n\
         | at most 3 LUT levels between registers | {} | {} |\n\
         | estimated period well under {:.3} ns (aim: {AIM_NS} ns) | {:.2} ns | {} |\n\
         | fewer DSP48E1 than the paper's {} | {} | {} |\n\
         | fewer block RAMs than the paper's {} | {} | {} |\n",
        r.dsp_without_mreg,
        r.dsp_without_preg,
        met(r.dsp_without_mreg == 0 && r.dsp_without_preg == 0),
        r.deepest.luts,
        met(r.deepest.luts <= 3),
        paper.period_ns,
        period,
        met(period <= AIM_NS),
        paper.dsp,
        res.dsp,
        met(res.dsp < paper.dsp),
        paper.ramb36.unwrap_or(0),
        ram,
        met(ram < paper.ramb36.unwrap_or(0) as f64),
    );
}

/// The delay model's figures.
fn delay_model(s: &mut String, d: &DelayModel) {
    let _ = writeln!(
        s,
        "## Delay model (ns)\n\n\
         A path is clock-to-output + each LUT level (LUT with its input route) + each MUXF7/F8 \
         + each carry chain (entry, blocks, exit) + setup. Fabric figures from yosys' \
         `cells_sim.v` (Artix-7, prjxray) with a route allowance per LUT level, checked on small \
         probes (docs/hardware.md, \"Synthesis estimate\"); block RAM and DSP48E1 figures from \
         `cells_sim.v`, rounded up. No placement, no clock skew, no routing congestion.\n\n\
         | element | ns |\n| --- | --- |\n\
         | flip-flop clock to Q | {} |\n| LUT level (LUT + route) | {} |\n| MUXF7/F8 | {} |\n\
         | carry chain entry / per CARRY4 / exit | {} / {} / {} |\n| flip-flop setup | {} |\n\
         | shift register clock to Q | {} |\n\
         | block RAM clock to out, without / with DO_REG | {} / {} |\n\
         | block RAM setup | {} |\n\
         | DSP48E1 clock to P with PREG / MREG only / input registers only | {} / {} / {} |\n\
         | DSP48E1 setup to input register / to M / to P / cascade PCIN | {} / {} / {} / {} |",
        d.clock_to_q,
        d.lut_level,
        d.muxf,
        d.carry_in,
        d.carry_block,
        d.carry_out,
        d.setup,
        d.srl_clock_to_q,
        d.bram_clock_to_out,
        d.bram_clock_to_out_reg,
        d.bram_setup,
        d.dsp_clock_to_p,
        d.dsp_m_to_p,
        d.dsp_a_to_p,
        d.dsp_setup,
        d.dsp_setup_m,
        d.dsp_setup_p,
        d.dsp_setup_pcin,
    );
}
