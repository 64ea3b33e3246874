//! What `gen-rtl` writes: the Verilog of each block for a configuration, and a manifest (the
//! configuration, each module's ports and latency). Deterministic: the same configuration gives
//! the same bytes.

use crate::core::{self, address_bits, sort_key_bits, ObbCore};
use crate::flow::emit;
use crate::grid::GridPhase;
use crate::projection::{self, Projection};
use crate::radix::KeySort;
use crate::sat::{self, Sat};
use anyhow::{bail, Context, Result};
use obb_model::fixed::grid::MAX_KEY_BITS;
use obb_model::fixed::{cycles, grid, BroadPhase, HwConfig};
use obb_model::radix::RadixSorter;
use serde::Serialize;
use std::path::Path;

/// One port of a top-level module, as declared in its Verilog.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PortInfo {
    pub name: String,
    pub direction: String,
    pub bits: usize,
    pub signed: bool,
}

/// One emitted module.
#[derive(Clone, Debug, Serialize)]
pub struct ModuleInfo {
    pub module: String,
    pub file: String,
    /// Clocks from an input to its result.
    pub latency: u64,
    /// Inputs accepted per clock.
    pub throughput: u64,
    /// The module's ports, as in its Verilog.
    pub ports: Vec<PortInfo>,
}

#[derive(Clone, Debug, Serialize)]
pub struct Manifest {
    pub generator: String,
    pub configuration: HwConfig,
    pub core: CoreInfo,
    pub modules: Vec<ModuleInfo>,
}

/// The ports of module `top` in emitted Verilog, in declaration order.
pub fn ports(verilog: &str, top: &str) -> Vec<PortInfo> {
    let start = verilog
        .find(&format!("module {top}("))
        .expect("the top module is in the text");
    let body = &verilog[start..];
    let body = &body[..body.find("endmodule").unwrap_or(body.len())];
    body.lines()
        .map(str::trim)
        .filter_map(|l| {
            let (direction, rest) = l.split_once(' ')?;
            if direction != "input" && direction != "output" {
                return None;
            }
            let rest = rest.trim_end_matches(';');
            let signed = rest.contains(" signed ");
            let bits = match (rest.find('['), rest.find(':')) {
                (Some(a), Some(b)) => rest[a + 1..b].trim().parse::<usize>().ok()? + 1,
                _ => 1,
            };
            let name = rest.split_whitespace().last()?.to_string();
            Some(PortInfo {
                name,
                direction: direction.to_string(),
                bits,
                signed,
            })
        })
        .collect()
}

/// The stage latencies and sizes of the core, for the manifest (`obb_model::fixed::cycles`).
#[derive(Clone, Debug, Serialize)]
pub struct CoreInfo {
    /// Clocks of the projection pipeline.
    pub lat_project: u64,
    /// Clocks of the key table's write after the projection.
    pub lat_key_write: u64,
    /// Clocks from a broad-phase visit to the SAT's inputs.
    pub lat_broad: u64,
    /// Clocks of the SAT.
    pub lat_sat: u64,
    /// Radix sort: the digit's bits; each pass takes `2^digit + n + 6` clocks, plus 3 per sort
    /// (`cycles::sort_cycles`).
    pub sort_digit_bits: u32,
    /// Radix sort: passes per sort.
    pub sort_passes: u32,
    /// Entries of every per-box table (a power of two at least `capacity`).
    pub table_depth: u64,
    /// Entries of the pair FIFO.
    pub fifo_depth: u64,
    /// The pair FIFO's fill at which the broad phase stalls.
    pub fifo_stall_fill: u64,
    /// Width of the status counters (`cycles`, `visits`, `sat_tests`, `pairs`).
    pub counter_bits: usize,
    /// The grid's clocks (`obb_model::fixed::grid_clocks`), with `broad_phase = "grid"`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub grid: Option<GridInfo>,
}

