//! Stacks in a study (issue 40, item 3): `[[grid.stack]]` read and refused
//! as a user mistypes it, a two-block study run end to end (its columns,
//! limit states by body, a fitted curve), and the plumbing checked against
//! the single block: a stack whose base cannot move gives its top the
//! single block's overturning, row by row.

use rockfrag::pipeline;
use rockfrag::spec::Study;
use rockfrag::study::RunOptions;
use std::path::Path;

/// Writes `text` as `dir/name` and loads it as a study.
fn load(dir: &Path, name: &str, text: &str) -> rockfrag::error::Result<Study> {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    Study::load(&path)
}

const HEAD: &str =
    "name = \"s\"\nseed = 3\nrecords = 2\n[motion]\nduration = 4.0\n[grid]\npga = [0.3]\n";

/// Every mistake is refused with the file, the field's path and the value.
#[test]
fn stack_specs_are_read_and_bad_ones_refused_by_field() {
    let dir = tempfile::tempdir().unwrap();
    let good = format!(
        "{HEAD}[[grid.stack]]\nblocks = [{{ width = 0.8, height = 1.0 }}, {{ width = 0.3, aspect = 4 }}]\n\
         interfaces = [{{ restitution = 0.3, friction = \"inf\" }}, {{ restitution = 0.3, mu_s = 0.5, mu_k = 0.4 }}]\n"
    );
    let study = load(dir.path(), "good.toml", &good).unwrap();
    // stacks alone: no block cases
    assert!(study.aspects.is_empty());
    assert_eq!(study.stacks.len(), 1);
    let s = &study.stacks[0];
    assert_eq!(s.name.as_str(), "stack1");
    // aspect 4 of a 0.3 m block: 2H = 1.2 m; equal density: mass = width × height
    assert_eq!(s.stack.bodies[1].height, 1.2);
    assert_eq!(s.stack.bodies[0].mass, 0.8);
    assert!((s.stack.bodies[1].mass - 0.36).abs() < 1e-15);
    // the canonical spec reads back as the same study
    let back = load(dir.path(), "back.toml", &study.to_toml()).unwrap();
    assert_eq!(back.stacks, study.stacks);
    assert_eq!(back.hash(), study.hash());

    let bad = |name: &str, blocks: &str, interfaces: &str, field: &str, value: &str| {
        let text =
            format!("{HEAD}[[grid.stack]]\nblocks = [{blocks}]\ninterfaces = [{interfaces}]\n");
        let err = load(dir.path(), name, &text).unwrap_err().to_string();
        for want in [name, field, value] {
            assert!(err.contains(want), "{name}: {want:?} not in {err}");
        }
    };
    let two = "{ restitution = 0 }, { restitution = 0 }";
    bad(
        "height.toml",
        "{ width = 0.8, height = 1.0 }, { width = 0.3, height = -1 }",
        two,
        "grid.stack[0].blocks[1].height",
        "-1",
    );
    bad(
        "nosize.toml",
        "{ width = 0.8, height = 1.0 }, { width = 0.3 }",
        two,
        "grid.stack[0].blocks[1].height",
        "missing",
    );
    bad(
        "mass.toml",
        "{ width = 0.8, height = 1.0, mass = 2 }, { width = 0.3, height = 1.2 }",
        two,
        "grid.stack[0].blocks[0].mass",
        "2",
    );
    bad(
        "footprint.toml",
        "{ width = 0.8, height = 1.0 }, { width = 0.3, height = 1.2, offset = 0.3 }",
        two,
        "grid.stack[0].blocks[1].offset",
        "0.3",
    );
    bad(
        "e.toml",
        "{ width = 0.8, height = 1.0 }, { width = 0.3, height = 1.2 }",
        "{ restitution = 0 }, { restitution = 1.5 }",
        "grid.stack[0].interfaces[1].restitution",
        "1.5",
    );
    bad(
        "mu.toml",
        "{ width = 0.8, height = 1.0 }, { width = 0.3, height = 1.2 }",
        "{ restitution = 0 }, { restitution = 0, mu_s = 0.4, mu_k = 0.5 }",
        "grid.stack[0].interfaces[1].mu_k",
        "0.5",
    );
    bad(
        "fric.toml",
        "{ width = 0.8, height = 1.0 }, { width = 0.3, height = 1.2 }",
        "{ restitution = 0 }, { restitution = 0, friction = \"infinite\" }",
        "grid.stack[0].interfaces[1].friction",
        "infinite",
    );
    bad(
        "count.toml",
        "{ width = 0.8, height = 1.0 }, { width = 0.3, height = 1.2 }",
        "{ restitution = 0 }",
        "grid.stack[0].interfaces",
        "1 interfaces",
    );
    bad(
        "one.toml",
        "{ width = 0.8, height = 1.0 }",
        "{ restitution = 0 }",
        "grid.stack[0].blocks",
        "1 blocks",
    );
    // a limit state naming a body no stack has
    let ls = |measure: &str| {
        format!(
            "{good}[fragility]\n[[fragility.limit_state]]\nname = \"x\"\nmeasure = \"{measure}\"\n"
        )
    };
    for (measure, want) in [
        ("statue.overturned", "no body \"statue\""),
        ("middle.overturned", "no stack has three blocks"),
        ("top.flying", "FIELD one of"),
    ] {
        let err = load(dir.path(), "ls.toml", &ls(measure))
            .unwrap_err()
            .to_string();
        for w in ["ls.toml", "fragility.limit_state[0].measure", measure, want] {
            assert!(err.contains(w), "{measure}: {w:?} not in {err}");
        }
    }
    // a body's limit state in a study of blocks alone
    let blocks = format!(
        "{HEAD}width = [0.3]\naspect = [4]\n[fragility]\n[[fragility.limit_state]]\nname = \"x\"\n\
         measure = \"top.overturned\"\n"
    );
    let err = load(dir.path(), "blocks.toml", &blocks)
        .unwrap_err()
        .to_string();
    assert!(err.contains("a study with stacks"), "{err}");
    // a block's draw in a study of stacks alone is refused, not ignored,
    // and says where a stack's draws go
    let drawn = format!(
        "{good}[uncertainty]\nrestitution = {{ dist = \"uniform\", min = 0, max = 0.5 }}\n"
    );
    let err = load(dir.path(), "drawn.toml", &drawn)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("uncertainty.restitution") && err.contains("[uncertainty.stack.NAME.BODY]"),
        "{err}"
    );
}

