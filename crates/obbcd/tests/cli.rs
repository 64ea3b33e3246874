//! The command line end to end: scene -> detect -> pairs file, and clear errors on bad input.

mod common;

use common::{fails_with, field, ok, Scratch};
use std::path::PathBuf;
use std::process::Command;

#[test]
fn scene_detect_and_stats() {
    let scratch = Scratch::new();
    let scene = scratch.file("s.json");
    ok(&[
        "scene",
        "surgical",
        "--n",
        "1200",
        "--seed",
        "4",
        "-o",
        scene.to_str().unwrap(),
    ]);
    let mut results = Vec::new();
    for engine in ["brute", "sap", "improved-sap", "sweep", "grid"] {
        let pairs = scratch.file(&format!("{engine}.json"));
        let out = ok(&[
            "detect",
            "--scene",
            scene.to_str().unwrap(),
            "--engine",
            engine,
            "--groups",
            "cross",
            "--repeat",
            "3",
            "-o",
            pairs.to_str().unwrap(),
        ]);
        let line = String::from_utf8(out.stdout).unwrap();
        assert_eq!(field(&line, "engine"), engine);
        assert_eq!(field(&line, "obbs"), "1200");
        field(&line, "time_ms").parse::<f64>().unwrap();
        let json: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&pairs).unwrap()).unwrap();
        let list = json["pairs"].as_array().unwrap().clone();
        assert_eq!(list.len().to_string(), field(&line, "pairs"));
        results.push(list);
    }
    assert!(results.iter().all(|r| *r == results[0]));
    let out = ok(&["stats", "--scene", scene.to_str().unwrap()]);
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.starts_with("groups\tpairs\toverlap_x"));
    assert_eq!(
        text.lines().count(),
        1 + 1 + 6 + 1,
        "header, all, six group pairs, grid"
    );
    // The surgical scene's boxes are of similar sizes: all pairs take the corner layout.
    let grid = text.lines().last().unwrap();
    assert!(grid.starts_with("grid layout=corner cell_mm="), "{grid}");
    assert!(grid.contains(" entries_per_box=1.00 "), "{grid}");
}

/// `detect` with no scene runs the built-in surgical scene (what `scene surgical` writes), says
/// so, and counts the pairs by group pair; the same pairs as from the written file.
#[test]
fn detect_without_a_scene_runs_the_builtin_surgical_scene() {
    let scratch = Scratch::new();
    let out = ok(&["detect"]);
    let stdout = String::from_utf8(out.stdout).unwrap();
    let stderr = String::from_utf8(out.stderr).unwrap();
    assert!(
        stderr.contains("the built-in surgical scene, 17500 OBBs"),
        "{stderr}"
    );
    assert!(
        stderr.contains("next: `obbcd detect --engine model`"),
        "{stderr}"
    );
    assert_eq!(field(&stdout, "obbs"), "17500");
    let by_groups = stdout
        .lines()
        .find_map(|l| l.strip_prefix("pairs_by_groups "))
        .unwrap_or_else(|| panic!("no pairs_by_groups line in `{stdout}`"));
    let counts: Vec<(&str, usize)> = by_groups
        .split_whitespace()
        .map(|kv| {
            let (k, v) = kv.split_once('=').unwrap();
            (k, v.parse().unwrap())
        })
        .collect();
    let total: usize = counts.iter().map(|c| c.1).sum();
    assert_eq!(total.to_string(), field(&stdout, "pairs"));
    // The instruments touch the tissue: the pairs that matter are there.
    assert!(
        counts.iter().any(|&(k, n)| k == "0-1" && n > 0),
        "{by_groups}"
    );
    let scene = scratch.file("builtin.json");
    ok(&["scene", "surgical", "-o", scene.to_str().unwrap()]);
    let from_file = ok(&["detect", "--scene", scene.to_str().unwrap()]);
    let from_file = String::from_utf8(from_file.stdout).unwrap();
    assert_eq!(field(&from_file, "pairs"), field(&stdout, "pairs"));
    assert!(from_file.contains(&format!("pairs_by_groups {by_groups}")));
}

