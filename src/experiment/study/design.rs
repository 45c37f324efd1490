//! The samples of a study: a full grid of listed values, or a quasi-random design (scrambled
//! Sobol, Latin hypercube) over ranges. Every sample is a pure function of its index and the
//! seed, so any share of them can be computed anywhere.

/// The values one varied key takes.
#[derive(Debug, Clone, PartialEq)]
pub enum Domain {
    /// Exactly these values (a grid uses each; a quasi-random design picks among them).
    Values(Vec<f64>),
    /// A continuous range; `count` points for a grid (ends included), `log` spacing on a
    /// logarithmic scale.
    Range {
        /// First value.
        start: f64,
        /// Last value.
        stop: f64,
        /// Grid points (ends included).
        count: Option<usize>,
        /// Logarithmic spacing.
        log: bool,
    },
}

impl Domain {
    /// The grid values (a range needs its count).
    pub fn grid(&self) -> Option<Vec<f64>> {
        match self {
            Domain::Values(v) => Some(v.clone()),
            Domain::Range { start, stop, count, log } => {
                let n = (*count)?;
                Some(
                    (0..n)
                        .map(|i| {
                            let u = if n == 1 { 0.0 } else { i as f64 / (n - 1) as f64 };
                            at(*start, *stop, *log, u)
                        })
                        .collect(),
                )
            }
        }
    }

    /// The value at `u` in [0, 1).
    pub fn at(&self, u: f64) -> f64 {
        match self {
            Domain::Values(v) => v[((u * v.len() as f64) as usize).min(v.len() - 1)],
            Domain::Range { start, stop, log, .. } => at(*start, *stop, *log, u),
        }
    }
}

fn at(start: f64, stop: f64, log: bool, u: f64) -> f64 {
    if log {
        start * (stop / start).powf(u)
    } else {
        start + (stop - start) * u
    }
}

/// How samples are drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Design {
    /// Every combination of the varied values (the first varied key changes slowest).
    Grid,
    /// `samples` points of an Owen-scrambled Sobol sequence (sobol_burley), seeded.
    Sobol {
        /// Number of samples.
        samples: usize,
        /// Seed of the scrambling.
        seed: u32,
    },
    /// `samples` points of a Latin hypercube: each range cut into `samples` equal strata,
    /// each stratum used once per key, in a seeded random order, at a seeded random place.
    LatinHypercube {
        /// Number of samples (and strata).
        samples: usize,
        /// Seed of the orders and places.
        seed: u32,
    },
    /// A grid refined where the answer changes (`lattice.rs`): round 0 every `2^levels`-th
    /// value of each key, then `levels` rounds that halve the step where a cell's corners
    /// disagree on `refine`.
    Adaptive {
        /// Halvings of the step after the coarse grid.
        levels: u32,
        /// The answer whose change between corners refines a cell.
        refine: Refine,
    },
}

/// What an adaptive design compares between the corners of a cell.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Refine {
    /// Whether every claim holds (the edge of the region where the whole claim set holds).
    All,
    /// The number of claims that hold.
    Count,
    /// Every claim's outcome (holds, fails, not evaluable, unsettled).
    Outcomes,
    /// One claim's outcome (its check number in the study's table).
    Check(usize),
}

impl Refine {
    /// The name used in files and manifests.
    pub fn name(self) -> String {
        match self {
            Refine::All => "all".into(),
            Refine::Count => "count".into(),
            Refine::Outcomes => "outcomes".into(),
            Refine::Check(k) => format!("check {k}"),
        }
    }
}

impl Design {
    /// The name used in files.
    pub fn name(self) -> &'static str {
        match self {
            Design::Grid => "grid",
            Design::Sobol { .. } => "sobol",
            Design::LatinHypercube { .. } => "latin_hypercube",
            Design::Adaptive { .. } => "adaptive",
        }
    }

    /// The fine lattice of an adaptive design over `domains` (`None` for other designs, or
    /// when a domain has no grid of `2^levels * k + 1` values: validation refuses those).
    pub fn lattice(self, domains: &[Domain]) -> Option<super::lattice::Lattice> {
        let Design::Adaptive { levels, .. } = self else {
            return None;
        };
        let sizes: Option<Vec<usize>> = domains.iter().map(|d| d.grid().map(|g| g.len())).collect();
        super::lattice::Lattice::new(sizes?, levels).ok()
    }
}

