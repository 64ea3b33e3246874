//! `gen-rtl`: deterministic output, `rtl-out/` equal to a fresh run for the default
//! configuration, a manifest that matches the Verilog, and clear errors for bad configurations.

use obb_model::fixed::HwConfig;
use obb_rtl::flow::generate::{files, ports};
use std::path::Path;

/// `gen-rtl`'s files for the default configuration, generated once for the tests that read
/// them (rust-hdl takes seconds over the whole core).
fn default_files() -> &'static [(String, String)] {
    static FILES: std::sync::OnceLock<Vec<(String, String)>> = std::sync::OnceLock::new();
    FILES.get_or_init(|| files(&HwConfig::default()).unwrap())
}

#[test]
fn rtl_out_is_what_gen_rtl_writes_for_the_default_configuration() {
    let fresh = default_files();
    assert_eq!(fresh, files(&HwConfig::default()).unwrap(), "deterministic");
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../rtl-out");
    for (name, text) in fresh {
        let committed = std::fs::read_to_string(dir.join(name))
            .unwrap_or_else(|e| panic!("rtl-out/{name}: {e}; run `cargo run --bin gen-rtl`"));
        assert!(
            committed == *text,
            "rtl-out/{name} is stale: run `cargo run --bin gen-rtl` and commit the result"
        );
    }
    let mut names = Vec::new();
    for entry in std::fs::read_dir(&dir).unwrap() {
        let entry = entry.unwrap();
        let name = entry.file_name().into_string().unwrap();
        if entry.file_type().unwrap().is_dir() {
            for inner in std::fs::read_dir(entry.path()).unwrap() {
                names.push(format!(
                    "{name}/{}",
                    inner.unwrap().file_name().into_string().unwrap()
                ));
            }
        } else {
            names.push(name);
        }
    }
    names.sort();
    let mut expected: Vec<_> = fresh.iter().map(|(n, _)| n.clone()).collect();
    expected.sort();
    assert_eq!(names, expected, "rtl-out holds exactly the generated files");
}

/// The text of generated file `name`.
fn file<'a>(fresh: &'a [(String, String)], name: &str) -> &'a str {
    &fresh.iter().find(|(n, _)| n == name).unwrap().1
}

#[test]
fn the_manifest_lists_the_verilog_ports() {
    let fresh = default_files();
    let json: serde_json::Value = serde_json::from_str(file(fresh, "manifest.json")).unwrap();
    let module = |name: &str| {
        json["modules"]
            .as_array()
            .unwrap()
            .iter()
            .find(|m| m["module"] == name)
            .unwrap_or_else(|| panic!("{name} in the manifest"))
            .clone()
    };
    // Every module's ports as its Verilog declares them.
    for (name, path, count) in [
        (
            "obb_core",
            "obb_core.v",
            // clock; frame_start, frame_update; the box's handshake, center, half-lengths,
            // axes and group; the pair stream; done, busy, capacity_exceeded, pair_overflow;
            // the counters.
            1 + 2 + 3 + 3 + 3 + 9 + 1 + 4 + 4 + 4,
        ),
        (
            "projection",
            "blocks/projection.v",
            1 + 1 + 3 + 3 + 9 + 1 + 3 + 3 + 1,
        ),
        ("sat", "blocks/sat.v", 1 + 1 + 2 * (3 + 3 + 9 + 1) + 2),
        ("radix_sort", "blocks/radix_sort.v", 10),
    ] {
        let p = ports(file(fresh, path), name);
        assert_eq!(p.len(), count, "{name}: {p:?}");
        assert_eq!(
            module(name)["ports"].as_array().unwrap().len(),
            count,
            "{name}"
        );
        assert_eq!(module(name)["file"], path);
    }
    let core = ports(file(fresh, "obb_core.v"), "obb_core");
    assert!(core
        .iter()
        .any(|p| p.name == "obb_axes$8" && p.signed && p.bits == 18));
    assert!(core
        .iter()
        .any(|p| p.name == "pair_ready" && p.direction == "input"));
    let sort = ports(file(fresh, "blocks/radix_sort.v"), "radix_sort");
    assert!(
        sort.iter().any(|p| p.name == "rd_addr" && p.bits == 15),
        "capacity 32768"
    );
    assert_eq!(
        module("projection")["latency"],
        obb_model::fixed::cycles::LAT_PROJECT
    );
    assert_eq!(module("sat")["latency"], obb_model::fixed::cycles::LAT_SAT);
    assert_eq!(json["core"]["table_depth"], 32768);
    assert_eq!(
        json["core"]["lat_broad"],
        obb_model::fixed::cycles::LAT_BROAD
    );
    assert_eq!(json["configuration"]["key_bits"], 20);
    assert_eq!(json["configuration"]["broad_phase"], "grid");
}