/// A closed output pipe (`obbcd detect | head -1`) ends `obbcd` by SIGPIPE, as it ends `cat`:
/// no panic.
#[test]
fn a_closed_output_pipe_ends_obbcd_quietly() {
    use std::os::unix::process::ExitStatusExt;
    let scratch = Scratch::new();
    let scene = scratch.file("s.json");
    ok(&[
        "scene",
        "uniform",
        "--n",
        "300",
        "-o",
        scene.to_str().unwrap(),
    ]);
    let (reader, writer) = std::io::pipe().unwrap();
    drop(reader);
    let out = Command::new(env!("CARGO_BIN_EXE_obbcd"))
        .args(["detect", "--scene", scene.to_str().unwrap()])
        .stdout(writer)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.signal(), Some(libc::SIGPIPE), "{err}");
    assert!(!err.contains("panicked"), "{err}");
}

#[test]
fn bad_input_fails_with_a_message() {
    let scratch = Scratch::new();
    let bad = scratch.write("bad.json", r#"{"obbs":[{"center":[0,0,0],"axes":[[1,0,0],[0,1,0],[0,0,1]],"half":[1,-1,1],"group":0}]}"#);
    let empty = scratch.write("empty.json", "");
    let short = scratch.write(
        "short.json",
        r#"{"obbs":[{"center":[0,0],"axes":[[1,0,0],[0,1,0],[0,0,1]],"half":[1,1,1]}]}"#,
    );
    let typed = scratch.write("typed.json", r#"{"obbs":[{"center":[0,0,0],"axes":[[1,0,0],[0,1,0],[0,0,1]],"half":[1,1,1]},{"center":[0,0,0],"axes":[[1,0,0],[0,1,"x"],[0,0,1]],"half":[1,1,1]}]}"#);
    let cases: [(&[&str], &str); 13] = [
        (
            &["detect", "--scene", bad.to_str().unwrap()],
            "obb 0: field `half` has -1",
        ),
        (&["detect", "--scene", empty.to_str().unwrap()], "is empty"),
        (
            &["detect", "--scene", "/no/such.json"],
            "cannot read scene file /no/such.json: No such file",
        ),
        (
            &["detect", "--scene", short.to_str().unwrap()],
            "obb 0, field `center`: invalid length 2, expected an array of length 3",
        ),
        (
            &["detect", "--scene", typed.to_str().unwrap()],
            "obb 1, field `axes[1][2]`: invalid type: string",
        ),
        (
            &["detect", "--engine", "model", "--config", "/no/such.toml"],
            "cannot read configuration /no/such.toml: No such file",
        ),
        (
            &["scene", "uniform", "--n", "10", "-o", "/no/such/dir/x.json"],
            "cannot write scene file /no/such/dir/x.json",
        ),
        (
            &[
                "detect",
                "--scene",
                bad.to_str().unwrap(),
                "--engine",
                "fast",
            ],
            "unknown engine `fast`",
        ),
        (
            &[
                "detect",
                "--scene",
                bad.to_str().unwrap(),
                "--groups",
                "0:1",
            ],
            "not a pair like 0-1",
        ),
        (
            &["scene", "uniform", "--n", "0", "-o", "/tmp/x.json"],
            "--n must be at least 1",
        ),
        (
            &["cosim", "--waves", "/tmp/w.txt"],
            "the extension names the format, .vcd or .fst",
        ),
        (
            &[
                "cosim",
                "--waves",
                "/tmp/w.fst",
                "--waves-from",
                "9",
                "--waves-to",
                "9",
            ],
            "the waveform window is empty",
        ),
        (&["bench", "--runs", "0"], "--runs must be at least 1"),
    ];
    fails_with(&cases);
}

/// A bench over in a second: small scenes, three races of few frames each.
const TINY_BENCH: &[&str] = &[
    "--sizes",
    "300",
    "--surgical-n",
    "500",
    "--repeat",
    "2",
    "--runs",
    "3",
    "--warmup-ms",
    "1",
    "--turn-ms",
    "2",
    "--rounds",
    "1",
    "--quadratic-max",
    "0",
];

/// `bench --neighbour-mb` runs its random reads on a core the worker threads leave free (it
/// refuses when they leave none) and says so in its first line, with the reads' pace at the
/// end.
#[test]
fn bench_beside_a_neighbour() {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let all = cores.to_string();
    fails_with(&[(
        &["--threads", all.as_str(), "bench", "--neighbour-mb", "4"],
        "--neighbour-mb needs a core of its own beside the",
    )]);
    assert!(
        cores >= 2,
        "a neighbour beside one worker thread needs two cores"
    );
    fails_with(&[(
        &["--threads", "1", "bench", "--neighbour-mb", "0"],
        "--neighbour-mb must be from 1 to 4096, not 0",
    )]);
    let args = [
        &["--threads", "1", "bench", "--neighbour-mb", "2"],
        TINY_BENCH,
    ]
    .concat();
    let text = String::from_utf8(ok(&args).stdout).unwrap();
    let head = text.lines().next().unwrap_or_default();
    assert!(
        head.ends_with("1 threads, beside random reads over 2 MB"),
        "{head}"
    );
    let pace = text
        .lines()
        .find_map(|l| l.strip_prefix("neighbour: random reads over 2 MB, a load every "))
        .and_then(|rest| rest.split(' ').next())
        .and_then(|ns| ns.parse::<f64>().ok())
        .unwrap_or_else(|| panic!("no neighbour line with its pace in {text}"));
    assert!(pace > 0.0 && pace < 1e5, "{pace} ns a load");
    assert!(text.lines().any(|l| l.starts_with("speedup ")), "{text}");
}

/// `bench --runs N` races the grid against parry3d N times per scene and prints, per scene and
/// thread count, each race's speed-up (parry3d's median frame over the grid's) with their min,
/// median and max; the table's times are the medians over the races. Its first line says when,
/// on which CPU and with which vector code it measured.
#[test]
fn bench_lists_the_speedup_of_every_race() {
    let out = ok(&[&["bench"], TINY_BENCH].concat());
    let text = String::from_utf8(out.stdout).unwrap();
    // It says first when (UTC), on which CPU and with which vector code it measured.
    let head = text.lines().next().unwrap_or_default();
    let stamp = head
        .strip_prefix("bench ")
        .and_then(|r| r.split(", ").next());
    assert!(
        stamp.is_some_and(|t| humantime::parse_rfc3339(t).is_ok()),
        "`{head}` does not start with `bench <UTC time>, `"
    );
    let vectors = format!("vector code {:?}", obb_model::simd::Vectors::detected());
    assert!(
        head.contains(&vectors),
        "`{head}` does not name the {vectors}"
    );
    let lines: Vec<&str> = text.lines().filter(|l| l.starts_with("speedup ")).collect();
    // Three scenes (surgical all pairs and cross-group, uniform), the grid on all threads and,
    // where there are more, on one.
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    assert_eq!(lines.len(), if threads > 1 { 6 } else { 3 }, "{text}");
    for scene in [
        "surgical 500 groups=all",
        "surgical 500 groups=cross",
        "uniform 300 groups=all",
    ] {
        assert!(
            lines.iter().any(|l| l.contains(scene)),
            "no {scene} in {text}"
        );
    }
    for line in lines {
        let (runs, summary) = line
            .split_once(": ")
            .and_then(|(_, rest)| rest.split_once("x (min "))
            .unwrap_or_else(|| panic!("`{line}` is not `speedup ...: r r rx (min ...)`"));
        let mut runs: Vec<f64> = runs.split(' ').map(|r| r.parse().unwrap()).collect();
        assert_eq!(runs.len(), 3, "{line}");
        assert!(runs.iter().all(|&r| r > 0.0 && r.is_finite()), "{line}");
        runs.sort_by(f64::total_cmp);
        let summary: Vec<f64> = summary
            .trim_end_matches(')')
            .split(", ")
            .map(|part| part.rsplit(' ').next().unwrap().parse().unwrap())
            .collect();
        assert_eq!(summary, [runs[0], runs[1], runs[2]], "{line}");
    }
}

#[test]
fn model_engine_and_error_table() {
    let scratch = Scratch::new();
    let scene = scratch.file("m.json");
    ok(&[
        "scene",
        "surgical",
        "--n",
        "1500",
        "--seed",
        "2",
        "-o",
        scene.to_str().unwrap(),
    ]);
    let s = scene.to_str().unwrap();
    let run = |extra: &[&str], file: &PathBuf| {
        let mut args = vec!["detect", "--scene", s, "-o", file.to_str().unwrap()];
        args.extend_from_slice(extra);
        let out = ok(&args);
        let line = String::from_utf8(out.stdout).unwrap();
        let json: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(file).unwrap()).unwrap();
        (line, json["pairs"].as_array().unwrap().clone())
    };
    let (cpu_line, cpu) = run(&["--groups", "all"], &scratch.file("cpu.json"));
    let (line, model) = run(
        &["--engine", "model", "--groups", "all"],
        &scratch.file("model.json"),
    );
    assert_eq!(field(&line, "engine"), "model");
    assert_eq!(field(&line, "false_negatives"), "0");
    assert!(field(&line, "cycles").parse::<u64>().unwrap() > 1500);
    // Every CPU pair is in the model's file; the extra ones are the false positives.
    assert!(cpu.iter().all(|p| model.contains(p)));
    let fp: usize = field(&line, "false_positives").parse().unwrap();
    assert_eq!(model.len(), cpu.len() + fp, "{cpu_line} / {line}");
    // A configuration file: its groups apply unless --groups is given.
    let cfg = scratch.write(
        "hw.toml",
        "key_bits = 16\ngroups = \"cross\"\nbroad_phase = \"sweep\"\n",
    );
    let (line, _) = run(
        &["--engine", "model", "--config", cfg.to_str().unwrap()],
        &scratch.file("m2.json"),
    );
    assert_eq!(field(&line, "groups"), "cross");
    assert_eq!(field(&line, "broad_phase"), "sweep");

    // Error against run time: two widths, two broad phases, no synthesis in an empty cache, so
    // every period is `clock_ns`.
    let csv = scratch.file("err.csv");
    let svg = scratch.file("err.svg");
    let out = ok(&[
        "error",
        "--scene",
        s,
        "--widths",
        "14..15",
        "--broad-phases",
        "grid,sweep",
        "--cache",
        scratch.file("empty-cache").to_str().unwrap(),
        "--csv",
        csv.to_str().unwrap(),
        "--svg",
        svg.to_str().unwrap(),
    ]);
    let printed = String::from_utf8(out.stdout).unwrap();
    assert_eq!(
        printed.lines().count(),
        2 + 4,
        "summary, header, one row per width and broad phase: {printed}"
    );
    let table = std::fs::read_to_string(&csv).unwrap();
    let rows: Vec<&str> = table.lines().collect();
    assert_eq!(
        rows[0],
        "width,broad_phase,lsb_um,pairs,false_positives,fp_rate,false_negatives,inflation_um,\
         clocks,period_ns,period_from,frame_ms,rate_hz,pareto"
    );
    assert_eq!(rows.len(), 5);
    let mut points = Vec::new();
    for (row, (w, phase)) in
        rows[1..]
            .iter()
            .zip([(14, "grid"), (14, "sweep"), (15, "grid"), (15, "sweep")])
    {
        let cols: Vec<&str> = row.split(',').collect();
        assert_eq!((cols[0], cols[1]), (w.to_string().as_str(), phase), "{row}");
        assert_eq!(cols[6], "0", "false negatives: {row}");
        assert_eq!((cols[9], cols[10]), ("4", "clock_ns"), "{row}");
        let clocks: f64 = cols[8].parse().unwrap();
        let frame_ms: f64 = cols[11].parse().unwrap();
        assert!((frame_ms - clocks * 4e-6).abs() <= 1e-9 * frame_ms, "{row}");
        let fp_rate: f64 = cols[5].parse().unwrap();
        points.push((frame_ms, fp_rate, cols[13] == "true"));
    }
    // On the Pareto front exactly when no other row is as fast and as accurate, and better in
    // one of the two.
    for &(t, e, on_front) in &points {
        let beaten = points
            .iter()
            .any(|&(ot, oe, _)| ot <= t && oe <= e && (ot < t || oe < e));
        assert_eq!(on_front, !beaten, "{table}");
    }
    let plot = std::fs::read_to_string(&svg).unwrap();
    assert!(plot.starts_with("<svg") && plot.contains("Pareto front") && plot.contains("sweep"));
}

#[test]
fn model_errors_name_the_problem() {
    let scratch = Scratch::new();
    let far = scratch.write("far.json", r#"{"obbs":[{"center":[0,0,0],"axes":[[1,0,0],[0,1,0],[0,0,1]],"half":[1,1,1]},{"center":[900,0,0],"axes":[[1,0,0],[0,1,0],[0,0,1]],"half":[1,1,1]}]}"#);
    let bad_cfg = scratch.write("bad.toml", "rot_bits = 30\n");
    let typo = scratch.write("typo.toml", "keybits = 12\n");
    let f = far.to_str().unwrap();
    // A 100 mm plate on the grid's 2 mm cells: its window, 52 cells long, is not read.
    let plate = scratch.write("plate.json", r#"{"obbs":[{"center":[0,0,0],"axes":[[1,0,0],[0,1,0],[0,0,1]],"half":[50,1,1]},{"center":[0,0,1],"axes":[[1,0,0],[0,1,0],[0,0,1]],"half":[1,1,1]}]}"#);
    let grid_cfg = scratch.write("grid.toml", "broad_phase = \"grid\"\ngroups = \"all\"\n");
    // An empty configuration is the built-in one, whose centers reach ±512 mm.
    let empty_cfg = scratch.write("empty.toml", "");
    let cases: [(&[&str], &str); 8] = [
        (
            &[
                "detect",
                "--scene",
                f,
                "--engine",
                "model",
                "--config",
                empty_cfg.to_str().unwrap(),
            ],
            "obb 1: center[0] 900 mm",
        ),
        (
            &["plan", "--scene", f, "--fp-rate", "2"],
            "false-positive rate aim 2",
        ),
        (
            &["error", "--scene", f, "--broad-phases", "grid,warp"],
            "unknown broad phase `warp`",
        ),
        (
            &[
                "detect",
                "--scene",
                f,
                "--engine",
                "model",
                "--config",
                bad_cfg.to_str().unwrap(),
            ],
            "rot_bits",
        ),
        (
            &[
                "detect",
                "--scene",
                f,
                "--engine",
                "model",
                "--config",
                typo.to_str().unwrap(),
            ],
            "keybits",
        ),
        (
            &["detect", "--scene", f, "--config", typo.to_str().unwrap()],
            "--engine model only",
        ),
        (
            &["error", "--scene", f, "--widths", "12..36"],
            "width 24 is not supported",
        ),
        (
            &[
                "detect",
                "--scene",
                plate.to_str().unwrap(),
                "--engine",
                "model",
                "--config",
                grid_cfg.to_str().unwrap(),
            ],
            "spans more than 23 grid cells of 2 mm",
        ),
    ];
    fails_with(&cases);
}

/// `cosim` end to end on a small core (capacity 512, all pairs) in Verilator: the pairs file
/// equals the model's from `detect --engine model`, the cycles equal the model's, and with
/// back-pressure nothing changes but the clock count; a scene over capacity and bad options
/// fail with a message.
#[test]
fn cosim_matches_the_model_and_reports_problems() {
    let scratch = Scratch::new();
    let scene = scratch.file("cosim-scene.json");
    let config = scratch.write("cosim.toml", "capacity = 512\ngroups = \"all\"\n");
    // obb-rtl's tests build the same core (their `aborted_frames_give_the_whole_new_frame`)
    // in this cache: a build of it is shared.
    let cache = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("cosim-cache");
    let s = scene.to_str().unwrap();
    let c = config.to_str().unwrap();
    let k = cache.to_str().unwrap();
    ok(&[
        "scene",
        "uniform",
        "--n",
        "150",
        "--density",
        "0.3",
        "-o",
        s,
    ]);
    let model_pairs = scratch.file("cosim-model.json");
    let m = model_pairs.to_str().unwrap();
    let out = ok(&[
        "detect", "--engine", "model", "--scene", s, "--config", c, "-o", m,
    ]);
    let model_line = String::from_utf8_lossy(&out.stdout).to_string();
    for ready in ["1", "5"] {
        let pairs = scratch.file(&format!("cosim-pairs-{ready}.json"));
        let p = pairs.to_str().unwrap();
        let out = ok(&[
            "cosim",
            "--scene",
            s,
            "--config",
            c,
            "--cache",
            k,
            "--ready-every",
            ready,
            "-o",
            p,
        ]);
        let line = String::from_utf8_lossy(&out.stdout).to_string();
        assert_eq!(field(&line, "simulator"), "verilator");
        assert_eq!(field(&line, "pairs"), field(&model_line, "pairs"), "{line}");
        assert_eq!(field(&line, "model_cycles"), field(&model_line, "cycles"));
        if ready == "1" {
            assert_eq!(
                field(&line, "cycles"),
                field(&model_line, "cycles"),
                "{line}"
            );
        }
        assert_eq!(
            std::fs::read_to_string(&pairs).unwrap(),
            std::fs::read_to_string(&model_pairs).unwrap()
        );
        assert!(field(&model_line, "pairs").parse::<u64>().unwrap() > 0);
    }
    let big = scratch.file("cosim-big.json");
    let b = big.to_str().unwrap();
    ok(&["scene", "uniform", "--n", "600", "-o", b]);
    fails_with(&[
        (
            &["cosim", "--scene", b, "--config", c, "--cache", k],
            "exceed the configured capacity of 512",
        ),
        (
            &["cosim", "--scene", s, "--ready-every", "0", "--cache", k],
            "--ready-every must be at least 1",
        ),
    ]);
}

/// Without `--config` the model plans for the scene: a scene beyond the built-in ranges (a
/// 498 mm box 900 mm out) and a one-group scene run, with the CPU engines' default mask (all
/// pairs), and `plan`'s TOML is a configuration `detect --config` takes, with the same result.
#[test]
fn the_model_plans_for_any_scene_the_cpu_engines_take() {
    let scratch = Scratch::new();
    let wide = scratch.write(
        "wide.json",
        r#"{"obbs":[
        {"center":[0,0,0],"axes":[[1,0,0],[0,1,0],[0,0,1]],"half":[498.37,1,1]},
        {"center":[900,0,0],"axes":[[1,0,0],[0,1,0],[0,0,1]],"half":[1,1,1]},
        {"center":[497,0.5,0],"axes":[[0.6,0.8,0],[-0.8,0.6,0],[0,0,1]],"half":[1,2,3]},
        {"center":[-10,0,2.5],"axes":[[1,0,0],[0,1,0],[0,0,1]],"half":[1,1,1.5]}]}"#,
    );
    let one_group = scratch.file("one.json");
    ok(&[
        "scene",
        "uniform",
        "--n",
        "300",
        "--density",
        "0.2",
        "-o",
        one_group.to_str().unwrap(),
    ]);
    for scene in [&wide, &one_group] {
        let s = scene.to_str().unwrap();
        let cpu = String::from_utf8(
            ok(&[
                "detect",
                "--scene",
                s,
                "-o",
                scratch.file("plan-cpu.json").to_str().unwrap(),
            ])
            .stdout,
        )
        .unwrap();
        let out = ok(&[
            "detect",
            "--scene",
            s,
            "--engine",
            "model",
            "-o",
            scratch.file("plan-model.json").to_str().unwrap(),
        ]);
        let line = String::from_utf8(out.stdout).unwrap();
        let told = String::from_utf8(out.stderr).unwrap();
        assert!(told.contains("planned for the scene"), "{told}");
        assert_eq!(field(&line, "groups"), "all");
        assert_eq!(field(&line, "false_negatives"), "0");
        let pairs: usize = field(&cpu, "pairs").parse().unwrap();
        assert!(pairs > 0, "{s}: the scene has colliding pairs");
        let fp: usize = field(&line, "false_positives").parse().unwrap();
        assert_eq!(
            field(&line, "pairs").parse::<usize>().unwrap(),
            pairs + fp,
            "{cpu} / {line}"
        );

        // The plan, written and read back: the same configuration, the same frame.
        let toml = scratch.file("planned.toml");
        let planned = ok(&["plan", "--scene", s, "-o", toml.to_str().unwrap()]);
        let figures = String::from_utf8(planned.stdout).unwrap();
        assert!(figures.contains("wrote"), "{figures}");
        let text = std::fs::read_to_string(&toml).unwrap();
        // Each planned key follows the comment that says why.
        let lines: Vec<&str> = text.lines().collect();
        for key in ["center_bits", "lsb_mm", "capacity", "broad_phase", "groups"] {
            let at = lines
                .iter()
                .position(|l| l.starts_with(&format!("{key} = ")))
                .unwrap_or_else(|| panic!("no {key} in {text}"));
            assert!(
                at > 0 && lines[at - 1].starts_with("# ") && !lines[at - 1].contains("not planned"),
                "{key} has no reason: {text}"
            );
        }
        let again = ok(&[
            "detect",
            "--scene",
            s,
            "--engine",
            "model",
            "--config",
            toml.to_str().unwrap(),
        ]);
        let again = String::from_utf8(again.stdout).unwrap();
        for key in [
            "pairs",
            "false_positives",
            "cycles",
            "broad_phase",
            "groups",
        ] {
            assert_eq!(
                field(&again, key),
                field(&line, key),
                "{key}: {again} / {line}"
            );
        }
    }
}

/// A box as `(center, axes, half)`.
type Box3 = ([f64; 3], [[f64; 3]; 3], [f64; 3]);

/// A scene file of the given boxes.
fn boxes_scene(scratch: &Scratch, name: &str, boxes: &[Box3]) -> PathBuf {
    let obbs: Vec<String> = boxes
        .iter()
        .map(|(c, a, h)| {
            // `{:?}` of an f64 is valid JSON (1e-310, 1000000.0) and reads back exactly.
            format!(r#"{{"center":{c:?},"axes":{a:?},"half":{h:?}}}"#)
        })
        .collect();
    scratch.write(name, format!(r#"{{"obbs":[{}]}}"#, obbs.join(",")))
}

/// `obbcd detect` under a limit of 3 GiB of address space and 120 s: it must finish and succeed.
fn detect_within_limits(scene: &PathBuf, engine: &str) -> String {
    let mut child = Command::new("sh")
        .args(["-c", r#"ulimit -v 3145728 && exec "$0" "$@""#])
        .arg(env!("CARGO_BIN_EXE_obbcd"))
        .args([
            "detect",
            "--scene",
            scene.to_str().unwrap(),
            "--engine",
            engine,
        ])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("sh runs");
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(120);
    while child.try_wait().unwrap().is_none() {
        if std::time::Instant::now() > deadline {
            child.kill().unwrap();
            panic!("{engine} on {scene:?}: still running after 120 s");
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let out = child.wait_with_output().unwrap();
    assert!(
        out.status.success(),
        "{engine} on {scene:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).unwrap()
}

/// Every engine, the fixed-point model included, finishes within a memory and time limit on
/// scenes at the ends of f64's range and on degenerate ones, and reports every colliding pair:
/// boxes of subnormal size (the grid's cells once had an infinite inverse and filled memory),
/// crossing plates whose axes have subnormal entries, boxes of 1e6 mm at the coordinate limit
/// with a 1e-300 mm box where they touch, 1,000 tiny boxes inside one huge one, and 300
/// zero-size boxes at one point. The pairs are counted by construction (docs/sat.md,
/// "Underflow").
#[test]
fn every_engine_finishes_on_tiny_huge_and_degenerate_scenes() {
    let scratch = Scratch::new();
    const I: [[f64; 3]; 3] = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let tilted = |t: f64| [[1.0, 0.0, 0.0], [t, 1.0, 0.0], [t, 0.0, 1.0]];
    let scenes = [
        (
            boxes_scene(
                &scratch,
                "subnormal.json",
                &[
                    ([0.0; 3], I, [1e-310; 3]),
                    ([1e-310, 0.0, 0.0], I, [1e-310; 3]),
                ],
            ),
            1,
        ),
        (
            boxes_scene(
                &scratch,
                "plates.json",
                &[
                    ([0.0; 3], tilted(2.5e-323), [0.0, 0.7, 0.7]),
                    ([-6.4e-323, 0.0, 0.0], tilted(-2.5e-323), [0.0, 0.7, 0.7]),
                ],
            ),
            1,
        ),
        (
            boxes_scene(
                &scratch,
                "huge.json",
                &[
                    ([1e6; 3], I, [1e6; 3]),
                    ([-1e6; 3], I, [1e6; 3]),
                    ([0.0; 3], I, [1e-300; 3]),
                    ([1e6, -1e6, 0.0], I, [0.0; 3]),
                ],
            ),
            3,
        ),
        (
            boxes_scene(
                &scratch,
                "tiny-in-huge.json",
                &std::iter::once(([0.0; 3], I, [1e6; 3]))
                    .chain((0..1000).map(|k| ([k as f64 * 1e-299, 0.0, 0.0], I, [1e-300; 3])))
                    .collect::<Vec<_>>(),
            ),
            1000,
        ),
        (
            boxes_scene(
                &scratch,
                "one-point.json",
                &vec![([0.5, -0.25, 3.0], I, [0.0; 3]); 300],
            ),
            300 * 299 / 2,
        ),
    ];
    for (scene, want) in &scenes {
        for engine in ["brute", "sap", "improved-sap", "sweep", "grid", "model"] {
            let line = detect_within_limits(scene, engine);
            let pairs: usize = field(&line, "pairs").parse().unwrap();
            if engine == "model" {
                // The fixed-point model may add false positives, never lose a pair.
                assert!(pairs >= *want, "{engine} on {scene:?}: {line}");
                assert_eq!(field(&line, "false_negatives"), "0", "{scene:?}: {line}");
            } else {
                assert_eq!(pairs, *want, "{engine} on {scene:?}: {line}");
            }
        }
    }
}

/// `detect --contacts`: one contact per pair in the pairs' order, with the grid and the model
/// alike; on boxes set face to face and into each other by known amounts, each pair's depth
/// and normal exactly; without `-o`, a clear error.
#[test]
fn detect_writes_a_contact_per_pair() {
    let scratch = Scratch::new();
    let aligned = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    // Unit cubes: 0-1 face to face on x (depth 0), 1-2 into each other by 0.25 on y, 3 apart.
    let scene = boxes_scene(
        &scratch,
        "contacts.json",
        &[
            ([0.0, 0.0, 0.0], aligned, [1.0; 3]),
            ([2.0, 0.5, 0.0], aligned, [1.0; 3]),
            ([2.0, 2.25, 0.3], aligned, [1.0; 3]),
            ([9.0, 0.0, 0.0], aligned, [1.0; 3]),
        ],
    );
    for engine in ["grid", "model"] {
        let pairs = scratch.file(&format!("contacts-{engine}.json"));
        let args = [
            "detect",
            "--scene",
            scene.to_str().unwrap(),
            "--engine",
            engine,
            "--contacts",
            "-o",
            pairs.to_str().unwrap(),
        ];
        let out = String::from_utf8(ok(&args).stdout).unwrap();
        let line = out.lines().find(|l| l.starts_with("contacts=")).unwrap();
        assert_eq!(field(line, "contacts"), "2", "{out}");
        assert_eq!(field(line, "max_depth"), "0.250000", "{out}");
        let json: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&pairs).unwrap()).unwrap();
        assert_eq!(
            json["pairs"],
            serde_json::json!([[0, 1], [1, 2]]),
            "{engine}"
        );
        assert_eq!(
            json["contacts"],
            serde_json::json!([
                {"normal": [1.0, 0.0, 0.0], "depth": 0.0},
                {"normal": [0.0, 1.0, 0.0], "depth": 0.25},
            ]),
            "{engine}"
        );
    }
    fails_with(&[(
        &["detect", "--scene", scene.to_str().unwrap(), "--contacts"],
        "--output",
    )]);
}
