//! The ISE hand-off, as far as it can be checked without ISE: the committed UCF and xtclsh
//! script are what `gen-rtl` writes for the default configuration; every NET in the UCF is a
//! port of `obb_core`; the script parses and runs under `tclsh` with stub `project`, `xfile`
//! and `process` procedures, sets the XC6VHX565T project up and adds files that exist.

use obb_model::fixed::HwConfig;
use obb_rtl::flow::generate::{files, handoff, ports};
use std::path::Path;
use std::process::Command;

fn root() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
}

fn committed(path: &str) -> String {
    std::fs::read_to_string(root().join(path))
        .unwrap_or_else(|e| panic!("{path}: {e}; run `cargo run --bin gen-rtl`"))
}

#[test]
fn the_committed_handoff_is_what_gen_rtl_writes() {
    let (ucf, tcl) = handoff(
        &HwConfig::default(),
        "../../rtl-out/obb_core.v",
        "../../constraints/obb_core.ucf",
    )
    .unwrap();
    assert!(
        committed("constraints/obb_core.ucf") == ucf,
        "constraints/obb_core.ucf is stale: run `cargo run --bin gen-rtl`"
    );
    assert!(
        committed("scripts/ise/build.tcl") == tcl,
        "scripts/ise/build.tcl is stale: run `cargo run --bin gen-rtl`"
    );
    // The period follows the configuration.
    let (fast, _) = handoff(
        &HwConfig {
            clock_ns: 3.2,
            ..HwConfig::default()
        },
        "",
        "",
    )
    .unwrap();
    assert!(fast.contains("PERIOD \"clock\" 3.200 ns"), "{fast}");
}

#[test]
fn every_ucf_net_is_a_port_of_obb_core() {
    let fresh = files(&HwConfig::default()).unwrap();
    let verilog = &fresh.iter().find(|(n, _)| n == "obb_core.v").unwrap().1;
    let names: Vec<String> = ports(verilog, "obb_core")
        .into_iter()
        .map(|p| p.name)
        .collect();
    let ucf = committed("constraints/obb_core.ucf");
    let nets: Vec<&str> = ucf
        .lines()
        .filter(|l| l.trim_start().starts_with("NET"))
        .map(|l| l.split('"').nth(1).expect("NET \"name\""))
        .collect();
    assert!(!nets.is_empty(), "the UCF constrains something");
    for net in nets {
        assert!(
            names.iter().any(|n| n == net),
            "NET {net} is not a port of obb_core"
        );
    }
}

#[test]
fn the_ise_script_runs_under_tclsh_with_stubs() {
    let script = root().join("scripts/ise/build.tcl").canonicalize().unwrap();
    // Stubs record every call; `xfile add` also requires the file to exist.
    let driver = format!(
        "proc project {{args}} {{ puts \"project [join $args {{ }}]\" }}\n\
         proc process {{args}} {{ puts \"process [join $args {{ }}]\" }}\n\
         proc xfile {{args}} {{\n\
           if {{![file exists [lindex $args 1]]}} {{ error \"missing [lindex $args 1]\" }}\n\
           puts \"xfile [lindex $args 0] [file tail [lindex $args 1]]\"\n\
         }}\n\
         source {{{}}}\n",
        script.display()
    );
    let dir = obb_rtl::flow::verilator::scratch_dir("tclsh").unwrap();
    std::fs::write(dir.join("driver.tcl"), driver).unwrap();
    let out = Command::new("tclsh")
        .current_dir(&dir)
        .arg("driver.tcl")
        .output()
        .expect("tclsh runs (scripts/test.sh installs tcl)");
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{text}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let calls: Vec<&str> = text.lines().collect();
    for want in [
        "project new obb_core.xise",
        "project set family Virtex6",
        "project set device xc6vhx565t",
        "project set package ff1923",
        "project set speed -2",
        "xfile add obb_core.v",
        "xfile add obb_core.ucf",
        "project set top obb_core",
        "process run Synthesize - XST",
        "process run Implement Design",
        "process run Generate Programming File",
        "project close",
    ] {
        assert!(calls.contains(&want), "`{want}` in {calls:?}");
    }
    // The project is set up before anything runs, and closed last.
    let at = |c: &str| calls.iter().position(|l| *l == c).unwrap();
    assert!(at("project set device xc6vhx565t") < at("process run Synthesize - XST"));
    assert!(at("xfile add obb_core.ucf") < at("process run Implement Design"));
    assert_eq!(calls.last(), Some(&"project close"));
}
