//! Running studies: results independent of threads, shards and
//! interruptions; failures recorded, not fatal; every form of motion input.

use rockfrag::case::Param;
use rockfrag::error::Error;
use rockfrag::motion::{SynthesisSettings, synthesize, write_csv};
use rockfrag::pipeline;
use rockfrag::spec::Study;
use rockfrag::study::{self, RunOptions, Shard, files};
use std::path::{Path, PathBuf};

fn small() -> Study {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/specs/small.toml");
    Study::load(&path).unwrap()
}

fn opts(dir: &Path, threads: usize) -> RunOptions {
    RunOptions {
        threads,
        ..RunOptions::new(dir)
    }
}

fn read(dir: &Path, name: &str) -> Vec<u8> {
    std::fs::read(dir.join(name)).unwrap_or_else(|e| panic!("{}/{name}: {e}", dir.display()))
}

/// Runs the whole study as `rockfrag run` does (analyses, then summary.md).
fn run_whole(study: &Study, dir: &Path, threads: usize) -> study::RunReport {
    let report = pipeline::run(study, &opts(dir, threads)).unwrap().run;
    assert!(report.complete);
    report
}

/// One thread or two, one chunk or several: the rows are put in canonical
/// order before they are written, so outcomes.csv and summary.md are
/// byte-identical; so does the order in which units are solved.
#[test]
fn thread_count_does_not_change_the_results() {
    let study = small();
    let tmp = tempfile::tempdir().unwrap();
    let (a, b, c) = (
        tmp.path().join("t1"),
        tmp.path().join("t2"),
        tmp.path().join("t2c"),
    );
    let ra = run_whole(&study, &a, 1);
    let rb = run_whole(&study, &b, 2);
    let chunked = RunOptions {
        chunk_analyses: 5,
        ..opts(&c, 2)
    };
    assert!(pipeline::run(&study, &chunked).unwrap().run.complete);
    // With progress shown, a pilot (one unit per level) is solved first and
    // its rows kept for their chunk: the same bytes.
    let p = tmp.path().join("pilot");
    let shown = RunOptions {
        progress: true,
        chunk_analyses: 5,
        ..opts(&p, 2)
    };
    assert!(pipeline::run(&study, &shown).unwrap().run.complete);
    assert_eq!(read(&a, files::OUTCOMES), read(&b, files::OUTCOMES));
    assert_eq!(read(&a, files::OUTCOMES), read(&c, files::OUTCOMES));
    assert_eq!(read(&a, files::OUTCOMES), read(&p, files::OUTCOMES));
    assert_eq!(read(&a, files::SUMMARY), read(&b, files::SUMMARY));
    assert_eq!(ra.counts, rb.counts);
    // 2 levels × 3 records × (2 aspects × 2 e) analyses, plus the header.
    let text = String::from_utf8(read(&a, files::OUTCOMES)).unwrap();
    assert_eq!(text.lines().count(), 1 + 24);
    assert_eq!(ra.counts.analyses, 24);
}

/// Shards 1/3, 2/3, 3/3 (run in any order, with different thread counts)
/// merged give the unsharded run's outcomes.csv and summary.md, byte for byte.
#[test]
fn merged_shards_equal_the_unsharded_run() {
    let study = small();
    let tmp = tempfile::tempdir().unwrap();
    let whole = tmp.path().join("whole");
    run_whole(&study, &whole, 2);
    let mut dirs = Vec::new();
    for k in [3, 1, 2] {
        let dir = tmp.path().join(format!("shard-{k}"));
        let o = RunOptions {
            shard: Shard::new(k, 3).unwrap(),
            threads: k % 2 + 1,
            ..RunOptions::new(&dir)
        };
        assert!(study::run(&study, &o).unwrap().complete);
        dirs.push(dir);
    }
    let merged = tmp.path().join("merged");
    let m = study::merge(&dirs, &merged).unwrap();
    pipeline::finish(&study, &merged, None).unwrap();
    assert_eq!(
        read(&whole, files::OUTCOMES),
        read(&merged, files::OUTCOMES)
    );
    assert_eq!(read(&whole, files::SUMMARY), read(&merged, files::SUMMARY));
    assert_eq!(m.counts.analyses, 24);
    assert_eq!(m.merged_from.len(), 3);
}

