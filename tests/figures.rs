//! Figures: the record plot in both formats, and the file handling every
//! figure shares (format by extension, atomic write, errors).

use std::f64::consts::PI;
use std::fs;
use std::path::Path;

use rockfrag::Error;
use rockfrag::figures::{Format, plot_record, style};
use rockfrag::motion::{G_STANDARD, Record};

/// A 30 s record at Δt = 0.02 s (the paper's sampling): four sines under a
/// sin² envelope. The acceleration is the exact second derivative of the
/// displacement Σ Aᵢ w(t) sin(ωᵢ t), w = sin²(πt/T), so velocity and
/// displacement (integrated by the linear-acceleration rule) start and end
/// near rest, as a high-passed record does. Peak about 0.33 g.
fn synthetic_record(name: &str) -> Record {
    let (dt, t_end) = (0.02, 30.0);
    let n = (t_end / dt) as usize + 1;
    let parts = [(0.004, 2.1), (0.0025, 3.7), (0.002, 1.3), (0.001, 5.9)];
    let a = PI / t_end;
    let acc = (0..n)
        .map(|k| {
            let t = k as f64 * dt;
            let (w, w1, w2) = (
                (a * t).sin().powi(2),
                a * (2.0 * a * t).sin(),
                2.0 * a * a * (2.0 * a * t).cos(),
            );
            parts
                .iter()
                .map(|&(amp, f)| {
                    let om = 2.0 * PI * f;
                    let (s, c) = (om * t).sin_cos();
                    amp * (w2 * s + 2.0 * w1 * om * c - w * om * om * s)
                })
                .sum()
        })
        .collect();
    Record::from_acc(name, dt, acc).unwrap()
}

