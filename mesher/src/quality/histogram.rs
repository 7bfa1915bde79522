//! Histograms with the bins of the paper's figures (§8): `Q_K` histograms (Figs. 16-17)
//! and normalised edge-length histograms (Figs. 13-15).
//!
//! A histogram has `n` bins given by their lower edges `e_0 < ... < e_{n-1}`: bin `i` is
//! `[e_i, e_{i+1})` and the last bin is `[e_{n-1}, inf)`. Values below `e_0` fall in the
//! first bin (for `Q_K` they are `1 - epsilon` from round-off; lengths are never
//! negative). NaN values are counted apart in `invalid`. Only finite numbers are stored,
//! so the type serialises to plain JSON.

use serde::{Deserialize, Serialize};

/// Lower edges of the paper's `Q_K` bins: `[1,2) [2,3) ... [9,10) [10,inf)`.
pub const QUALITY_BIN_EDGES: [f64; 10] = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0, 10.0];

/// Lower edges of the paper's normalised-length bins: `[0,.2) [.2,.4) [.4,.6) [.6,.8)
/// [.8,1) [1,1.25) [1.25,1.67) [1.67,2.5) [2.5,5) [5,inf)`. The edges above 1 are the
/// exact reciprocals of those below (1.67 is `1/0.6`), so a length and its reciprocal
/// fall in mirror bins, i.e. the bins are those of the edge quality `min(l, 1/l)`.
pub const LENGTH_BIN_EDGES: [f64; 10] = [0.0, 0.2, 0.4, 0.6, 0.8, 1.0, 1.25, 1.0 / 0.6, 2.5, 5.0];

const LENGTH_BIN_LABELS: [&str; 10] = [
    "[0,0.2)",
    "[0.2,0.4)",
    "[0.4,0.6)",
    "[0.6,0.8)",
    "[0.8,1)",
    "[1,1.25)",
    "[1.25,1.67)",
    "[1.67,2.5)",
    "[2.5,5)",
    "[5,inf)",
];

/// A histogram over fixed bins (see the module docs for the bin rule).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Histogram {
    /// Lower edge of each bin; the last bin is unbounded above.
    pub edges: Vec<f64>,
    /// Human-readable label of each bin, e.g. `"[1,2)"`, `"[10,inf)"`.
    pub labels: Vec<String>,
    /// Count per bin.
    pub counts: Vec<u64>,
    /// NaN values, not in any bin.
    pub invalid: u64,
}

impl Histogram {
    /// Empty histogram over bins with the given increasing lower edges and labels.
    /// Labels are generated as `[e_i,e_{i+1})` when `labels` is `None`.
    pub fn new(edges: &[f64], labels: Option<&[&str]>) -> Histogram {
        let n = edges.len();
        let labels = match labels {
            Some(l) => l.iter().map(|s| s.to_string()).collect(),
            None => (0..n)
                .map(|i| match edges.get(i + 1) {
                    Some(hi) => format!("[{},{})", edges[i], hi),
                    None => format!("[{},inf)", edges[i]),
                })
                .collect(),
        };
        Histogram {
            edges: edges.to_vec(),
            labels,
            counts: vec![0; n],
            invalid: 0,
        }
    }

    /// Empty histogram with the paper's `Q_K` bins.
    pub fn quality() -> Histogram {
        Histogram::new(&QUALITY_BIN_EDGES, None)
    }

    /// Empty histogram with the paper's normalised-length bins.
    pub fn length() -> Histogram {
        Histogram::new(&LENGTH_BIN_EDGES, Some(&LENGTH_BIN_LABELS))
    }

    /// Index of the bin of `x` (`None` for NaN or a histogram without bins).
    #[inline]
    pub fn bin(&self, x: f64) -> Option<usize> {
        if x.is_nan() || self.edges.is_empty() {
            return None;
        }
        Some(self.edges.partition_point(|&e| e <= x).saturating_sub(1))
    }

    /// Counts one value.
    #[inline]
    pub fn add(&mut self, x: f64) {
        match self.bin(x) {
            Some(i) => self.counts[i] += 1,
            None => self.invalid += 1,
        }
    }

    /// Number of binned values (excluding `invalid`).
    pub fn total(&self) -> u64 {
        self.counts.iter().sum()
    }

    /// Adds the counts of `other`, which must have the same bins.
    pub fn merge(&mut self, other: &Histogram) {
        debug_assert_eq!(self.edges, other.edges);
        for (c, o) in self.counts.iter_mut().zip(&other.counts) {
            *c += o;
        }
        self.invalid += other.invalid;
    }
}

