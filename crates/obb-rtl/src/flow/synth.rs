//! Synthesis estimates for the XC6VHX565T: yosys `synth_xilinx -family xc6v` stands in for
//! ISE's XST. From its flattened netlist this module counts the resources and walks every
//! register-to-register path for its logic depth (LUT levels, CARRY4 blocks), the DSP48E1s
//! without their pipeline registers and the block RAM reads without an output register, and
//! turns the worst path into a clock period with the stated delay model (`DelayModel`). The
//! period is an estimate: yosys has no Virtex-6 timing and places nothing.

use crate::flow::cache;
use anyhow::{bail, Context, Result};
use serde::Serialize;
use serde_json::Value;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::process::Command;

/// The target device, as the paper's tables give it.
pub struct Device {
    pub name: &'static str,
    pub luts: u64,
    pub registers: u64,
    pub dsp: u64,
    /// 36 Kb block RAMs (a RAMB18 is half of one).
    pub ramb36: u64,
}

pub const XC6VHX565T: Device = Device {
    name: "XC6VHX565T",
    luts: 354_240,
    registers: 708_480,
    dsp: 864,
    ramb36: 912,
};

/// One of the paper's resource tables (Zhang et al. 2016).
pub struct PaperTable {
    pub what: &'static str,
    pub luts: u64,
    pub registers: u64,
    pub dsp: u64,
    pub ramb36: Option<u64>,
    pub period_ns: f64,
}

/// Table 1 (the SAT alone) and Table 2 (the whole design, 16,384 boxes).
pub const PAPER: [PaperTable; 2] = [
    PaperTable {
        what: "paper, Table 1 (SAT)",
        luts: 31_504,
        registers: 30_543,
        dsp: 525,
        ramb36: None,
        period_ns: 8.110,
    },
    PaperTable {
        what: "paper, Table 2 (whole)",
        luts: 66_061,
        registers: 47_634,
        dsp: 630,
        ramb36: Some(705),
        period_ns: 8.509,
    },
];

/// The delay model that turns logic depth into a period (ns). Fabric figures are yosys'
/// `cells_sim.v` delays (Artix-7, prjxray) with a route allowance per LUT level, checked on small
/// probe designs (docs/hardware.md, "Synthesis estimate"): a LUT with its input route; a carry
/// chain's entry, blocks and exit. The block RAM and DSP figures are `cells_sim.v`'s rounded up.
/// No placement: every LUT level pays the same route.
#[derive(Clone, Debug, Serialize)]
pub struct DelayModel {
    pub clock_to_q: f64,
    pub lut_level: f64,
    pub muxf: f64,
    pub carry_in: f64,
    pub carry_block: f64,
    pub carry_out: f64,
    pub setup: f64,
    /// Shift register (SRL16E/SRLC32E) clock to output.
    pub srl_clock_to_q: f64,
    /// Block RAM clock to data out, without the output register (DO_REG).
    pub bram_clock_to_out: f64,
    /// Block RAM clock to data out, with the output register (DO_REG).
    pub bram_clock_to_out_reg: f64,
    /// Block RAM address and data setup.
    pub bram_setup: f64,
    /// DSP48E1 clock to P with PREG.
    pub dsp_clock_to_p: f64,
    /// DSP48E1 clock to P with MREG only.
    pub dsp_m_to_p: f64,
    /// DSP48E1 clock to P with only input registers.
    pub dsp_a_to_p: f64,
    /// DSP48E1 input setup to its input register.
    pub dsp_setup: f64,
    /// DSP48E1 input setup to M, when A/B are not registered.
    pub dsp_setup_m: f64,
    /// DSP48E1 input setup to P.
    pub dsp_setup_p: f64,
    /// DSP48E1 cascade input (PCIN) setup.
    pub dsp_setup_pcin: f64,
}

pub const DELAYS: DelayModel = DelayModel {
    clock_to_q: 0.40,
    lut_level: 0.52,
    muxf: 0.30,
    carry_in: 0.40,
    carry_block: 0.08,
    carry_out: 0.30,
    setup: 0.10,
    srl_clock_to_q: 1.20,
    bram_clock_to_out: 2.45,
    bram_clock_to_out_reg: 0.88,
    bram_setup: 0.57,
    dsp_clock_to_p: 0.60,
    dsp_m_to_p: 1.90,
    dsp_a_to_p: 2.90,
    dsp_setup: 0.30,
    dsp_setup_m: 2.60,
    dsp_setup_p: 3.00,
    dsp_setup_pcin: 1.03,
};

