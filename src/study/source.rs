//! Where a unit's record comes from: a synthetic ensemble member scaled to
//! the level, or a recorded motion scaled to it.
//!
//! PGA levels: synthetic records are generated at the target PGA (exact to
//! the bit, see `Synthesizer::generate_into`); recorded motions are scaled by
//! target/PGA. PGV levels: the record (synthetic at 1 g) is scaled by
//! target/PGV, acceleration, velocity and displacement alike. Scale factors:
//! the recorded motion times the factor.
//!
//! Record pairs: the pair is scaled as a whole, by target/RotD50 (PGA or
//! PGV levels, the RotD50 of the unscaled pair measured once) or by the
//! factor, then turned to the direction φ the unit's blocks face
//! ([`Orientation::member`]): cos φ·H1 + sin φ·H2.
//!
//! On a floor (`[support] floor`), the scaled ground record is then filtered
//! through the building ([`crate::motion::floor_record`]): the level stays
//! the ground's, and the blocks feel the floor ([`Source::motion`]).

use crate::error::{Error, Result};
use crate::im::{Felt, Im, ImValues};
use crate::motion::{
    MeasuredPair, Natural, Pair, Record, Synthesizer, floor_record, read_record,
    second_component_seed,
};
use crate::spec::{Intensity, Motions, Orientation, RecordFile, Study};
use rayon::prelude::*;
use std::collections::HashMap;
use std::sync::Arc;

/// The most memory the natural parts of a run's synthetic members may take
/// ([`Members`]): 8 bytes a sample, 12 kB a 30-s record at Δt = 0.02 s.
/// Past it, every unit makes its record afresh.
const MEMBERS_BYTES: usize = 16 << 20;

/// The natural part of each member of a synthetic ensemble that a run uses
/// at several levels ([`Source::prepare`]): filtered once, then only scaled
/// at each level, bit for bit the record made afresh
/// ([`Synthesizer::scaled_into`]). One block of memory, handed back whole
/// when the run ends.
#[derive(Debug)]
pub struct Members {
    samples: usize,
    /// The slot of each record index in `acc` (`u32::MAX`: none).
    slot: Vec<u32>,
    /// The natural accelerations, `samples` a slot.
    acc: Vec<f64>,
    /// Their initial velocities and peaks (`None`: a member that could not
    /// be made, made again by its units, which report why).
    natural: Vec<Option<Natural>>,
}

impl Members {
    /// Member `record`'s natural acceleration and values, if kept.
    fn get(&self, record: usize) -> Option<(&[f64], &Natural)> {
        let slot = *self.slot.get(record)? as usize;
        let natural = self.natural.get(slot)?.as_ref()?;
        Some((
            &self.acc[slot * self.samples..(slot + 1) * self.samples],
            natural,
        ))
    }
}

/// A record maker; clone one per worker thread.
#[derive(Clone, Debug)]
pub enum Source {
    /// A synthetic ensemble.
    Synthetic {
        /// The generator (its scratch buffers are per clone).
        synth: Box<Synthesizer>,
        /// Ensemble seed.
        seed: u64,
        /// The natural parts of the members a run uses at several levels
        /// ([`Source::prepare`]).
        members: Option<Arc<Members>>,
    },
    /// A synthetic ensemble of pairs (`components = 2`): member k's H1 is
    /// record k of the ensemble, its H2 record k of the ensemble
    /// [`second_component_seed`]`(seed)`, both at the model's own amplitude.
    SyntheticPairs {
        /// The generator (its scratch buffers are per clone).
        synth: Box<Synthesizer>,
        /// Ensemble seed.
        seed: u64,
        /// The directions the blocks face.
        orientation: Arc<Orientation>,
    },
    /// Recorded motions, as read (unscaled).
    Files(Arc<Vec<Record>>),
    /// Record pairs, as read (unscaled), and the directions the blocks face.
    Pairs(Arc<(Vec<Arc<MeasuredPair>>, Orientation)>),
}

/// Refuses two record files with the same motion (time step and every
/// acceleration, bit for bit: a copy under another name), naming both as
/// the spec gives them: the study would count one record twice.
fn distinct<'a>(records: impl Iterator<Item = (&'a RecordFile, &'a Record)>) -> Result<()> {
    let mut seen: HashMap<u64, Vec<(&RecordFile, &Record)>> = HashMap::new();
    for (file, record) in records {
        // FNV-1a over Δt's and the accelerations' bits.
        let key = std::iter::once(record.dt)
            .chain(record.acc.iter().copied())
            .fold(0xcbf2_9ce4_8422_2325_u64, |h, x| {
                (h ^ x.to_bits()).wrapping_mul(0x0100_0000_01b3)
            });
        let same = seen.entry(key).or_default();
        if let Some((first, _)) = same
            .iter()
            .find(|(_, r)| r.dt == record.dt && r.acc == record.acc)
        {
            return Err(Error::Conflict {
                path: file.path.clone(),
                message: format!(
                    "record_files lists \"{}\" and \"{}\", which hold the same motion (the same \
                     time step and accelerations): one record would count twice; list it once",
                    first.given, file.given
                ),
            });
        }
        same.push((file, record));
    }
    Ok(())
}