/// Serde helper for `f64` fields that may be infinite or NaN (JSON has no such numbers):
/// finite values are numbers, the others the strings `"inf"`, `"-inf"`, `"NaN"`. Use with
/// `#[serde(with = "crate::quality::histogram::nonfinite")]`.
pub mod nonfinite {
    use serde::{de::Error, Deserialize, Deserializer, Serializer};

    #[derive(Deserialize)]
    #[serde(untagged)]
    enum Repr {
        Num(f64),
        Str(String),
    }

    /// Serialises `v`.
    pub fn serialize<S: Serializer>(v: &f64, s: S) -> Result<S::Ok, S::Error> {
        if v.is_finite() {
            s.serialize_f64(*v)
        } else if v.is_nan() {
            s.serialize_str("NaN")
        } else if *v > 0.0 {
            s.serialize_str("inf")
        } else {
            s.serialize_str("-inf")
        }
    }

    /// Deserialises a number or one of the strings written by [`serialize`].
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
        match Repr::deserialize(d)? {
            Repr::Num(x) => Ok(x),
            Repr::Str(s) => match s.as_str() {
                "inf" | "+inf" | "Infinity" => Ok(f64::INFINITY),
                "-inf" | "-Infinity" => Ok(f64::NEG_INFINITY),
                "NaN" | "nan" => Ok(f64::NAN),
                _ => Err(D::Error::custom(format!("not a number: {s:?}"))),
            },
        }
    }

    /// The same for `Option<f64>` (`None` is `null`).
    pub mod option {
        use serde::{Deserialize, Deserializer, Serializer};

        /// Serialises `v`.
        pub fn serialize<S: Serializer>(v: &Option<f64>, s: S) -> Result<S::Ok, S::Error> {
            match v {
                Some(x) => super::serialize(x, s),
                None => s.serialize_none(),
            }
        }

        /// Deserialises `null`, a number or a non-finite string.
        pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Option<f64>, D::Error> {
            #[derive(Deserialize)]
            struct W(#[serde(with = "super")] f64);
            Ok(Option::<W>::deserialize(d)?.map(|W(x)| x))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quality_bins() {
        let mut h = Histogram::quality();
        assert_eq!(h.labels[0], "[1,2)");
        assert_eq!(h.labels[9], "[10,inf)");
        for x in [
            1.0,
            1.999,
            2.0,
            9.99,
            10.0,
            1e300,
            f64::INFINITY,
            1.0 - 1e-15,
            f64::NAN,
        ] {
            h.add(x);
        }
        assert_eq!(h.counts, vec![3, 1, 0, 0, 0, 0, 0, 0, 1, 3]);
        assert_eq!((h.invalid, h.total()), (1, 8));
    }

    #[test]
    fn length_bins_mirror() {
        let h = Histogram::length();
        assert_eq!(h.labels[6], "[1.25,1.67)");
        for x in [0.1, 0.3, 0.5, 0.7, 0.9] {
            let (i, j) = (h.bin(x).unwrap(), h.bin(1.0 / x).unwrap());
            assert_eq!(i + j, 9, "{x}");
        }
        assert_eq!(h.bin(0.0), Some(0));
        assert_eq!(h.bin(1.0), Some(5));
        assert_eq!(h.bin(0.999_999), Some(4));
    }

    #[test]
    fn serde_round_trip() {
        let mut h = Histogram::length();
        h.add(0.5);
        h.add(f64::NAN);
        let s = serde_json::to_string(&h).unwrap();
        let back: Histogram = serde_json::from_str(&s).unwrap();
        assert_eq!(back, h);
    }

    #[test]
    fn nonfinite_round_trip() {
        #[derive(Serialize, Deserialize)]
        struct T {
            #[serde(with = "nonfinite")]
            a: f64,
            #[serde(with = "nonfinite::option")]
            b: Option<f64>,
            #[serde(with = "nonfinite::option")]
            c: Option<f64>,
        }
        let t = T {
            a: f64::INFINITY,
            b: Some(f64::NAN),
            c: None,
        };
        let s = serde_json::to_string(&t).unwrap();
        assert_eq!(s, r#"{"a":"inf","b":"NaN","c":null}"#);
        let back: T = serde_json::from_str(&s).unwrap();
        assert_eq!(back.a, f64::INFINITY);
        assert!(back.b.unwrap().is_nan() && back.c.is_none());
        let t: T = serde_json::from_str(r#"{"a":2.5,"b":1.0,"c":"-inf"}"#).unwrap();
        assert_eq!((t.a, t.b, t.c), (2.5, Some(1.0), Some(f64::NEG_INFINITY)));
    }
}
