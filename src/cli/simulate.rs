//! `rockfrag simulate`: one block under one record, printing the outcome.

use super::args::{
    choice, damping_ratio, finite, free_motion_s, non_negative, open_unit_interval, pga_g, pgv_m_s,
    positive, unit_interval,
};
use anyhow::Context;
use clap::ValueEnum;
use rockfrag::error::{fixed, number};
use rockfrag::im::Im;
use rockfrag::motion::{self, G_STANDARD, MeasuredPair, Pair, Record, SynthesisSettings};
use rockfrag::outcome::{Mode, Outcome};
use rockfrag::solver::{
    Analysis, Block, Friction, History, ImpactLaw, Initial, Integrator, Model, RockImpact,
    Sensitivity, SolverSettings, sensitivity, simulate,
};
use std::path::PathBuf;

/// Friction model, as a CLI value.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum FrictionArg {
    /// Contacts never slip.
    Inf,
}

/// Flags of `rockfrag simulate`.
#[derive(Debug, clap::Args)]
#[command(group = clap::ArgGroup::new("source").args(["motion", "seed", "study"]).required(true))]
pub struct SimulateArgs {
    /// One analysis of a study, solved again: the study's spec file or
    /// finished folder (its manifest.json). With --case, --level and
    /// --record it is the analysis of outcomes.csv at that case, level and
    /// record, drawn parameters, record pair and floor included, and
    /// --csv prints its row as the run wrote it, bit for bit; without
    /// --case, the block of --width, --aspect, --restitution, --mu-s and
    /// --mu-k under the motion that record and level give in the study. The
    /// study's solver settings apply.
    #[arg(long, value_name = "SPEC.toml|DIR", conflicts_with_all = [
        "motion", "seed", "pga", "pgv", "scale", "motion2", "orientation", "index",
        "floor_period", "floor_damping", "floor_participation", "model", "integrator",
        "impact", "rock_impact", "rtol", "settle_tol", "follow_cascades", "g",
        "free_motion_max",
    ])]
    pub study: Option<PathBuf>,
    /// With --study: the case, by its id (the `case_id` of fragility.csv,
    /// e.g. `a4_w0p2_edrawn_mudrawn`); its block, drawn values drawn as the
    /// run drew them, or a stack's bodies (`stack_NAME`), each reported.
    #[arg(long, value_name = "CASE_ID", requires = "study", conflicts_with_all = [
        "width", "aspect", "restitution", "mu_s", "mu_k", "friction",
    ])]
    pub case: Option<String>,
    /// With --study: the intensity level, one of the study's, in its unit
    /// (g for PGA, m/s for PGV, the factor for scale factors).
    #[arg(long, value_name = "X", requires = "study", value_parser = positive)]
    pub level: Option<f64>,
    /// With --study: the record, 0-based (outcomes.csv's `record` column).
    #[arg(long, value_name = "N", requires = "study")]
    pub record: Option<usize>,
    /// With --study and --case: print outcomes.csv's header and the
    /// analysis's row as the run wrote it.
    #[arg(long, requires = "case", conflicts_with_all = ["json", "history"])]
    pub csv: bool,
    /// Base width 2B of the block (m).
    #[arg(long, value_name = "M", default_value_t = 0.5, value_parser = positive, allow_negative_numbers = true)]
    pub width: f64,
    /// Aspect ratio H/B of the block.
    #[arg(long, value_name = "H/B", default_value_t = 4.0, value_parser = positive, allow_negative_numbers = true)]
    pub aspect: f64,
    /// Coefficient of restitution e in [0, 1].
    #[arg(long, value_name = "E", default_value_t = 0.0, value_parser = unit_interval, allow_negative_numbers = true)]
    pub restitution: f64,
    /// Friction model: `inf` (contacts never slip); give --mu-s for Coulomb friction.
    #[arg(long, value_enum, default_value_t = FrictionArg::Inf)]
    pub friction: FrictionArg,
    /// Static friction coefficient μs: selects finite (Coulomb) friction.
    #[arg(long = "mu-s", value_name = "X", value_parser = non_negative, conflicts_with = "friction")]
    pub mu_s: Option<f64>,
    /// Kinetic friction coefficient μk ≤ μs [default: μs].
    #[arg(long = "mu-k", value_name = "Y", value_parser = non_negative, requires = "mu_s")]
    pub mu_k: Option<f64>,
    /// Ground-motion record: CSV `t,acc[,vel,disp]` (s, m/s²) or PEER `.AT2` (g),
    /// used as recorded unless --scale, --pga or --pgv scales it.
    #[arg(long, value_name = "FILE", conflicts_with = "seed")]
    pub motion: Option<PathBuf>,
    /// Second horizontal component H2 of the --motion record (H1), same
    /// format, sampled together with it: the block feels
    /// cos φ·H1 + sin φ·H2 with φ from --orientation. --scale multiplies
    /// both components; --pga and --pgv then scale the pair to its RotD50
    /// PGA or PGV (orientation-independent), not the rotated component's.
    #[arg(long, value_name = "FILE", requires_all = ["motion", "orientation"])]
    pub motion2: Option<PathBuf>,
    /// Angle φ (degrees) from the --motion component H1 towards --motion2
    /// (H2) of the plane the block rocks in: 0 gives H1, 90 gives H2 bit
    /// for bit.
    #[arg(long, value_name = "DEG", value_parser = finite, requires = "motion2", allow_negative_numbers = true)]
    pub orientation: Option<f64>,
    /// Multiply the --motion record by X (acceleration, velocity and displacement).
    #[arg(long, value_name = "X", value_parser = positive, requires = "motion", conflicts_with_all = ["pga", "pgv"], allow_negative_numbers = true)]
    pub scale: Option<f64>,
    /// Scale the --motion record to this peak ground velocity (m/s).
    #[arg(long, value_name = "V", value_parser = pgv_m_s, requires = "motion", conflicts_with = "pga", allow_negative_numbers = true)]
    pub pgv: Option<f64>,
    /// Ensemble seed of a synthetic record (with --pga).
    #[arg(long, value_name = "N", requires = "pga")]
    pub seed: Option<u64>,
    /// Index of the synthetic record within the ensemble.
    #[arg(long, value_name = "I", default_value_t = 0)]
    pub index: u64,
    /// Peak ground acceleration (g): of the synthetic record (with --seed), or
    /// the --motion record scaled to it.
    #[arg(long, value_name = "G", value_parser = pga_g, allow_negative_numbers = true)]
    pub pga: Option<f64>,
    /// The block stands on a floor of a linear building: the natural period
    /// T (s) of one of its modes; repeat for several modes. The record (as
    /// scaled) is the ground's, filtered through the modes.
    #[arg(long = "floor-period", value_name = "T", value_parser = positive, allow_negative_numbers = true)]
    pub floor_period: Vec<f64>,
    /// Damping ratio ζ of the floor's modes: once for all, or once per
    /// --floor-period.
    #[arg(long = "floor-damping", value_name = "Z", value_parser = damping_ratio, allow_negative_numbers = true)]
    pub floor_damping: Vec<f64>,
    /// Participation Γφ of the floor's modes at the floor: once for all, or
    /// once per --floor-period [default: 1].
    #[arg(long = "floor-participation", value_name = "G", value_parser = finite, allow_negative_numbers = true)]
    pub floor_participation: Vec<f64>,
    /// Initial rotation θ0 (rad).
    #[arg(
        long = "theta0",
        value_name = "RAD",
        default_value_t = 0.0,
        allow_negative_numbers = true
    )]
    pub theta0: f64,
    /// Initial angular velocity θ̇0 (rad/s).
    #[arg(
        long = "theta-dot0",
        value_name = "RAD/S",
        default_value_t = 0.0,
        allow_negative_numbers = true
    )]
    pub theta_dot0: f64,
    /// Relative tolerance of the integrator.
    #[arg(long, value_name = "X", default_value_t = SolverSettings::default().rtol, value_parser = open_unit_interval)]
    pub rtol: f64,
    /// Ring-down settle threshold ε (rebounds below ε·√(gR) are plastic).
    #[arg(long, value_name = "X", default_value_t = SolverSettings::default().settle_tol, value_parser = open_unit_interval)]
    pub settle_tol: f64,
    /// Follow every impact: of an e = 0 ring-down instead of settling the
    /// cascade once it provably dies out, and of an e > 0 bounce series
    /// instead of closing its tail in closed form (the cascade rules).
    #[arg(long)]
    pub follow_cascades: bool,
    /// Rock equation: the nonlinear eq. (1) (integrated by --integrator), or
    /// linearised in θ, piecewise exact.
    #[arg(long, value_parser = choice::<Model>(Model::names()), default_value_t = Model::default())]
    pub model: Model,
    /// Integrator of the nonlinear rock equation: a Taylor series over each
    /// sample (fastest), or Dormand–Prince 5(4) with dense output.
    #[arg(long, value_parser = choice::<Integrator>(Integrator::names()), default_value_t = Integrator::default())]
    pub integrator: Integrator,
    /// Impact law: Newton restitution without slip (the paper's), or
    /// energy-consistent (never adds kinetic energy).
    #[arg(long, value_parser = choice::<ImpactLaw>(ImpactLaw::names()), default_value_t = ImpactLaw::default())]
    pub impact: ImpactLaw,
    /// What a rock impact with e > 0 leads to (infinite friction): the
    /// impact law in full, the block flies and rings down (physics); or
    /// `rock`, the block keeps rocking with ω₂/ω₁ = 1 − 1.5(1+e)sin²θc, no
    /// flight (a reading of the paper's program, not physics).
    #[arg(long, value_parser = choice::<RockImpact>(RockImpact::names()), default_value_t = RockImpact::default())]
    pub rock_impact: RockImpact,
    /// Longest free motion (s) followed after the record's end: a body still
    /// moving then goes on under still ground until it rests or overturns;
    /// one still moving this long after the record is a failure naming it.
    /// 0 stops at the record's end (the paper's program); at most 3600.
    #[arg(long = "free-motion-max", value_name = "SECONDS", default_value_t = SolverSettings::default().free_motion_max, value_parser = free_motion_s, allow_negative_numbers = true)]
    pub free_motion_max: f64,
    /// Gravity (m/s²), also used to convert accelerations given in g.
    #[arg(long, value_name = "M/S2", default_value_t = G_STANDARD, value_parser = positive)]
    pub g: f64,
    /// Track the ground's work and report the energy residual.
    #[arg(long)]
    pub audit_energy: bool,
    /// Write the time history (CSV `t,mode,theta,theta_dot,x,x_dot,y,y_dot,N,F`).
    #[arg(long, value_name = "FILE")]
    pub history: Option<PathBuf>,
    /// Solve a stack of blocks instead of one block: each body's width 2B
    /// and height 2H in m, bottom first, e.g. `0.8x1.0,0.3x1.2` (a statue
    /// on a pedestal). --restitution, --mu-s and --mu-k are the ground
    /// interface's; the motion options keep their meaning.
    #[arg(long, value_name = "WxH,WxH[,WxH]", conflicts_with_all = [
        "study", "model", "rock_impact", "theta0", "theta_dot0", "sensitivity", "audit_energy",
        "motion2", "orientation",
    ])]
    pub stack: Option<String>,
    /// With --stack: the bodies' masses, relative, bottom first [default:
    /// width × height, the same density].
    #[arg(long, value_name = "M,M[,M]", requires = "stack")]
    pub masses: Option<String>,
    /// With --stack: each body's horizontal offset (m) from the centre of
    /// the body below [default: 0, centred].
    #[arg(
        long,
        value_name = "X,X[,X]",
        requires = "stack",
        allow_hyphen_values = true
    )]
    pub offsets: Option<String>,
    /// With --stack: each interface's friction, bottom first: `inf`, μs, or
    /// μs:μk (the first is the ground's, overriding --mu-s).
    #[arg(long = "interface-mu", value_name = "MU,MU[,MU]", requires = "stack")]
    pub interface_mu: Option<String>,
    /// With --stack: each interface's coefficient of restitution, bottom
    /// first [default: --restitution for all].
    #[arg(
        long = "interface-restitution",
        value_name = "E,E[,E]",
        requires = "stack"
    )]
    pub interface_restitution: Option<String>,
    /// With --stack: each body's initial rotation (rad) relative to the body
    /// below, about the corner on the side of its sign [default: 0].
    #[arg(
        long,
        value_name = "RAD,RAD[,RAD]",
        requires = "stack",
        allow_hyphen_values = true
    )]
    pub tilts: Option<String>,
    /// Print the outcome as one JSON object.
    #[arg(long)]
    pub json: bool,
    /// Also solve the run under the record scaled by 1 + 1e-9 and say whether
    /// it is sensitive: overturning flipped, θmax/θc moved by more than 1e-3,
    /// or the overturning time by more than 0.01 s (one more solve).
    #[arg(long)]
    pub sensitivity: bool,
}