/// The grid's latencies and queues, for the manifest (`obb_model::fixed::cycles`).
#[derive(Clone, Debug, Serialize)]
pub struct GridInfo {
    /// Clocks from a box's keys to its first possible visit.
    pub lat_probe: u64,
    /// Boxes accepted and not retired, at most: the load waits beyond.
    pub credits: usize,
    /// Clocks from a visit to its SAT test's first possible issue.
    pub lat_check: u64,
    /// Clocks from the issue to the SAT's inputs.
    pub issue_to_sat: u64,
    /// The test queue's fill at which the walker pauses.
    pub test_stall_fill: usize,
    /// Buckets a bank: the clocks of the list heads' clear at the end of a frame.
    pub buckets: u64,
    /// Cells per axis a large box's window may span on the slow path: a wider one raises
    /// `capacity_exceeded` (the frame is incomplete).
    pub max_window: u64,
}

// Improved-sap's end point keys take one bit more than `key_bits`, which `validate` bounds by
// `center_bits` and so by the DSP port: the core's sort keys always hold them.
const _: () = assert!(obb_model::fixed::config::DSP_A_BITS as usize - 2 < crate::radix::KEY);

/// Checks that the hardware supports `cfg` (valid; improved-sap's and the grid's bounds).
pub fn check_supported(cfg: &HwConfig) -> Result<()> {
    cfg.validate()?;
    match cfg.broad_phase {
        BroadPhase::Brute | BroadPhase::Sweep => {}
        BroadPhase::ImprovedSap => {
            if cfg.capacity > 1 << 19 {
                bail!(
                    "configuration key `capacity`: {} with improved-sap, which sorts two end \
                     points per box with 20-bit values: at most 524288",
                    cfg.capacity
                );
            }
        }
        BroadPhase::Grid => check_grid(cfg)?,
    }
    Ok(())
}

/// Calls `$f::<A, A + 1>($args)` for the address width `$a` (8 to 20): rust-hdl's widths are
/// type parameters, so each supported width is its own instance.
macro_rules! by_address_bits {
    ($a:expr, $f:ident($($args:expr),*)) => {
        match $a {
            8 => $f::<8, 9>($($args),*),
            9 => $f::<9, 10>($($args),*),
            10 => $f::<10, 11>($($args),*),
            11 => $f::<11, 12>($($args),*),
            12 => $f::<12, 13>($($args),*),
            13 => $f::<13, 14>($($args),*),
            14 => $f::<14, 15>($($args),*),
            15 => $f::<15, 16>($($args),*),
            16 => $f::<16, 17>($($args),*),
            17 => $f::<17, 18>($($args),*),
            18 => $f::<18, 19>($($args),*),
            19 => $f::<19, 20>($($args),*),
            20 => $f::<20, 21>($($args),*),
            a => bail!("{a} address bits: the tables support 2^8 to 2^20 entries"),
        }
    };
}

fn core_verilog<const A: usize, const C: usize>(cfg: &HwConfig) -> Result<String> {
    emit::verilog(&mut ObbCore::<A, C>::new(cfg), "obb_core")
}

fn radix_verilog<const A: usize, const C: usize>(cfg: &HwConfig) -> Result<String> {
    emit::verilog(
        &mut KeySort::<A, C>::new(sort_key_bits(cfg), cfg.radix_digit_bits),
        "radix_sort",
    )
}

/// The Verilog of the whole core for `cfg` (top `obb_core`), as `obb_core.v` holds it.
pub fn core(cfg: &HwConfig) -> Result<String> {
    check_supported(cfg)?;
    Ok(header(cfg) + &by_address_bits!(address_bits(cfg), core_verilog(cfg))?)
}

/// The files for configuration `cfg`: (path below the output directory, contents). The top,
/// One block of the core as its own top module: `projection`, `sat`, `radix_sort`, or the
/// grid's `grid_phase`.
pub fn block(cfg: &HwConfig, module: &str) -> Result<String> {
    let body = if module == "grid_phase" {
        check_grid(cfg)?;
        by_address_bits!(address_bits(cfg), grid_verilog(cfg))?
    } else {
        check_supported(cfg)?;
        match module {
            "projection" => emit::verilog(&mut Projection::new(cfg), "projection")?,
            "sat" => emit::verilog(&mut Sat::new(cfg), "sat")?,
            "radix_sort" => by_address_bits!(address_bits(cfg), radix_verilog(cfg))?,
            _ => bail!("no block `{module}`: projection, sat, radix_sort or grid_phase"),
        }
    };
    Ok(header(cfg) + &body)
}