/// Cell counts of the netlist.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Resources {
    /// LUT1 to LUT6 and inverters (a LUT1 each).
    pub luts: u64,
    /// LUTs used as memory: distributed RAM and shift registers.
    pub lutram: u64,
    /// Flip-flops (FDRE and its kin).
    pub registers: u64,
    /// CARRY4 carry chains.
    pub carry4: u64,
    /// MUXF7 and MUXF8.
    pub muxf: u64,
    /// DSP48E1 slices.
    pub dsp: u64,
    /// RAMB36E1 block RAMs.
    pub ramb36: u64,
    /// RAMB18E1 block RAMs.
    pub ramb18: u64,
}

impl Resources {
    /// Block RAM in 36 Kb units.
    pub fn ramb36_equivalent(&self) -> f64 {
        self.ramb36 as f64 + self.ramb18 as f64 / 2.0
    }
}

/// One register-to-register path: its delay under the model (the slowest path), its LUT
/// levels and CARRY4 blocks, and the cells it runs between.
#[derive(Clone, Debug, Default, Serialize)]
pub struct PathInfo {
    pub delay_ns: f64,
    pub luts: u32,
    pub carry4: u32,
    pub from: String,
    pub to: String,
}

/// The path with the most LUT levels.
#[derive(Clone, Debug, Default, Serialize)]
pub struct DeepPath {
    pub luts: u32,
    pub from: String,
    pub to: String,
}

/// The period the core aims at (ns): the report lists the paths slower than it.
pub const AIM_NS: f64 = 4.0;

/// Path endpoints between two register families (a register's name without its bit index,
/// e.g. `radix.idx`): those behind more than 3 LUT levels, or those slower than [`AIM_NS`].
#[derive(Clone, Debug, Default, Serialize)]
pub struct PathGroup {
    pub from: String,
    pub to: String,
    /// Endpoints (bits) in the group.
    pub endpoints: u64,
    /// The most LUT levels among them.
    pub luts: u32,
    /// The slowest delay among them (ns).
    pub ns: f64,
}

/// Groups endpoints by the register families of their path's start and end.
#[derive(Default)]
struct Grouping(HashMap<(String, String), PathGroup>);

impl Grouping {
    fn add(&mut self, from: &str, to: &str, luts: u32, ns: f64) {
        let (from, to) = (family(from), family(to));
        let g = self
            .0
            .entry((from.clone(), to.clone()))
            .or_insert(PathGroup {
                from,
                to,
                ..Default::default()
            });
        g.endpoints += 1;
        g.luts = g.luts.max(luts);
        g.ns = g.ns.max(ns);
    }

    /// The groups, worst first by `key`.
    fn sorted<K: PartialOrd>(self, key: impl Fn(&PathGroup) -> K) -> Vec<PathGroup> {
        let mut g: Vec<PathGroup> = self.0.into_values().collect();
        g.sort_by(|a, b| {
            key(b)
                .partial_cmp(&key(a))
                .unwrap_or(std::cmp::Ordering::Equal)
                .then(b.endpoints.cmp(&a.endpoints))
                .then(a.from.cmp(&b.from))
                .then(a.to.cmp(&b.to))
        });
        g
    }
}

/// What the netlist says.
#[derive(Clone, Debug, Serialize)]
pub struct Report {
    pub resources: Resources,
    /// DSP48E1s that multiply without MREG.
    pub dsp_without_mreg: u64,
    /// DSP48E1s that multiply without PREG.
    pub dsp_without_preg: u64,
    /// Block RAMs with a read port whose output register (DO_REG) is off.
    pub bram_without_output_register: u64,
    /// Path endpoints (bits) fed through more than 3 LUT levels.
    pub endpoints_over_3_luts: u64,
    /// Those endpoints by the register families they run between, deepest first.
    pub deep_groups: Vec<PathGroup>,
    /// Path endpoints slower than [`AIM_NS`] under the delay model.
    pub endpoints_over_aim: u64,
    /// Those endpoints by the register families they run between, slowest first.
    pub slow_groups: Vec<PathGroup>,
    /// The slowest path under the delay model.
    pub worst: PathInfo,
    /// The path with the most LUT levels.
    pub deepest: DeepPath,
    pub delays: DelayModel,
}

/// What a netlist is for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mapping {
    /// The resource and depth report: block RAMs as the device has them.
    Report,
    /// Gate-level simulation: yosys 0.23's `cells_sim.v` declares RAMB18E1/RAMB36E1 without
    /// any behaviour (their outputs float), so the memories are mapped to distributed RAM and
    /// registers instead (`-nobram`), which it does simulate. Everything else (DSP48E1 cascades
    /// and post-adders, LUTs, carry chains) is mapped as for the report.
    Simulation,
}

