//! Units of the inputs (issue 37): a record, a hazard curve or a floor mode
//! in another unit than the one declared is refused, naming the file or
//! field, the value and the likely unit, instead of giving outcomes 9.81 or
//! 100 times off (a PGV of 23.5 m/s, a floor at 3·10⁴ g).

mod common;

use std::path::Path;

use rockfrag::motion::{
    At2, Floor, G_STANDARD as G, SynthesisSettings, Synthesizer, floor_record, read_csv,
    read_record, write_csv,
};
use rockfrag::risk::HazardCurve;

/// A synthetic record of PGA 0.3 g, as rockfrag writes it (SI CSV): its
/// rows `t,acc,vel,disp`.
fn record_rows(dir: &Path) -> (rockfrag::motion::Record, Vec<[f64; 4]>) {
    let mut syn = Synthesizer::new(&SynthesisSettings::default()).unwrap();
    let rec = syn.generate(5, 0, 0.3 * G).unwrap();
    let path = dir.join("si.csv");
    write_csv(&path, &rec).unwrap();
    let rows = std::fs::read_to_string(&path)
        .unwrap()
        .lines()
        .skip(1)
        .map(|l| {
            let v: Vec<f64> = l.split(',').map(|x| x.parse().unwrap()).collect();
            [v[0], v[1], v[2], v[3]]
        })
        .collect();
    (rec, rows)
}

/// Writes `rows` with each column times `scale` (and only the first
/// `columns`) as `name`.
fn write_scaled(dir: &Path, name: &str, rows: &[[f64; 4]], scale: [f64; 4], columns: usize) {
    let header = ["t", "acc", "vel", "disp"][..columns].join(",");
    let mut text = format!("{header}\n");
    for r in rows {
        let fields: Vec<String> = (0..columns)
            .map(|c| format!("{:?}", r[c] * scale[c]))
            .collect();
        text.push_str(&fields.join(","));
        text.push('\n');
    }
    std::fs::write(dir.join(name), text).unwrap();
}

fn error(r: rockfrag::Result<rockfrag::motion::Record>) -> String {
    match r {
        Ok(rec) => panic!("{} was read (PGA {} m/s²)", rec.name, rec.pga()),
        Err(e) => e.to_string(),
    }
}

/// A CSV record is SI. Its own columns read back (ratio 1); `vel` in cm/s
/// (100 times its integral of `acc`: a study scaled it 100 times too weakly
/// to PGV and reported PGVs of 23.5 m/s), `disp` in cm, `acc` in g with
/// `vel` in m/s (ratio 9.81), `acc` in cm/s² (peak 294 m/s², above 50) and
/// a record in g with `t,acc` only (a 0.004 g record: peak 0.0039 m/s²,
/// below 0.05) are refused, naming the file, the column and the likely
/// unit; the floor's record that `rockfrag floor` writes (its velocity from
/// the oscillators, not a trapezoid of its acceleration) reads back.
#[test]
fn csv_records_in_other_units_are_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    let (rec, rows) = record_rows(d);
    read_csv(d.join("si.csv")).unwrap();
    let cases: [(&str, [f64; 4], usize, &[&str]); 5] = [
        (
            "vel-cm.csv",
            [1.0, 1.0, 100.0, 1.0],
            4,
            &[
                "vel-cm.csv:1:",
                "column 'vel' is 100 times",
                "(vel in cm/s?)",
            ],
        ),
        (
            "disp-cm.csv",
            [1.0, 1.0, 1.0, 100.0],
            4,
            &["column 'disp' is 100 times", "(disp in cm?)"],
        ),
        (
            "acc-g.csv",
            [1.0, 1.0 / G, 1.0, 1.0],
            4,
            &["column 'vel' is 9.81 times", "(acc in g?)"],
        ),
        (
            "acc-cm.csv",
            [1.0, 100.0, 1.0, 1.0],
            2,
            &["peak acceleration 294 m/s² (30.0 g)", "divide them by 100"],
        ),
        (
            "weak-g.csv",
            [1.0, 0.0133 / G, 1.0, 1.0],
            2,
            &[
                "weak-g.csv:1: column 'acc': peak acceleration 0.00399 m/s²",
                "below 0.05 m/s²",
                "multiply them by 9.81",
            ],
        ),
    ];
    for (name, scale, columns, wants) in cases {
        write_scaled(d, name, &rows, scale, columns);
        let e = error(read_record(d.join(name), G));
        for w in wants {
            assert!(e.contains(w), "{name}: no {w:?} in {e}");
        }
    }
    let roof = floor_record(&rec, &Floor::one_mode(0.8, 0.05, 1.3)).unwrap();
    write_csv(d.join("roof.csv"), &roof).unwrap();
    read_csv(d.join("roof.csv")).unwrap();
}