impl SimulateArgs {
    /// μk ≤ μs, checked with the arguments rather than when the record is
    /// solved (which named the record, not the flags).
    /// The pair's checks are the spec's: two different files, and an
    /// orientation in [0°, 360°) (each direction once).
    pub fn check(&self) -> Result<(), clap::Error> {
        let usage = |message: String| {
            Err(clap::Error::raw(
                clap::error::ErrorKind::ValueValidation,
                message + "\n",
            ))
        };
        if self.study.is_some() && (self.level.is_none() || self.record.is_none()) {
            return usage(
                "--study needs --level X and --record N: the analysis's intensity level and \
                 record (the `pga` or `pgv` and `record` columns of outcomes.csv)"
                    .to_string(),
            );
        }
        if let (Some(h1), Some(h2)) = (&self.motion, &self.motion2)
            && rockfrag::io_util::same_file(h1, h2)
        {
            return usage(format!(
                "--motion2 {} is the --motion file {}: give the second horizontal component, a \
                 file other than the first",
                h2.display(),
                h1.display()
            ));
        }
        if let Some(phi) = self.orientation
            && !rockfrag::motion::is_orientation(phi)
        {
            return usage(format!(
                "invalid value '{}' for --orientation <DEG>: expected {}",
                rockfrag::error::number(phi),
                rockfrag::motion::ORIENTATION_EXPECTED
            ));
        }
        match (self.mu_s, self.mu_k) {
            (Some(s), Some(k)) if k > s => Err(clap::Error::raw(
                clap::error::ErrorKind::ArgumentConflict,
                format!(
                    "--mu-k {k} is larger than --mu-s {s}: the kinetic friction coefficient \
                     cannot exceed the static one (give --mu-k ≤ {s}, or leave it out for μk = μs)\n"
                ),
            )),
            _ => Ok(()),
        }
    }
}

