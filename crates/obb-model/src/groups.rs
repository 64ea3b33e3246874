//! Group-pair masks: which pairs of object groups a detection reports.

use std::fmt;
use std::str::FromStr;

/// Which unordered group pairs {g, h} are wanted. In configuration files it is the same string
/// as on the command line.
#[derive(Clone, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(try_from = "String", into = "String")]
pub enum GroupMask {
    /// Every pair of boxes.
    #[default]
    All,
    /// Only boxes of different groups (tissue-instrument, instrument-instrument).
    Cross,
    /// Only the listed group pairs, each stored as (min, max), sorted.
    Pairs(Vec<(u32, u32)>),
}

impl GroupMask {
    #[inline]
    pub fn allows(&self, g: u32, h: u32) -> bool {
        match self {
            GroupMask::All => true,
            GroupMask::Cross => g != h,
            GroupMask::Pairs(list) => list.contains(&(g.min(h), g.max(h))),
        }
    }
}

impl FromStr for GroupMask {
    type Err = String;

    /// `all`, `cross`, or a comma-separated list of group pairs such as `0-1,0-2,1-2` (`1-1`
    /// selects the pairs inside group 1).
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.trim() {
            "all" => return Ok(GroupMask::All),
            "cross" => return Ok(GroupMask::Cross),
            _ => {}
        }
        let mut list = Vec::new();
        for item in s.split(',') {
            let (g, h) = item.trim().split_once('-').ok_or_else(|| {
                format!("group mask `{s}`: `{item}` is not a pair like 0-1 (or use `all`, `cross`)")
            })?;
            let parse = |v: &str| {
                v.trim().parse::<u32>().map_err(|_| {
                    format!("group mask `{s}`: `{v}` in `{item}` is not a group number")
                })
            };
            let (g, h) = (parse(g)?, parse(h)?);
            list.push((g.min(h), g.max(h)));
        }
        list.sort_unstable();
        list.dedup();
        Ok(GroupMask::Pairs(list))
    }
}

impl fmt::Display for GroupMask {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            GroupMask::All => write!(f, "all"),
            GroupMask::Cross => write!(f, "cross"),
            GroupMask::Pairs(list) => {
                let items: Vec<String> = list.iter().map(|(g, h)| format!("{g}-{h}")).collect();
                write!(f, "{}", items.join(","))
            }
        }
    }
}

impl TryFrom<String> for GroupMask {
    type Error = String;

    fn try_from(s: String) -> Result<Self, Self::Error> {
        s.parse()
    }
}

impl From<GroupMask> for String {
    fn from(m: GroupMask) -> String {
        m.to_string()
    }
}
