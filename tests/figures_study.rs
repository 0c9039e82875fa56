//! Study figures (`rockfrag figures`): drawn from a small synthetic study
//! folder, through the library and through the binary.
//!
//! How curves are counted in the SVG. Plotters writes a solid line series as
//! one `<polyline>` holding every point, and a dashed series as one short
//! `<polyline>` per dash, consecutively. Legends never draw polylines, and
//! reference curves, axes and ticks are black. So, among the `<polyline>`s
//! whose stroke is not black:
//! - a *solid series* is one polyline with exactly as many points as the
//!   series has (a dash is far shorter than the spacing of the data points
//!   here, so it never holds that many);
//! - a *dashed series* is a maximal run of consecutive shorter polylines of
//!   one stroke colour (the figures draw every solid series before the dashed
//!   ones, so a run never borders a solid series of its colour).
//!
//! Confidence bands are `<polygon>`s and observed points `<circle>`s in the
//! series' colour (legend markers are black; hollow markers add a white
//! `<circle>` beneath, which is not counted).

mod common;

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::fs;
use std::path::{Path, PathBuf};

use rockfrag::figures::StudyData;
use rockfrag::figures::{FigureOptions, study_figures};
use rockfrag::figures::{HistoryCase, HistoryFigure, mode_colour};
use rockfrag::motion::SynthesisSettings;

const ASPECTS: [f64; 2] = [2.0, 4.0];
const RESTITUTIONS: [f64; 4] = [0.0, 0.3, 0.6, 0.9];
const FRICTIONS: [&str; 2] = ["inf", "coulomb"];
const PGAS: [f64; 4] = [0.3, 0.6, 0.9, 1.2];
const RECORDS: u64 = 5;
/// Points of each fitted curve in `fragility_curves.csv`.
const IM_POINTS: usize = 30;

use common::FIGURES;

/// Writes `outcomes.csv` (and `fragility_curves.csv` if `curves`) for the
/// grid above into `dir`, rows in reverse order if `reversed`. Outcomes are
/// plausible and deterministic: record 0 never overturns (so every cell has
/// a mean θmax/θc), higher PGA and slenderer blocks overturn more. One failed
/// analysis and an unknown column are included; both must be ignored.
fn write_study(dir: &Path, curves: bool, reversed: bool) {
    let mut rows = Vec::new();
    for &aspect in &ASPECTS {
        for &e in &RESTITUTIONS {
            for friction in FRICTIONS {
                let (mu_s, mu_k) = if friction == "inf" {
                    ("", "")
                } else {
                    ("0.7", "0.6")
                };
                for &pga in &PGAS {
                    let p = (pga * aspect / 4.0 - 0.1 + 0.1 * e).clamp(0.0, 0.8);
                    for record in 0..RECORDS {
                        let overturned = record >= 1 && (record as f64) <= p * RECORDS as f64;
                        rows.push(format!(
                            "{aspect},0.5,{e},{friction},{mu_s},{mu_k},{pga},{record},ok,{overturned},false,{},{},{},{},0,0,0.001,x,",
                            0.1 + 0.3 * pga + 0.01 * record as f64 - 0.05 * e,
                            0.75 / aspect + 0.05 * pga,
                            if e == 0.0 { 0.3 / aspect * 2.0 } else { 0.35 * (1.0 + 20.0 * e) },
                            3 + record,
                        ));
                    }
                }
            }
        }
    }
    rows.push("4,0.5,0.3,inf,,,0.6,99,failed,,,,,,,,,,x,solver failed".to_string());
    if reversed {
        rows.reverse();
    }
    let mut text = String::from(
        "aspect,width,restitution,friction,mu_s,mu_k,pga,record,status,overturned,uplifted,\
         theta_max_over_theta_c,mu_motion,mu_impact,impacts,flights,uplifts,slip_max,unknown,error\n",
    );
    for r in rows {
        text.push_str(&r);
        text.push('\n');
    }
    fs::write(dir.join("outcomes.csv"), text).unwrap();

    if curves {
        // The header the fragility command writes.
        let mut text = format!("{}\n", rockfrag::fragility::CURVES_HEADER);
        let mut case = 0;
        for &aspect in &ASPECTS {
            for &e in &RESTITUTIONS {
                for friction in FRICTIONS {
                    let (mu_s, mu_k) = if friction == "inf" {
                        ("", "")
                    } else {
                        ("0.7", "0.6")
                    };
                    case += 1;
                    for k in 1..=IM_POINTS {
                        let im = 0.05 * k as f64;
                        let p = 1.0 / (1.0 + (-(im - 2.4 / aspect) / 0.15).exp());
                        writeln!(
                            text,
                            "{case},{aspect},0.5,{e},{friction},{mu_s},{mu_k},overturning,pga,{im},{p},{},{}",
                            0.8 * p,
                            (1.2 * p + 0.02).min(1.0)
                        )
                        .unwrap();
                    }
                }
            }
        }
        fs::write(dir.join("fragility_curves.csv"), text).unwrap();
    }
}

