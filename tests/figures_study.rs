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
//!
//! The fragility figure draws a fitted curve over its case's stripes in the
//! curve's colour and its extrapolated parts (below the lowest stripe,
//! above the highest) dotted, in a lighter tint: many two-point polylines
//! of a colour no curve has over the stripes. [`Marks::curves`] and
//! [`Marks::dashed_in`] count the curves by their colours over the stripes.

mod common;

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::fs;
use std::path::{Path, PathBuf};

use rockfrag::figures::StudyData;
use rockfrag::figures::{FigureOptions, study_figures};
use rockfrag::figures::{HistoryFigure, bounce_colour, mode_colour};
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

    /// Colours of the polylines of at least `points` points: the solid
    /// curves' colours over the stripes.
    fn curve_colours(&self, points: usize) -> std::collections::BTreeSet<&str> {
        self.lines
            .iter()
            .filter(|l| l.1 >= points)
            .map(|l| l.0.as_str())
            .collect()
    }

    /// Solid curves: polylines of at least `points` points.
    fn curves(&self, points: usize) -> usize {
        self.lines.iter().filter(|l| l.1 >= points).count()
    }

    /// Dashed series in `colours`: maximal runs of consecutive polylines of
    /// one of those colours with fewer than `points` points.
    fn dashed_in(&self, points: usize, colours: &std::collections::BTreeSet<&str>) -> usize {
        let mut runs = 0;
        let mut prev: Option<&str> = None;
        for (stroke, n) in &self.lines {
            if *n >= points || !colours.contains(stroke.as_str()) {
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

    /// Short polylines in colours no curve over the stripes has: the dotted
    /// extrapolated parts.
    fn dotted(&self, points: usize) -> usize {
        let colours = self.curve_colours(points);
        self.lines
            .iter()
            .filter(|l| l.1 < points && !colours.contains(l.0.as_str()))
            .count()
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
/// its own band: twice the solid and dashed series and twice the bands (one
/// per distinct curve: the fixture's Coulomb curves are its μ = ∞ ones, and
/// a curve drawn on its twin gets no band of its own); the title names both
/// in order of severity and the legend has a row for each; the axis says
/// P(exceeded).
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
    let long = IM_POINTS / 2;
    assert_eq!(f.curves(long), 2 * series, "solid curves (μ = ∞)");
    let colours = f.curve_colours(long);
    assert_eq!(
        f.dashed_in(long, &colours),
        2 * series,
        "dashed curves (Coulomb)"
    );
    assert_eq!(f.polygons, 2 * series, "a band for every distinct curve");
    assert!(f.has_text("P(exceeded)"), "{:?}", f.texts);
    assert!(
        f.texts
            .iter()
            .any(|t| t.contains("uplift, overturning (light to dark)")),
        "{:?}",
        f.texts
    );
    assert!(f.dotted(long) > 0, "extrapolated parts drawn dotted");
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
    let long = IM_POINTS / 2;
    assert_eq!(f.curves(long), series, "solid fitted curves (μ = ∞)");
    let colours = f.curve_colours(long);
    assert_eq!(
        f.dashed_in(long, &colours),
        series,
        "dashed fitted curves (Coulomb)"
    );
    // the Coulomb curves are the μ = ∞ ones: one band for the two
    assert_eq!(f.polygons, series, "one 90 % band per distinct curve");
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
    // each panel its own y label and its own legend (issue 29: (a) had no
    // y label, and its PGA entries shared rows with (b)'s e entries)
    for t in [
        "Mean μₘₒₜ = max |F|/N",
        "Mean max |Pₜ/Pₙ|",
        "PGA (g):",
        "e:",
    ] {
        assert!(d.has_text(t), "friction demand lacks {t:?}: {:?}", d.texts);
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
        // the fixture's Coulomb runs are its μ = ∞ runs: said, as the
        // dashed lines lie hidden under the solid ones
        "μₛ = 0.7, μₖ = 0.6 (as μ = ∞)",
    ] {
        assert!(r.has_text(t), "restitution lacks {t:?}: {:?}", r.texts);
    }

    // target and records as lines, what the records should show dashed,
    // the stationary process as markers
    let s = marks(&svg(&out, "spectrum"));
    assert_eq!(s.lines.len(), 1, "the records (coloured)");
    // the target (black) and the dashes of the records' expected spectrum
    assert!(s.long_any > 2, "{}", s.long_any);
    assert!(s.has_text("S(f) through envelope and high-pass"));
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
    // the paper layer chooses the record among 25 (through the ensemble
    // primitive); the figure solves that one with its history
    let case = rockfrag::paper::history_case(&SynthesisSettings::default(), 1).unwrap();
    assert_eq!(
        (
            case.aspect,
            case.width,
            case.restitution,
            case.mu_s,
            case.mu_k
        ),
        (2.0, 0.5, 0.6, 0.6, 0.4)
    );
    assert_eq!((case.pga, case.seed, case.records), (0.9, 1, 25));
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
        // but two flights with a bounce (an impact) between them
        let bounce = w[0].mode == rockfrag::outcome::Mode::Flight && fig.impacts.contains(&w[1].t0);
        assert!(w[0].mode != w[1].mode || bounce, "neighbours differ");
    }

    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("history.svg");
    rockfrag::figures::save(&fig, &path).unwrap();
    let h = marks(&path);
    assert_eq!(h.long_any, 2, "acceleration and θ/θc");
    let key = |c: plotters::style::RGBColor| format!("#{:02X}{:02X}{:02X}", c.0, c.1, c.2);
    let flight = rockfrag::outcome::Mode::Flight;
    let shaded: usize = rockfrag::outcome::Mode::ALL
        .iter()
        .map(|&m| h.rects.get(&key(mode_colour(m))).copied().unwrap_or(0))
        .sum::<usize>()
        + h.rects
            .get(&key(bounce_colour(flight)))
            .copied()
            .unwrap_or(0);
    // legend blocks: one per mode, and one for a flight after a bounce
    let bounces = fig.intervals.windows(2).any(|w| w[0].mode == w[1].mode);
    assert_eq!(shaded, 2 * fig.intervals.len() + 5 + usize::from(bounces));
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

/// Writes `fragility.csv` and `fragility_curves.csv` of lognormal fits for
/// the fixture's cases, θ = `theta(aspect, e, friction)`, β = `beta`, the
/// curves sampled as the fragility command samples them (IM_POINTS points,
/// 0.05 g apart, up to 1.5 g: short of the top of the stockier blocks').
fn write_lognormal_fits(dir: &Path, theta: &dyn Fn(f64, f64, &str) -> f64, beta: f64) {
    use statrs::distribution::{ContinuousCDF, Normal};
    let phi = Normal::standard();
    let mut fits = String::from(
        "aspect,width,restitution,friction,mu_s,mu_k,limit_state,im,median,beta,status,im_unit\n",
    );
    let mut curves = format!("{}\n", rockfrag::fragility::CURVES_HEADER);
    let mut case = 0;
    for &aspect in &ASPECTS {
        for &e in &RESTITUTIONS {
            for friction in FRICTIONS {
                let (mu_s, mu_k) = if friction == "inf" {
                    ("", "")
                } else {
                    ("0.7", "0.6")
                };
                let median = theta(aspect, e, friction);
                writeln!(
                    fits,
                    "{aspect},0.5,{e},{friction},{mu_s},{mu_k},overturning,pga,{median},{beta},ok,g"
                )
                .unwrap();
                for k in 1..=IM_POINTS {
                    let im = 0.05 * k as f64;
                    let p = phi.cdf((im / median).ln() / beta);
                    writeln!(
                        curves,
                        "{case},{aspect},0.5,{e},{friction},{mu_s},{mu_k},overturning,pga,{im},{p},{},{}",
                        0.9 * p,
                        (1.1 * p).min(1.0)
                    )
                    .unwrap();
                }
                case += 1;
            }
        }
    }
    fs::write(dir.join("fragility.csv"), fits).unwrap();
    fs::write(dir.join("fragility_curves.csv"), curves).unwrap();
}

/// Issue 29: the fragility axis stopped at the last stripe, cutting the
/// H/B 2 curves off at P ≈ 0.6. With θ and β in `fragility.csv`, the axis
/// runs on to where every curve reaches P = 0.95, and each curve is drawn on
/// to it (the file's points then the extension), dotted beyond the
/// stripes; the bands stop at the last stripe. When a curve would need
/// more than 1.5× the last point of the data, the axis stops there and the
/// title says how many curves are still below 0.95 (issue 37: it ran to
/// 3×).
#[test]
fn the_fragility_axis_reaches_where_every_curve_is_at_0_95() {
    use rockfrag::figures::{FragilityFigure, ShortCurves};
    let z95 = 1.6448536269514722;
    let study = tempfile::tempdir().unwrap();
    write_study(study.path(), true, false);
    let (beta, theta) = (0.3, |aspect: f64, _: f64, _: &str| 2.4 / aspect);
    write_lognormal_fits(study.path(), &theta, beta);
    let fig = FragilityFigure::from_study(&StudyData::load(study.path()).unwrap());
    // H/B 2: θ = 1.2 g reaches 0.95 at 1.2·e^(1.645·0.3) ≈ 1.97 g
    let needed = 1.2 * (z95 * beta).exp();
    assert!(
        fig.x_max >= needed && fig.x_max < 1.1 * needed,
        "{}",
        fig.x_max
    );
    assert_eq!(fig.short_of_reach, ShortCurves::default());
    assert!(!fig.title.contains("below P"), "{}", fig.title);
    let n_ext = fig.panels[0].series[0].extension[0].len();
    assert!(n_ext >= 2, "{n_ext}");
    for s in fig.panels.iter().flat_map(|p| &p.series) {
        let end = s.extension[0].last().expect("extended to the axis end");
        assert!(end.1 >= 0.95, "curve ends at P = {}", end.1);
        assert_eq!(s.extension[0].len(), n_ext);
        // over the stripes (0.3–1.2 g) in full, dotted beyond
        let [below, middle, above] = s.curve_parts(0);
        assert_eq!(s.stripe_range, Some((0.3, 1.2)));
        assert!(middle.iter().all(|p| (0.3..=1.2).contains(&p.0)));
        assert!(below.iter().all(|p| p.0 <= 0.3) && above.iter().all(|p| p.0 >= 1.2));
        assert_eq!(above.last().map(|p| p.0), Some(fig.x_max));
    }
    let out = study.path().join("figures");
    study_figures(study.path(), &out, &quick()).unwrap();
    let f = marks(&svg(&out, "fragility"));
    let series = ASPECTS.len() * RESTITUTIONS.len();
    assert_eq!(f.curves(IM_POINTS / 2), series, "solid curves");
    assert!(f.dotted(IM_POINTS / 2) > 0, "extrapolated, dotted");
    assert_eq!(f.polygons, series, "bands, over the stripes");
    assert!(f.has_text("over the stripes"), "{:?}", f.texts);
    assert!(
        f.has_text("extrapolated beyond the stripes"),
        "{:?}",
        f.texts
    );

    // β = 1: θ·e^(1.645) ≈ 6.2 g for H/B 2, beyond 1.5 × 1.5 g
    write_lognormal_fits(study.path(), &theta, 1.0);
    let fig = FragilityFigure::from_study(&StudyData::load(study.path()).unwrap());
    assert!((fig.x_max - 1.03 * 1.5 * 1.5).abs() < 1e-9, "{}", fig.x_max);
    let capped = fig.short_of_reach.capped;
    assert!(capped > 0 && fig.short_of_reach.unextended == 0);
    assert!(
        fig.title.contains(&format!(
            "{capped} curves below P = 0.95 at the axis end (1.5 × the last stripe)"
        )),
        "{}",
        fig.title
    );
    // the fixture's own curves (no fragility.csv) stop short for H/B 2;
    // its Coulomb curves are drawn on their μ = ∞ twins and not counted
    // again
    fs::remove_file(study.path().join("fragility.csv")).unwrap();
    write_study(study.path(), true, false);
    let fig = FragilityFigure::from_study(&StudyData::load(study.path()).unwrap());
    assert_eq!(fig.short_of_reach.unextended, RESTITUTIONS.len());
    assert!(
        fig.title
            .contains("4 curves end below P = 0.95 (no θ, β in fragility.csv)"),
        "{}",
        fig.title
    );
}

/// Issue 29: a friction model that changes no outcome draws its dashed
/// curve exactly on the solid one, where it cannot be seen. When every
/// Coulomb curve is its μ = ∞ twin, the legend says `(as μ = ∞)`; when only
/// some are, each panel names the e values at its top left and the legend
/// does not.
#[test]
fn fragility_names_friction_curves_hidden_under_the_solid_ones() {
    let study = tempfile::tempdir().unwrap();
    write_study(study.path(), true, false);
    let out = study.path().join("figures");
    // the fixture's outcomes and curves do not depend on friction
    write_lognormal_fits(study.path(), &|a, _, _| 2.4 / a, 0.3);
    study_figures(study.path(), &out, &quick()).unwrap();
    let f = marks(&svg(&out, "fragility"));
    assert!(f.has_text("μₛ = 0.7, μₖ = 0.6 (as μ = ∞)"), "{:?}", f.texts);
    assert!(!f.has_text("dashed = solid"), "{:?}", f.texts);

    // now the Coulomb fit at e = 0.9 differs
    let theta = |a: f64, e: f64, f: &str| {
        if f == "coulomb" && e == 0.9 {
            3.0 / a
        } else {
            2.4 / a
        }
    };
    write_lognormal_fits(study.path(), &theta, 0.3);
    study_figures(study.path(), &out, &quick()).unwrap();
    let f = marks(&svg(&out, "fragility"));
    assert!(!f.has_text("(as μ = ∞)"), "{:?}", f.texts);
    let notes = f
        .texts
        .iter()
        .filter(|t| t.as_str() == "dashed = solid: e = 0, 0.3, 0.6")
        .count();
    assert_eq!(notes, ASPECTS.len(), "{:?}", f.texts);
}

/// The shipped example hazard curve (OpenQuake CSV, PGA).
fn example_hazard() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("studies/hazard/hazard_curve-mean-PGA_example.csv")
}

/// Issue 29, items 9 and 10: `rockfrag figures` draws the risk figure once
/// `rockfrag risk` has run, in SVG (the same bytes `risk` wrote) and in PNG,
/// from the hazard curve `risk` kept beside `risk.csv`; every limit state is
/// in the legend, one without a fit said on its row. Without that curve,
/// or when the fit has changed since, it says why there is no risk figure
/// instead of drawing one that disagrees with `risk.csv`.
#[test]
fn figures_draw_the_risk_figure_once_risk_has_run() {
    let study = tempfile::tempdir().unwrap();
    let d = study.path();
    write_study(d, true, false);
    write_lognormal_fits(d, &|a, _, _| 2.4 / a, 0.3);
    // a second limit state for the first two cases: fitted for the first,
    // not for the second
    let fits = fs::read_to_string(d.join("fragility.csv")).unwrap();
    let mut lines: Vec<&str> = fits.lines().collect();
    lines.insert(2, "2,0.5,0,inf,,,uplift,pga,0.4,0.3,ok,g");
    lines.insert(4, "2,0.5,0,coulomb,0.7,0.6,uplift,pga,,,separated,g");
    fs::write(d.join("fragility.csv"), lines.join("\n") + "\n").unwrap();
    let dir = d.to_str().unwrap();
    let figures = |extra: &[&str]| {
        let mut args = vec!["figures", dir];
        args.extend_from_slice(extra);
        let o = common::rockfrag(&args);
        assert!(o.status.success(), "{}", common::stderr(&o));
        (common::stdout(&o), common::stderr(&o))
    };

    // no risk.csv: no risk figure, and nothing to say about it
    let (listed, notes) = figures(&[]);
    assert!(!listed.contains("risk"), "{listed}");
    assert!(!notes.contains("risk"), "{notes}");

    let hazard = example_hazard();
    let o = common::rockfrag(&["risk", dir, "--hazard", hazard.to_str().unwrap()]);
    assert!(o.status.success(), "{}", common::stderr(&o));
    assert!(d.join("risk_hazard.csv").is_file());
    let drawn_by_risk = fs::read(d.join("figures/risk.svg")).unwrap();

    let (listed, _) = figures(&[]);
    assert!(listed.contains("risk.svg"), "{listed}");
    assert_eq!(fs::read(d.join("figures/risk.svg")).unwrap(), drawn_by_risk);
    let r = marks(&d.join("figures/risk.svg"));
    for t in [
        "overturning",
        "uplift",
        "uplift: no fit (separated)",
        "site 0 of hazard_curve-mean-PGA_example.csv",
    ] {
        assert!(r.has_text(t), "risk lacks {t:?}: {:?}", r.texts);
    }

    let png = d.join("png");
    let (listed, _) = figures(&["--format", "png", "--out", png.to_str().unwrap()]);
    assert!(listed.contains("risk.png"), "{listed}");
    assert!(
        fs::read(png.join("risk.png"))
            .unwrap()
            .starts_with(b"\x89PNG")
    );

    // refitted since: the rates no longer those of risk.csv
    let refit = fs::read_to_string(d.join("fragility.csv"))
        .unwrap()
        .replace(",overturning,pga,1.2,", ",overturning,pga,1.3,");
    fs::write(d.join("fragility.csv"), refit).unwrap();
    fs::remove_file(d.join("figures/risk.svg")).unwrap();
    let (listed, notes) = figures(&[]);
    assert!(!listed.contains("risk"), "{listed}");
    assert!(
        notes.contains("does not hold the rates of the fit"),
        "{notes}"
    );

    // a risk.csv without the hazard it was computed over
    fs::remove_file(d.join("risk_hazard.csv")).unwrap();
    let (listed, notes) = figures(&[]);
    assert!(!listed.contains("risk"), "{listed}");
    assert!(
        notes.contains("no risk_hazard.csv") && notes.contains("rerun `rockfrag risk"),
        "{notes}"
    );
}

/// Issue 29, item 10: the deaggregation curves of the risk figure were
/// sawtooths, the log–log interpolated hazard's slope jumping at each of its
/// levels. Drawn with the slope smoothed, as the peak is located, each
/// rises to one maximum, at its peak mark, and falls; the legend names the
/// hazard's extrapolation only where it is drawn.
#[test]
fn risk_deaggregation_curves_are_smooth_and_peak_at_their_marks() {
    use rockfrag::figures::RiskFigure;
    use rockfrag::risk::{RiskOptions, assess, read_fragility, read_hazard};
    let study = tempfile::tempdir().unwrap();
    let d = study.path();
    write_lognormal_fits(d, &|a, e, _| 2.4 / a + 0.1 * e, 0.3);
    let fragility = read_fragility(d).unwrap();
    let hazard = read_hazard(&example_hazard(), None)
        .unwrap()
        .in_unit_of(rockfrag::im::Im::PGA)
        .unwrap();
    let rows = assess(&fragility, &hazard, &RiskOptions::default()).unwrap();
    let figure = RiskFigure::new(&rows, &hazard);
    let series: Vec<_> = figure.cases.iter().flat_map(|c| &c.series).collect();
    assert_eq!(series.len(), rows.len());
    for s in series {
        let y: Vec<f64> = s.integrand.iter().map(|p| p.1).collect();
        let maxima = (1..y.len() - 1)
            .filter(|&i| y[i] > y[i - 1] && y[i] >= y[i + 1])
            .count();
        assert_eq!(maxima, 1, "one maximum, not a sawtooth: {y:?}");
        let top = (0..y.len()).max_by(|&i, &j| y[i].total_cmp(&y[j])).unwrap();
        let step = (s.integrand[1].0 / s.integrand[0].0).ln();
        assert!(
            (s.integrand[top].0 / s.peak_im).ln().abs() <= step,
            "the curve peaks at {} and its mark is at {}",
            s.integrand[top].0,
            s.peak_im
        );
    }
    let out = d.join("risk.svg");
    rockfrag::figures::save(&figure, &out).unwrap();
    let svg = marks(&out);
    assert!(!svg.has_text("extrapolated"), "{:?}", svg.texts);
    // a hazard curve that stops short of the fits: its extension drawn and named
    let short = rockfrag::risk::HazardCurve::from_rates(
        Path::new("short.csv"),
        &[0.3, 0.6, 0.9],
        &[3e-3, 8e-4, 2e-4],
    )
    .unwrap();
    let rows = assess(&fragility, &short, &RiskOptions::default()).unwrap();
    rockfrag::figures::save(&RiskFigure::new(&rows, &short), &out).unwrap();
    let svg = marks(&out);
    assert!(svg.has_text("extrapolated"), "{:?}", svg.texts);
}