/// A PEER `.AT2` file whose header says G (or says nothing) but whose values
/// are in cm/s² reads as a 294 g record: refused at the peak's line,
/// saying how to state the unit; with the header's units line saying
/// CM/SEC/SEC it reads as the 0.3 g record it is.
#[test]
fn an_at2_record_in_cm_s2_labelled_g_is_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let d = tmp.path();
    let (rec, _) = record_rows(d);
    let mut at2 = At2::from_record(&rec, G);
    at2.acc_g.iter_mut().for_each(|a| *a *= 100.0 * G);
    at2.write(d.join("gal.AT2")).unwrap();
    let e = error(read_record(d.join("gal.AT2"), G));
    assert!(
        e.contains("gal.AT2:")
            && e.contains("(294 g), read in g")
            && e.contains("IN UNITS OF CM/SEC/SEC"),
        "{e}"
    );
    at2.header[2] = "ACCELERATION TIME SERIES IN UNITS OF CM/SEC/SEC".into();
    at2.write(d.join("gal.AT2")).unwrap();
    let back = read_record(d.join("gal.AT2"), G).unwrap();
    assert!((back.pga() / (0.3 * G) - 1.0).abs() < 1e-9);
}

/// A plain hazard file is taken in the fit's unit: levels 4.9–490 (cm/s²)
/// or 0.049–49 (m/s²) for a PGA fit are refused, naming the file, the
/// levels and the likely units, instead of a warning to give the curve
/// lower levels; the same curve in g passes. A PGV curve in cm/s too.
#[test]
fn a_hazard_curve_in_another_unit_is_refused() {
    let p = Path::new("hazard.csv");
    let rates = [2e-2, 2e-3, 2e-4];
    for (iml, im, wants) in [
        (
            [4.9, 49.0, 490.0],
            "pga",
            "cm/s² (gal; divide by 981 for g)",
        ),
        ([0.049, 0.49, 49.0], "pga", "m/s² (divide by 9.81)"),
        ([5.0, 50.0, 200.0], "pgv", "cm/s (divide by 100 for m/s)"),
    ] {
        let h = HazardCurve::from_rates(p, &iml, &rates).unwrap();
        let e = h.in_unit_of(im.parse().unwrap()).unwrap_err().to_string();
        assert!(
            e.contains("hazard.csv") && e.contains("levels from") && e.contains(wants),
            "{e}"
        );
    }
    let g = HazardCurve::from_rates(p, &[0.005, 0.05, 0.5], &rates).unwrap();
    assert!(g.in_unit_of(rockfrag::im::Im::PGA).is_ok());
}

/// A floor mode with Γφ = 10⁵ made the floor accelerate at 3·10⁴ g, and a
/// period of 10⁻³⁰⁰ s (ω² overflowing) left it standing still: both are
/// refused in a spec, naming `support.floor[0]`'s field, the value and the
/// accepted range; Γφ = −0.4 (a higher mode) and T = 0.8 s pass.
#[test]
fn absurd_floor_modes_are_refused() {
    let spec = |mode: &str| {
        rockfrag::spec::Study::from_toml(
            &format!("[support]\nfloor = [{mode}]\n"),
            Path::new("roof.toml"),
        )
    };
    for (mode, field, want) in [
        (
            "{ period = 0.8, damping = 0.05, participation = 1e5 }",
            "support.floor[0].participation",
            "from −3 to 3",
        ),
        (
            "{ period = 1e-300, damping = 0.05 }",
            "support.floor[0].period",
            "from 0.001 to 100 s",
        ),
    ] {
        let e = spec(mode).unwrap_err().to_string();
        assert!(
            e.contains("roof.toml") && e.contains(field) && e.contains(want),
            "{e}"
        );
    }
    assert!(spec("{ period = 0.8, damping = 0.05, participation = -0.4 }").is_ok());
}