/// Runs `rockfrag simulate`.
pub fn run(args: SimulateArgs) -> anyhow::Result<()> {
    if let Some(history) = &args.history {
        for (flag, input) in [("--motion", &args.motion), ("--motion2", &args.motion2)] {
            if let Some(input) = input {
                let what = format!("the {flag} record");
                rockfrag::io_util::refuse_overwriting_input(history, "--history", input, &what)?;
            }
        }
    }
    if let Some(path) = &args.study {
        return run_study(&args, path);
    }
    let (ground, rotd50) = load_record(&args)?;
    let floor = super::floor::floor_of(
        &args.floor_period,
        &args.floor_damping,
        &args.floor_participation,
        "floor-",
    )?;
    let record = if floor.is_ground() {
        ground.clone()
    } else {
        motion::floor_record(&ground, &floor)?
    };
    if let Some(spec) = &args.stack {
        let flags = super::stack::StackFlags {
            spec: spec.clone(),
            masses: args.masses.clone(),
            offsets: args.offsets.clone(),
            interface_mu: args.interface_mu.clone(),
            interface_restitution: args.interface_restitution.clone(),
            tilts: args.tilts.clone(),
            restitution: args.restitution,
            mu_s: args.mu_s,
            mu_k: args.mu_k,
            g: args.g,
            impact: args.impact,
            rtol: args.rtol,
            settle_tol: args.settle_tol,
            json: args.json,
            history: args.history.clone(),
            free_motion_max: args.free_motion_max,
        };
        return super::stack::run(&flags, &record);
    }
    let block = Block::new(args.width, args.aspect, args.g)?;
    let mut analysis = Analysis::new(block, args.restitution);
    if let Some(mu_s) = args.mu_s {
        analysis.friction = Friction::Coulomb {
            mu_s,
            mu_k: args.mu_k.unwrap_or(mu_s),
        };
    }
    analysis.initial = Initial {
        theta: args.theta0,
        theta_dot: args.theta_dot0,
        ..Initial::default()
    };
    let settings = SolverSettings {
        model: args.model,
        integrator: args.integrator,
        impact: args.impact,
        rock_impact: args.rock_impact,
        rtol: args.rtol,
        settle_tol: args.settle_tol,
        settle_cascades: !args.follow_cascades,
        audit_energy: args.audit_energy,
        free_motion_max: args.free_motion_max,
        ..SolverSettings::default()
    };
    let mut history = args.history.as_ref().map(|_| History::default());
    let outcome = simulate(&analysis, &record, &settings, history.as_mut())
        .with_context(|| format!("solving record {}", record.name))?;
    if let (Some(path), Some(h)) = (&args.history, &history) {
        h.write_csv(path)?;
    }
    let sens = match args.sensitivity {
        true => Some(
            sensitivity(&analysis, &record, &settings, &outcome)
                .with_context(|| format!("solving record {} scaled by 1 + 1e-9", record.name))?,
        ),
        false => None,
    };
    if args.json {
        let mut v = outcome.to_json();
        if let Some(s) = &sens {
            v["sensitivity"] = serde_json::to_value(s)?;
        }
        println!("{v}");
    } else {
        let own = (args.width, args.aspect, args.restitution);
        print_summary(args.g, own, args.mu_s.is_some(), &block, &ground, &outcome);
        if let (Some(pga), Some(phi)) = (rotd50, args.orientation) {
            println!(
                "pair              RotD50 PGA {} g, the block faces φ = {}° from H1",
                fixed(pga / args.g, 3),
                number(phi)
            );
        }
        if !floor.is_ground() {
            println!(
                "floor             PFA {} g, PFV {} m/s ({} mode{})",
                fixed(record.pga() / args.g, 3),
                fixed(record.pgv(), 3),
                floor.modes.len(),
                if floor.modes.len() == 1 { "" } else { "s" }
            );
        }
        if let Some(s) = &sens {
            print_sensitivity(&outcome, s);
        }
    }
    Ok(())
}