/// Figure options that keep the test quick (a 20-record spectrum).
/// Fast options for the fixture: a 20-record spectrum.
fn quick() -> FigureOptions {
    FigureOptions {
        spectrum_records: 20,
        ..FigureOptions::default()
    }
}

/// A parsed SVG's data marks.
struct Marks {
    /// Non-black polylines, in document order: (stroke, number of points).
    lines: Vec<(String, usize)>,
    /// Non-black polylines with more than 2 points, any colour.
    long_any: usize,
    /// `<polygon>` count.
    polygons: usize,
    /// `<circle>`s whose stroke or fill is not black.
    coloured_circles: usize,
    /// `<rect>` count by fill colour.
    rects: BTreeMap<String, usize>,
    /// All `<text>` contents.
    texts: Vec<String>,
}

fn marks(path: &Path) -> Marks {
    let text = fs::read_to_string(path).unwrap();
    let doc = roxmltree::Document::parse(&text)
        .unwrap_or_else(|e| panic!("{} parses as XML: {e}", path.display()));
    assert_eq!(doc.root_element().tag_name().name(), "svg");
    // black marks are axes, ticks, references and legend samples; white
    // ones are the interiors of hollow markers
    let black = |c: Option<&str>| c.is_none_or(|c| c == "#000000" || c == "#FFFFFF" || c == "none");
    let mut m = Marks {
        lines: vec![],
        long_any: 0,
        polygons: 0,
        coloured_circles: 0,
        rects: BTreeMap::new(),
        texts: vec![],
    };
    for n in doc.descendants() {
        match n.tag_name().name() {
            "polyline" => {
                let points = n
                    .attribute("points")
                    .unwrap_or("")
                    .split_whitespace()
                    .count();
                if points > 2 {
                    m.long_any += 1;
                }
                if !black(n.attribute("stroke")) {
                    m.lines
                        .push((n.attribute("stroke").unwrap().to_string(), points));
                }
            }
            "polygon" => m.polygons += 1,
            "circle" if !black(n.attribute("stroke")) || !black(n.attribute("fill")) => {
                m.coloured_circles += 1;
            }
            "rect" => {
                *m.rects
                    .entry(n.attribute("fill").unwrap_or("").to_string())
                    .or_default() += 1;
            }
            "text" => m.texts.push(n.text().unwrap_or("").trim().to_string()),
            _ => {}
        }
    }
    m
}

impl Marks {
    /// Solid series of `points` points.
    fn solid(&self, points: usize) -> usize {
        self.lines.iter().filter(|l| l.1 == points).count()
    }

    /// Dashed series: maximal runs of consecutive polylines of one colour
    /// with fewer than `points` points.
    fn dashed(&self, points: usize) -> usize {
        let mut runs = 0;
        let mut prev: Option<&str> = None;
        for (stroke, n) in &self.lines {
            if *n >= points {
                prev = None;
                continue;
            }
            if prev != Some(stroke.as_str()) {
                runs += 1;
            }
            prev = Some(stroke);
        }
        runs
    }

    fn has_text(&self, needle: &str) -> bool {
        self.texts.iter().any(|t| t.contains(needle))
    }
}

