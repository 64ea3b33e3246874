//! Single mutations of emitted Verilog, for `tests/mutants.rs`. The core's Verilog is what
//! ships, so its mutants are made where it is read: each changes one expression (or swaps two
//! wires) of rust-hdl's output or of a hand-written leaf, and every one changes the emitted
//! Verilog by construction. Source-level mutants (`cargo mutants` on obb-rtl) need a rebuild of
//! the test binaries for each, about six minutes here; a Verilog mutant needs one Verilator
//! build of the core, about 40 seconds.
//!
//! The Verilog this reads is rust-hdl's: one statement per line, ports and signals declared one
//! per line, combinational code in `always @(*)` blocks after a `// Update code` comment,
//! registers as `always @(posedge clock)` blocks.

use std::collections::HashMap;
use std::fmt;

/// What a mutant changes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Kind {
    /// A comparison: `<` and `<=`, `>` and `>=`, `==` and `!=` exchanged.
    Compare,
    /// `+` and `-` exchanged.
    Arithmetic,
    /// `&` and `|`, `&&` and `||` exchanged; `^` made `|`.
    Logic,
    /// `<<` and `>>` exchanged, `>>>` made `>>`.
    Shift,
    /// A `~` or `!` removed.
    Invert,
    /// A sized constant one more (or, at its largest, one less).
    Constant,
    /// An `if`'s condition negated.
    Condition,
    /// The right-hand sides of two neighbouring assignments of equal width swapped.
    Swap,
    /// A register bypassed: its `always @(posedge clock)` made `always @(*)`.
    Bypass,
}

impl Kind {
    pub const ALL: [Kind; 9] = [
        Kind::Compare,
        Kind::Arithmetic,
        Kind::Logic,
        Kind::Shift,
        Kind::Invert,
        Kind::Constant,
        Kind::Condition,
        Kind::Swap,
        Kind::Bypass,
    ];
}

impl fmt::Display for Kind {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        write!(f, "{}", format!("{self:?}").to_lowercase())
    }
}

/// One mutant: whole lines of the Verilog replaced (by index from 0).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Mutant {
    pub kind: Kind,
    /// The module the lines are in.
    pub module: String,
    pub edits: Vec<(usize, String)>,
}

impl Mutant {
    /// The Verilog with this mutant's lines replaced.
    pub fn apply(&self, verilog: &str) -> String {
        let mut lines: Vec<&str> = verilog.lines().collect();
        for (at, line) in &self.edits {
            lines[*at] = line;
        }
        let mut out = lines.join("\n");
        out.push('\n');
        out
    }

    /// The same mutant in `to`, a design that holds this mutant's module of `from` under the
    /// name `name` (a block's own Verilog): the same lines of that module, if they read the same
    /// there (a line naming a submodule differs, but no mutant changes one).
    pub fn moved(&self, from: &str, to: &str, name: &str) -> Option<Mutant> {
        let start = |verilog: &str, module: &str| {
            let head = format!("module {module}(");
            verilog.lines().position(|l| l.starts_with(&head))
        };
        let (here, there) = (start(from, &self.module)?, start(to, name)?);
        let (from_lines, to_lines): (Vec<&str>, Vec<&str>) =
            (from.lines().collect(), to.lines().collect());
        let edits = self
            .edits
            .iter()
            .map(|(at, line)| {
                let moved = there + (at - here);
                (to_lines.get(moved) == Some(&from_lines[*at])).then(|| (moved, line.clone()))
            })
            .collect::<Option<Vec<_>>>()?;
        Some(Mutant {
            kind: self.kind,
            module: name.to_string(),
            edits,
        })
    }

    /// `module:line kind: `old` -> `new``, for each replaced line (lines counted from 1).
    pub fn describe(&self, verilog: &str) -> String {
        let lines: Vec<&str> = verilog.lines().collect();
        let edits: Vec<String> = self
            .edits
            .iter()
            .map(|(at, line)| format!("`{}` -> `{}`", lines[*at].trim(), line.trim()))
            .collect();
        format!(
            "{} line {} {}: {}",
            self.module,
            self.edits[0].0 + 1,
            self.kind,
            edits.join(", ")
        )
    }
}