/// The sensitivity lines: whether the run is sensitive and why, and what
/// the perturbed run found.
fn print_sensitivity(o: &Outcome, s: &Sensitivity) {
    let mut why = Vec::new();
    if o.overturned != s.overturned {
        why.push("overturning flipped".to_string());
    }
    let dth = s.theta_max_over_theta_c - o.theta_max_over_theta_c;
    if dth.abs() > sensitivity::THETA_TOL {
        why.push(format!("θmax/θc moved by {dth:+.6}"));
    }
    if let (Some(a), Some(b)) = (o.overturn_time, s.overturn_time)
        && (b - a).abs() > sensitivity::TIME_TOL
    {
        why.push(format!("overturning moved by {:+.4} s", b - a));
    }
    println!(
        "sensitive         {}",
        if s.sensitive {
            format!("yes: {}", why.join(", "))
        } else {
            "no".to_string()
        }
    );
    println!(
        "record × (1+1e-9) overturned {}{}, θmax/θc {:.6}",
        s.overturned,
        s.overturn_time
            .map_or(String::new(), |t| format!(" at {t:.4} s")),
        s.theta_max_over_theta_c
    );
}

/// The ground motion the block feels, scaled as asked, and with --motion2
/// the RotD50 PGA of the scaled pair (m/s²).
fn load_record(args: &SimulateArgs) -> anyhow::Result<(Record, Option<f64>)> {
    match (&args.motion, args.seed, args.pga) {
        (Some(path), _, _) => {
            let record = motion::read_record(path, args.g)?;
            let pair = match &args.motion2 {
                Some(path2) => {
                    let h2 = motion::read_record(path2, args.g)?;
                    let pair = Pair::new(record.clone(), h2).with_context(|| {
                        format!(
                            "--motion {} and --motion2 {} are not a pair of components",
                            path.display(),
                            path2.display()
                        )
                    })?;
                    Some(MeasuredPair::new(pair)?)
                }
                None => None,
            };
            // The peaks the scaling reads: of the record, or the pair's RotD50.
            let (pga, pgv) = match &pair {
                Some(p) => (p.pga, p.pgv),
                None => (record.pga(), record.pgv()),
            };
            // The factor that brings the record to the asked scale.
            let (k, what) = match (args.scale, args.pga, args.pgv) {
                (Some(x), _, _) => (x, "--scale"),
                (_, Some(g), _) => (g * args.g / pga, "--pga"),
                (_, _, Some(v)) => (v / pgv, "--pgv"),
                _ => (1.0, ""),
            };
            if !(k.is_finite() && k > 0.0) {
                anyhow::bail!(
                    "cannot scale {} by {what}: its PGA is {} m/s² and its PGV {} m/s{}",
                    path.display(),
                    number(pga),
                    number(pgv),
                    if pair.is_some() {
                        " (RotD50 of the pair)"
                    } else {
                        ""
                    }
                );
            }
            match (pair, args.orientation) {
                (Some(p), Some(phi)) => {
                    // as a study of record pairs turns its pairs, to the bit
                    let rotated = p
                        .felt(k, phi)
                        .with_context(|| format!("--orientation {phi}"))?;
                    // (scaling both by k > 0 scales every rotated peak by k)
                    Ok((rotated, Some(k * p.pga)))
                }
                _ => Ok((record.scaled(k), None)),
            }
        }
        (None, Some(seed), Some(pga)) => {
            let settings = SynthesisSettings {
                g: args.g,
                ..SynthesisSettings::default()
            };
            Ok((
                motion::synthesize(&settings, seed, args.index, pga * args.g)?,
                None,
            ))
        }
        _ => anyhow::bail!("give either --motion FILE or both --seed N and --pga G"),
    }
}

