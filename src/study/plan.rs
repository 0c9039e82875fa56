//! The layout of a study: block cases, work units, shards, and their
//! canonical order.
//!
//! A **case** is one block with its contact properties (aspect × width × e ×
//! friction, in that nesting order). A **unit** is one (intensity level,
//! record) pair: the record is made once and every case is solved on it.
//! Units are numbered level-major, `unit = level · records + record`, and
//! `outcomes.csv` lists units in that order and, within a unit, cases in
//! theirs. Shard K/N owns the units with `unit mod N = K − 1` (round-robin,
//! so every shard gets weak and strong levels alike).
//!
//! A parameter drawn under `[uncertainty]` is one placeholder (NaN) on its
//! axis of cases; each analysis draws its own value ([`Case::analysis`]),
//! from a stream keyed by (seed, record, level, case number), so the draws do
//! not depend on which thread or shard runs the analysis.

use crate::error::{Error, Result};
use crate::outcomes_csv::{CaseKey, Columns};
use crate::solver::{Analysis, Block, Friction};
use crate::spec::{Draw, Intensity, Motions, Study};
use std::fmt;
use std::str::FromStr;

/// One block case of a study.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Case {
    /// Aspect ratio H/B.
    pub aspect: f64,
    /// Base width 2B, m.
    pub width: f64,
    /// Coefficient of restitution e.
    pub restitution: f64,
    /// Friction model.
    pub friction: Friction,
    /// Indices into the study's grids: (aspect, width, restitution, friction).
    pub index: [usize; 4],
    /// Position of the case in canonical order.
    pub number: usize,
}

impl Case {
    /// The analysis of this case on unit `unit` of `study` (block at rest),
    /// and the case columns of its row in `outcomes.csv`: the grid's values,
    /// with the parameters of `[uncertainty]` drawn for this (record, level,
    /// case). Fails only if drawn values make no valid block.
    pub fn analysis(
        &self,
        study: &Study,
        unit: &Unit,
    ) -> crate::error::Result<(CaseKey, Analysis)> {
        let grid = Draw {
            width: self.width,
            aspect: self.aspect,
            restitution: self.restitution,
            friction: self.friction,
        };
        let d = match &study.uncertainty {
            Some(u) => u.draw(grid, unit.record, unit.level, self.number),
            None => grid,
        };
        let block = Block::new(d.width, d.aspect, study.g)?;
        let mut analysis = Analysis::new(block, d.restitution);
        analysis.friction = d.friction;
        let key = CaseKey {
            aspect: d.aspect,
            width: d.width,
            restitution: d.restitution,
            friction: d.friction,
        };
        Ok((key, analysis))
    }

    /// The case columns of this case: the grid's values, NaN for a drawn
    /// parameter (the key every analysis of the case pools to, see
    /// [`CaseKey::pooled`]).
    pub fn key(&self) -> CaseKey {
        CaseKey {
            aspect: self.aspect,
            width: self.width,
            restitution: self.restitution,
            friction: self.friction,
        }
    }
}

/// The optional columns of `study`'s `outcomes.csv`.
pub fn columns(study: &Study) -> Columns {
    Columns {
        pgv: matches!(study.intensity, Intensity::Pgv(_)),
        scale: matches!(study.intensity, Intensity::Scale(_)),
        files: matches!(study.motions, Motions::Files(_)),
        time_in_mode: study.output.time_in_mode,
        stats: study.output.stats,
    }
}

/// Every case of `study`, in canonical order (aspect, then width, then e,
/// then friction).
pub fn cases(study: &Study) -> Vec<Case> {
    let mut out = Vec::new();
    for (ia, &aspect) in study.aspects.iter().enumerate() {
        for (iw, &width) in study.widths.iter().enumerate() {
            for (ie, &restitution) in study.restitutions.iter().enumerate() {
                for (iff, &friction) in study.frictions.iter().enumerate() {
                    out.push(Case {
                        aspect,
                        width,
                        restitution,
                        friction,
                        index: [ia, iw, ie, iff],
                        number: out.len(),
                    });
                }
            }
        }
    }
    out
}

/// A work unit: one intensity level and one record.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Unit {
    /// Global unit number (level-major).
    pub index: usize,
    /// Index of the intensity level.
    pub level: usize,
    /// Index of the record within the ensemble.
    pub record: usize,
}

/// Total number of units of `study`.
pub fn unit_count(study: &Study) -> usize {
    study.intensity.levels().len() * study.records()
}

/// Unit number `index` of `study`.
pub fn unit(study: &Study, index: usize) -> Unit {
    let n = study.records();
    Unit {
        index,
        level: index / n,
        record: index % n,
    }
}

/// A slice of a study for one job of a job array: shard `index` of `count`
/// (1-based), written `K/N`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Shard {
    /// This shard, 1..=count.
    pub index: usize,
    /// Number of shards.
    pub count: usize,
}

impl Shard {
    /// The whole study.
    pub const WHOLE: Shard = Shard { index: 1, count: 1 };

    /// Builds a shard, checking 1 ≤ index ≤ count.
    pub fn new(index: usize, count: usize) -> Result<Shard> {
        if count == 0 || index == 0 || index > count {
            return Err(Error::invalid(
                "shard",
                format!("{index}/{count}"),
                "K/N with 1 ≤ K ≤ N",
            ));
        }
        Ok(Shard { index, count })
    }

    /// Whether this shard runs unit `unit`.
    pub fn owns(&self, unit: usize) -> bool {
        unit % self.count == self.index - 1
    }

    /// The units of this shard out of `total`, in canonical order.
    pub fn units(&self, total: usize) -> impl Iterator<Item = usize> + use<> {
        (self.index - 1..total).step_by(self.count)
    }

    /// Number of units of this shard out of `total`.
    pub fn unit_count(&self, total: usize) -> usize {
        total.saturating_sub(self.index - 1).div_ceil(self.count)
    }
}

impl fmt::Display for Shard {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

impl FromStr for Shard {
    type Err = Error;

    fn from_str(s: &str) -> Result<Shard> {
        let parse = |t: &str| t.trim().parse::<usize>().ok();
        match s.split_once('/').map(|(k, n)| (parse(k), parse(n))) {
            Some((Some(k), Some(n))) => Shard::new(k, n),
            _ => Err(Error::invalid("shard", s, "K/N with 1 ≤ K ≤ N, e.g. 2/8")),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shards_partition_the_units() {
        for total in [0, 1, 7, 12] {
            for n in 1..5 {
                let mut seen = vec![0; total];
                for k in 1..=n {
                    let s = Shard::new(k, n).unwrap();
                    let units: Vec<usize> = s.units(total).collect();
                    assert_eq!(units.len(), s.unit_count(total));
                    for u in units {
                        assert!(s.owns(u));
                        seen[u] += 1;
                    }
                }
                assert!(seen.iter().all(|&c| c == 1));
            }
        }
    }

    #[test]
    fn shard_parses_k_over_n() {
        assert_eq!(
            "2/3".parse::<Shard>().unwrap(),
            Shard { index: 2, count: 3 }
        );
        assert!("0/3".parse::<Shard>().is_err());
        assert!("4/3".parse::<Shard>().is_err());
        assert!("x".parse::<Shard>().is_err());
    }
}