/// The yosys script for `top` mapped for `mapping`, and the cache entry of `verilog`'s netlist
/// (keyed by the Verilog, yosys' version and the script).
fn netlist_entry(verilog: &str, top: &str, mapping: Mapping) -> Result<(String, String)> {
    let version = Command::new("yosys")
        .arg("-V")
        .output()
        .context("cannot run yosys: is it installed? (scripts/test.sh installs it)")?
        .stdout;
    // Virtex-6 primitives, flattened, no I/O buffers (the core is a block inside a larger
    // design).
    let script = format!(
        "read_verilog core.v; synth_xilinx -family xc6v -top {top} -flatten -noiopad{}; \
         tee -q -o stat.txt stat -tech xilinx; write_json net.json; write_verilog -noattr syn.v",
        match mapping {
            Mapping::Report => "",
            Mapping::Simulation => " -nobram",
        }
    );
    let name = format!(
        "{NETLIST_PREFIX}{}",
        cache::key(&[verilog.as_bytes(), &version, script.as_bytes()])
    );
    Ok((script, name))
}

/// The start of a netlist's cache entry name.
const NETLIST_PREFIX: &str = "yosys-";

/// Whether `cache` holds any netlist: a cheap look before generating Verilog to find one.
pub fn has_netlists(cache: &Path) -> bool {
    std::fs::read_dir(cache)
        .map(|d| {
            d.flatten()
                .any(|e| e.file_name().to_string_lossy().starts_with(NETLIST_PREFIX))
        })
        .unwrap_or(false)
}

/// The yosys netlist of `verilog` (top module `top`) mapped for `mapping`, from `cache` or
/// synthesized into it: returns the entry's directory, with `net.json` (for `analyze`),
/// `syn.v` (for gate-level simulation), yosys' own cell counts `stat.txt` and `yosys.log`, and
/// whether it was cached.
pub fn netlist(
    verilog: &str,
    top: &str,
    mapping: Mapping,
    cache: &Path,
) -> Result<(PathBuf, bool)> {
    let (script, name) = netlist_entry(verilog, top, mapping)?;
    cache::entry(cache, &name, |dir| {
        std::fs::write(dir.join("core.v"), verilog)?;
        let out = Command::new("yosys")
            .current_dir(dir)
            .args(["-q", "-l", "yosys.log", "-p", &script])
            .output()
            .context("cannot run yosys")?;
        if !out.status.success() {
            bail!(
                "yosys failed (log in {}):\n{}",
                dir.join("yosys.log").display(),
                String::from_utf8_lossy(&out.stderr)
            );
        }
        Ok(())
    })
}

/// The estimated period (ns, the slowest path under [`DELAYS`]) of `verilog`'s report netlist
/// in `cache`. With `synthesize` a missing netlist is synthesized (minutes; the grid core about
/// half an hour); without it, `None` when there is none (or no yosys to key it by). The
/// analysis is kept in the cache beside the netlist, so a second look is immediate.
pub fn period_ns(verilog: &str, top: &str, cache: &Path, synthesize: bool) -> Result<Option<f64>> {
    let name = match netlist_entry(verilog, top, Mapping::Report) {
        Ok((_, name)) => name,
        Err(_) if !synthesize => return Ok(None),
        Err(e) => return Err(e),
    };
    let netlist = match cache::built(cache, &name) {
        Some(dir) => dir,
        None if synthesize => netlist(verilog, top, Mapping::Report, cache)?.0,
        None => return Ok(None),
    };
    let (dir, _) = cache::entry(cache, &format!("period-{name}"), |dir| {
        let report = analyze(&netlist.join("net.json"), top)?;
        std::fs::write(dir.join("period_ns"), report.worst.delay_ns.to_string())?;
        Ok(())
    })?;
    let text = std::fs::read_to_string(dir.join("period_ns"))?;
    let ns = text
        .trim()
        .parse()
        .with_context(|| format!("{}: not a period", dir.join("period_ns").display()))?;
    Ok(Some(ns))
}

/// A parameter's value: yosys writes numbers as binary strings.
fn param(params: &Value, name: &str) -> Option<u64> {
    let v = params.get(name)?;
    match v {
        Value::Number(n) => n.as_u64(),
        Value::String(s) => u64::from_str_radix(s.trim(), 2).ok(),
        _ => None,
    }
}

/// What a cell is to the path walk.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Kind {
    Lut,
    Muxf,
    Carry,
    /// Distributed RAM: its read is combinational from the address.
    LutRam,
    Flop,
    Srl,
    Bram,
    Dsp,
    ClockBuffer,
}