/// Names of the files in `dir`.
fn listing(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

#[test]
fn synthetic_record_is_a_plausible_ground_motion() {
    // The test record must look like a record (so the figure is judged on
    // realistic data): peak about 0.3 g and ending near rest, not drifting.
    let r = synthetic_record("check");
    let pga_g = r.pga() / G_STANDARD;
    assert!((0.2..0.5).contains(&pga_g), "pga = {pga_g} g");
    assert!(r.vel.last().unwrap().abs() < 0.01 * r.pgv());
    let peak_disp = r.disp.iter().fold(0.0_f64, |m, d| m.max(d.abs()));
    assert!(r.disp.last().unwrap().abs() < 0.01 * peak_disp);
}

#[test]
fn svg_has_three_series_and_labelled_axes() {
    // The SVG is what goes into papers: it must be well-formed XML, one
    // column wide (700 px at 200 px/in), carry exactly the three data series
    // (plotters writes each line series as one <polyline> with every sample;
    // axes and tick marks are 2-point polylines), and label every quantity
    // with its unit, as text a reader can search and an editor can restyle.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("record.svg");
    let record = synthetic_record("synthetic 0.33 g");
    plot_record(&record, &path).unwrap();

    let text = fs::read_to_string(&path).unwrap();
    let doc = roxmltree::Document::parse(&text).expect("SVG parses as XML");
    let svg = doc.root_element();
    assert_eq!(svg.tag_name().name(), "svg");
    let width: f64 = svg.attribute("width").unwrap().parse().unwrap();
    assert_eq!(width, style::COLUMN_WIDTH_IN * style::SVG_PX_PER_IN);

    let series: Vec<_> = doc
        .descendants()
        .filter(|n| n.has_tag_name("polyline") || n.has_tag_name("path"))
        .filter(|n| {
            let points = n.attribute("points").unwrap_or("");
            points.split_whitespace().count() > 2
        })
        .collect();
    assert_eq!(series.len(), 3, "one series per panel");
    let blue = format!(
        "#{:02X}{:02X}{:02X}",
        style::PALETTE[0].0,
        style::PALETTE[0].1,
        style::PALETTE[0].2
    );
    for s in &series {
        assert_eq!(s.attribute("stroke"), Some(blue.as_str()));
        let points = s.attribute("points").unwrap().split_whitespace().count();
        assert_eq!(points, record.len(), "every sample is drawn");
    }

    let texts: Vec<String> = doc
        .descendants()
        .filter(|n| n.has_tag_name("text"))
        .map(|n| n.text().unwrap_or("").trim().to_string())
        .collect();
    for label in [
        "Acceleration (g)",
        "Velocity (cm/s)",
        "Displacement (cm)",
        "Time (s)",
        "synthetic 0.33 g",
    ] {
        let count = texts.iter().filter(|t| *t == label).count();
        assert_eq!(count, 1, "text {label:?} once, in {texts:?}");
    }
    // Tick labels are compact ("10", not "10.0") and use a true minus sign.
    assert!(texts.iter().any(|t| t == "30"), "{texts:?}");
    assert!(!texts.iter().any(|t| t.ends_with(".0")), "{texts:?}");
    assert!(texts.iter().any(|t| t.starts_with('\u{2212}')), "{texts:?}");
}

#[test]
fn png_is_a_png_at_print_resolution() {
    // PNG output must be a real PNG (magic bytes) of a single column at
    // 300 px/in: 1050 px wide, read from the IHDR chunk.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("record.png");
    plot_record(&synthetic_record("png"), &path).unwrap();

    let bytes = fs::read(&path).unwrap();
    assert!(!bytes.is_empty());
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
    assert_eq!(&bytes[12..16], b"IHDR");
    let width = u32::from_be_bytes(bytes[16..20].try_into().unwrap());
    assert_eq!(width, 1050);
}

#[test]
fn unknown_extension_is_an_error_naming_the_file() {
    // A typo or an unsupported format (.pdf) must be refused up front with a
    // message that names the file and says what is accepted, and must leave
    // nothing behind.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("record.pdf");
    let err = plot_record(&synthetic_record("pdf"), &path).unwrap_err();
    match &err {
        Error::InvalidParameter { field, value, .. } => {
            assert_eq!(field, "plot");
            assert!(value.ends_with("record.pdf"), "{value}");
        }
        other => panic!("expected InvalidParameter, got {other:?}"),
    }
    let message = err.to_string();
    assert!(message.contains("record.pdf") && message.contains(".svg"));
    assert!(listing(dir.path()).is_empty());
}

#[test]
fn extension_picks_the_format_and_svg_is_the_default() {
    // The extension alone decides the format, case-insensitively; a name
    // without one gets SVG, written under exactly the name given.
    assert_eq!(Format::from_path(Path::new("a.svg")).unwrap(), Format::Svg);
    assert_eq!(Format::from_path(Path::new("a.SVG")).unwrap(), Format::Svg);
    assert_eq!(Format::from_path(Path::new("a.Png")).unwrap(), Format::Png);
    assert_eq!(
        Format::from_path(Path::new("dir.d/a")).unwrap(),
        Format::Svg
    );
    assert!(Format::from_path(Path::new("a.jpg")).is_err());

    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("record");
    plot_record(&synthetic_record("bare"), &path).unwrap();
    let text = fs::read_to_string(&path).unwrap();
    assert!(text.starts_with("<svg"));
    assert_eq!(listing(dir.path()), ["record"]);
}

#[test]
fn writes_are_atomic_and_leave_no_temporary_files() {
    // A figure replaces an older one in one step (rename), and neither a
    // success nor a failure leaves temporary files in the directory.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("record.svg");
    fs::write(&path, "old").unwrap();
    plot_record(&synthetic_record("new"), &path).unwrap();
    assert!(fs::read_to_string(&path).unwrap().starts_with("<svg"));
    plot_record(&synthetic_record("png"), &dir.path().join("record.png")).unwrap();
    assert_eq!(listing(dir.path()), ["record.png", "record.svg"]);
}

#[test]
fn unwritable_destination_is_an_io_error_naming_the_file() {
    // A destination that cannot be a file's (its "directory" is a file) is
    // an I/O error that names the figure's path (not the temporary file's),
    // for both formats.
    let dir = tempfile::tempdir().unwrap();
    let blocker = dir.path().join("not-a-dir");
    fs::write(&blocker, "a file").unwrap();
    for name in ["record.svg", "record.png"] {
        let path = blocker.join(name);
        let err = plot_record(&synthetic_record("io"), &path).unwrap_err();
        match &err {
            Error::Io { path: p, .. } => assert_eq!(p, &path),
            other => panic!("expected Io, got {other:?}"),
        }
    }
    assert_eq!(listing(dir.path()), ["not-a-dir"]);
}

#[test]
fn invalid_record_is_refused_before_drawing() {
    // A record with a non-finite sample would draw nonsense: it is refused
    // as an invalid record and no file is written.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("record.svg");
    let mut record = synthetic_record("bad");
    record.vel[10] = f64::NAN;
    let err = plot_record(&record, &path).unwrap_err();
    assert!(matches!(err, Error::InvalidRecord { .. }), "{err:?}");
    assert!(listing(dir.path()).is_empty());
}

#[test]
fn figures_can_be_drawn_from_several_threads() {
    // Studies draw figures in parallel: font registration happens once and
    // temporary names never collide, even for the same destination.
    let dir = tempfile::tempdir().unwrap();
    let record = synthetic_record("parallel");
    std::thread::scope(|s| {
        for i in 0..4 {
            let (dir, record) = (dir.path(), &record);
            s.spawn(move || {
                plot_record(record, &dir.join(format!("r{i}.svg"))).unwrap();
                plot_record(record, &dir.join("same.svg")).unwrap();
            });
        }
    });
    assert_eq!(
        listing(dir.path()),
        ["r0.svg", "r1.svg", "r2.svg", "r3.svg", "same.svg"]
    );
}
