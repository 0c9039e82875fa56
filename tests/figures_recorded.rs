//! `rockfrag figures` on a study of recorded motions: the figures show the
//! study's own records, not a synthetic ensemble it never ran, and go into
//! the study folder's `figures/` by default.

mod common;

use std::path::Path;
use std::process::Command;

use rockfrag::case::Param;
use rockfrag::motion::{SynthesisSettings, synthesize, write_csv};
use rockfrag::paper::is_papers;
use rockfrag::spec::{Motions, Study};

/// A study of two recorded motions (CSV files beside the spec, PGA 0.25 g
/// and 0.35 g as recorded, so neither is the synthetic sample's 0.6 g), run
/// by the binary into `root/out`, the spec given by absolute path.
fn run_recorded_study(root: &Path) -> std::path::PathBuf {
    let settings = SynthesisSettings {
        duration: 8.0,
        ..SynthesisSettings::default()
    };
    for (i, pga_g) in [0.25, 0.35].into_iter().enumerate() {
        let r = synthesize(&settings, 9, i as u64, pga_g * settings.g).unwrap();
        write_csv(root.join(format!("rec-{i}.csv")), &r).unwrap();
    }
    let spec = root.join("recorded.toml");
    std::fs::write(
        &spec,
        "name = \"recorded\"\nrecord_files = [\"rec-0.csv\", \"rec-1.csv\"]\n\
         [grid]\naspect = [4]\nrestitution = [0]\npga = [0.3, 0.9]\n",
    )
    .unwrap();
    let out = root.join("out");
    let o = common::run_spec(&spec, &out);
    assert!(o.status.success(), "{}", common::stderr(&o));
    out
}

/// Without `--out`, the figures go to `DIR/figures/` (not `figures/` in the
/// working directory, which stays empty). The sample record is the study's
/// first file as recorded (its name and PGA 0.25 g in the title), the
/// history is chosen among the study's files (a file name in its title,
/// no ensemble seed), and the spectrum is that of the study's two records
/// as recorded, with no synthetic target.
#[test]
fn recorded_study_figures_show_its_records_in_its_folder() {
    let root = tempfile::tempdir().unwrap();
    let study = run_recorded_study(root.path());
    let cwd = tempfile::tempdir().unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_rockfrag"))
        .args(["figures", study.to_str().unwrap()])
        .current_dir(cwd.path())
        .output()
        .unwrap();
    let err = common::stderr(&o);
    assert!(o.status.success(), "{err}");
    assert_eq!(std::fs::read_dir(cwd.path()).unwrap().count(), 0);
    let figures = study.join("figures");
    let listed = common::stdout(&o);
    for name in ["motion", "history", "fragility", "restitution"] {
        let path = figures.join(format!("{name}.svg"));
        assert!(path.is_file(), "{}", path.display());
        assert!(listed.contains(&path.display().to_string()), "{listed}");
    }
    let spectrum = std::fs::read_to_string(figures.join("spectrum.svg")).unwrap();
    assert!(
        spectrum.contains("Mean spectrum of 2 recorded motions"),
        "spectrum title"
    );
    assert!(!spectrum.contains("eq. (6)"), "no synthetic target");
    assert!(!err.contains("spectrum: skipped"), "{err}");
    let motion = std::fs::read_to_string(figures.join("motion.svg")).unwrap();
    assert!(
        motion.contains("rec-0.csv, as recorded (PGA 0.25 g)"),
        "motion title"
    );
    assert!(!motion.contains("ensemble seed"));
    let history = std::fs::read_to_string(figures.join("history.svg")).unwrap();
    assert!(
        history.contains("; rec-"),
        "history title names a record file"
    );
    assert!(!history.contains("of seed"));
    // H/B 4, e 0, PGA 0.3 and 0.9 g are cells of the paper's tables, but
    // these are not the paper's motions: no paper markers, no legend entry.
    let demand = std::fs::read_to_string(figures.join("friction_demand.svg")).unwrap();
    assert!(demand.contains("this study, mean"));
    assert!(!demand.contains("paper, Tables"), "paper markers drawn");
}

/// The paper's markers are for the paper's set-up only: the built-in study
/// is one; the same study with recorded motions, another block width, or
/// fewer records is not.
#[test]
fn only_the_papers_setup_draws_the_papers_values() {
    let paper = Study::shenton_jones();
    assert!(is_papers(&paper));
    let mut wide = paper.clone();
    wide.widths = vec![Param::Fixed(1.0)];
    assert!(!is_papers(&wide));
    let mut few = paper.clone();
    if let Motions::Synthetic { records, .. } = &mut few.motions {
        *records = 5;
    }
    assert!(!is_papers(&few));
    let mut recorded = paper.clone();
    recorded.motions = Motions::Files(Vec::new());
    assert!(!is_papers(&recorded));
}
