//! `rockfrag simulate --stack`: one analysis of a stack of blocks under one
//! record, printing what happened to each body (bottom first).

use anyhow::{Context, bail};
use rockfrag::error::fixed;
use rockfrag::motion::Record;
use rockfrag::solver::stack::{
    Stack, StackBody, StackHistory, StackInterface, StackOutcome, simulate_stack,
};
use rockfrag::solver::{Friction, ImpactLaw, SolverSettings};
use std::path::PathBuf;

/// What `simulate` passes on for `--stack`: the stack's flags and the
/// single block's that keep their meaning.
pub struct StackFlags {
    /// `--stack`: WIDTHxHEIGHT per body, bottom first.
    pub spec: String,
    /// `--masses`.
    pub masses: Option<String>,
    /// `--offsets`.
    pub offsets: Option<String>,
    /// `--interface-mu`.
    pub interface_mu: Option<String>,
    /// `--interface-restitution`.
    pub interface_restitution: Option<String>,
    /// `--tilts`.
    pub tilts: Option<String>,
    /// `--restitution` (every interface unless `--interface-restitution`).
    pub restitution: f64,
    /// `--mu-s` of the ground interface.
    pub mu_s: Option<f64>,
    /// `--mu-k` of the ground interface.
    pub mu_k: Option<f64>,
    /// `--g`.
    pub g: f64,
    /// `--impact`.
    pub impact: ImpactLaw,
    /// `--rtol`.
    pub rtol: f64,
    /// `--settle-tol`.
    pub settle_tol: f64,
    /// `--json`.
    pub json: bool,
    /// `--history`.
    pub history: Option<PathBuf>,
    /// `--free-motion-max`.
    pub free_motion_max: f64,
}

/// A list flag's values, one per body: `what` names the flag in errors.
fn per_body(flag: &str, text: &str, n: usize) -> anyhow::Result<Vec<String>> {
    let items: Vec<String> = text.split(',').map(|s| s.trim().to_string()).collect();
    if items.len() != n {
        bail!(
            "{flag} {text}: {} values for {n} bodies (give one per body, bottom first, \
             separated by commas)",
            items.len()
        );
    }
    Ok(items)
}

fn number(flag: &str, item: &str, text: &str) -> anyhow::Result<f64> {
    match item.parse::<f64>() {
        Ok(x) if x.is_finite() => Ok(x),
        _ => bail!("{flag} {text}: '{item}' is not a number"),
    }
}

/// The stack the flags describe.
pub fn stack_of(args: &StackFlags) -> anyhow::Result<Stack> {
    let spec = args.spec.as_str();
    let mut bodies = Vec::new();
    for item in spec.split(',') {
        let item = item.trim();
        let Some((w, h)) = item.split_once(['x', 'X']) else {
            bail!(
                "--stack {spec}: '{item}' is not WIDTHxHEIGHT (the body's width 2B and height \
                 2H in m, e.g. 0.8x1.0; bodies bottom first, separated by commas)"
            );
        };
        let (w, h) = (number("--stack", w, spec)?, number("--stack", h, spec)?);
        bodies.push(StackBody::new(w, h));
    }
    let n = bodies.len();
    if let Some(text) = &args.masses {
        for (b, m) in bodies.iter_mut().zip(per_body("--masses", text, n)?) {
            b.mass = number("--masses", &m, text)?;
        }
    }
    if let Some(text) = &args.offsets {
        for (b, x) in bodies.iter_mut().zip(per_body("--offsets", text, n)?) {
            b.offset = number("--offsets", &x, text)?;
        }
    }
    // the ground interface takes --restitution, --mu-s and --mu-k
    let ground = match args.mu_s {
        Some(mu_s) => Friction::Coulomb {
            mu_s,
            mu_k: args.mu_k.unwrap_or(mu_s),
        },
        None => Friction::Infinite,
    };
    let mut interfaces = vec![
        StackInterface {
            restitution: args.restitution,
            friction: Friction::Infinite,
        };
        n
    ];
    interfaces[0].friction = ground;
    if let Some(text) = &args.interface_restitution {
        for (f, e) in interfaces
            .iter_mut()
            .zip(per_body("--interface-restitution", text, n)?)
        {
            f.restitution = number("--interface-restitution", &e, text)?;
        }
    }
    if let Some(text) = &args.interface_mu {
        for (f, mu) in interfaces
            .iter_mut()
            .zip(per_body("--interface-mu", text, n)?)
        {
            f.friction = if mu.eq_ignore_ascii_case("inf") {
                Friction::Infinite
            } else {
                let (s, k) = mu.split_once(':').unwrap_or((&mu, &mu));
                Friction::Coulomb {
                    mu_s: number("--interface-mu", s, text)?,
                    mu_k: number("--interface-mu", k, text)?,
                }
            };
        }
    }
    let mut stack = Stack {
        bodies,
        interfaces,
        initial_tilt: Vec::new(),
        g: args.g,
    };
    if let Some(text) = &args.tilts {
        stack.initial_tilt = per_body("--tilts", text, n)?
            .iter()
            .map(|t| number("--tilts", t, text))
            .collect::<anyhow::Result<_>>()?;
    }
    stack
        .validate()
        .with_context(|| format!("--stack {spec}"))?;
    Ok(stack)
}

