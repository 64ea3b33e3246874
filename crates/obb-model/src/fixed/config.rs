//! The hardware configuration: number formats, capacity, broad phase, group mask, lanes. Read
//! from TOML; every key has a default that suits the surgical scene, and an inconsistent
//! configuration is rejected with the key and the reason.

use crate::aabb::Aabb;
use crate::groups::GroupMask;
use crate::scene::Scene;
use serde::{Deserialize, Serialize};
use std::path::Path;
use thiserror::Error;

/// The broad phase the core runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum BroadPhase {
    /// Spatial hash of power-of-two cells, built while the boxes arrive; a box probes the
    /// lists of the cells its AABB covers (docs/hardware.md, "The grid").
    Grid,
    /// Single-axis sweep over the sorted min keys, other axes checked against an AABB table.
    Sweep,
    /// The paper's Algorithm 2: every box between an OBB's min and max key, three axes.
    ImprovedSap,
    /// Every pair.
    Brute,
}

impl std::fmt::Display for BroadPhase {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            BroadPhase::Grid => "grid",
            BroadPhase::Sweep => "sweep",
            BroadPhase::ImprovedSap => "improved-sap",
            BroadPhase::Brute => "brute",
        })
    }
}

impl BroadPhase {
    /// Every broad phase, the default first.
    pub const ALL: [BroadPhase; 4] = [
        BroadPhase::Grid,
        BroadPhase::Sweep,
        BroadPhase::ImprovedSap,
        BroadPhase::Brute,
    ];
}

impl std::str::FromStr for BroadPhase {
    type Err = String;

    /// The names `Display` writes (and the TOML takes).
    fn from_str(s: &str) -> Result<Self, String> {
        BroadPhase::ALL
            .into_iter()
            .find(|b| b.to_string() == s)
            .ok_or_else(|| format!("unknown broad phase `{s}`: grid, sweep, improved-sap or brute"))
    }
}

/// Width of a box's group number in the core: groups 0 to 7.
pub const GROUP_BITS: u32 = 3;
/// The most grid walker lanes (`lanes`).
pub const MAX_LANES: u32 = 8;

/// Operand width of a DSP48E1 multiplier's A port (signed).
pub const DSP_A_BITS: u32 = 25;
/// Operand width of a DSP48E1 multiplier's B port (signed).
pub const DSP_B_BITS: u32 = 18;