/// `simulate --study`: one analysis of the study at --level and --record,
/// of its --case or of the block of the flags (see [`SimulateArgs::study`]).
fn run_study(args: &SimulateArgs, path: &std::path::Path) -> anyhow::Result<()> {
    use rockfrag::study::{locate, reanalyse};
    let study = if path.is_dir() {
        rockfrag::figures::study_of_folder(path)?.ok_or_else(|| {
            anyhow::anyhow!(
                "{}: holds no manifest.json: give a study's spec file, or the folder of a \
                 finished `rockfrag run`",
                path.display()
            )
        })?
    } else {
        rockfrag::spec::Study::load(path)?
    };
    let (level, record) = (args.level.expect("checked"), args.record.expect("checked"));
    let mut history = args.history.as_ref().map(|_| History::default());
    let (analysis, motion, outcome, drawn, own) = match &args.case {
        Some(id) => {
            let r = reanalyse(&study, id, level, record, history.as_mut())?;
            if args.csv {
                print!("{}{}", r.header, r.row);
                return Ok(());
            }
            let motion = r.motion.map_err(|e| anyhow::anyhow!("record: {e}"))?;
            let analysis = match r.analysed.analysis {
                Some(rockfrag::case::Scene::Block(a)) => a,
                Some(rockfrag::case::Scene::Stack(stack)) => {
                    let report = super::stack::Report {
                        json: args.json,
                        history: args.history.as_deref(),
                        g: study.g,
                        heading: Some(format!(
                            "study             {} ({}), case {id}, level {} and record {record}",
                            study.name,
                            path.display(),
                            number(level)
                        )),
                    };
                    return report.solve(&stack, &motion.felt, &study.solver);
                }
                None => anyhow::bail!("block: {}", r.analysed.result.clone().unwrap_err()),
            };
            let outcome = r
                .analysed
                .result
                .map_err(|e| anyhow::anyhow!("solving record {}: {e}", motion.felt.name))?;
            let o = r.analysed.own;
            let drawn: Vec<String> = r
                .case
                .0
                .drawn()
                .iter()
                .map(|f| match f {
                    rockfrag::case::Field::Friction => match o.friction {
                        Friction::Coulomb { mu_s, mu_k } => {
                            format!("μs = {}, μk = {}", number(mu_s), number(mu_k))
                        }
                        Friction::Infinite => "μs = -, μk = -".to_string(),
                    },
                    rockfrag::case::Field::Aspect => format!("H/B = {}", number(o.aspect)),
                    rockfrag::case::Field::Width => format!("2B = {} m", number(o.width)),
                    rockfrag::case::Field::Restitution => format!("e = {}", number(o.restitution)),
                })
                .collect();
            let own = (o.width, o.aspect, o.restitution);
            (analysis, motion, outcome, drawn, own)
        }
        None => {
            locate(&study, level, record)?;
            let motion = rockfrag::study::Source::new(&study)?.motion(&study, level, record)?;
            let block = Block::new(args.width, args.aspect, study.g)?;
            let mut analysis = Analysis::new(block, args.restitution);
            if let Some(mu_s) = args.mu_s {
                analysis.friction = Friction::Coulomb {
                    mu_s,
                    mu_k: args.mu_k.unwrap_or(mu_s),
                };
            }
            let outcome = simulate(&analysis, &motion.felt, &study.solver, history.as_mut())
                .with_context(|| format!("solving record {}", motion.felt.name))?;
            let own = (args.width, args.aspect, args.restitution);
            (analysis, motion, outcome, Vec::new(), own)
        }
    };
    if let (Some(path), Some(h)) = (&args.history, &history) {
        h.write_csv(path)?;
    }
    if args.json {
        println!("{}", outcome.to_json());
        return Ok(());
    }
    println!(
        "study             {} ({}), {}level {} and record {record}{}",
        study.name,
        path.display(),
        args.case
            .as_ref()
            .map_or(String::new(), |id| format!("case {id}, ")),
        number(level),
        if drawn.is_empty() {
            String::new()
        } else {
            format!(" (drawn: {})", drawn.join(", "))
        }
    );
    let b = &analysis.block;
    let coulomb = matches!(analysis.friction, Friction::Coulomb { .. });
    print_summary(study.g, own, coulomb, b, &motion.felt, &outcome);
    if let Some(phi) = motion.phi() {
        println!(
            "pair              RotD50 PGA {} g, the block faces φ = {}° from H1",
            fixed(motion.im(Im::PGA_ROTD50).unwrap_or(0.0), 3),
            number(phi)
        );
    }
    if let (Some(pfa), Some(pfv), Some(pga)) =
        (motion.im(Im::PFA), motion.im(Im::PFV), motion.im(Im::PGA))
    {
        println!(
            "floor             PFA {} g, PFV {} m/s under the ground's PGA {} g",
            fixed(pfa, 3),
            fixed(pfv, 3),
            fixed(pga, 3)
        );
    }
    Ok(())
}