fn run(study: &Study, dir: &Path) {
    let opts = RunOptions {
        threads: 2,
        ..RunOptions::new(dir)
    };
    assert!(pipeline::run(study, &opts).unwrap().run.complete);
}

/// The `outcomes.csv` rows of `dir` as maps from column name to field.
fn rows(dir: &Path) -> Vec<std::collections::HashMap<String, String>> {
    let mut r = csv::Reader::from_path(dir.join("outcomes.csv")).unwrap();
    let header: Vec<String> = r.headers().unwrap().iter().map(String::from).collect();
    r.records()
        .map(|rec| {
            let rec = rec.unwrap();
            header
                .iter()
                .cloned()
                .zip(rec.iter().map(String::from))
                .collect()
        })
        .collect()
}

/// A tiny two-block study end to end: the stack's columns, the limit states
/// of its bodies counted from its own rows, and a fitted curve per body.
#[test]
fn a_two_block_study_runs_with_columns_and_limit_states_by_body() {
    let dir = tempfile::tempdir().unwrap();
    let spec = "name = \"tiny\"\nseed = 40\nrecords = 12\n[motion]\nduration = 8.0\n[grid]\n\
         pga = [0.2, 0.4, 0.6, 0.8, 1.0]\n\
         [[grid.stack]]\nname = \"statue\"\n\
         blocks = [{ width = 0.6, height = 1.0 }, { width = 0.3, height = 1.2 }]\n\
         interfaces = [{ restitution = 0 }, { restitution = 0 }]\n\
         [fragility]\nbootstrap = 0\n\
         [[fragility.limit_state]]\nname = \"top-rocks\"\nmeasure = \"top.theta_max_over_theta_c\"\nexceeds = 0.5\n\
         [[fragility.limit_state]]\nname = \"top-falls\"\nmeasure = \"top.overturned\"\n\
         [[fragility.limit_state]]\nname = \"base-falls\"\nmeasure = \"base.overturned\"\n\
         [[fragility.limit_state]]\nname = \"any-falls\"\nmeasure = \"any.overturned\"\n";
    let study = load(dir.path(), "tiny.toml", spec).unwrap();
    let out = dir.path().join("out");
    run(&study, &out);
    let header = std::fs::read_to_string(out.join("outcomes.csv")).unwrap();
    let header = header.lines().next().unwrap();
    assert!(header.starts_with("stack,aspect,width,"), "{header}");
    for c in [
        "first_overturned",
        "base.theta_max_over_theta_c",
        "base.overturned",
        "base.slip_max",
        "top.overturned",
        "top.overturn_time",
    ] {
        assert!(header.split(',').any(|h| h == c), "{c} not in {header}");
    }
    assert!(!header.contains("middle."), "no stack of three: {header}");
    let rows = rows(&out);
    assert_eq!(rows.len(), 5 * 12);
    let ok: Vec<_> = rows.iter().filter(|r| r["status"] == "ok").collect();
    for r in &rows {
        assert_eq!(r["stack"], "statue");
        // the case columns of a stack are its top block's
        assert_eq!((r["aspect"].as_str(), r["width"].as_str()), ("4", "0.3"));
        if r["status"] == "failed" {
            assert!(r["error"].starts_with("stack solver: "), "{r:?}");
        }
    }
    // the stack-wide columns summarise the bodies; the ones the stack
    // solver does not compute are empty, not zero
    for r in &ok {
        let any = r["base.overturned"] == "true" || r["top.overturned"] == "true";
        assert_eq!(r["overturned"] == "true", any, "{r:?}");
        assert_eq!(r["mu_motion"], "", "{r:?}");
        // a body under one that fell takes it down: the base never falls alone
        if r["base.overturned"] == "true" {
            assert_eq!(r["top.overturned"], "true", "{r:?}");
        }
        assert_eq!(r["first_overturned"].is_empty(), !any, "{r:?}");
    }
    let top_fell = ok.iter().filter(|r| r["top.overturned"] == "true").count();
    assert!(
        top_fell > 5 && top_fell < ok.len() - 5,
        "{top_fell} of {}",
        ok.len()
    );
    assert!(ok.len() >= 55, "{} of 60 analyses ok", ok.len());

    let fits = rockfrag::fragility::read_fragility_csv(&out.join("fragility.csv")).unwrap();
    let fit = |ls: &str| {
        fits.iter()
            .find(|f| f.limit_state == ls)
            .unwrap_or_else(|| panic!("no {ls} in fragility.csv"))
    };
    for f in &fits {
        assert_eq!(f.case.id(), "stack_statue");
    }
    // the statue (H/B 4, tan θc = 0.25) topples between the grid's 0.2 g and 1 g
    let falls = fit("top-falls");
    let median = falls.median.expect("the top's overturning is fitted");
    assert!(median > 0.25 && median < 1.0, "median {median}");
    // rocking past θc/2 comes at lower shaking than falling
    let rocks = fit("top-rocks").median.expect("fitted");
    assert!(rocks < median, "{rocks} vs {median}");
    // the figures: every body's curves side by side; the history draws
    // every body of the stack (a study of stacks only), not its top block
    // alone as if it were a block
    let options = rockfrag::figures::FigureOptions::for_folder(&out).unwrap();
    let report = rockfrag::figures::study_figures(&out, &out.join("figs"), &options).unwrap();
    assert!(
        out.join("figs/stacks.svg").is_file(),
        "{:?}",
        report.written
    );
    let history = std::fs::read_to_string(out.join("figs/history.svg")).unwrap();
    assert!(history.contains("Stack "), "the history is a stack's");
    assert!(
        history.contains("base on the ground") && history.contains("top on the base"),
        "the history draws every body"
    );
    assert!(
        !report
            .notes
            .iter()
            .any(|n| n.starts_with("history: skipped")),
        "{:?}",
        report.notes
    );
    // every fall here is the top's, so any.overturned is the top's curve
    if !ok.iter().any(|r| r["base.overturned"] == "true") {
        let any = fit("any-falls");
        assert_eq!(any.n_exceeded, falls.n_exceeded);
        if falls.beta_model == "separate" {
            assert_eq!(any.median, falls.median);
        } else {
            // the top's curves would cross, so its limit states share one β
            // (the crossing rule); any.overturned, of no body, is fitted
            // alone: the same data, a median within 2 % (0.5 % here)
            let (a, f) = (any.median.unwrap(), falls.median.unwrap());
            assert!((a / f - 1.0).abs() < 0.02, "{a} vs {f}");
        }
        assert!(fit("base-falls").median.is_none());
    }
}