fn kind(ty: &str) -> Option<Kind> {
    Some(match ty {
        "LUT1" | "LUT2" | "LUT3" | "LUT4" | "LUT5" | "LUT6" | "INV" => Kind::Lut,
        "MUXF7" | "MUXF8" => Kind::Muxf,
        "CARRY4" => Kind::Carry,
        "SRL16E" | "SRLC32E" => Kind::Srl,
        "RAMB36E1" | "RAMB18E1" => Kind::Bram,
        "DSP48E1" => Kind::Dsp,
        "BUFG" => Kind::ClockBuffer,
        t if t.starts_with("FD") => Kind::Flop,
        t if t.starts_with("RAM") && (t.ends_with('M') || t.contains('X')) => Kind::LutRam,
        _ => return None,
    })
}

fn is_clock_pin(pin: &str) -> bool {
    matches!(pin, "C" | "CLK" | "CLKARDCLK" | "CLKBWRCLK" | "WCLK")
}

/// How late a signal is and by which path (its LUT levels, CARRY4 blocks and launching cell);
/// and, apart, the most LUT levels of any path to it.
#[derive(Clone, Copy, Debug)]
struct Arrival {
    t: f64,
    luts: u32,
    carry: u32,
    from: usize,
    /// Driven by a CARRY4: leaving the chain costs `carry_out`.
    in_chain: bool,
    depth: u32,
    depth_from: usize,
}

struct Cell {
    name: String,
    kind: Kind,
    // (pin, bits) of inputs and outputs; a bit is a net number or None for a constant.
    inputs: Vec<(String, Vec<Option<u64>>)>,
    outputs: Vec<(String, Vec<Option<u64>>)>,
    ty: String,
    params: Value,
}

fn bits(v: &Value) -> Vec<Option<u64>> {
    v.as_array()
        .map(|a| a.iter().map(Value::as_u64).collect())
        .unwrap_or_default()
}

/// Reads the flattened netlist `net.json` and analyses module `top`.
pub fn analyze(json: &Path, top: &str) -> Result<Report> {
    let text =
        std::fs::read_to_string(json).with_context(|| format!("cannot read {}", json.display()))?;
    let netlist: Value = serde_json::from_str(&text)?;
    let module = netlist
        .get("modules")
        .and_then(|m| m.get(top))
        .with_context(|| format!("no module {top} in {}", json.display()))?;
    let mut cells = Vec::new();
    let mut unknown = std::collections::BTreeSet::new();
    for (name, c) in module["cells"].as_object().context("no cells")? {
        let ty = c["type"].as_str().unwrap_or_default();
        let Some(kind) = kind(ty) else {
            unknown.insert(ty.to_string());
            continue;
        };
        let dirs = &c["port_directions"];
        let (mut inputs, mut outputs) = (Vec::new(), Vec::new());
        for (pin, b) in c["connections"].as_object().context("no connections")? {
            let entry = (pin.clone(), bits(b));
            match dirs[pin].as_str() {
                Some("output") => outputs.push(entry),
                _ => inputs.push(entry),
            }
        }
        cells.push(Cell {
            name: name.trim_start_matches('\\').to_string(),
            kind,
            inputs,
            outputs,
            ty: ty.to_string(),
            params: c["parameters"].clone(),
        });
    }
    if !unknown.is_empty() {
        bail!("cells the analysis does not know: {unknown:?}");
    }
    // Cells are named by yosys (`$auto$ff.cc...`): a path end is named by the net its cell
    // drives, which keeps the RTL's register name.
    let mut names: HashMap<u64, String> = HashMap::new();
    for (name, n) in module["netnames"].as_object().context("no netnames")? {
        if n["hide_name"].as_u64() == Some(1) {
            continue;
        }
        for (k, b) in bits(&n["bits"]).into_iter().enumerate() {
            if let Some(b) = b {
                names
                    .entry(b)
                    .or_insert_with(|| format!("{}[{k}]", name.trim_start_matches('\\')));
            }
        }
    }
    for c in &mut cells {
        let named = c
            .outputs
            .iter()
            .flat_map(|(_, bs)| bs.iter().flatten())
            .find_map(|b| names.get(b));
        if let Some(n) = named {
            c.name = n.clone();
        }
    }
    Ok(walk(&cells, &DELAYS))
}

/// Whether a distributed RAM's input `pin` reaches its output `out` within the clock (its read
/// side): a RAM32M's or RAM64M's port x is read at `ADDRx` (port D's address is also the write
/// address), a dual-port `X1D`'s `SPO` at its write address `A` and `DPO` at `DPRA`, a
/// single-port one's `O` at `A`. The data and the write enable reach no output before the edge.
fn lutram_arc(out: &str, pin: &str) -> bool {
    if let Some(port) = out.strip_prefix("DO") {
        return pin.strip_prefix("ADDR") == Some(port);
    }
    if out == "DPO" {
        return pin.starts_with("DPRA");
    }
    pin.starts_with('A') && !pin.starts_with("ADDR")
}