/// The values of a lattice point (`point[k]` indexes key `k`'s grid).
pub fn values_at(domains: &[Domain], point: &[usize]) -> Vec<f64> {
    domains.iter().zip(point).map(|(d, &i)| d.grid().map_or(f64::NAN, |g| g[i])).collect()
}

/// The points of `design` over `domains` (one value per domain each); an adaptive design's
/// round 0 (the coarse grid).
pub fn points(design: Design, domains: &[Domain]) -> Vec<Vec<f64>> {
    match design {
        Design::Adaptive { .. } => design
            .lattice(domains)
            .map(|l| l.coarse().iter().map(|p| values_at(domains, p)).collect())
            .unwrap_or_default(),
        Design::Grid => {
            let grids: Vec<Vec<f64>> = domains.iter().map(|d| d.grid().unwrap_or_default()).collect();
            let mut out: Vec<Vec<f64>> = vec![Vec::new()];
            for g in &grids {
                out = out.iter().flat_map(|p| g.iter().map(move |v| [p.as_slice(), &[*v]].concat())).collect();
            }
            out
        }
        Design::Sobol { samples, seed } => (0..samples)
            .map(|i| {
                domains
                    .iter()
                    .enumerate()
                    .map(|(d, dom)| dom.at(f64::from(sobol_burley::sample(i as u32, d as u32, seed))))
                    .collect()
            })
            .collect(),
        Design::LatinHypercube { samples, seed } => {
            let columns: Vec<Vec<f64>> = domains
                .iter()
                .enumerate()
                .map(|(d, dom)| {
                    let mut rng = SplitMix64(u64::from(seed) ^ (0x9e37_79b9_7f4a_7c15_u64.wrapping_mul(d as u64 + 1)));
                    let mut order: Vec<usize> = (0..samples).collect();
                    for i in (1..samples).rev() {
                        let j = (rng.next() % (i as u64 + 1)) as usize;
                        order.swap(i, j);
                    }
                    order.iter().map(|&k| dom.at((k as f64 + rng.unit()) / samples as f64)).collect()
                })
                .collect();
            (0..samples).map(|i| columns.iter().map(|c| c[i]).collect()).collect()
        }
    }
}

/// SplitMix64 (Steele, Lea, Flood 2014): a small seeded generator, the same on every machine.
struct SplitMix64(u64);

impl SplitMix64 {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1), 53 bits.
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_is_the_full_product_first_key_slowest() {
        let d = [Domain::Values(vec![1.0, 2.0]), Domain::Range { start: 0.1, stop: 0.3, count: Some(3), log: false }];
        let p = points(Design::Grid, &d);
        assert_eq!(p.len(), 6);
        assert_eq!(p[0], vec![1.0, 0.1]);
        assert!((p[2][1] - 0.3).abs() < 1e-15);
        assert_eq!(p[3][0], 2.0);
        let log = Domain::Range { start: 0.001, stop: 0.1, count: Some(3), log: true }.grid().unwrap();
        assert!((log[1] - 0.01).abs() < 1e-15);
    }

    #[test]
    fn latin_hypercube_uses_every_stratum_once_and_repeats_with_its_seed() {
        let d = vec![Domain::Range { start: 0.0, stop: 1.0, count: None, log: false }; 2];
        let p = points(Design::LatinHypercube { samples: 10, seed: 7 }, &d);
        for k in 0..2 {
            let mut strata: Vec<usize> = p.iter().map(|x| (x[k] * 10.0) as usize).collect();
            strata.sort_unstable();
            assert_eq!(strata, (0..10).collect::<Vec<_>>());
        }
        assert_eq!(p, points(Design::LatinHypercube { samples: 10, seed: 7 }, &d));
        assert_ne!(p, points(Design::LatinHypercube { samples: 10, seed: 8 }, &d));
    }

    #[test]
    fn sobol_fills_each_half_evenly() {
        let d = vec![Domain::Range { start: 0.0, stop: 1.0, count: None, log: false }; 3];
        let p = points(Design::Sobol { samples: 64, seed: 1 }, &d);
        for k in 0..3 {
            // A (0, m, s)-net in base 2: each half (and quarter) of every axis holds exactly its share.
            for q in 0..4 {
                let n = p.iter().filter(|x| (x[k] * 4.0) as usize == q).count();
                assert_eq!(n, 16, "axis {k} quarter {q}");
            }
        }
    }
}