/// The configuration of one core. Lengths are integers in units of the LSB `lsb_mm`; rotation
/// entries are signed fixed point Q1.f with f = `rot_bits` - 2 (docs/numerics.md).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct HwConfig {
    /// The length LSB q in mm, a power of two so that quantizing is exact scaling.
    pub lsb_mm: f64,
    /// Width of a center coordinate (signed); every AABB end point must fit it too.
    pub center_bits: u32,
    /// Width of a half-length (unsigned).
    pub half_bits: u32,
    /// Width of a rotation entry (signed Q1.f, f = rot_bits - 2), at most one DSP B port.
    pub rot_bits: u32,
    /// Width of a sort key: the top `key_bits` of an AABB end point, rounded outward.
    pub key_bits: u32,
    /// Largest deviation from orthonormality (every entry of `A Aᵀ - I`) the core's margins
    /// cover; a box beyond it is rejected on the host.
    pub ortho_tol: f64,
    /// Most OBBs in a frame.
    pub capacity: u32,
    /// The broad phase the core is built with.
    pub broad_phase: BroadPhase,
    /// Which group pairs are reported (`all`, `cross`, or a list like `0-1,0-2,1-2`).
    pub groups: GroupMask,
    /// Grid: walker lanes, each with its own lists, enumerator, walker, key check and test
    /// queue, so that a clock makes up to `lanes` visits (a power of two up to 8; 1 with the other
    /// broad phases). Box `i` is on lane `i mod lanes`. The SAT takes one pair per clock.
    pub lanes: u32,
    /// Digit width of the radix sort.
    pub radix_digit_bits: u32,
    /// Grid: the cell edge in mm, a power of two (at least one key unit is used). Boxes whose
    /// AABB spans more than a cell on some axis take the slow path.
    pub grid_cell_mm: f64,
    /// Grid: buckets per bank are `2^grid_hash_bits`.
    pub grid_hash_bits: u32,
    /// Grid: groups with lists of their own, 0 to `grid_groups - 1`; a box of a higher group
    /// is rejected on the host.
    pub grid_groups: u32,
    /// Grid: groups whose boxes stay in the core between frames (the tissue, rebuilt at about
    /// 25 Hz): an *update* frame loads them (first, before the other groups' boxes) with
    /// everything else; a *haptic* frame streams only the other groups' boxes, which meet the
    /// resident ones in the lists the update left. Empty: every frame loads every box.
    pub resident_groups: Vec<u32>,
    /// Grid: a list per group in each bucket (true), so that a probe walks only the lists of
    /// the groups its own pairs with, or one list for every group (false): the list heads'
    /// memory over `grid_groups`, for a mask that pairs every group with every group (each
    /// list is then walked whole anyway), at the cost of more lists of mixed cells.
    pub grid_group_lists: bool,
    /// Width of the SAT's 15 comparisons: both sides drop their low bits down to this width
    /// when their full width, center_bits + rot_bits + 2, is wider.
    pub sat_bits: u32,
    /// Target clock period in ns, for the ISE constraints (`gen-rtl` writes the UCF).
    pub clock_ns: f64,
    /// Speed grade of the XC6VHX565T for the ISE project (2 means -2).
    pub speed_grade: u32,
}

impl Default for HwConfig {
    /// The surgical scene: ±512 mm at 2^-10 mm (about 1 µm), half-lengths up to 128 mm, 20-bit
    /// sort keys (the paper's narrower width), cross-group pairs, 32,768 OBBs, the grid broad
    /// phase (the fewest clocks on the surgical and uniform scenes, README) with 2 mm cells
    /// (the scene's largest AABB spans 1.71 mm).
    fn default() -> Self {
        HwConfig {
            lsb_mm: 1.0 / 1024.0,
            center_bits: 20,
            half_bits: 17,
            rot_bits: 18,
            key_bits: 20,
            ortho_tol: 1e-5,
            capacity: 32768,
            broad_phase: BroadPhase::Grid,
            groups: GroupMask::Cross,
            lanes: 1,
            radix_digit_bits: 8,
            grid_cell_mm: 2.0,
            grid_hash_bits: 10,
            grid_groups: 3,
            resident_groups: Vec::new(),
            grid_group_lists: true,
            sat_bits: 40,
            clock_ns: 4.0,
            speed_grade: 2,
        }
    }
}

/// The grid's most bucket bits (`grid_hash_bits`): the fingerprint's rows come after them.
pub const MAX_HASH_BITS: u32 = 12;
/// The widest sort keys the grid block takes: its cell coordinates (keys shifted, plus 2) are
/// 23-bit registers (`obb_rtl::grid_cells::COORD`).
pub const MAX_KEY_BITS: u32 = 22;

/// η: the quantized axes' Gram matrix deviates from `2^2f I` by at most `η 2^2f` per entry
/// (docs/numerics.md, "The quantized axes are nearly orthonormal").
pub fn eta(cfg: &HwConfig) -> f64 {
    let two_f = f64::from(1u32 << cfg.frac_bits());
    let tol = cfg.ortho_tol;
    tol + 3f64.sqrt() * (1.0 + tol) / two_f + 0.75 / (two_f * two_f)
}

