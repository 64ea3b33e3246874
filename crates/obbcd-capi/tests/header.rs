//! include/obbcd.h is what cbindgen makes of the sources (as rtl-out/ is what gen-rtl emits),
//! it compiles as C and as C++, and every name it defines is obbcd's own.

mod common;

use std::path::Path;

#[test]
fn header_is_generated_from_the_sources() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let config = cbindgen::Config::from_file(dir.join("cbindgen.toml")).expect("cbindgen.toml");
    let mut builder = cbindgen::Builder::new().with_config(config);
    for file in ["lib.rs", "types.rs"] {
        builder = builder.with_src(dir.join("src").join(file));
    }
    let mut fresh = Vec::new();
    builder
        .generate()
        .expect("cbindgen cannot read the sources")
        .write(&mut fresh);
    let path = dir.join("include/obbcd.h");
    if std::env::var_os("OBBCD_WRITE_HEADER").is_some() {
        std::fs::write(&path, &fresh).expect("cannot write include/obbcd.h");
    }
    let committed = std::fs::read(&path).expect("include/obbcd.h is missing");
    assert!(
        committed == fresh,
        "include/obbcd.h is not what cbindgen makes of src/: regenerate it with \
         OBBCD_WRITE_HEADER=1 cargo test -p obbcd-capi --test header"
    );
}

#[test]
fn header_compiles_as_c_and_cpp() {
    let header = Path::new(env!("CARGO_MANIFEST_DIR")).join("include/obbcd.h");
    for (compiler, lang) in [("cc", "c"), ("c++", "c++")] {
        common::run(
            std::process::Command::new(compiler)
                .args(["-Wall", "-Wextra", "-Werror", "-fsyntax-only", "-x", lang])
                .arg(&header),
        );
    }
}

/// A C or C++ program shares one namespace with every header it includes: each macro, type,
/// enum constant and function the header defines starts with `OBBCD_`, `Obbcd` or `obbcd_`.
/// (It fails on a bare `#define MAX_THREADS`, as the header had.)
#[test]
fn header_defines_only_prefixed_names() {
    let header =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("include/obbcd.h"))
            .expect("include/obbcd.h is missing");
    let names = defined_names(&header);
    for kind in ["macro", "type", "constant", "function"] {
        assert!(
            names.iter().any(|(k, _)| *k == kind),
            "no {kind} found in the header: the scan below no longer reads it"
        );
    }
    let foreign: Vec<_> = names
        .iter()
        .filter(|(_, name)| {
            !["OBBCD_", "Obbcd", "obbcd_"]
                .iter()
                .any(|p| name.starts_with(p))
        })
        .collect();
    assert!(
        foreign.is_empty(),
        "names without obbcd's prefix: {foreign:?}"
    );
}

/// The names a cbindgen header defines at file scope, each with its kind, from the shapes
/// cbindgen writes: `#define NAME`, `typedef struct NAME NAME;`, `} NAME;` closing a typedef,
/// `  NAME = 1,` in an enum, and a declaration `Type name(` starting a line.
fn defined_names(header: &str) -> Vec<(&'static str, String)> {
    let ident = |s: &str| -> String {
        s.chars()
            .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
            .collect()
    };
    let mut names = Vec::new();
    for line in header.lines() {
        if let Some(rest) = line.strip_prefix("#define ") {
            names.push(("macro", ident(rest)));
        } else if let Some(rest) = line
            .strip_prefix("typedef struct ")
            .filter(|r| r.ends_with(';'))
        {
            names.extend(
                rest.trim_end_matches(';')
                    .split(' ')
                    .map(|n| ("type", ident(n))),
            );
        } else if let Some(rest) = line.strip_prefix("} ").filter(|r| r.ends_with(';')) {
            names.push(("type", ident(rest)));
        } else if line.starts_with("  ") && line.trim_end().ends_with(',') && line.contains(" = ") {
            names.push(("constant", ident(line.trim_start())));
        } else if let Some((head, _)) = line.split_once('(') {
            if !line.starts_with([' ', '#', '/', '}']) {
                let name = head.rsplit([' ', '*']).next().unwrap_or_default();
                names.push(("function", name.to_string()));
            }
        }
    }
    names
}
