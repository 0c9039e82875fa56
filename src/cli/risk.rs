//! `rockfrag risk`: the annual rate of each limit state at a site, the
//! study's fitted fragility integrated over the site's hazard curve.

use std::io::Write;
use std::path::PathBuf;

use anyhow::Context;
use rockfrag::io_util::sig3;
use rockfrag::risk::{
    HazardSource, RELATIVE_TOLERANCE, RiskOptions, RiskRow, describe_hazard, standing_rows,
    survival_cell,
};

/// Flags of `rockfrag risk`.
#[derive(Debug, clap::Args)]
pub struct RiskArgs {
    /// Study directory holding `fragility.csv` (and `fragility_bootstrap.csv`
    /// for the 90 % band).
    #[arg(value_name = "DIR")]
    pub dir: PathBuf,
    /// Hazard curve for the fit's IM: OpenQuake's hazard-curve CSV
    /// (`hazard_curve-mean-PGA_*.csv`) or a plain CSV `iml,annual_rate`
    /// (IML in the fit's unit).
    #[arg(long, value_name = "FILE")]
    pub hazard: PathBuf,
    /// Exposure time N, years: for the probability of exceedance
    /// 1 − exp(−λN), and of a case still standing after N years, exp(−λN)
    /// (a precariously balanced rock that has stood N years).
    #[arg(long, value_name = "N", default_value_t = RiskOptions::default().years)]
    pub years: f64,
    /// Site of an OpenQuake file: its 0-based data row [default: 0].
    #[arg(long, value_name = "K")]
    pub site: Option<usize>,
    /// Folder to write risk.csv, risk_hazard.csv (the hazard as
    /// integrated) and figures/risk.svg into [default: DIR] (`rockfrag
    /// figures` redraws the figure from them, also as PNG); DIR's summary.md
    /// gets its `## Risk` section only when they go to DIR.
    #[arg(long, value_name = "OUT_DIR")]
    pub out: Option<PathBuf>,
}

/// Runs `rockfrag risk`.
pub fn run(args: RiskArgs) -> anyhow::Result<()> {
    let options = RiskOptions {
        years: args.years,
        ..RiskOptions::default()
    };
    let report = rockfrag::pipeline::risk(
        &args.dir,
        &args.hazard,
        args.site,
        &options,
        args.out.as_deref(),
    )?;
    let (rows, hazard) = (&report.rows, &report.hazard);
    let [csv, used, figure] = &report.written;

    // The table is the data (stdout); what was read and written is status
    // (stderr), as for every subcommand.
    let mut text = format!("hazard: {}\n", describe_hazard(hazard).replace('`', ""));
    if hazard.source == HazardSource::Plain {
        text.push_str(&format!(
            "note: plain hazard file: its levels are taken in the fit's unit ({} {})\n",
            report.im,
            report.im.unit()
        ));
    }
    if hazard.dropped_low + hazard.dropped_high > 0 {
        text.push_str(&format!(
            "note: left out {} level(s) at the low end with poe = 1 or too close to 1 for \
             its digits to fix the rate to 0.1 %, and {} with rate 0 at the high end\n",
            hazard.dropped_low, hazard.dropped_high
        ));
    }
    if !report.banded {
        text.push_str(
            "note: no fragility_bootstrap.csv: no band on the rates (rerun rockfrag \
             fragility DIR with --bootstrap N)\n",
        );
    }
    text.push_str(&format!(
        "wrote {}, {}, {}{}\n",
        csv.display(),
        used.display(),
        figure.display(),
        report
            .summary
            .as_ref()
            .map_or(String::new(), |p| format!(", {} (## Risk)", p.display()))
    ));
    for r in rows {
        if let Some(w) = r.tail_warning(options.tail_warning) {
            eprintln!("warning: {w}");
        }
        if let Some(i) = r
            .integral
            .filter(|i| i.error > 1e3 * RELATIVE_TOLERANCE * i.rate)
        {
            eprintln!(
                "warning: {} {}: quadrature error estimate {} of the rate",
                r.curve.key,
                r.curve.limit_state,
                sig3(i.error / i.rate)
            );
        }
    }
    eprint!("{text}");
    let mut stdout = std::io::stdout().lock();
    let data = format!(
        "{}{}",
        table(rows, &options),
        still_standing(rows, &options)
    );
    match stdout.write_all(data.as_bytes()) {
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
        other => other.context("writing to standard output"),
    }
}

/// P(still standing after N years) = exp(−λN) for each case, λ the rate
/// of its limit state named `overturning` (else of its last, most severe):
/// for a precariously balanced rock that has stood N years, how likely the
/// hazard curve makes that.
fn still_standing(rows: &[RiskRow], options: &RiskOptions) -> String {
    let pct = (options.confidence * 100.0).round();
    let mut cells = vec![vec![
        "case".to_string(),
        format!(
            "P(still standing after {} years) [{pct}%]",
            rockfrag::io_util::number(options.years)
        ),
    ]];
    for r in standing_rows(rows) {
        cells.push(vec![
            r.curve.key.to_string(),
            survival_cell(r, options.years),
        ]);
    }
    rockfrag::io_util::aligned(&cells)
}

fn table(rows: &[RiskRow], options: &RiskOptions) -> String {
    let years = sig3(options.years);
    let pct = (options.confidence * 100.0).round();
    let header: Vec<String> = [
        "case".to_string(),
        "limit state".to_string(),
        format!("annual rate [{pct}%]"),
        "return period (yr)".to_string(),
        format!("P in {years} yr"),
        "peak IM".to_string(),
        "below/above".to_string(),
    ]
    .to_vec();
    let mut cells = vec![header];
    for r in rows {
        let c = &r.curve;
        let row = match r.integral {
            None => vec![
                c.key.to_string(),
                c.limit_state.clone(),
                format!("not fitted ({})", c.status),
                String::new(),
                String::new(),
                String::new(),
                String::new(),
            ],
            Some(i) => {
                let band = r.band.map_or(String::new(), |b| {
                    format!(" [{}, {}]", sig3(b.lo), sig3(b.hi))
                });
                let (below, above) = r.shares().unwrap_or_default();
                vec![
                    c.key.to_string(),
                    c.limit_state.clone(),
                    format!("{}{band}", sig3(i.rate)),
                    r.return_period_text().unwrap_or_default(),
                    sig3(r.poe(options.years).unwrap_or(f64::NAN)),
                    r.peak_text(),
                    format!("{:.2}%/{:.2}%", 100.0 * below, 100.0 * above),
                ]
            }
        };
        cells.push(row);
    }
    rockfrag::io_util::aligned(&cells)
}