/// A distributed RAM's read-only address pins: a RAM32M's or RAM64M's ports A to C, `DPRA`.
fn lutram_read_address(pin: &str) -> bool {
    matches!(pin, "ADDRA" | "ADDRB" | "ADDRC") || pin.starts_with("DPRA")
}

/// LUTs a distributed RAM primitive takes: the multi-port RAM32M/RAM64M four (three write ports'
/// data and a read-only port), the dual-port `X1D` two, deeper single-port ones one per 64 bits.
fn lutram_luts(ty: &str) -> u64 {
    match ty {
        "RAM32M" | "RAM64M" | "RAM128X1D" | "RAM256X1S" => 4,
        "RAM32X1D" | "RAM64X1D" | "RAM128X1S" => 2,
        _ => 1,
    }
}

fn count(cells: &[Cell]) -> Resources {
    let mut r = Resources::default();
    for c in cells {
        match c.kind {
            Kind::Lut => r.luts += 1,
            Kind::LutRam => r.lutram += lutram_luts(&c.ty),
            Kind::Srl => r.lutram += 1,
            Kind::Flop => r.registers += 1,
            Kind::Carry => r.carry4 += 1,
            Kind::Muxf => r.muxf += 1,
            Kind::Dsp => r.dsp += 1,
            Kind::Bram if c.ty == "RAMB36E1" => r.ramb36 += 1,
            Kind::Bram => r.ramb18 += 1,
            Kind::ClockBuffer => {}
        }
    }
    r
}

/// A DSP48E1's registers: (input A/B registered, MREG, PREG, multiplier used).
fn dsp_regs(params: &Value) -> (bool, bool, bool, bool) {
    let on = |p: &str| param(params, p).unwrap_or(0) > 0;
    let mult = params["USE_MULT"]
        .as_str()
        .is_none_or(|s| !s.contains("NONE"));
    (on("AREG") && on("BREG"), on("MREG"), on("PREG"), mult)
}

/// Whether a block RAM's data-out pin `pin` (port A or B) has its output register on.
fn bram_port_registered(c: &Cell, pin: &str) -> bool {
    let reg = if pin.starts_with("DOA") || pin.starts_with("DOPA") {
        "DOA_REG"
    } else {
        "DOB_REG"
    };
    param(&c.params, reg).unwrap_or(0) > 0
}

/// Clock-to-output of a sequential cell's output pin, or None for a combinational output.
fn launch(c: &Cell, pin: &str, d: &DelayModel) -> Option<f64> {
    match c.kind {
        Kind::Flop => Some(d.clock_to_q),
        Kind::Srl => Some(d.srl_clock_to_q),
        Kind::Bram => Some(if bram_port_registered(c, pin) {
            d.bram_clock_to_out_reg
        } else {
            d.bram_clock_to_out
        }),
        Kind::Dsp => {
            let (ab, m, p, _) = dsp_regs(&c.params);
            Some(if p {
                d.dsp_clock_to_p
            } else if m {
                d.dsp_m_to_p
            } else if ab {
                d.dsp_a_to_p
            } else {
                // Nothing registered inside: treated as launched like the slowest case.
                d.dsp_a_to_p + d.dsp_setup_p
            })
        }
        _ => None,
    }
}

/// Setup of a sequential cell's input pin (None: not a path endpoint).
fn capture(c: &Cell, pin: &str, d: &DelayModel) -> Option<f64> {
    if is_clock_pin(pin) {
        return None;
    }
    match c.kind {
        Kind::Flop | Kind::Srl => Some(d.setup),
        // A distributed RAM captures its write: the data, the enable and the write address
        // (which is also port D's or SPO's read address); a read-only address is not captured.
        Kind::LutRam if lutram_read_address(pin) => None,
        Kind::LutRam => Some(d.setup),
        Kind::Bram => Some(d.bram_setup),
        Kind::Dsp => {
            if pin.starts_with("PCIN") {
                return Some(d.dsp_setup_pcin);
            }
            let (_, m, _, _) = dsp_regs(&c.params);
            // A pin's own input register (A with AREG, B with BREG, ...) captures it; without
            // one, the multiplier's (A, B, D) or the post-adder's (C) inputs do.
            let own = match pin.chars().next() {
                Some('A') if !pin.starts_with("ACIN") && !pin.starts_with("ALU") => "AREG",
                Some('B') if !pin.starts_with("BCIN") => "BREG",
                Some('C') if !pin.starts_with("CARRY") && !pin.starts_with("CE") => "CREG",
                Some('D') => "DREG",
                _ => "",
            };
            let registered = !own.is_empty() && param(&c.params, own).unwrap_or(0) > 0;
            Some(if registered {
                d.dsp_setup
            } else if m && own != "CREG" {
                d.dsp_setup_m
            } else {
                d.dsp_setup_p
            })
        }
        _ => None,
    }
}