/// Every mutant of `verilog`, in the order of its lines.
pub fn mutants(verilog: &str) -> Vec<Mutant> {
    let mut out = Vec::new();
    let mut module = String::new();
    let mut widths: HashMap<String, usize> = HashMap::new();
    let mut update = false;
    // The previous line's plain assignment `lhs = name;`, a candidate for a swap.
    let mut previous: Option<(usize, Assignment)> = None;
    let lines: Vec<&str> = verilog.lines().collect();
    for (at, &line) in lines.iter().enumerate() {
        let trimmed = line.trim();
        let indent = &line[..line.len() - line.trim_start().len()];
        let mut push = |kind, text: String| {
            out.push(Mutant {
                kind,
                module: module.clone(),
                edits: vec![(at, format!("{indent}{text}"))],
            })
        };
        let mut assignment = None;
        if let Some(rest) = trimmed.strip_prefix("module ") {
            module = rest.split('(').next().unwrap_or(rest).to_string();
            widths.clear();
            update = false;
        } else if trimmed.starts_with("endmodule") {
            update = false;
        } else if trimmed.starts_with("// Update code") {
            update = true;
        } else if !update {
            if let Some((name, bits)) = declaration(trimmed) {
                widths.insert(name, bits);
            }
            if trimmed.starts_with("localparam ") {
                for (text, kind) in
                    expression_mutants(trimmed, trimmed.find('=').map_or(0, |e| e + 1))
                {
                    push(kind, text);
                }
            }
        } else if trimmed == "always @(posedge clock) begin" {
            push(Kind::Bypass, "always @(*) begin".into());
        } else if let Some(cond) = condition(trimmed) {
            let (open, close) = cond;
            push(
                Kind::Condition,
                format!(
                    "{}!({}){}",
                    &trimmed[..open],
                    &trimmed[open..close],
                    &trimmed[close..]
                ),
            );
            for (text, kind) in expression_mutants(&trimmed[..close], open) {
                push(kind, format!("{text}{}", &trimmed[close..]));
            }
        } else if let Some(a) = assign(trimmed) {
            if !a.rhs_text(trimmed).eq_ignore_ascii_case("clock") {
                for (text, kind) in expression_mutants(trimmed, a.rhs) {
                    push(kind, text);
                }
            }
            assignment = Some(a);
        }
        // Two neighbouring plain assignments of equal width, not rust-hdl's defaults
        // (`x$d = x$q`, which the block's own code overrides), swapped.
        if let (Some(a), Some((before, b))) = (&assignment, &previous) {
            let (lhs_a, rhs_a) = (a.lhs_text(trimmed), a.rhs_text(trimmed));
            let prev_line = lines[*before];
            let prev_trim = prev_line.trim();
            let (lhs_b, rhs_b) = (b.lhs_text(prev_trim), b.rhs_text(prev_trim));
            let plain = |s: &str| {
                !s.is_empty()
                    && s.chars()
                        .all(|c| c.is_alphanumeric() || c == '_' || c == '$')
            };
            let default = |lhs: &str, rhs: &str| {
                lhs.strip_suffix("$d")
                    .is_some_and(|r| rhs.strip_suffix("$q") == Some(r))
            };
            if plain(rhs_a)
                && plain(rhs_b)
                && rhs_a != rhs_b
                && rhs_a != "clock"
                && !default(lhs_a, rhs_a)
                && !default(lhs_b, rhs_b)
                && widths.contains_key(lhs_a)
                && widths.get(lhs_a) == widths.get(lhs_b)
            {
                let indent_b = &prev_line[..prev_line.len() - prev_line.trim_start().len()];
                out.push(Mutant {
                    kind: Kind::Swap,
                    module: module.clone(),
                    edits: vec![
                        (
                            *before,
                            format!("{indent_b}{} {rhs_a};", &prev_trim[..b.rhs]),
                        ),
                        (at, format!("{indent}{} {rhs_b};", &trimmed[..a.rhs])),
                    ],
                });
            }
        }
        previous = assignment.map(|a| (at, a));
    }
    out
}

/// A statement `lhs = rhs;` or `lhs <= rhs;`: where the right-hand side starts, and the
/// length of the left-hand side.
#[derive(Clone, Copy, Debug)]
struct Assignment {
    lhs_end: usize,
    rhs: usize,
}

impl Assignment {
    fn lhs_text<'a>(&self, line: &'a str) -> &'a str {
        line[..self.lhs_end]
            .trim()
            .trim_start_matches("assign ")
            .trim()
    }
    fn rhs_text<'a>(&self, line: &'a str) -> &'a str {
        line[self.rhs..].trim().trim_end_matches(';').trim()
    }
}

fn assign(line: &str) -> Option<Assignment> {
    if !line.ends_with(';') || line.starts_with("for ") || line.starts_with("localparam") {
        return None;
    }
    let body = line.strip_prefix("assign ").unwrap_or(line);
    let offset = line.len() - body.len();
    // The left-hand side: a name with an optional bit select.
    let end = body
        .find(|c: char| !(c.is_alphanumeric() || "_$[]: ".contains(c)))
        .unwrap_or(body.len());
    let lhs = body[..end].trim_end();
    if lhs.is_empty() || lhs.contains(' ') && !lhs.contains('[') {
        return None;
    }
    let after = &body[end..];
    let op = if after.starts_with("<=") {
        2
    } else if after.starts_with('=') && !after.starts_with("==") {
        1
    } else {
        return None;
    };
    Some(Assignment {
        lhs_end: offset + end,
        rhs: offset + end + op,
    })
}