/// Merging refuses an incomplete set of shards and shards of another study.
#[test]
fn merge_refuses_missing_or_foreign_shards() {
    let study = small();
    let tmp = tempfile::tempdir().unwrap();
    let shard = |study: &Study, k: usize, name: &str| {
        let dir = tmp.path().join(name);
        let o = RunOptions {
            shard: Shard::new(k, 2).unwrap(),
            ..RunOptions::new(&dir)
        };
        study::run(study, &o).unwrap();
        dir
    };
    let one = shard(&study, 1, "a1");
    let err = study::merge(std::slice::from_ref(&one), &tmp.path().join("m")).unwrap_err();
    // The message names the shard that is missing (it used to say only
    // "1 shard folders given for 2 shards") and where the given one is.
    assert!(
        err.to_string().contains("shard 2/2 missing")
            && err
                .to_string()
                .contains(&format!("1/2 in {}", one.display())),
        "{err}"
    );
    let mut other = study.clone();
    other.restitutions = vec![Param::Fixed(0.0)];
    let two = shard(&other, 2, "b2");
    let err = study::merge(&[one, two], &tmp.path().join("m")).unwrap_err();
    assert!(err.to_string().contains("different studies"), "{err}");
}

/// A run stopped midway (as if killed, after 2 of 6 units), with junk
/// appended to its partial file after the last checkpoint (a write cut
/// short), resumes and ends with the uninterrupted run's outcomes.csv.
/// While stopped, no final file exists.
#[test]
fn interrupted_run_resumes_to_the_same_outcomes() {
    let study = small();
    let tmp = tempfile::tempdir().unwrap();
    let whole = tmp.path().join("whole");
    run_whole(&study, &whole, 2);

    let dir = tmp.path().join("resumed");
    let stop = RunOptions {
        stop_after_units: Some(2),
        chunk_analyses: 4,
        ..opts(&dir, 1)
    };
    let first = pipeline::run(&study, &stop).unwrap().run;
    assert!(!first.complete);
    assert_eq!(first.analyses_run, 2 * 4);
    for name in [files::OUTCOMES, files::SUMMARY, files::MANIFEST] {
        assert!(
            !dir.join(name).exists(),
            "{name} written by an unfinished run"
        );
    }
    assert!(dir.join(files::CHECKPOINT).exists());
    // A killed writer may have left part of a chunk after the checkpoint.
    use std::io::Write;
    let mut partial = std::fs::OpenOptions::new()
        .append(true)
        .open(dir.join(files::PARTIAL))
        .unwrap();
    partial.write_all(b"4,0.5,0,inf,,,0.8,1,ok,tru").unwrap();
    drop(partial);

    let second = pipeline::run(&study, &opts(&dir, 2)).unwrap().run;
    assert!(second.complete);
    assert_eq!(second.resumed_at_unit, 2);
    assert_eq!(second.analyses_run, 4 * 4);
    assert_eq!(read(&whole, files::OUTCOMES), read(&dir, files::OUTCOMES));
    assert_eq!(read(&whole, files::SUMMARY), read(&dir, files::SUMMARY));
    assert!(!dir.join(files::CHECKPOINT).exists());
    assert!(!dir.join(files::PARTIAL).exists());
}

/// A folder holding an unfinished run of another spec (or another shard)
/// is not resumed with this one: the error says why and what to do.
#[test]
fn resume_refuses_another_spec_or_shard() {
    let study = small();
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("run");
    let stop = RunOptions {
        stop_after_units: Some(1),
        ..opts(&dir, 1)
    };
    assert!(!study::run(&study, &stop).unwrap().complete);

    let mut other = study.clone();
    other.aspects = vec![Param::Fixed(5.0)];
    let err = study::run(&other, &opts(&dir, 1)).unwrap_err();
    assert!(matches!(err, Error::Conflict { .. }), "{err}");
    let msg = err.to_string();
    assert!(
        msg.contains("refusing to resume") && msg.contains("analyses hash"),
        "{msg}"
    );

    let sharded = RunOptions {
        shard: Shard::new(1, 2).unwrap(),
        ..opts(&dir, 1)
    };
    let msg = study::run(&study, &sharded).unwrap_err().to_string();
    assert!(msg.contains("shard 1/1"), "{msg}");
}