/// The committed top lints clean in Verilator (LATCH and every other warning but WIDTH,
/// DECLFILENAME and UNUSED fatal); the core tests simulate it at a smaller capacity.
#[test]
fn the_default_core_lints_clean() {
    let fresh = default_files();
    let dir = obb_rtl::flow::verilator::scratch_dir("lint-obb-core").unwrap();
    obb_rtl::flow::verilator::lint(&dir, file(fresh, "obb_core.v"), "obb_core").unwrap();
}

#[test]
fn unsupported_configurations_are_rejected() {
    let bad = HwConfig {
        rot_bits: 20,
        ..HwConfig::default()
    };
    let e = files(&bad).unwrap_err().to_string();
    assert!(e.contains("rot_bits"), "{e}");
    // Beyond what the blocks hold: said so, naming the key.
    for (cfg, key) in [
        (
            HwConfig {
                broad_phase: obb_model::fixed::BroadPhase::Grid,
                center_bits: 23,
                key_bits: 23,
                ..HwConfig::default()
            },
            "key_bits",
        ),
        (
            HwConfig {
                broad_phase: obb_model::fixed::BroadPhase::ImprovedSap,
                capacity: 1 << 20,
                ..HwConfig::default()
            },
            "capacity",
        ),
    ] {
        let e = files(&cfg).unwrap_err().to_string();
        assert!(
            e.contains(key) && (e.contains("with the grid") || e.contains("two end points")),
            "{e}"
        );
    }
}

/// The smallest capacities generate too: the tables and the sort never shrink below what the
/// sort's bin counters need (this panicked in rust-hdl for capacities under 256); and so do the
/// widest keys.
#[test]
fn the_smallest_capacities_generate() {
    for (capacity, mode) in [
        (1, obb_model::fixed::BroadPhase::Sweep),
        (16, obb_model::fixed::BroadPhase::Brute),
        (2, obb_model::fixed::BroadPhase::ImprovedSap),
        (1, obb_model::fixed::BroadPhase::Grid),
    ] {
        let cfg = HwConfig {
            capacity,
            broad_phase: mode,
            ..HwConfig::default()
        };
        let out = files(&cfg).unwrap();
        assert!(file(&out, "obb_core.v").contains("module obb_core("));
    }
    // A core of another broad phase ignores the grid's keys: the widest keys with the smallest
    // cells generate the sweep (the grid refuses them: `unsupported_configurations_are_rejected`).
    let wide = HwConfig {
        broad_phase: obb_model::fixed::BroadPhase::Sweep,
        center_bits: 23,
        key_bits: 23,
        grid_cell_mm: 1.0 / 1024.0,
        ..HwConfig::default()
    };
    assert!(file(&files(&wide).unwrap(), "obb_core.v").contains("module obb_core("));
}

