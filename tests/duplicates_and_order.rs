//! One record counted twice and levels in another order (issue 37):
//! `record_files = ["good.AT2", "./good.AT2"]` ran the record twice, and an
//! unsorted `pga` list was taken and gave other draws than the sorted one.
//! Both are refused, naming the spec's fields.

use std::path::Path;

use rockfrag::motion::{At2, G_STANDARD as G, SynthesisSettings, Synthesizer};
use rockfrag::spec::Study;
use rockfrag::study::Source;

/// Writes synthetic record `index` (PGA 0.3 g) as `name` in `dir`.
fn record(dir: &Path, name: &str, index: u64) {
    let mut syn = Synthesizer::new(&SynthesisSettings::default()).unwrap();
    let rec = syn.generate(8, index, 0.3 * G).unwrap();
    At2::from_record(&rec, G).write(dir.join(name)).unwrap();
}

fn study(dir: &Path, files: &str, grid: &str) -> rockfrag::Result<Study> {
    let path = dir.join("spec.toml");
    let text = format!("name = \"d\"\nrecord_files = [{files}]\n[grid]\naspect = [4]\n{grid}\n");
    std::fs::write(&path, &text).unwrap();
    Study::load(&path)
}

/// The same file named two ways (`./`, `sub/..`, a symbolic link) is
/// refused at the second entry, naming the first; two pairs sharing a
/// component too. A copy under another name (the same motion bit for bit)
/// is refused when the records are read, naming both entries; two
/// different records pass.
#[test]
fn a_record_listed_twice_is_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    record(d, "good.AT2", 0);
    record(d, "other.AT2", 1);
    std::fs::create_dir(d.join("sub")).unwrap();
    std::fs::copy(d.join("good.AT2"), d.join("copy.AT2")).unwrap();
    #[cfg(unix)]
    std::os::unix::fs::symlink(d.join("good.AT2"), d.join("link.AT2")).unwrap();
    let grid = "pga = [0.3, 0.6]";
    let mut twice = vec![
        (
            "\"good.AT2\", \"./good.AT2\"",
            "record_files[1] = \"./good.AT2\"",
        ),
        (
            "\"good.AT2\", \"sub/../good.AT2\"",
            "record_files[1] = \"sub/../good.AT2\"",
        ),
        (
            "[\"good.AT2\", \"other.AT2\"], [\"copy.AT2\", \"./other.AT2\"]",
            "record_files[1][1] = \"./other.AT2\"",
        ),
    ];
    if cfg!(unix) {
        twice.push((
            "\"good.AT2\", \"link.AT2\"",
            "record_files[1] = \"link.AT2\"",
        ));
    }
    for (files, want) in twice {
        let e = study(d, files, grid).unwrap_err().to_string();
        assert!(
            e.contains("spec.toml") && e.contains(want) && e.contains("record_files[0]"),
            "{files}: {e}"
        );
        assert!(e.contains("count one record twice"), "{e}");
    }
    let copy = study(d, "\"good.AT2\", \"copy.AT2\"", grid).unwrap();
    let e = Source::new(&copy).unwrap_err().to_string();
    assert!(
        e.contains("\"good.AT2\" and \"copy.AT2\"") && e.contains("same motion"),
        "{e}"
    );
    let two = study(d, "\"good.AT2\", \"other.AT2\"", grid).unwrap();
    Source::new(&two).unwrap();
}

/// Intensity levels out of increasing order (`pga`, `pgv`, `scale_factors`)
/// are refused at the first out of order, naming it, its value and the one
/// before it; increasing lists pass. (A level's number keys its analyses'
/// draws: `[0.6, 0.3]` was another study than `[0.3, 0.6]`.)
#[test]
fn levels_out_of_order_are_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    record(d, "good.AT2", 0);
    for (grid, want) in [
        ("pga = [0.3, 0.9, 0.6]", "grid.pga[2] = 0.6"),
        ("pgv = [0.5, 0.2]", "grid.pgv[1] = 0.2"),
        (
            "scale_factors = [1.0, 2.0, 0.5]",
            "grid.scale_factors[2] = 0.5",
        ),
    ] {
        let e = study(d, "\"good.AT2\"", grid).unwrap_err().to_string();
        assert!(
            e.contains(want) && e.contains("increasing order"),
            "{grid}: {e}"
        );
    }
    for grid in [
        "pga = [0.3, 0.6, 0.9]",
        "pgv = [0.2, 0.5]",
        "scale_factors = [0.5, 1.0]",
    ] {
        study(d, "\"good.AT2\"", grid).unwrap();
    }
}