/// What is wrong with a configuration. Each message states its cause itself (not also chained
/// as `source`, which would print it twice under `{:#}`).
#[derive(Debug, Error)]
pub enum ConfigError {
    #[error("cannot read configuration {path}: {cause}")]
    Io { path: String, cause: std::io::Error },
    #[error("configuration {path} is not valid TOML for obbcd: {cause}")]
    Toml {
        path: String,
        cause: Box<toml::de::Error>,
    },
    #[error("configuration key `{key}`: {problem}")]
    Invalid { key: &'static str, problem: String },
}

/// `value` must be a positive, normal power of two (scaling by it is exact), such as `example`.
fn power_of_two(key: &'static str, value: f64, example: &str) -> Result<(), ConfigError> {
    if value.is_normal() && value > 0.0 && value.to_bits() & ((1 << 52) - 1) == 0 {
        Ok(())
    } else {
        Err(invalid(
            key,
            format!("{value} is not a positive power of two (such as {example})"),
        ))
    }
}

fn invalid(key: &'static str, problem: impl Into<String>) -> ConfigError {
    ConfigError::Invalid {
        key,
        problem: problem.into(),
    }
}

/// `value` must lie in `lo..=hi`.
fn in_range(key: &'static str, value: u32, lo: u32, hi: u32, why: &str) -> Result<(), ConfigError> {
    if (lo..=hi).contains(&value) {
        Ok(())
    } else {
        Err(invalid(
            key,
            format!("{value} is outside {lo}..={hi} ({why})"),
        ))
    }
}

impl HwConfig {
    /// Reads and checks a TOML file.
    pub fn load(path: &Path) -> Result<HwConfig, ConfigError> {
        let shown = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|cause| ConfigError::Io {
            path: shown.clone(),
            cause,
        })?;
        Self::parse(&text, &shown)
    }

    /// Parses and checks TOML text; `origin` names it in errors.
    pub fn parse(text: &str, origin: &str) -> Result<HwConfig, ConfigError> {
        let cfg: HwConfig = toml::from_str(text).map_err(|cause| ConfigError::Toml {
            path: origin.to_string(),
            cause: Box::new(cause),
        })?;
        cfg.validate()?;
        Ok(cfg)
    }

    /// The configuration as TOML (every key).
    pub fn to_toml(&self) -> String {
        toml::to_string(self).expect("a configuration always serialises")
    }