// The model's bound on the grid's keys is the block's.
const _: () = assert!(MAX_KEY_BITS as usize == crate::grid_cells::COORD - 1);

/// Checks that the grid block supports `cfg`: valid, and cell coordinates (keys shifted by the
/// cell bits, plus 2) within the keys' width.
pub fn check_grid(cfg: &HwConfig) -> Result<()> {
    cfg.validate()?;
    if cfg.key_bits > MAX_KEY_BITS {
        bail!(
            "configuration key `key_bits`: {} with the grid, whose cell coordinates take up to \
             `key_bits` + 1 bits of {}: at most {MAX_KEY_BITS}",
            cfg.key_bits,
            crate::grid_cells::COORD,
        );
    }
    Ok(())
}

fn grid_verilog<const A: usize, const C: usize>(cfg: &HwConfig) -> Result<String> {
    emit::verilog(&mut GridPhase::<A, C>::new(cfg), "grid_phase")
}

/// `obb_core.v`, holds the whole core; `blocks/` holds each block as its own top module (for
/// per-block synthesis estimates); the manifest comes last.
pub fn files(cfg: &HwConfig) -> Result<Vec<(String, String)>> {
    check_supported(cfg)?;
    let a = address_bits(cfg);
    let mut out = Vec::new();
    let mut modules = Vec::new();
    let mut add = |module: &str, file: String, text: String, latency: u64| {
        modules.push(ModuleInfo {
            module: module.into(),
            file: file.clone(),
            latency,
            throughput: 1,
            ports: ports(&text, module),
        });
        out.push((file, text));
    };
    // The core works on frames: its clocks per frame are `cycles::frame_cycles`.
    add("obb_core", "obb_core.v".into(), core(cfg)?, 0);
    // The radix sort is not a pipeline: its clocks are `cycles::sort_cycles` after `go`.
    // The grid is not a pipeline either: its clocks are `grid_clocks`'.
    let grid = (cfg.broad_phase == BroadPhase::Grid).then_some(("grid_phase", 0));
    for (module, latency) in [
        ("projection", projection::LATENCY),
        ("sat", sat::LATENCY),
        ("radix_sort", 0),
    ]
    .into_iter()
    .chain(grid)
    {
        add(
            module,
            format!("blocks/{module}.v"),
            block(cfg, module)?,
            latency,
        );
    }
    let sorter = RadixSorter::<u32>::new(cfg.radix_digit_bits);
    let core = CoreInfo {
        lat_project: cycles::LAT_PROJECT,
        lat_key_write: cycles::LAT_KEY_WRITE,
        lat_broad: cycles::LAT_BROAD,
        lat_sat: cycles::LAT_SAT,
        sort_digit_bits: sorter.digit_bits(sort_key_bits(cfg)),
        sort_passes: sorter.passes(sort_key_bits(cfg)),
        table_depth: 1 << a,
        fifo_depth: core::FIFO_DEPTH,
        fifo_stall_fill: core::FIFO_STALL,
        counter_bits: core::COUNT,
        grid: (cfg.broad_phase == BroadPhase::Grid).then(|| GridInfo {
            lat_probe: cycles::LAT_PROBE,
            credits: cycles::GRID_CREDITS,
            lat_check: cycles::LAT_GRID_CHECK,
            issue_to_sat: cycles::GRID_ISSUE_TO_SAT,
            test_stall_fill: cycles::GRID_TEST_STALL,
            buckets: 1 << cfg.grid_hash_bits,
            max_window: grid::MAX_WINDOW,
        }),
    };
    let manifest = Manifest {
        generator: format!(
            "obb-rtl {} (cargo run --bin gen-rtl)",
            env!("CARGO_PKG_VERSION")
        ),
        configuration: cfg.clone(),
        core,
        modules,
    };
    out.push((
        "manifest.json".to_string(),
        serde_json::to_string_pretty(&manifest)? + "\n",
    ));
    Ok(out)
}