impl Source {
    /// Builds the source of `study`: the generator, or every record file read
    /// once (an unreadable file is an error here, before any analysis runs).
    pub fn new(study: &Study) -> Result<Source> {
        match &study.motions {
            Motions::Synthetic {
                settings,
                seed,
                pairs: None,
                ..
            } => Ok(Source::Synthetic {
                synth: Box::new(Synthesizer::new(settings)?),
                seed: *seed,
                members: None,
            }),
            Motions::Synthetic {
                settings,
                seed,
                pairs: Some(orientation),
                ..
            } => Ok(Source::SyntheticPairs {
                synth: Box::new(Synthesizer::new(settings)?),
                seed: *seed,
                orientation: Arc::new(orientation.clone()),
            }),
            Motions::Files(files) => {
                let records = files
                    .iter()
                    .map(|f| read_record(&f.path, study.g))
                    .collect::<Result<Vec<_>>>()?;
                distinct(files.iter().zip(&records))?;
                Ok(Source::Files(Arc::new(records)))
            }
            Motions::Pairs { pairs, orientation } => {
                let read = pairs
                    .iter()
                    .map(|[h1, h2]| {
                        Ok([
                            read_record(&h1.path, study.g)?,
                            read_record(&h2.path, study.g)?,
                        ])
                    })
                    .collect::<Result<Vec<_>>>()?;
                distinct(pairs.iter().flatten().zip(read.iter().flatten()))?;
                let pairs = pairs
                    .iter()
                    .zip(read)
                    .map(|([h1, h2], [r1, r2])| {
                        let pair = Pair::new(r1, r2).map_err(|e| Error::InvalidRecord {
                            name: format!("record pair {} + {}", h1.given, h2.given),
                            message: e.to_string(),
                        })?;
                        MeasuredPair::new(pair).map(Arc::new)
                    })
                    .collect::<Result<Vec<_>>>()?;
                Ok(Source::Pairs(Arc::new((pairs, orientation.clone()))))
            }
        }
    }

    /// The record of ensemble member `record` scaled to intensity `level`
    /// (PGA in g or PGV in m/s, per `intensity`), with gravity `g`.
    pub fn record(
        &mut self,
        intensity: &Intensity,
        level: f64,
        record: usize,
        g: f64,
    ) -> Result<Record> {
        match (self, intensity) {
            (
                Source::Synthetic {
                    synth,
                    seed,
                    members,
                },
                Intensity::Pga(_),
            ) => synthetic(synth, *seed, members.as_deref(), record, level * g),
            (
                Source::Synthetic {
                    synth,
                    seed,
                    members,
                },
                Intensity::Pgv(_),
            ) => {
                let r = synthetic(synth, *seed, members.as_deref(), record, g)?;
                let pgv = r.pgv();
                scaled(r, level, pgv, &Im::PGV.short())
            }
            (Source::Files(records), Intensity::Pga(_)) => {
                let r = records[record].clone();
                let pga = r.pga();
                scaled(r, level * g, pga, &Im::PGA.short())
            }
            (Source::Files(records), Intensity::Pgv(_)) => {
                let r = records[record].clone();
                let pgv = r.pgv();
                scaled(r, level, pgv, &Im::PGV.short())
            }
            (Source::Files(records), Intensity::Scale(_)) => {
                Ok(records[record].clone().scaled(level))
            }
            (source @ (Source::Pairs(_) | Source::SyntheticPairs { .. }), intensity) => {
                Ok(source.turned(intensity, level, record, g)?.0)
            }
            (Source::Synthetic { .. }, Intensity::Scale(_)) => Err(Error::invalid(
                "grid.scale_factors",
                level,
                "record_files (the spec's validation refuses scale factors on synthetic records)",
            )),
        }
    }
}