/// Only what decides the analyses must match to resume: a run stopped
/// midway resumes under a spec whose name, description and `[fragility]`
/// changed (the bootstrap, say), and ends with the uninterrupted run's
/// outcomes.csv; its fragility fit follows the new spec.
#[test]
fn resume_after_a_change_to_post_processing_only() {
    let study = small();
    let tmp = tempfile::tempdir().unwrap();
    let whole = tmp.path().join("whole");
    run_whole(&study, &whole, 2);

    let dir = tmp.path().join("run");
    let stop = RunOptions {
        stop_after_units: Some(2),
        chunk_analyses: 4,
        ..opts(&dir, 1)
    };
    assert!(!pipeline::run(&study, &stop).unwrap().run.complete);
    let mut changed = study.clone();
    changed.name = "small-renamed".into();
    changed.description = "the same analyses, fitted".into();
    changed.fragility = Some(rockfrag::fragility::FragilityOptions {
        bootstrap: 20,
        ..Default::default()
    });
    assert_ne!(changed.hash(), study.hash());
    assert_eq!(changed.analyses_hash(), study.analyses_hash());
    let report = pipeline::run(&changed, &opts(&dir, 2)).unwrap();
    assert!(report.run.complete);
    assert_eq!(report.run.resumed_at_unit, 2);
    assert_eq!(read(&whole, files::OUTCOMES), read(&dir, files::OUTCOMES));
    assert!(report.finish.unwrap().fit.is_some());
    assert!(dir.join("fragility.csv").exists());
}

/// A finished run rerun with the same analyses runs none of them: its
/// outcomes.csv is kept byte for byte (its modification time too) and what
/// follows it is redone under the new spec (here a fit it did not have);
/// `force` runs them all again, to the same bytes.
#[test]
fn rerun_of_a_finished_study_reuses_its_analyses() {
    let study = small();
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("run");
    let first = run_whole(&study, &dir, 2);
    assert!(!first.already_finished);
    let total = first.analyses_run;
    assert_eq!(total, 3 * 2 * 4);
    let bytes = read(&dir, files::OUTCOMES);
    let mtime = std::fs::metadata(dir.join(files::OUTCOMES))
        .unwrap()
        .modified()
        .unwrap();

    let mut fitted = study.clone();
    fitted.fragility = Some(rockfrag::fragility::FragilityOptions {
        bootstrap: 20,
        ..Default::default()
    });
    let again = pipeline::run(&fitted, &opts(&dir, 2)).unwrap();
    assert!(again.run.already_finished && again.run.complete);
    assert_eq!(again.run.analyses_run, 0);
    assert_eq!(again.run.counts.analyses, total);
    assert_eq!(read(&dir, files::OUTCOMES), bytes);
    let mtime_after = std::fs::metadata(dir.join(files::OUTCOMES))
        .unwrap()
        .modified()
        .unwrap();
    assert_eq!(mtime, mtime_after, "outcomes.csv was rewritten");
    assert!(dir.join("fragility.csv").exists());
    let manifest = study::Manifest::read(&dir.join(files::MANIFEST)).unwrap();
    assert!(
        manifest.spec_toml.contains("[fragility]"),
        "the manifest keeps the old spec"
    );
    assert_eq!(
        manifest.analyses_run, total,
        "the manifest forgot the run's own work"
    );

    let forced = RunOptions {
        force: true,
        ..opts(&dir, 2)
    };
    let rerun = pipeline::run(&fitted, &forced).unwrap().run;
    assert!(!rerun.already_finished);
    assert_eq!(rerun.analyses_run, total);
    assert_eq!(read(&dir, files::OUTCOMES), bytes);
}