/// A cell's register family: its name up to the bit index or yosys' suffix (`radix.idx$q[8]`
/// and `radix.idx$q[0]` are both `radix.idx`; `core.hist[3]$q` is `core.hist`), and a memory's
/// slices one family (`fifo.ram.mem.0.9` is `fifo.ram.mem`). A block in a list of blocks is
/// named without its place (`grid$0.e_rem$3$q` is `grid.e_rem`).
fn family(name: &str) -> String {
    let mut name = name.to_string();
    while let Some(p) = listed_block(&name) {
        let dot = p + name[p..].find('.').expect("a listed block's path goes on");
        name.replace_range(p..dot, "");
    }
    let mut end = name.find(['$', '[']).unwrap_or(name.len());
    if let Some(m) = name[..end].find(".mem.") {
        end = m + ".mem".len();
    }
    name[..end].trim_start_matches('\\').to_string()
}

/// Where `$k.` (a block's place in its list: digits, then the path goes on) starts in `name`.
fn listed_block(name: &str) -> Option<usize> {
    name.match_indices('$').map(|(p, _)| p).find(|&p| {
        let digits = name[p + 1..]
            .chars()
            .take_while(char::is_ascii_digit)
            .count();
        digits > 0 && name[p + 1 + digits..].starts_with('.')
    })
}

/// Walks every path from a launching output through the combinational cells to a capturing
/// input, in topological order, and reads the pipelining off the cells.
fn walk(cells: &[Cell], d: &DelayModel) -> Report {
    let arrival = arrivals(cells, d);
    let ends = endpoints(cells, &arrival, d);
    let (dsp_without_mreg, dsp_without_preg, bram_without_output_register) = pipelining(cells);
    Report {
        resources: count(cells),
        dsp_without_mreg,
        dsp_without_preg,
        bram_without_output_register,
        endpoints_over_3_luts: ends.over,
        deep_groups: ends.deep_groups.sorted(|g| g.luts),
        endpoints_over_aim: ends.slow,
        slow_groups: ends.slow_groups.sorted(|g| g.ns),
        worst: ends.worst,
        deepest: ends.deepest,
        delays: d.clone(),
    }
}

/// When a path's signal leaves its cell: a carry chain's output takes the chain's exit.
fn leave(a: &Arrival, d: &DelayModel) -> f64 {
    a.t + if a.in_chain { d.carry_out } else { 0.0 }
}