/// Each committed synthesis report of a fixed configuration is `obbcd synth`'s on the core that
/// configuration generates now: when the RTL changes, the report must be made again (the
/// synthesis takes minutes to an hour, so the test compares the RTL's digest the report names
/// instead of synthesizing). The default core's report is so also the committed `rtl-out/`'s
/// (`rtl_out_is_what_gen_rtl_writes_for_the_default_configuration`).
#[test]
fn the_synthesis_reports_are_for_the_current_rtl() {
    use obb_model::fixed::BroadPhase;
    use obb_model::GroupMask;
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let sweep = HwConfig {
        broad_phase: BroadPhase::Sweep,
        ..HwConfig::default()
    };
    let lanes8 = HwConfig {
        groups: GroupMask::All,
        lanes: 8,
        grid_hash_bits: 7,
        ..HwConfig::default()
    };
    let reports = [
        // (The default core's files are generated once for every test that reads them.)
        ("synth.md", None, "the default configuration"),
        (
            "synth-sweep.md",
            Some(sweep),
            "`--config` a file of `broad_phase = \"sweep\"`",
        ),
        (
            "synth-lanes8.md",
            Some(lanes8),
            "`--config` a file of `groups = \"all\"`, `lanes = 8`, `grid_hash_bits = 7`",
        ),
    ];
    for (name, config, how) in reports {
        let fresh;
        let generated = match config {
            None => default_files(),
            Some(config) => {
                fresh = files(&config).unwrap();
                &fresh
            }
        };
        let rtl = file(generated, "obb_core.v");
        let digest = obb_rtl::flow::cache::key(&[rtl.as_bytes()]);
        let report = std::fs::read_to_string(root.join("reports").join(name))
            .unwrap_or_else(|e| panic!("reports/{name}: {e}"));
        assert!(
            report.contains(&format!("SHA-256 prefix `{digest}`")),
            "reports/{name} is stale: run `cargo run --release -p obbcd -- synth -o \
             reports/{name}` with {how}"
        );
    }
}

/// `gen-rtl --scene` plans for the scenes and writes that plan's core; a configuration and
/// scenes together are refused with a message.
#[test]
fn gen_rtl_plans_for_scenes() {
    use obb_model::fixed::plan::{plan, Aims};
    let dir = obb_rtl::flow::verilator::scratch_dir("gen").unwrap();
    let scene = obb_model::generate::surgical(400, 1).unwrap();
    let path = dir.join("scene.json");
    scene.save(&path).unwrap();
    let out = dir.join("rtl");
    let run = |extra: &[&str]| {
        let mut args = vec![
            "--scene".to_string(),
            path.display().to_string(),
            "--out".to_string(),
            out.display().to_string(),
            "--ucf".to_string(),
            dir.join("c.ucf").display().to_string(),
            "--tcl".to_string(),
            dir.join("b.tcl").display().to_string(),
        ];
        args.extend(extra.iter().map(|s| s.to_string()));
        std::process::Command::new(env!("CARGO_BIN_EXE_gen-rtl"))
            .args(&args)
            .output()
            .unwrap()
    };
    let done = run(&["--groups", "cross"]);
    let said = String::from_utf8_lossy(&done.stdout);
    assert!(
        done.status.success(),
        "{said} {}",
        String::from_utf8_lossy(&done.stderr)
    );
    assert!(said.starts_with("planned: "), "{said}");
    let aims = Aims {
        groups: obb_model::GroupMask::Cross,
        ..Aims::default()
    };
    let planned = plan(std::slice::from_ref(&scene), &aims).unwrap().cfg;
    assert_ne!(planned, HwConfig::default(), "the plan is the scene's own");
    for (name, text) in files(&planned).unwrap() {
        let written = std::fs::read_to_string(out.join(&name)).unwrap();
        assert!(written == text, "{name} is not the planned core's");
    }
    let both = run(&["--config", path.to_str().unwrap()]);
    let err = String::from_utf8_lossy(&both.stderr);
    assert!(
        !both.status.success() && err.contains("--config and --scene"),
        "{err}"
    );
    // A closed output pipe (`gen-rtl | head -1`) ends it by SIGPIPE, as it ends `cat`, at the
    // plan's line: no panic.
    let (reader, writer) = std::io::pipe().unwrap();
    drop(reader);
    let closed = std::process::Command::new(env!("CARGO_BIN_EXE_gen-rtl"))
        .args([
            "--scene",
            path.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ])
        .stdout(writer)
        .output()
        .unwrap();
    use std::os::unix::process::ExitStatusExt;
    let err = String::from_utf8_lossy(&closed.stderr);
    assert_eq!(closed.status.signal(), Some(libc::SIGPIPE), "{err}");
    assert!(!err.contains("panicked"), "{err}");
}