impl Source {
    /// Member `record` of a study of pairs at intensity `level`: the pair
    /// (read, or generated at the model's own amplitude) scaled to the
    /// level's RotD50 (or by the factor) and turned to the member's
    /// direction; with the pair, the factor k it was scaled by and the
    /// direction φ (degrees). Single components: an error.
    fn turned(
        &mut self,
        intensity: &Intensity,
        level: f64,
        record: usize,
        g: f64,
    ) -> Result<(Record, Arc<MeasuredPair>, f64, f64)> {
        let (pair, phi) = match self {
            Source::Pairs(pairs) => {
                let (pairs, orientation) = &**pairs;
                let (p, phi) = orientation.member(record);
                (pairs[p].clone(), phi)
            }
            Source::SyntheticPairs {
                synth,
                seed,
                orientation,
            } => {
                let (p, phi) = orientation.member(record);
                let h1 = synth.generate_natural(*seed, p as u64)?;
                let h2 = synth.generate_natural(second_component_seed(*seed), p as u64)?;
                (Arc::new(MeasuredPair::new(Pair::new(h1, h2)?)?), phi)
            }
            Source::Synthetic { .. } | Source::Files(_) => {
                unreachable!("only a source of pairs turns a pair")
            }
        };
        let (target, peak, what) = match intensity {
            Intensity::Pga(_) => (level * g, pair.pga, "RotD50 PGA"),
            Intensity::Pgv(_) => (level, pair.pgv, "RotD50 PGV"),
            Intensity::Scale(_) => (level, 1.0, "scale"),
        };
        if !(peak.is_finite() && peak > 0.0) {
            return Err(Error::InvalidRecord {
                name: pair.pair.name(),
                message: format!("the pair's {what} is {peak}; it cannot be scaled to {target}"),
            });
        }
        let k = target / peak;
        Ok((pair.felt(k, phi)?, pair, k, phi))
    }
}

impl Source {
    /// Makes, in parallel on the current rayon pool, the natural part of
    /// every synthetic member that `units` (of `study`) use at two levels
    /// or more, so that each is filtered once and only scaled at each
    /// level. Does nothing for other sources, for scale
    /// factors, when the units are all at one level, or past
    /// 16 MB of kept samples (8 bytes each).
    pub fn prepare(&mut self, study: &Study, units: &[usize]) {
        let Source::Synthetic {
            synth,
            seed,
            members,
        } = self
        else {
            return;
        };
        if matches!(study.intensity, Intensity::Scale(_)) || units.is_empty() {
            return;
        }
        let unit = |u: usize| super::plan::unit(study, u);
        let first = unit(units[0]).level;
        if units.iter().all(|&u| unit(u).level == first) {
            return;
        }
        let mut slot = vec![u32::MAX; study.records()];
        let mut records = Vec::new();
        for &u in units {
            let r = unit(u).record;
            if slot[r] == u32::MAX {
                slot[r] = records.len() as u32;
                records.push(r);
            }
        }
        let samples = synth.samples();
        if records.len().saturating_mul(samples) > MEMBERS_BYTES / 8 {
            return;
        }
        let mut acc = vec![0.0; records.len() * samples];
        let mut natural = vec![None; records.len()];
        let (seed, synth): (u64, &Synthesizer) = (*seed, synth);
        acc.par_chunks_mut(samples)
            .zip(natural.par_iter_mut())
            .zip(records.par_iter())
            .for_each_init(
                || (synth.clone(), Vec::with_capacity(samples)),
                |(s, buf), ((out, made), &r)| {
                    // a member that fails is left out: its units make it
                    // again and report why
                    if let Ok(n) = s.natural(seed, r as u64, buf) {
                        out.copy_from_slice(buf);
                        *made = Some(n);
                    }
                },
            );
        *members = Some(Arc::new(Members {
            samples,
            slot,
            acc,
            natural,
        }));
    }
}

/// What the blocks of one unit feel, and the intensities measured on it.
#[derive(Clone, Debug)]
pub struct UnitMotion {
    /// The motion the blocks feel: the scaled ground record, or the floor's
    /// absolute motion under it.
    pub felt: Record,
    /// The scaled ground record under the floor (`None` on the ground,
    /// where it is `felt`).
    pub ground: Option<Record>,
    /// The record pair, the factor it was scaled by and the direction φ
    /// (degrees) the blocks face (`None` without pairs).
    pub pair: Option<(Arc<MeasuredPair>, f64, f64)>,
    /// Gravity of the study, m/s².
    pub g: f64,
    /// The intensities of [`Im::COLUMNS`] this motion has (the ground's
    /// peaks; a pair's RotD50; the floor's peaks), measured once.
    pub measured: ImValues,
}

impl UnitMotion {
    /// The scaled ground record (of a pair: the component the blocks face).
    pub fn ground(&self) -> &Record {
        self.ground.as_ref().unwrap_or(&self.felt)
    }