/// The arrival at every net driven by a launching output or a combinational cell: the latest
/// and the deepest path to it, in Kahn's order over the combinational cells.
fn arrivals(cells: &[Cell], d: &DelayModel) -> HashMap<u64, Arrival> {
    // The combinational cells and the read side of distributed RAM.
    let comb = |c: &Cell| matches!(c.kind, Kind::Lut | Kind::Muxf | Kind::Carry | Kind::LutRam);
    let mut driver: HashMap<u64, usize> = HashMap::new();
    for (i, c) in cells.iter().enumerate() {
        for (_, bs) in &c.outputs {
            for b in bs.iter().flatten() {
                driver.insert(*b, i);
            }
        }
    }
    // Kahn's order over combinational cells.
    let reads = |c: &Cell, pin: &str| match c.kind {
        Kind::LutRam => c.outputs.iter().any(|(out, _)| lutram_arc(out, pin)),
        _ => true,
    };
    let mut waiting = vec![0usize; cells.len()];
    let mut users: Vec<Vec<usize>> = vec![Vec::new(); cells.len()];
    for (i, c) in cells.iter().enumerate().filter(|(_, c)| comb(c)) {
        for (pin, bs) in &c.inputs {
            if !reads(c, pin) {
                continue;
            }
            for b in bs.iter().flatten() {
                if let Some(&k) = driver.get(b) {
                    if comb(&cells[k]) {
                        waiting[i] += 1;
                        users[k].push(i);
                    }
                }
            }
        }
    }
    let mut arrival: HashMap<u64, Arrival> = HashMap::new();
    for (i, c) in cells.iter().enumerate() {
        for (pin, bs) in &c.outputs {
            if let Some(t) = launch(c, pin, d) {
                for b in bs.iter().flatten() {
                    arrival.insert(
                        *b,
                        Arrival {
                            t,
                            luts: 0,
                            carry: 0,
                            from: i,
                            in_chain: false,
                            depth: 0,
                            depth_from: i,
                        },
                    );
                }
            }
        }
    }
    let mut ready: Vec<usize> = (0..cells.len())
        .filter(|&i| comb(&cells[i]) && waiting[i] == 0)
        .collect();
    while let Some(i) = ready.pop() {
        let c = &cells[i];
        // The latest input and the deepest one among those `arc` admits, with what this cell
        // adds.
        let lut = u32::from(matches!(c.kind, Kind::Lut | Kind::LutRam));
        let carry = u32::from(c.kind == Kind::Carry);
        let through = |arc: &dyn Fn(&str) -> bool| {
            let mut out: Option<Arrival> = None;
            for (pin, bs) in c.inputs.iter().filter(|(pin, _)| arc(pin)) {
                for b in bs.iter().flatten() {
                    let Some(a) = arrival.get(b) else { continue };
                    let t = match (c.kind, pin.as_str()) {
                        (Kind::Carry, "CI") => a.t + d.carry_block,
                        (Kind::Carry, _) => leave(a, d) + d.carry_in,
                        (Kind::Muxf, _) => leave(a, d) + d.muxf,
                        _ => leave(a, d) + d.lut_level,
                    };
                    let next = Arrival {
                        t,
                        luts: a.luts + lut,
                        carry: a.carry + carry,
                        from: a.from,
                        in_chain: c.kind == Kind::Carry,
                        depth: a.depth + lut,
                        depth_from: a.depth_from,
                    };
                    out = Some(match out {
                        None => next,
                        Some(o) => {
                            let mut m = if next.t > o.t { next } else { o };
                            (m.depth, m.depth_from) = if next.depth > o.depth {
                                (next.depth, next.depth_from)
                            } else {
                                (o.depth, o.depth_from)
                            };
                            m
                        }
                    });
                }
            }
            out
        };
        // A distributed RAM's outputs each follow their own read address; every other cell's
        // outputs follow all its inputs.
        let outs: Vec<(&Vec<Option<u64>>, Option<Arrival>)> = if c.kind == Kind::LutRam {
            c.outputs
                .iter()
                .map(|(out, bs)| (bs, through(&|pin: &str| lutram_arc(out, pin))))
                .collect()
        } else {
            let all = through(&|_: &str| true);
            c.outputs.iter().map(|(_, bs)| (bs, all)).collect()
        };
        for (bs, a) in outs {
            if let Some(a) = a {
                for b in bs.iter().flatten() {
                    arrival.insert(*b, a);
                }
            }
        }
        for &u in &users[i] {
            waiting[u] -= 1;
            if waiting[u] == 0 {
                ready.push(u);
            }
        }
    }
    arrival
}

/// What the capturing inputs see.
#[derive(Default)]
struct Endpoints {
    /// The slowest path under the delay model.
    worst: PathInfo,
    /// The path with the most LUT levels.
    deepest: DeepPath,
    /// Endpoint bits behind more than 3 LUT levels.
    over: u64,
    /// Endpoint bits slower than `AIM_NS`.
    slow: u64,
    /// The deep endpoints by register families.
    deep_groups: Grouping,
    /// The slow endpoints by register families.
    slow_groups: Grouping,
}

/// Every capturing input's path: the slowest, the deepest, and those over the aims, grouped.
fn endpoints(cells: &[Cell], arrival: &HashMap<u64, Arrival>, d: &DelayModel) -> Endpoints {
    let mut e = Endpoints::default();
    for c in cells {
        for (pin, bs) in &c.inputs {
            let Some(setup) = capture(c, pin, d) else {
                continue;
            };
            for b in bs.iter().flatten() {
                let Some(a) = arrival.get(b) else { continue };
                let total = leave(a, d) + setup;
                if total > e.worst.delay_ns {
                    e.worst = PathInfo {
                        delay_ns: total,
                        luts: a.luts,
                        carry4: a.carry,
                        from: cells[a.from].name.clone(),
                        to: format!("{}.{pin}", c.name),
                    };
                }
                if a.depth > e.deepest.luts {
                    e.deepest = DeepPath {
                        luts: a.depth,
                        from: cells[a.depth_from].name.clone(),
                        to: format!("{}.{pin}", c.name),
                    };
                }
                if a.depth > 3 {
                    e.over += 1;
                    e.deep_groups
                        .add(&cells[a.depth_from].name, &c.name, a.depth, total);
                }
                if total > AIM_NS {
                    e.slow += 1;
                    e.slow_groups
                        .add(&cells[a.from].name, &c.name, a.luts, total);
                }
            }
        }
    }
    e
}