    /// Checks that the formats are consistent and fit the DSP48E1 operands (docs/numerics.md).
    pub fn validate(&self) -> Result<(), ConfigError> {
        power_of_two("lsb_mm", self.lsb_mm, "0.0009765625 = 2^-10")?;
        power_of_two("grid_cell_mm", self.grid_cell_mm, "2")?;
        in_range(
            "grid_hash_bits",
            self.grid_hash_bits,
            1,
            MAX_HASH_BITS,
            "a bank's buckets, one list head per bucket and group",
        )?;
        in_range(
            "grid_groups",
            self.grid_groups,
            1,
            1 << GROUP_BITS,
            "groups are 3 bits in the core",
        )?;
        // The SAT truncates t = T·a to center_bits + 2 bits, one DSP A port.
        in_range(
            "center_bits",
            self.center_bits,
            8,
            DSP_A_BITS - 2,
            "T·a must fit a DSP48E1 A port",
        )?;
        // A half-length enters every radius product on the 18-bit B port, as a positive number.
        in_range(
            "half_bits",
            self.half_bits,
            1,
            (DSP_B_BITS - 1).min(self.center_bits - 1),
            "a half-length is a positive operand of the 18-bit DSP port and fits the center range",
        )?;
        in_range(
            "rot_bits",
            self.rot_bits,
            4,
            DSP_B_BITS,
            "a rotation entry is one 18-bit DSP operand",
        )?;
        in_range(
            "key_bits",
            self.key_bits,
            4,
            self.center_bits,
            "a key is the top bits of an end point",
        )?;
        // Below 1e-12 even exact axes fail the f64 measurement of their own Gram matrix.
        if !(self.ortho_tol.is_finite() && (1e-12..=1e-3).contains(&self.ortho_tol)) {
            return Err(invalid(
                "ortho_tol",
                format!("{} is outside 1e-12..=1e-3", self.ortho_tol),
            ));
        }
        in_range(
            "capacity",
            self.capacity,
            1,
            1 << 20,
            "box indices are 20 bits",
        )?;
        in_range("lanes", self.lanes, 1, MAX_LANES, "the grid's walker lanes")?;
        if !self.lanes.is_power_of_two() {
            return Err(invalid(
                "lanes",
                format!(
                    "{} is not a power of two (a box's lane is its index's low bits)",
                    self.lanes
                ),
            ));
        }
        if self.lanes > 1 && self.broad_phase != BroadPhase::Grid {
            return Err(invalid(
                "lanes",
                format!(
                    "{} with broad phase `{}`: only the grid has several walker lanes",
                    self.lanes, self.broad_phase
                ),
            ));
        }
        in_range(
            "radix_digit_bits",
            self.radix_digit_bits,
            1,
            self.key_bits.min(8),
            "a digit is part of a key, and the hardware keeps one register per bin",
        )?;
        // |t̂| = |T·a| / 2^f <= √3 √(1+η) 2^center_bits must fit the DSP's 25-bit port; only
        // the coarsest rotations (f = 2, η about 0.5) with 23-bit centers fail.
        let t_hat =
            3f64.sqrt() * (1.0 + eta(self)).sqrt() * f64::from(1u32 << self.center_bits) + 1.0;
        if t_hat >= f64::from(1u32 << (DSP_A_BITS - 1)) {
            return Err(invalid(
                "center_bits",
                format!(
                    "{} with rot_bits {}: T·a / 2^f would reach {t_hat:.0}, beyond the \
                     DSP48E1's 25-bit port (use rot_bits of at least 5, or fewer center bits)",
                    self.center_bits, self.rot_bits
                ),
            ));
        }
        if let Some(&g) = self
            .resident_groups
            .iter()
            .find(|&&g| g >= self.grid_groups)
        {
            return Err(invalid(
                "resident_groups",
                format!(
                    "group {g} is beyond the grid's {} groups (`grid_groups`)",
                    self.grid_groups
                ),
            ));
        }
        if !self.resident_groups.is_empty() && self.broad_phase != BroadPhase::Grid {
            return Err(invalid(
                "resident_groups",
                format!(
                    "{:?} with broad phase `{}`: only the grid keeps boxes between frames",
                    self.resident_groups, self.broad_phase
                ),
            ));
        }
        let gg = self.grid_groups;
        let every_pair = (0..gg).all(|g| (0..gg).all(|h| self.groups.allows(g, h)));
        let one_list_fits = every_pair && self.resident_groups.is_empty();
        if !self.grid_group_lists && !one_list_fits {
            return Err(invalid(
                "grid_group_lists",
                format!(
                    "false (one list for every group) needs a mask that pairs every group with \
                     every group and no resident group; `groups` is `{}`",
                    self.groups
                ),
            ));
        }
        if let GroupMask::Pairs(list) = &self.groups {
            if let Some(&(_, h)) = list.iter().find(|&&(_, h)| h >= 1 << GROUP_BITS) {
                return Err(invalid(
                    "groups",
                    format!("group {h} is beyond the core's {} groups", 1 << GROUP_BITS),
                ));
            }
        }
        in_range(
            "sat_bits",
            self.sat_bits,
            16,
            48,
            "the width of the SAT's comparators",
        )?;
        if !(self.clock_ns.is_finite() && (1.0..=100.0).contains(&self.clock_ns)) {
            return Err(invalid(
                "clock_ns",
                format!("{} is outside 1..=100 ns", self.clock_ns),
            ));
        }
        in_range(
            "speed_grade",
            self.speed_grade,
            1,
            3,
            "Virtex-6 speed grades are -1, -2 and -3",
        )?;
        Ok(())
    }

    /// Full width of the SAT's comparisons: |T·L| on a cross axis is below
    /// 2^(center_bits + f + 4) (docs/numerics.md, "Comparison width").
    pub fn sat_full_bits(&self) -> u32 {
        self.center_bits + self.frac_bits() + 4
    }