    /// The motion as [`Im::on`] reads it.
    pub fn view(&self) -> Felt<'_> {
        Felt {
            ground: self.ground(),
            floor: self.ground.as_ref().map(|_| &self.felt),
            pair: self.pair.as_ref().map(|(p, k, _)| (&**p, *k)),
            g: self.g,
        }
    }

    /// Intensity measure `im` of this motion: measured once for those of
    /// [`Im::COLUMNS`], else measured now (`None` where it is not defined).
    pub fn im(&self, im: Im) -> Option<f64> {
        self.measured.get(im).or_else(|| im.on(&self.view()))
    }

    /// The direction φ (degrees) the blocks face, for a pair.
    pub fn phi(&self) -> Option<f64> {
        self.pair.as_ref().map(|p| p.2)
    }
}

impl Source {
    /// The motion of ensemble member `record` at intensity `level` of
    /// `study`: [`Source::record`], then the study's floor if it has one.
    /// One floor filter per unit (a few flops per sample per mode), shared
    /// by every case of the unit.
    pub fn motion(&mut self, study: &Study, level: f64, record: usize) -> Result<UnitMotion> {
        let (ground, pair) = match self {
            Source::Pairs(_) | Source::SyntheticPairs { .. } => {
                let (r, pair, k, phi) = self.turned(&study.intensity, level, record, study.g)?;
                (r, Some((pair, k, phi)))
            }
            _ => (self.record(&study.intensity, level, record, study.g)?, None),
        };
        let (ground, felt) = if study.floor.is_ground() {
            (None, ground)
        } else {
            let felt = floor_record(&ground, &study.floor)?;
            (Some(ground), felt)
        };
        let mut motion = UnitMotion {
            felt,
            ground,
            pair,
            g: study.g,
            measured: ImValues::new(),
        };
        motion.measured = ImValues::of(&Im::COLUMNS, &motion.view());
        Ok(motion)
    }
}

/// Member `record` of the ensemble `seed` at the peak `pga` (m/s²): scaled
/// from its natural part in `members` when kept there, else generated.
fn synthetic(
    synth: &mut Synthesizer,
    seed: u64,
    members: Option<&Members>,
    record: usize,
    pga: f64,
) -> Result<Record> {
    match members.and_then(|m| m.get(record)) {
        Some((acc, natural)) => {
            let mut r = Record::empty(synth.settings().dt);
            synth.scaled_into(acc, natural, pga, &mut r)?;
            Ok(r)
        }
        None => synth.generate(seed, record as u64, pga),
    }
}

/// Scales every series of `r` by `target / peak`.
fn scaled(r: Record, target: f64, peak: f64, what: &str) -> Result<Record> {
    if !(peak.is_finite() && peak > 0.0) {
        return Err(Error::InvalidRecord {
            name: r.name,
            message: format!("{what} is {peak}; it cannot be scaled to {target}"),
        });
    }
    Ok(r.scaled(target / peak))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    /// The records of a prepared source (members filtered once, scaled at
    /// each level) are those of a source that makes every record afresh,
    /// bit for bit, at PGA and PGV levels alike; a source prepared for
    /// units of one level keeps nothing.
    #[test]
    fn prepared_members_give_the_records_made_afresh() {
        for grid in ["pga = [0.2, 0.7, 1.3]", "pgv = [0.1, 0.45]"] {
            let text =
                format!("name = \"t\"\nseed = 11\nrecords = 4\n[grid]\naspect = [4]\n{grid}\n");
            let study = Study::from_toml(&text, Path::new("t.toml")).unwrap();
            let units: Vec<usize> = (0..super::super::plan::unit_count(&study)).collect();
            let mut fresh = Source::new(&study).unwrap();
            let mut kept = Source::new(&study).unwrap();
            kept.prepare(&study, &units);
            assert!(matches!(
                &kept,
                Source::Synthetic {
                    members: Some(_),
                    ..
                }
            ));
            let levels = study.intensity.levels();
            for &u in &units {
                let unit = super::super::plan::unit(&study, u);
                let level = levels[unit.level];
                let a = fresh.motion(&study, level, unit.record).unwrap();
                let b = kept.motion(&study, level, unit.record).unwrap();
                let bits = |r: &Record| {
                    [&r.acc, &r.vel, &r.disp]
                        .map(|v| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>())
                };
                assert_eq!(bits(&a.felt), bits(&b.felt), "{grid}, unit {u}");
                assert_eq!(a.felt.name, b.felt.name);
                assert_eq!(a.measured, b.measured);
            }
            let mut one_level = Source::new(&study).unwrap();
            one_level.prepare(&study, &units[..4]);
            assert!(matches!(
                &one_level,
                Source::Synthetic { members: None, .. }
            ));
        }
    }
}