fn header(cfg: &HwConfig) -> String {
    format!(
        "// Generated by `cargo run --bin gen-rtl` from obb-rtl {}: do not edit.\n\
         // Configuration: center_bits={} half_bits={} rot_bits={} key_bits={} lsb_mm={}\n",
        env!("CARGO_PKG_VERSION"),
        cfg.center_bits,
        cfg.half_bits,
        cfg.rot_bits,
        cfg.key_bits,
        cfg.lsb_mm
    )
}

/// The ISE hand-off for `cfg`: the UCF, and the xtclsh script that reaches `obb_core.v` and
/// the UCF by the given paths relative to the script's directory.
pub fn handoff(cfg: &HwConfig, verilog: &str, constraints: &str) -> Result<(String, String)> {
    check_supported(cfg)?;
    let head = header(cfg);
    Ok((
        crate::flow::handoff::ucf(cfg, &head),
        crate::flow::handoff::build_tcl(cfg, &head, verilog, constraints),
    ))
}

/// The file `to` as a path relative to the directory `from` (both directories exist), with
/// `/` separators.
fn relative(from: &Path, to: &Path) -> Result<String> {
    let canon = |p: &Path| {
        p.canonicalize()
            .with_context(|| format!("cannot resolve {}", p.display()))
    };
    let name = to
        .file_name()
        .with_context(|| format!("{} names no file", to.display()))?;
    let (from, to_dir) = (canon(from)?, canon(&dir_of(to))?);
    let common = from
        .components()
        .zip(to_dir.components())
        .take_while(|(a, b)| a == b)
        .count();
    let up = std::iter::repeat_n("..".to_string(), from.components().count() - common);
    let down = to_dir
        .components()
        .skip(common)
        .map(|c| c.as_os_str().to_string_lossy().into_owned());
    let mut parts: Vec<String> = up.chain(down).collect();
    parts.push(name.to_string_lossy().into_owned());
    Ok(parts.join("/"))
}

/// The directory of file `p` (`.` for a bare name).
fn dir_of(p: &Path) -> std::path::PathBuf {
    match p.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => Path::new(".").to_path_buf(),
    }
}

/// Writes the UCF to `ucf` and the xtclsh script to `tcl` (directories created if needed);
/// the script finds `obb_core.v` in `verilog_dir` and the UCF by relative paths.
pub fn write_handoff(cfg: &HwConfig, verilog_dir: &Path, ucf: &Path, tcl: &Path) -> Result<()> {
    for dir in [dir_of(ucf), dir_of(tcl)] {
        std::fs::create_dir_all(&dir)
            .with_context(|| format!("cannot create {}", dir.display()))?;
    }
    let verilog = relative(&dir_of(tcl), &verilog_dir.join("obb_core.v"))?;
    let constraints = relative(&dir_of(tcl), ucf)?;
    let (ucf_text, tcl_text) = handoff(cfg, &verilog, &constraints)?;
    std::fs::write(ucf, ucf_text).with_context(|| format!("cannot write {}", ucf.display()))?;
    std::fs::write(tcl, tcl_text).with_context(|| format!("cannot write {}", tcl.display()))?;
    Ok(())
}

/// Writes the files for `cfg` into `dir` (created if needed).
pub fn write(cfg: &HwConfig, dir: &Path) -> Result<Vec<String>> {
    let files = files(cfg)?;
    let mut names = Vec::new();
    for (name, text) in files {
        let path = dir.join(&name);
        let parent = path.parent().unwrap_or(dir);
        std::fs::create_dir_all(parent)
            .with_context(|| format!("cannot create {}", parent.display()))?;
        std::fs::write(&path, text).with_context(|| format!("cannot write {}", path.display()))?;
        names.push(name);
    }
    Ok(names)
}