/// Reads every file of `dir`, by name.
fn contents(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    fs::read_dir(dir)
        .unwrap()
        .map(|e| {
            let e = e.unwrap();
            (
                e.file_name().to_string_lossy().into_owned(),
                fs::read(e.path()).unwrap(),
            )
        })
        .collect()
}

fn svg(dir: &Path, name: &str) -> PathBuf {
    dir.join(format!("{name}.svg"))
}

/// A study fitted for a second limit state (`uplift`, every case, listed
/// before overturning as the milder one) has its curves drawn too, each with
/// its own band: twice the solid and dashed series and twice the bands; the
/// title names both in order of severity and the legend has a row for each;
/// the axis says P(exceeded).
#[test]
fn every_limit_state_is_drawn_with_its_band() {
    let study = tempfile::tempdir().unwrap();
    write_study(study.path(), true, false);
    let path = study.path().join("fragility_curves.csv");
    let text = fs::read_to_string(&path).unwrap();
    let mut lines = text.lines();
    let mut more = format!("{}\n", lines.next().unwrap());
    let body: Vec<&str> = lines.collect();
    for line in &body {
        let mut f: Vec<String> = line.split(',').map(str::to_string).collect();
        f[7] = "uplift".into();
        for i in [10, 11, 12] {
            let p: f64 = f[i].parse().unwrap();
            f[i] = p.sqrt().to_string();
        }
        more.push_str(&f.join(","));
        more.push('\n');
    }
    for line in &body {
        more.push_str(line);
        more.push('\n');
    }
    fs::write(&path, more).unwrap();
    let out = study.path().join("figures");
    study_figures(study.path(), &out, &quick()).unwrap();
    let series = ASPECTS.len() * RESTITUTIONS.len();
    let f = marks(&svg(&out, "fragility"));
    assert_eq!(f.solid(IM_POINTS), 2 * series, "solid curves (μ = ∞)");
    assert_eq!(f.dashed(IM_POINTS), 2 * series, "dashed curves (Coulomb)");
    assert_eq!(f.polygons, 2 * 2 * series, "a band for every curve");
    assert!(f.has_text("P(exceeded)"), "{:?}", f.texts);
    assert!(
        f.texts
            .iter()
            .any(|t| t.contains("uplift, overturning (light to dark)")),
        "{:?}",
        f.texts
    );
    assert!(
        f.has_text("uplift") && f.has_text("overturning"),
        "{:?}",
        f.texts
    );
}