/// The console summary of one analysis of the block `own` = (2B, H/B, e),
/// with `coulomb` friction, under `record` (the motion it felt), gravity
/// `g`.
fn print_summary(
    g: f64,
    own: (f64, f64, f64),
    coulomb: bool,
    block: &Block,
    record: &Record,
    o: &Outcome,
) {
    let opt = |x: Option<f64>| x.map_or("-".to_string(), |t| format!("{} s", fixed(t, 4)));
    println!(
        "record            {} ({} samples, dt {} s, PGA {} g)",
        record.name,
        record.len(),
        number(record.dt),
        fixed(record.pga() / g, 3)
    );
    println!(
        "block             2B = {} m, H/B = {}, θc = {} rad, e = {}",
        number(own.0),
        number(own.1),
        fixed(block.theta_c, 4),
        number(own.2)
    );
    println!(
        "overturned        {}{}",
        o.overturned,
        o.overturn_time
            .map_or(String::new(), |t| format!(" at {} s", fixed(t, 4)))
    );
    println!(
        "uplifted          {} ({} uplifts, {} held lift-offs)",
        o.uplifted, o.uplifts, o.liftoff_holds
    );
    println!("θmax/θc           {}", fixed(o.theta_max_over_theta_c, 6));
    println!("μ motion          {}", fixed(o.mu_motion, 6));
    println!(
        "μ impact          {} (paper's eq. (5): {})",
        fixed(o.mu_impact, 6),
        fixed(o.mu_impact_eq5, 6)
    );
    println!(
        "impacts           {} (first {}), flights {}, settles {}",
        o.impacts,
        opt(o.first_impact_time),
        o.flights,
        o.settles
    );
    println!("energy gains      {}", o.energy_gains);
    if coulomb {
        println!(
            "slip              max {} m, final {} m, {} Painlevé holds",
            fixed(o.slip_max, 6),
            fixed(o.slip_final, 6),
            o.stick_holds
        );
    }
    let modes: Vec<String> = Mode::ALL
        .iter()
        .filter(|m| o.time_in_mode[m.index()] > 0.0)
        .map(|m| format!("{} {} s", m.name(), fixed(o.time_in_mode[m.index()], 3)))
        .collect();
    println!("time in modes     {}", modes.join(", "));
    println!("end time          {} s", fixed(o.end_time, 4));
    println!(
        "work              {} RHS calls, {} steps ({} rejected), {} events",
        o.stats.rhs_calls, o.stats.steps_accepted, o.stats.steps_rejected, o.stats.events
    );
}