/// The plumbing against the single block: a base that cannot move (2 m wide,
/// 0.5 m tall, 10¹² times the top's mass, infinite friction under it) gives
/// the top in a study the same overturning, row by row, as the same block
/// alone on the ground in the same study (the solver-level limit case is
/// tests/stack.rs; this checks that the study feeds both the same motion
/// and reads both back alike). Both solvers on Dormand–Prince at rtol
/// 1e-11, every impact followed: θmax/θc agrees to 1e-7.
#[test]
fn an_immovable_base_gives_the_top_the_single_blocks_outcomes_in_a_study() {
    let dir = tempfile::tempdir().unwrap();
    let spec = "name = \"plumbing\"\nseed = 7\nrecords = 8\n[motion]\nduration = 8.0\n[grid]\n\
         pga = [0.3, 0.6]\nwidth = [0.25]\naspect = [4]\nrestitution = [0]\n\
         [[grid.stack]]\nname = \"fixed_base\"\n\
         blocks = [{ width = 2.0, height = 0.5, mass = 1e12 }, { width = 0.25, height = 1.0, mass = 1 }]\n\
         interfaces = [{ restitution = 0 }, { restitution = 0 }]\n\
         [solver]\nintegrator = \"dopri5\"\nrtol = 1e-11\natol = 1e-12\nsettle_cascades = false\n";
    let study = load(dir.path(), "plumbing.toml", spec).unwrap();
    let out = dir.path().join("out");
    run(&study, &out);
    let rows = rows(&out);
    assert_eq!(rows.len(), 2 * 8 * 2);
    let mut overturned = 0;
    for pair in rows.chunks(2) {
        let (block, stack) = (&pair[0], &pair[1]);
        assert_eq!(block["stack"], "");
        assert_eq!(stack["stack"], "fixed_base");
        assert_eq!(
            (block["pga"].as_str(), block["record"].as_str()),
            (stack["pga"].as_str(), stack["record"].as_str())
        );
        assert_eq!(stack["status"], "ok", "{stack:?}");
        assert_eq!(stack["base.moved"], "false", "{stack:?}");
        assert_eq!(
            block["overturned"], stack["top.overturned"],
            "{block:?}\n{stack:?}"
        );
        let num = |r: &std::collections::HashMap<String, String>, c: &str| -> f64 {
            r[c].parse().unwrap()
        };
        let d =
            (num(block, "theta_max_over_theta_c") - num(stack, "top.theta_max_over_theta_c")).abs();
        assert!(d < 1e-7, "Δθmax/θc {d:e}: {block:?}\n{stack:?}");
        overturned += usize::from(block["overturned"] == "true");
    }
    // both outcomes occur, so the comparison can fail either way
    assert!(
        overturned > 0 && overturned < 16,
        "{overturned} of 16 overturned"
    );
}