#[test]
fn every_figure_parses_and_has_its_curves() {
    // Each SVG is well-formed and carries the expected number of series (see
    // the module docs for how they are counted): fragility, 2 panels × 4 e,
    // solid for μ = ∞ and dashed for Coulomb, a band per curve and a point
    // per PGA stripe; friction demand, a line per PGA in (a) and per e in
    // (b); restitution, a line per PGA × friction in each of 2 × 2 panels;
    // the spectrum and the record their fixed series.
    let study = tempfile::tempdir().unwrap();
    write_study(study.path(), true, false);
    let out = study.path().join("figures");
    let report = study_figures(study.path(), &out, &quick()).unwrap();
    assert!(report.notes.is_empty(), "{:?}", report.notes);
    let names: Vec<PathBuf> = FIGURES.iter().map(|n| svg(&out, n)).collect();
    assert_eq!(report.written, names);

    let series = ASPECTS.len() * RESTITUTIONS.len();
    let f = marks(&svg(&out, "fragility"));
    assert_eq!(f.solid(IM_POINTS), series, "solid fitted curves (μ = ∞)");
    assert_eq!(
        f.dashed(IM_POINTS),
        series,
        "dashed fitted curves (Coulomb)"
    );
    assert_eq!(f.polygons, 2 * series, "one 90 % band per curve");
    assert_eq!(
        f.coloured_circles,
        2 * series * PGAS.len(),
        "observed stripes"
    );
    for t in [
        "H/B = 2",
        "H/B = 4",
        "PGA (g)",
        "P(overturning)",
        "e = 0.3",
        "μ = ∞",
    ] {
        assert!(f.has_text(t), "fragility lacks {t:?}: {:?}", f.texts);
    }
    assert!(f.has_text("μₛ = 0.7, μₖ = 0.6"));

    // (a) one line per PGA over the two B/H values, (b) one per e
    let d = marks(&svg(&out, "friction_demand"));
    assert_eq!(d.solid(ASPECTS.len()), PGAS.len() + RESTITUTIONS.len());
    assert_eq!(d.dashed(ASPECTS.len()), 0);
    for t in ["B/H", "eq. (8)", "0.75·B/H", "(log scale)"] {
        assert!(d.has_text(t), "friction demand lacks {t:?}");
    }
    // The generic figures know nothing of the seed paper: no published
    // values beside a study that is not the paper's (this fixture has no
    // manifest), though it shares the paper's grid values.
    for svg_file in ["friction_demand", "restitution"] {
        let m = marks(&svg(&out, svg_file));
        assert!(
            !m.texts.iter().any(|t| t.contains("paper")),
            "{svg_file}: {:?}",
            m.texts
        );
    }

    // 2 rows × 2 blocks × 4 PGA levels, each solid (μ = ∞) and dashed
    let r = marks(&svg(&out, "restitution"));
    let per_friction = 2 * ASPECTS.len() * PGAS.len();
    assert_eq!(r.solid(RESTITUTIONS.len()), per_friction);
    assert_eq!(r.dashed(RESTITUTIONS.len()), per_friction);
    assert_eq!(
        r.coloured_circles,
        2 * per_friction * RESTITUTIONS.len(),
        "a point per e on every line"
    );
    for t in [
        "Coefficient of restitution e",
        "Mean θmax/θc",
        "5 records per point",
    ] {
        assert!(r.has_text(t), "restitution lacks {t:?}: {:?}", r.texts);
    }

    // target and records as lines, the stationary process as markers
    let s = marks(&svg(&out, "spectrum"));
    assert_eq!(s.long_any, 2, "target (black) and records (coloured)");
    assert_eq!(s.lines.len(), 1);
    assert!(s.coloured_circles > 20, "stationary estimate markers");
    assert!(s.has_text("Frequency (Hz)"));

    let m = marks(&svg(&out, "motion"));
    assert_eq!(m.long_any, 3, "acceleration, velocity, displacement");
}

#[test]
fn history_shades_every_mode_interval_and_shows_several_modes() {
    // The history figure is one finite-friction run (μs = 0.6, μk = 0.4,
    // e = 0.6) chosen for showing modes: at least three, including a sliding
    // one. Its SVG has two curves (ground acceleration and θ/θc, black, every
    // sample) and one background rectangle per mode interval in each panel.
    let case = HistoryCase {
        aspect: 2.0,
        width: 0.5,
        restitution: 0.6,
        mu_s: 0.6,
        mu_k: 0.4,
        pga: 0.9,
        seed: 1,
        records: 25,
    };
    let fig = HistoryFigure::compute(&case, &SynthesisSettings::default()).unwrap();
    let modes: std::collections::BTreeSet<&str> =
        fig.intervals.iter().map(|iv| iv.mode.name()).collect();
    assert!(modes.len() >= 3, "{modes:?}");
    assert!(
        modes.contains("slide") || modes.contains("slide-rock"),
        "{modes:?}"
    );
    assert!(!fig.impacts.is_empty());
    assert!(fig.window.1 - fig.window.0 < 30.0, "zoomed in");
    for w in fig.intervals.windows(2) {
        assert_eq!(w[0].t1, w[1].t0, "intervals tile the window");
        assert_ne!(w[0].mode, w[1].mode, "neighbours differ");
    }

    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("history.svg");
    rockfrag::figures::save(&fig, &path).unwrap();
    let h = marks(&path);
    assert_eq!(h.long_any, 2, "acceleration and θ/θc");
    let shaded: usize = rockfrag::outcome::Mode::ALL
        .iter()
        .map(|&m| {
            let c = mode_colour(m);
            let key = format!("#{:02X}{:02X}{:02X}", c.0, c.1, c.2);
            h.rects.get(&key).copied().unwrap_or(0)
        })
        .sum();
    // legend blocks: one per mode
    assert_eq!(shaded, 2 * fig.intervals.len() + 5);
    for t in [
        "Time (s)",
        "Rotation θ/θc",
        "Ground acceleration (g)",
        "slide-rock",
        "impact",
    ] {
        assert!(h.has_text(t), "history lacks {t:?}");
    }
}