    /// Bits dropped from both sides of each SAT comparison.
    pub fn sat_shift(&self) -> u32 {
        self.sat_full_bits().saturating_sub(self.sat_bits)
    }

    /// Fraction bits f of a rotation entry (Q1.f).
    pub fn frac_bits(&self) -> u32 {
        self.rot_bits - 2
    }

    /// How many groups a box may be in: `grid_groups` with the grid, else every group the core
    /// knows.
    pub fn groups_allowed(&self) -> u32 {
        match self.broad_phase {
            BroadPhase::Grid => self.grid_groups,
            _ => 1 << GROUP_BITS,
        }
    }

    /// Grid: lists per bucket (and lane): one per group (`grid_groups`), or one for every
    /// group (`grid_group_lists = false`).
    pub fn list_groups(&self) -> u32 {
        match self.grid_group_lists {
            true => self.grid_groups,
            false => 1,
        }
    }

    /// Whether group `g`'s boxes stay in the core between frames (`resident_groups`).
    pub fn is_resident(&self, g: u32) -> bool {
        self.resident_groups.contains(&g)
    }

    /// The pairs a haptic frame reports: `groups` but those of two resident groups, which the
    /// last update frame reported and which no haptic frame changes.
    pub fn haptic_mask(&self) -> GroupMask {
        let all = 1 << GROUP_BITS;
        GroupMask::Pairs(
            (0..all)
                .flat_map(|g| (g..all).map(move |h| (g, h)))
                .filter(|&(g, h)| {
                    self.groups.allows(g, h) && !(self.is_resident(g) && self.is_resident(h))
                })
                .collect(),
        )
    }

    /// Bits dropped from an end point to make its sort key.
    pub fn key_shift(&self) -> u32 {
        self.center_bits - self.key_bits
    }

    /// log2 of the grid's cell edge in key units: `grid_cell_mm` over the key unit
    /// (`lsb_mm · 2^key_shift`), at least one unit and at most the whole key range.
    pub fn grid_cell_bits(&self) -> u32 {
        let exp = |v: f64| ((v.to_bits() >> 52) & 0x7ff) as i64;
        let cell = exp(self.grid_cell_mm) - exp(self.lsb_mm) - i64::from(self.key_shift());
        cell.clamp(0, i64::from(self.key_bits)) as u32
    }

    /// The same configuration with the finest power-of-two LSB at which every box of `scene`
    /// fits: its AABB within half the center range (the rest is room for rounding), its
    /// half-lengths within `half_bits`.
    pub fn fitted(&self, scene: &Scene) -> HwConfig {
        self.fitted_all([scene])
    }

    /// `fitted` for every box of `scenes` at once: the coarsest of their LSBs.
    pub fn fitted_all<'a>(&self, scenes: impl IntoIterator<Item = &'a Scene>) -> HwConfig {
        let mut reach: f64 = 0.0;
        let mut half: f64 = 0.0;
        for o in scenes.into_iter().flat_map(|s| &s.obbs) {
            let b = Aabb::of(o);
            reach = (0..3).fold(reach, |r, x| r.max(b.min[x].abs()).max(b.max[x].abs()));
            half = o.half.iter().fold(half, |h, &v| h.max(v));
        }
        let need = (reach / f64::from(1u32 << (self.center_bits - 2)))
            .max(half / f64::from(1u32 << (self.half_bits - 1)));
        // At least 2^-40 mm: a scene of zero size fits any LSB.
        let exp = need.max(2f64.powi(-40)).log2().ceil() as i32;
        HwConfig {
            lsb_mm: 2f64.powi(exp),
            ..self.clone()
        }
    }

    /// The same configuration with `key_bits` sort keys (and digits no wider than them).
    pub fn with_key_bits(&self, key_bits: u32) -> HwConfig {
        HwConfig {
            key_bits,
            radix_digit_bits: self.radix_digit_bits.min(key_bits),
            ..self.clone()
        }
    }
}
