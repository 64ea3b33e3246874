//! `gen-rtl`: deterministic output, `rtl-out/` equal to a fresh run for the default
//! configuration, a manifest that matches the Verilog, and clear errors for bad configurations.

use obb_model::fixed::HwConfig;
use obb_rtl::generate::{files, ports};
use std::path::Path;

#[test]
fn rtl_out_is_what_gen_rtl_writes_for_the_default_configuration() {
    let fresh = files(&HwConfig::default()).unwrap();
    assert_eq!(fresh, files(&HwConfig::default()).unwrap(), "deterministic");
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../rtl-out");
    for (name, text) in &fresh {
        let committed = std::fs::read_to_string(dir.join(name))
            .unwrap_or_else(|e| panic!("rtl-out/{name}: {e}; run `cargo run --bin gen-rtl`"));
        assert!(
            committed == *text,
            "rtl-out/{name} is stale: run `cargo run --bin gen-rtl` and commit the result"
        );
    }
    let mut names: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    names.sort();
    let mut expected: Vec<_> = fresh.iter().map(|(n, _)| n.clone()).collect();
    expected.sort();
    assert_eq!(names, expected, "rtl-out holds exactly the generated files");
}

#[test]
fn the_manifest_lists_the_verilog_ports() {
    let fresh = files(&HwConfig::default()).unwrap();
    let (_, verilog) = fresh.iter().find(|(n, _)| n == "projection.v").unwrap();
    let p = ports(verilog, "projection");
    assert_eq!(p.len(), 1 + 1 + 3 + 3 + 9 + 1 + 3 + 3 + 1);
    assert!(p
        .iter()
        .any(|p| p.name == "axes$8" && p.signed && p.bits == 18));
    let (_, manifest) = fresh.iter().find(|(n, _)| n == "manifest.json").unwrap();
    let json: serde_json::Value = serde_json::from_str(manifest).unwrap();
    assert_eq!(
        json["modules"][0]["ports"].as_array().unwrap().len(),
        p.len()
    );
    assert_eq!(
        json["modules"][0]["latency"],
        obb_model::fixed::cycles::LAT_PROJECT
    );
    let (_, sat) = fresh.iter().find(|(n, _)| n == "sat.v").unwrap();
    let sp = ports(sat, "sat");
    assert_eq!(sp.len(), 1 + 1 + 2 * (3 + 3 + 9 + 1) + 2);
    assert_eq!(
        json["modules"][1]["ports"].as_array().unwrap().len(),
        sp.len()
    );
    assert_eq!(
        json["modules"][1]["latency"],
        obb_model::fixed::cycles::LAT_SAT
    );
    let (_, sort) = fresh.iter().find(|(n, _)| n == "radix_sort.v").unwrap();
    let rp = ports(sort, "radix_sort");
    assert!(
        rp.iter().any(|p| p.name == "rd_addr" && p.bits == 15),
        "capacity 32768"
    );
    assert_eq!(json["configuration"]["key_bits"], 20);
}

#[test]
fn unsupported_configurations_are_rejected() {
    let bad = HwConfig {
        rot_bits: 20,
        ..HwConfig::default()
    };
    let e = files(&bad).unwrap_err().to_string();
    assert!(e.contains("rot_bits"), "{e}");
}
