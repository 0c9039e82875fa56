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
//! A stack (`[[grid.stack]]`) is a case of its own after the block cases,
//! in the order given ([`Case::stack`]); its analysis is a
//! [`Scene::Stack`], solved by the stack solver, where a block's is a
//! [`Scene::Block`], solved by the single block's.
//!
//! A parameter drawn under `[uncertainty]` is [`Param::Drawn`] on its axis
//! of cases; each analysis draws its own value ([`analysis`]), from a stream
//! keyed by (seed, record, level, case number), so the draws do not depend
//! on which thread or shard runs the analysis.

use crate::case::{Case, CaseValues, Param, Scene};
use crate::error::{Error, Result};
use crate::outcomes_csv::Columns;
use crate::spec::{Intensity, Motions, Study, analysis_values};
use std::fmt;
use std::str::FromStr;

/// The scene's own values on unit `unit` of `study`, for case `case`
/// (number `number` in canonical order): the case's values, with the
/// parameters of `[uncertainty]` drawn for this (record, level, case); and
/// what is simulated, at rest: the block (which fails only if drawn values
/// make no valid block) or the study's stack.
pub fn analysis(
    study: &Study,
    case: &Case,
    number: usize,
    unit: &Unit,
) -> (CaseValues, crate::error::Result<Scene>) {
    // a stack's case values are its own (nominal) ones; its draws are its
    // scene's
    let uncertainty = study.uncertainty.as_ref().filter(|_| case.stack.is_none());
    let own = analysis_values(uncertainty, case, unit.record, unit.level, number);
    let scene = match case.stack {
        Some(name) => match (
            study.stacks.iter().find(|s| s.name == name),
            study.stack_draws(name),
        ) {
            // a stack's draws: one stream per (record, level, case), as a block's
            (Some(s), Some(draws)) => {
                let seed = study.uncertainty.as_ref().map_or(0, |u| u.seed);
                let u = crate::uncertainty::stack_uniforms(
                    seed,
                    unit.record as u64,
                    unit.level as u64,
                    number as u64,
                );
                s.drawn(draws, &u).map(Scene::Stack)
            }
            (Some(s), None) => Ok(Scene::Stack(s.stack.clone())),
            (None, _) => Err(Error::invalid(
                "stack",
                name.to_string(),
                "a stack of the study",
            )),
        },
        None => own.analysis(study.g).map(Scene::Block),
    };
    (own, scene)
}

/// The optional columns of `study`'s `outcomes.csv`.
pub fn columns(study: &Study) -> Columns {
    Columns {
        pgv: matches!(study.intensity, Intensity::Pgv(_)),
        scale: matches!(study.intensity, Intensity::Scale(_)),
        files: !matches!(study.motions, Motions::Synthetic { .. }),
        pairs: study.motions.orientation().is_some(),
        time_in_mode: study.output.time_in_mode,
        stats: study.output.stats,
        floor: !study.floor.is_ground(),
        sensitivity: study.output.sensitivity,
        stack: !study.stacks.is_empty(),
        middle: study.stacks.iter().any(|s| s.stack.bodies.len() == 3),
        stack_values: study
            .uncertainty
            .as_ref()
            .is_some_and(|u| !u.stacks.is_empty()),
    }
}

/// Every case of `study`, in canonical order (aspect, then width, then e,
/// then friction; then the stacks, in the order given); a case's number is
/// its position here. A stack's case holds its top block and the interface
/// under it ([`Case::stack`]).
pub fn cases(study: &Study) -> Vec<Case> {
    let mut out = Vec::new();
    for &aspect in &study.aspects {
        for &width in &study.widths {
            for &restitution in &study.restitutions {
                for &friction in &study.frictions {
                    out.push(Case {
                        aspect,
                        width,
                        restitution,
                        friction,
                        stack: None,
                    });
                }
            }
        }
    }
    for s in &study.stacks {
        let (top, under) = (
            s.stack.bodies.last().expect("a stack has bodies"),
            s.stack
                .interfaces
                .last()
                .expect("an interface under each body"),
        );
        out.push(Case {
            aspect: Param::Fixed(top.height / top.width),
            width: Param::Fixed(top.width),
            restitution: Param::Fixed(under.restitution),
            friction: Param::Fixed(under.friction),
            stack: Some(s.name),
        });
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