/// An analysis the solver gives up on (here: a budget of 2 events, which
/// any rocking block exceeds) is written as `failed` with its reason and
/// counted; the run still completes and writes every file.
#[test]
fn failed_analyses_are_recorded_not_fatal() {
    let mut study = small();
    study.solver.max_events = 2;
    let tmp = tempfile::tempdir().unwrap();
    let report = run_whole(&study, tmp.path(), 2);
    let text = String::from_utf8(read(tmp.path(), files::OUTCOMES)).unwrap();
    let failed: Vec<&str> = text.lines().filter(|l| l.contains(",failed,")).collect();
    assert!(!failed.is_empty());
    assert_eq!(report.counts.failed, failed.len() as u64);
    assert!(
        failed.iter().all(|l| l.contains("max_events")),
        "{}",
        failed[0]
    );
    let manifest: serde_json::Value =
        serde_json::from_slice(&read(tmp.path(), files::MANIFEST)).unwrap();
    assert_eq!(manifest["counts"]["failed"], failed.len() as u64);
    assert!(read(tmp.path(), files::SUMMARY).starts_with(b"# Study"));
}

/// The manifest records the spec as parsed, its hash, the version, commit,
/// times, threads and counts; the canonical spec text parses back to the study.
#[test]
fn manifest_records_provenance() {
    let study = small();
    let tmp = tempfile::tempdir().unwrap();
    run_whole(&study, tmp.path(), 2);
    let m: serde_json::Value = serde_json::from_slice(&read(tmp.path(), files::MANIFEST)).unwrap();
    assert_eq!(m["spec_hash"], format!("fnv1a64:{:016x}", study.hash()));
    assert_eq!(m["rockfrag_version"], env!("CARGO_PKG_VERSION"));
    assert!(!m["git_commit"].as_str().unwrap().is_empty());
    assert_eq!(m["threads"], 2);
    assert!(m["finished_unix"].as_u64().unwrap() >= m["started_unix"].as_u64().unwrap());
    assert!(m["started_utc"].as_str().unwrap().ends_with('Z'));
    assert_eq!(m["counts"]["analyses"], 24);
    assert_eq!(m["spec"]["grid"]["aspect"], serde_json::json!([4.0, 6.0]));
    let back = Study::from_toml(m["spec_toml"].as_str().unwrap(), Path::new("x.toml")).unwrap();
    assert_eq!(back, study);
}

/// Recorded motions scaled to PGV levels: every row carries the PGV target,
/// the record file and the scaled record's PGA; the record's PGV is the target.
#[test]
fn recorded_motions_scaled_to_pgv() {
    let tmp = tempfile::tempdir().unwrap();
    let settings = SynthesisSettings {
        duration: 10.0,
        ..SynthesisSettings::default()
    };
    let mut names = Vec::new();
    for i in 0..2 {
        let r = synthesize(&settings, 9, i, 3.0).unwrap();
        let name = format!("rec-{i}.csv");
        write_csv(tmp.path().join(&name), &r).unwrap();
        names.push(format!("\"{name}\""));
    }
    let spec = format!(
        "name = \"pgv\"\nrecord_files = [{}]\n[grid]\naspect = [4]\nrestitution = [0]\npgv = [0.1, 0.3]\n",
        names.join(", ")
    );
    let spec_path = tmp.path().join("pgv.toml");
    std::fs::write(&spec_path, &spec).unwrap();
    let study = Study::load(&spec_path).unwrap();
    let out: PathBuf = tmp.path().join("out");
    let report = run_whole(&study, &out, 2);
    assert_eq!(report.counts.analyses, 4);
    let text = String::from_utf8(read(&out, files::OUTCOMES)).unwrap();
    let mut rows = csv::Reader::from_reader(text.as_bytes());
    let header = rows.headers().unwrap().clone();
    let col = |n: &str| header.iter().position(|h| h == n).unwrap();
    for row in rows.records() {
        let row = row.unwrap();
        assert_eq!(&row[col("status")], "ok");
        assert!(row[col("record_file")].starts_with("rec-"));
        let pga: f64 = row[col("pga")].parse().unwrap();
        assert!(pga > 0.0 && pga < 2.0, "pga {pga}");
        assert!(["0.1", "0.3"].contains(&&row[col("pgv")]));
    }
    // The scaling itself: the source's record has the target PGV.
    let mut source = study::Source::new(&study).unwrap();
    let r = source.record(&study.intensity, 0.3, 1, study.g).unwrap();
    assert!((r.pgv() - 0.3).abs() < 1e-12, "{}", r.pgv());
}