/// Solves the stack of `--stack` under `record` and prints the outcome.
pub fn run(args: &StackFlags, record: &Record) -> anyhow::Result<()> {
    let stack = stack_of(args)?;
    let settings = SolverSettings {
        impact: args.impact,
        rtol: args.rtol,
        settle_tol: args.settle_tol,
        free_motion_max: args.free_motion_max,
        ..SolverSettings::default()
    };
    let out = Report {
        json: args.json,
        history: args.history.as_deref(),
        g: args.g,
        heading: None,
    };
    out.solve(&stack, record, &settings)
}

/// How [`Report::solve`] reports one analysis of a stack: `simulate
/// --stack`'s and `simulate --study … --case stack_…`'s.
pub struct Report<'a> {
    /// `--json`: one JSON object `{"bodies": [...], ...}` instead of the summary.
    pub json: bool,
    /// `--history`: every body's state, written here.
    pub history: Option<&'a std::path::Path>,
    /// Gravity (m/s²), for the record's PGA in g.
    pub g: f64,
    /// A first line of the summary (the study's analysis it is).
    pub heading: Option<String>,
}

impl Report<'_> {
    /// Solves `stack` under `record` with `settings` and prints what
    /// happened to each body; an analysis that left the modes the solver
    /// models (or never came to rest) is printed, then an error. The
    /// numbers are a solve without history (as a study's row is made);
    /// with `history`, a second solve records it.
    pub fn solve(
        &self,
        stack: &Stack,
        record: &Record,
        settings: &SolverSettings,
    ) -> anyhow::Result<()> {
        let solving = || format!("solving the stack under record {}", record.name);
        let out = simulate_stack(stack, record, settings, None).with_context(solving)?;
        if let Some(path) = self.history {
            let mut h = StackHistory::default();
            simulate_stack(stack, record, settings, Some(&mut h)).with_context(solving)?;
            h.write_csv(path)?;
        }
        if self.json {
            println!("{}", out.to_json());
        } else {
            if let Some(line) = &self.heading {
                println!("{line}");
            }
            print_summary(stack, record, self.g, &out);
        }
        if let Some(reason) = &out.failure {
            bail!(
                "the analysis of the stack did not finish: {reason}; its numbers cover only the \
                 motion before and are not the run's response"
            );
        }
        Ok(())
    }
}

fn print_summary(stack: &Stack, record: &Record, g: f64, out: &StackOutcome) {
    println!(
        "record            {} ({} s, PGA {} g)",
        record.name,
        fixed(record.duration(), 2),
        fixed(record.pga() / g, 3)
    );
    for (k, (b, o)) in stack.bodies.iter().zip(&out.bodies).enumerate() {
        let name = match k {
            0 => "base".to_string(),
            k if k + 1 == stack.bodies.len() => "top".to_string(),
            k => format!("body {}", k + 1),
        };
        println!(
            "{name:<17} {}x{} m: θmax/θc {}, overturned {}{}, slip {} m",
            b.width,
            b.height,
            fixed(o.theta_max_over_theta_c, 4),
            if o.overturned { "yes" } else { "no" },
            o.overturn_time
                .map_or(String::new(), |t| format!(" at {} s", fixed(t, 3))),
            fixed(o.slip_max, 4)
        );
    }
    match out.first_overturned {
        Some(k) => println!("first overturned  body {} (bottom first)", k + 1),
        None => println!("first overturned  none"),
    }
    println!(
        "impacts           {} (energy gains {}, settles {}, lift-off holds {})",
        out.impacts, out.energy_gains, out.settles, out.liftoff_holds
    );
    println!("end time          {} s", fixed(out.end_time, 4));
    if let Some(reason) = &out.failure {
        println!("FAILED            {reason}");
    }
}
