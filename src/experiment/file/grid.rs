//! A frequency grid as files give it: a list, or a range with a step or a count.

use serde::Deserialize;

/// Frequencies: a table `{ start, stop, points or step }`, or a list of values. (Read by
/// hand: a derived struct would also take an array as its fields in order, so that
/// `[30.0, 40.0, 50]` would silently be a grid of 50 points from 30 to 40 Hz.)
#[derive(Debug)]
pub enum RawGrid {
    /// Evenly spaced.
    Range(RawRange),
    /// Each value, Hz.
    List(Vec<f64>),
}

impl<'de> Deserialize<'de> for RawGrid {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<RawGrid, D::Error> {
        use serde::de::value::{MapAccessDeserializer, SeqAccessDeserializer};
        struct Either;
        impl<'de> serde::de::Visitor<'de> for Either {
            type Value = RawGrid;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a grid { start, stop, points or step } or a list of frequencies (Hz)")
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(self, seq: A) -> std::result::Result<RawGrid, A::Error> {
                Vec::<f64>::deserialize(SeqAccessDeserializer::new(seq)).map(RawGrid::List)
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(self, map: A) -> std::result::Result<RawGrid, A::Error> {
                RawRange::deserialize(MapAccessDeserializer::new(map)).map(RawGrid::Range)
            }
        }
        d.deserialize_any(Either)
    }
}

/// An evenly spaced grid: `start`, `stop` and either `points` or `step`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawRange {
    /// First frequency, Hz.
    pub start: f64,
    /// Last frequency, Hz.
    pub stop: f64,
    #[serde(default)]
    /// Number of points (or `step`).
    pub points: Option<i64>,
    #[serde(default)]
    /// Spacing, Hz (or `points`).
    pub step: Option<f64>,
}