/// DSP48E1s multiplying without MREG, DSP48E1s without PREG, and block RAMs with a used read
/// port without its output register.
fn pipelining(cells: &[Cell]) -> (u64, u64, u64) {
    let dsp = cells.iter().filter(|c| c.kind == Kind::Dsp);
    let dsp_without_mreg = dsp
        .clone()
        .filter(|c| {
            let (_, m, _, mult) = dsp_regs(&c.params);
            mult && !m
        })
        .count() as u64;
    let dsp_without_preg = dsp.filter(|c| !dsp_regs(&c.params).2).count() as u64;
    let consumed: std::collections::HashSet<u64> = cells
        .iter()
        .flat_map(|c| {
            c.inputs
                .iter()
                .flat_map(|(_, bs)| bs.iter().flatten().copied())
        })
        .collect();
    let bram_without_output_register = cells
        .iter()
        .filter(|c| c.kind == Kind::Bram)
        .filter(|c| {
            // A port counts when its data out is used.
            c.outputs.iter().any(|(pin, bs)| {
                bs.iter().flatten().any(|b| consumed.contains(b)) && !bram_port_registered(c, pin)
            })
        })
        .count() as u64;
    (
        dsp_without_mreg,
        dsp_without_preg,
        bram_without_output_register,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dsp(params: serde_json::Value) -> Cell {
        Cell {
            name: "dsp".into(),
            kind: Kind::Dsp,
            inputs: Vec::new(),
            outputs: Vec::new(),
            ty: "DSP48E1".into(),
            params,
        }
    }

    #[test]
    fn families_drop_bit_indices_and_memory_slices() {
        assert_eq!(family("radix.idx$q[8]"), "radix.idx");
        assert_eq!(family("\\core.hist[3]$q"), "core.hist");
        assert_eq!(family("fifo.ram.mem.0.9"), "fifo.ram.mem");
        assert_eq!(family("radix.ram$1.mem.0.10"), "radix.ram.mem");
        assert_eq!(family("grid$0.e_rem$3$q[0]"), "grid.e_rem");
        assert_eq!(family("\\grid$0.cells.res1$4$q[1]"), "grid.cells.res1");
    }

    /// A RAM64M as yosys maps a one-write, one-read memory: ports A to C read at the read
    /// address, port D's address is the write address. A path runs from a read address to its
    /// port's output only, and ends at the write's pins, not at a read address.
    #[test]
    fn distributed_ram_reads_follow_their_own_address() {
        assert!(lutram_arc("DOA", "ADDRA") && lutram_arc("DOC", "ADDRC"));
        assert!(!lutram_arc("DOA", "ADDRD") && !lutram_arc("DOA", "DIA"));
        assert!(!lutram_arc("DOB", "WE") && lutram_arc("DOD", "ADDRD"));
        assert!(lutram_arc("SPO", "A3") && !lutram_arc("SPO", "DPRA3"));
        assert!(lutram_arc("DPO", "DPRA") && !lutram_arc("DPO", "A"));
        assert!(lutram_arc("O", "A") && !lutram_arc("O", "D"));
        let d = &DELAYS;
        let ram = Cell {
            name: "ram".into(),
            kind: Kind::LutRam,
            inputs: Vec::new(),
            outputs: Vec::new(),
            ty: "RAM64M".into(),
            params: serde_json::json!({}),
        };
        for pin in ["ADDRA", "ADDRB", "ADDRC", "DPRA"] {
            assert_eq!(capture(&ram, pin, d), None, "{pin}");
        }
        for pin in ["ADDRD", "DIA", "WE", "A", "D"] {
            assert_eq!(capture(&ram, pin, d), Some(d.setup), "{pin}");
        }
        assert_eq!(capture(&ram, "WCLK", d), None);
    }

    /// Each DSP48E1 input pin is captured by its own input register when that one is on: a
    /// multiplier fed on A through AREG, with a constant on B (no BREG), has A registered.
    #[test]
    fn dsp_pins_are_captured_by_their_own_registers() {
        let d = &DELAYS;
        let c = dsp(serde_json::json!({"AREG": "10", "BREG": "0", "MREG": "1", "PREG": "1"}));
        assert_eq!(capture(&c, "A[3]", d), Some(d.dsp_setup));
        assert_eq!(capture(&c, "B[0]", d), Some(d.dsp_setup_m));
        assert_eq!(capture(&c, "C[0]", d), Some(d.dsp_setup_p));
        assert_eq!(capture(&c, "PCIN[5]", d), Some(d.dsp_setup_pcin));
        assert_eq!(capture(&c, "CLK", d), None);
        let c = dsp(serde_json::json!({"AREG": "0", "CREG": "1", "MREG": "0", "PREG": "1"}));
        assert_eq!(capture(&c, "A[0]", d), Some(d.dsp_setup_p));
        assert_eq!(capture(&c, "C[0]", d), Some(d.dsp_setup));
    }
}
