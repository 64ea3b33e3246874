//! Recorded frames for `obbcd replay`: a compact binary format and JSON lines, both a sequence
//! of `FrameUpdate`s (README, "File formats").
//!
//! Binary, little endian: the 8 bytes `OBBFRM01`, then per frame `t_ms` (f64), the number of
//! replaced groups (u32) and the groups (u32 each), the number of boxes (u32), and per box 64
//! bytes: center (3 f32), axes (9 f32, one axis after the other), half-lengths (3 f32), group
//! (u32). Single precision is what a controller sends; it widens to f64 exactly.

use anyhow::{bail, Context, Result};
use obb_model::generate::FrameUpdate;
use obb_model::Obb;
use std::io::{BufRead, BufReader, BufWriter, Read, Write};
use std::path::Path;

const MAGIC: &[u8; 8] = b"OBBFRM01";
/// Most groups a frame may replace, and most boxes: bounds on what a corrupt count makes us
/// allocate.
const MAX_GROUPS: u32 = 1 << 16;
const MAX_BOXES: u32 = 1 << 28;

/// Whether `path` names a JSON lines file (`.jsonl`); anything else is binary.
fn is_jsonl(path: &Path) -> bool {
    path.extension().is_some_and(|e| e == "jsonl")
}

/// Writes frames one at a time, in the format the file's extension says.
pub struct FrameWriter {
    w: BufWriter<std::fs::File>,
    jsonl: bool,
}

impl FrameWriter {
    pub fn create(path: &Path) -> Result<FrameWriter> {
        let file = std::fs::File::create(path)
            .with_context(|| format!("cannot write {}", path.display()))?;
        let mut w = BufWriter::new(file);
        let jsonl = is_jsonl(path);
        if !jsonl {
            w.write_all(MAGIC)?;
        }
        Ok(FrameWriter { w, jsonl })
    }

    pub fn write(&mut self, f: &FrameUpdate) -> Result<()> {
        let w = &mut self.w;
        if self.jsonl {
            serde_json::to_writer(&mut *w, f)?;
            w.write_all(b"\n")?;
            return Ok(());
        }
        w.write_all(&f.t_ms.to_le_bytes())?;
        w.write_all(&(f.replace.len() as u32).to_le_bytes())?;
        for g in &f.replace {
            w.write_all(&g.to_le_bytes())?;
        }
        w.write_all(&(f.obbs.len() as u32).to_le_bytes())?;
        for b in &f.obbs {
            let floats = b
                .center
                .iter()
                .chain(b.axes.iter().flatten())
                .chain(&b.half);
            for v in floats {
                w.write_all(&(*v as f32).to_le_bytes())?;
            }
            w.write_all(&b.group.to_le_bytes())?;
        }
        Ok(())
    }

    pub fn finish(mut self) -> Result<()> {
        Ok(self.w.flush()?)
    }
}

/// Reads frames one at a time, each checked (`check_frame`); errors name the file and the frame.
pub struct FrameReader {
    r: BufReader<std::fs::File>,
    jsonl: bool,
    name: String,
    /// Frames read so far, and lines (JSON lines).
    frames: usize,
    line: usize,
}

impl FrameReader {
    pub fn open(path: &Path) -> Result<FrameReader> {
        let file =
            std::fs::File::open(path).with_context(|| format!("cannot read {}", path.display()))?;
        let mut r = BufReader::new(file);
        let name = path.display().to_string();
        let jsonl = is_jsonl(path);
        if !jsonl {
            let mut magic = [0u8; 8];
            r.read_exact(&mut magic).with_context(|| {
                format!("{name} is not an obbcd frame file: shorter than its 8-byte header")
            })?;
            if &magic != MAGIC {
                bail!("{name} is not an obbcd frame file: it does not start with OBBFRM01");
            }
        }
        Ok(FrameReader {
            r,
            jsonl,
            name,
            frames: 0,
            line: 0,
        })
    }

    /// The next frame, or None at the end of the file.
    pub fn next_frame(&mut self) -> Result<Option<FrameUpdate>> {
        let k = self.frames;
        let frame = if self.jsonl {
            self.next_line()
                .with_context(|| format!("{} line {}", self.name, self.line))?
        } else {
            read_binary(&mut self.r, k).with_context(|| self.name.clone())?
        };
        let Some(frame) = frame else {
            if k == 0 {
                bail!("{} holds no frame", self.name);
            }
            return Ok(None);
        };
        check_frame(&frame).with_context(|| format!("{}: frame {k}", self.name))?;
        self.frames += 1;
        Ok(Some(frame))
    }

    fn next_line(&mut self) -> Result<Option<FrameUpdate>> {
        let mut line = String::new();
        loop {
            line.clear();
            self.line += 1;
            if self.r.read_line(&mut line)? == 0 {
                return Ok(None);
            }
            if !line.trim().is_empty() {
                return Ok(Some(serde_json::from_str(&line)?));
            }
        }
    }
}

/// Frame `k` of a binary file, or None at a clean end (between frames).
fn read_binary(r: &mut impl Read, k: usize) -> Result<Option<FrameUpdate>> {
    let mut t = [0u8; 8];
    match r.read(&mut t[..1])? {
        0 => return Ok(None),
        _ => r.read_exact(&mut t[1..]).context(truncated(k))?,
    }
    let mut u32_of = |what: &str, max: u32| -> Result<u32> {
        let mut b = [0u8; 4];
        r.read_exact(&mut b).context(truncated(k))?;
        let v = u32::from_le_bytes(b);
        if v > max {
            bail!("frame {k}: {what} {v} is above {max}");
        }
        Ok(v)
    };
    let groups = u32_of("group count", MAX_GROUPS)?;
    let replace = (0..groups)
        .map(|_| u32_of("group", u32::MAX))
        .collect::<Result<Vec<_>>>()?;
    let count = u32_of("box count", MAX_BOXES)?;
    let mut obbs = Vec::with_capacity(count.min(1 << 20) as usize);
    let mut record = [0u8; 64];
    for _ in 0..count {
        r.read_exact(&mut record).context(truncated(k))?;
        let word = |i: usize| -> [u8; 4] { std::array::from_fn(|b| record[4 * i + b]) };
        let f = |i: usize| f64::from(f32::from_le_bytes(word(i)));
        obbs.push(Obb {
            center: [f(0), f(1), f(2)],
            axes: [[f(3), f(4), f(5)], [f(6), f(7), f(8)], [f(9), f(10), f(11)]],
            half: [f(12), f(13), f(14)],
            group: u32::from_le_bytes(word(15)),
        });
    }
    Ok(Some(FrameUpdate {
        t_ms: f64::from_le_bytes(t),
        replace,
        obbs,
    }))
}

fn truncated(k: usize) -> String {
    format!("frame {k} is cut short")
}

/// A frame's boxes are valid and each belongs to a group the frame replaces.
fn check_frame(f: &FrameUpdate) -> Result<()> {
    for (i, b) in f.obbs.iter().enumerate() {
        b.validate(i)?;
        if !f.replace.contains(&b.group) {
            bail!(
                "box {i} has group {}, not one of the groups the frame replaces {:?}",
                b.group,
                f.replace
            );
        }
    }
    Ok(())
}