/// `if (...) begin` or `end else if (...) begin`: the span of the condition inside the parens.
fn condition(line: &str) -> Option<(usize, usize)> {
    let open = if line.starts_with("if (") {
        4
    } else if line.starts_with("end else if (") {
        13
    } else {
        return None;
    };
    let close = line.rfind(") begin").filter(|&c| c > open)?;
    Some((open, close))
}

/// A declaration `input wire [h:l] name;`, `reg name;`, ...: its name and width.
fn declaration(line: &str) -> Option<(String, usize)> {
    let body = line.strip_suffix(';')?;
    let mut words = body.split_whitespace().peekable();
    let first = *words.peek()?;
    if !["input", "output", "reg", "wire"].contains(&first) {
        return None;
    }
    let words: Vec<&str> = words
        .filter(|w| !["input", "output", "reg", "wire", "signed"].contains(w))
        .collect();
    match words.as_slice() {
        [name] => Some((name.to_string(), 1)),
        [range, name] if range.starts_with('[') => {
            let (h, l) = range.trim_matches(['[', ']']).split_once(':')?;
            let bits = h.parse::<usize>().ok()? - l.parse::<usize>().ok()? + 1;
            Some((name.to_string(), bits))
        }
        _ => None,
    }
}

/// The mutants of the expression in `line` from byte `from` on: each the whole line with one
/// operator exchanged, one `~`/`!` removed, or one sized constant moved by one.
fn expression_mutants(line: &str, from: usize) -> Vec<(String, Kind)> {
    let mut out = Vec::new();
    let bytes = line.as_bytes();
    let mut k = from;
    let mut edit = |at: usize, len: usize, new: &str, kind| {
        out.push((format!("{}{new}{}", &line[..at], &line[at + len..]), kind));
    };
    while k < bytes.len() {
        let c = bytes[k] as char;
        if c.is_ascii_alphabetic() || c == '_' || c == '$' {
            // A name (or `$signed`): skip it.
            while k < bytes.len() && (bytes[k].is_ascii_alphanumeric() || b"_$".contains(&bytes[k]))
            {
                k += 1;
            }
            continue;
        }
        if c.is_ascii_digit() {
            let start = k;
            while k < bytes.len() && (bytes[k].is_ascii_alphanumeric() || b"'_".contains(&bytes[k]))
            {
                k += 1;
            }
            if let Some(text) = constant_plus_one(&line[start..k]) {
                edit(start, k - start, &text, Kind::Constant);
            }
            continue;
        }
        let rest = &line[k..];
        // Longest operators first; part selects (`+:`, `-:`) are not operators here.
        let table: [(&str, &[(&str, Kind)]); 20] = [
            (">>>", &[(">>", Kind::Shift)]),
            ("<<", &[(">>", Kind::Shift)]),
            (">>", &[("<<", Kind::Shift)]),
            ("<=", &[("<", Kind::Compare)]),
            (">=", &[(">", Kind::Compare)]),
            ("==", &[("!=", Kind::Compare)]),
            ("!=", &[("==", Kind::Compare)]),
            ("&&", &[("||", Kind::Logic)]),
            ("||", &[("&&", Kind::Logic)]),
            ("+:", &[]),
            ("-:", &[]),
            ("<", &[("<=", Kind::Compare)]),
            (">", &[(">=", Kind::Compare)]),
            ("+", &[("-", Kind::Arithmetic)]),
            ("-", &[("+", Kind::Arithmetic)]),
            ("&", &[("|", Kind::Logic)]),
            ("|", &[("&", Kind::Logic)]),
            ("^", &[("|", Kind::Logic)]),
            ("~", &[("", Kind::Invert)]),
            ("!", &[("", Kind::Invert)]),
        ];
        match table.iter().find(|(op, _)| rest.starts_with(op)) {
            Some((op, news)) => {
                for (new, kind) in news.iter() {
                    edit(k, op.len(), new, *kind);
                }
                k += op.len();
            }
            None => k += c.len_utf8(),
        }
    }
    out
}

/// A sized constant (`18'h3ffff`, `1'b0`, `32'd7`) one more, or at its largest one less, in
/// the same base and width; `None` for anything else (plain integers index loops and arrays).
fn constant_plus_one(text: &str) -> Option<String> {
    let (width, rest) = text.split_once('\'')?;
    let width: u32 = width.parse().ok()?;
    let (base, radix) = match rest.chars().next()? {
        'h' => ('h', 16),
        'd' => ('d', 10),
        'b' => ('b', 2),
        _ => return None,
    };
    let value = u128::from_str_radix(&rest[1..].replace('_', ""), radix).ok()?;
    if width == 0 || width > 127 {
        return None;
    }
    let new = if value + 1 < 1u128 << width {
        value + 1
    } else {
        value.checked_sub(1)?
    };
    let digits = match radix {
        16 => format!("{new:x}"),
        10 => format!("{new}"),
        _ => format!("{new:b}"),
    };
    Some(format!("{width}'{base}{digits}"))
}