#[test]
fn running_twice_or_reordering_rows_gives_identical_bytes() {
    // Determinism: the same study drawn twice gives byte-identical files, in
    // SVG and PNG, and so does the same study with its rows in another order
    // (the figures sort what they read).
    let a = tempfile::tempdir().unwrap();
    let b = tempfile::tempdir().unwrap();
    write_study(a.path(), true, false);
    write_study(b.path(), true, true);
    let mut options = quick();
    study_figures(a.path(), &a.path().join("one"), &options).unwrap();
    study_figures(a.path(), &a.path().join("two"), &options).unwrap();
    study_figures(b.path(), &b.path().join("one"), &options).unwrap();
    let one = contents(&a.path().join("one"));
    assert_eq!(one.len(), FIGURES.len());
    assert_eq!(one, contents(&a.path().join("two")));
    assert_eq!(one, contents(&b.path().join("one")));

    options.format = rockfrag::figures::Format::Png;
    study_figures(a.path(), &a.path().join("png1"), &options).unwrap();
    study_figures(a.path(), &a.path().join("png2"), &options).unwrap();
    let png = contents(&a.path().join("png1"));
    assert!(png.values().all(|b| b.starts_with(b"\x89PNG")));
    assert_eq!(png, contents(&a.path().join("png2")));
}

#[test]
fn without_fitted_curves_the_fragility_figure_says_so() {
    // No fragility_curves.csv: the figure joins the observed fractions (a
    // solid line per e for μ = ∞, dashed for Coulomb, one point per stripe),
    // draws no bands, says in its title that there are no fits, and the
    // report notes it.
    let study = tempfile::tempdir().unwrap();
    write_study(study.path(), false, false);
    let out = study.path().join("figures");
    let report = study_figures(study.path(), &out, &quick()).unwrap();
    assert_eq!(report.notes.len(), 1, "{:?}", report.notes);
    assert!(report.notes[0].contains("observed fractions only"));
    let f = marks(&svg(&out, "fragility"));
    let series = ASPECTS.len() * RESTITUTIONS.len();
    assert_eq!(f.solid(PGAS.len()), series);
    assert_eq!(f.dashed(PGAS.len()), series);
    assert_eq!(f.polygons, 0);
    assert!(f.has_text("no fits"), "{:?}", f.texts);
    assert!(StudyData::load(study.path()).unwrap().curves.is_none());
}

#[test]
fn the_binary_writes_the_figures_and_reports_them() {
    // `rockfrag figures DIR --out OUT` writes the six SVGs, lists them on
    // standard output, and a second run gives the same bytes; a folder
    // without outcomes.csv fails with a message naming the file.
    let study = tempfile::tempdir().unwrap();
    write_study(study.path(), true, false);
    let dir = study.path().to_str().unwrap();
    let run = |out: &str| {
        let out = study.path().join(out);
        let o = common::rockfrag(&["figures", dir, "--out", out.to_str().unwrap()]);
        assert!(o.status.success(), "{}", common::stderr(&o));
        (out, common::stdout(&o))
    };
    let (first, listed) = run("a");
    for name in FIGURES {
        assert!(listed.contains(&format!("{name}.svg")), "{listed}");
        marks(&svg(&first, name));
    }
    let (second, _) = run("b");
    assert_eq!(contents(&first), contents(&second));

    let empty = tempfile::tempdir().unwrap();
    let o = common::rockfrag(&["figures", empty.path().to_str().unwrap()]);
    assert!(!o.status.success());
    assert!(
        common::stderr(&o).contains("outcomes.csv"),
        "{}",
        common::stderr(&o)
    );
}