/// The statue on its pedestal with infinite friction at both interfaces,
/// as `studies/statue-on-pedestal.toml` had it first: at 0.8 g, record 5
/// of seed 40, the pedestal's flat contact ends while the statue rocks on
/// its right corner, and the contact-state selection found no state
/// consistent ("no contact state of the 2 bodies is consistent … after
/// Flat(0)"): the tie at the event's instant, where the pedestal's rocking
/// about its corner holds with equality. The analysis must run on.
#[test]
fn the_pedestal_lifting_under_a_rocking_statue_is_not_a_dead_end() {
    let dir = tempfile::tempdir().unwrap();
    let spec = "name = \"tie\"\nseed = 40\nrecords = 30\n[motion]\nduration = 12.0\n[grid]\n\
         pga = [0.8, 0.9]\n\
         [[grid.stack]]\nname = \"statue_on_pedestal\"\n\
         blocks = [{ width = 0.6, height = 1.0 }, { width = 0.3, height = 1.2 }]\n\
         interfaces = [{ restitution = 0 }, { restitution = 0 }]\n";
    let study = load(dir.path(), "tie.toml", spec).unwrap();
    for (level, record) in [(0.8, 5), (0.8, 15), (0.8, 20), (0.8, 28), (0.9, 20)] {
        let r = rockfrag::study::reanalyse(&study, "stack_statue_on_pedestal", level, record, None)
            .unwrap();
        assert!(
            r.analysed.result.is_ok(),
            "{level} g, record {record}: {:?}",
            r.analysed.result
        );
    }
}