/// Recorded motions multiplied by scale factors (an incremental dynamic
/// analysis; `[1.0]` alone is a cloud analysis): each row's `scale` is the
/// factor and its `pga` the scaled record's own measured peak, factor ×
/// the record's PGA (to 1e-12 relative: one multiplication per sample);
/// the rows are the same on 1 and 2 threads, and the fragility fit uses
/// those continuous intensities. Scale factors on a synthetic ensemble, or
/// beside `pga`, are refused naming the field.
#[test]
fn recorded_motions_multiplied_by_scale_factors() {
    let tmp = tempfile::tempdir().unwrap();
    let settings = SynthesisSettings {
        duration: 10.0,
        ..SynthesisSettings::default()
    };
    let mut names = Vec::new();
    let mut peaks = Vec::new();
    for i in 0..3 {
        let r = synthesize(&settings, 11, i, [2.0, 2.7, 3.9][i as usize]).unwrap();
        peaks.push(r.pga() / rockfrag::motion::G_STANDARD);
        let name = format!("rec-{i}.csv");
        write_csv(tmp.path().join(&name), &r).unwrap();
        names.push(format!("\"{name}\""));
    }
    let spec = format!(
        "name = \"ida\"\nrecord_files = [{}]\n[grid]\naspect = [4]\nrestitution = [0]\n\
         scale_factors = [0.5, 1.0, 2.0, 4.0]\n[fragility]\nbootstrap = 0\n",
        names.join(", ")
    );
    let spec_path = tmp.path().join("ida.toml");
    std::fs::write(&spec_path, &spec).unwrap();
    let study = Study::load(&spec_path).unwrap();
    let one = tmp.path().join("one");
    let two = tmp.path().join("two");
    run_whole(&study, &one, 1);
    run_whole(&study, &two, 2);
    assert_eq!(read(&one, files::OUTCOMES), read(&two, files::OUTCOMES));
    let text = String::from_utf8(read(&one, files::OUTCOMES)).unwrap();
    let mut rows = csv::Reader::from_reader(text.as_bytes());
    let header = rows.headers().unwrap().clone();
    let col = |n: &str| header.iter().position(|h| h == n).unwrap();
    let mut n = 0;
    for row in rows.records() {
        let row = row.unwrap();
        assert_eq!(&row[col("status")], "ok");
        let factor: f64 = row[col("scale")].parse().unwrap();
        let record: usize = row[col("record")].parse().unwrap();
        let pga: f64 = row[col("pga")].parse().unwrap();
        let expected = factor * peaks[record];
        assert!(
            (pga - expected).abs() <= 1e-12 * expected,
            "{pga} vs {expected}"
        );
        n += 1;
    }
    assert_eq!(n, 12);
    // The fit runs on the analyses' own PGAs (12 distinct intensities).
    let fits = rockfrag::fragility::fit_outcomes(
        &one.join(files::OUTCOMES),
        &rockfrag::fragility::FragilityOptions {
            bootstrap: 0,
            ..Default::default()
        },
    )
    .unwrap();
    assert_eq!(fits.len(), 1);
    assert_eq!(fits[0].n_analyses, 12);
    assert_eq!(fits[0].observations.len(), 12);

    for (extra, field) in [("pga = [0.3]\n", "grid.pga"), ("", "grid.scale_factors")] {
        let spec = if field == "grid.pga" {
            spec.replace("scale_factors", &format!("{extra}scale_factors"))
        } else {
            "name = \"s\"\n[grid]\nscale_factors = [1.0]\n".to_string()
        };
        std::fs::write(&spec_path, &spec).unwrap();
        let err = Study::load(&spec_path).unwrap_err().to_string();
        assert!(err.contains(field), "{err}");
    }
}
