//! `[[grid.stack]]`: stacks of two or three blocks in a study, bottom first,
//! as written ([`StackEntry`], in the raw stage) and validated ([`StudyStack`]).
//!
//! ```toml
//! [[grid.stack]]                    # bottom first
//! name = "statue_on_pedestal"       # default: stack1, stack2, … in order
//! blocks = [ { width = 0.8, height = 1.0 }, { width = 0.3, height = 1.2 } ]
//! interfaces = [ { restitution = 0.3, friction = "inf" },
//!                { restitution = 0.3, mu_s = 0.5, mu_k = 0.4 } ]
//! ```
//!
//! A block gives its width 2B (m) and its height 2H (m) or aspect H/B; its
//! `mass` (relative to the others': give it for every block or none) or
//! `density` (relative, default 1: every block of the same density, the
//! mass then density × width × height); and an `offset` (m) of its centre
//! from the centre of the block below (default 0, centred; the base's is
//! 0). The interface under each block (the ground's first) gives its
//! restitution e and friction: `friction = "inf"` (the default) or `mu_s`
//! and `mu_k`.

use super::locate::Origin;
use super::raw::{StackBlockEntry, StackEntry, StackInterfaceEntry};
use crate::case::StackName;
use crate::error::Result;
use crate::solver::Friction;
use crate::solver::stack::{Stack, StackBody, StackInterface};

/// A validated stack of a study: its name and the stack the solver takes.
#[derive(Clone, Debug)]
pub struct StudyStack {
    /// Its name (`outcomes.csv`'s `stack` column).
    pub name: StackName,
    /// The stack, at rest, under the study's gravity.
    pub stack: Stack,
    /// How each body gives its height and mass (bottom first), which a
    /// drawn width or height carries along (`StudyStack::drawn`).
    pub forms: Vec<BodyForm>,
}

/// How a body of `[[grid.stack]]` gives its height and mass, so that a
/// drawn width or height carries them along.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BodyForm {
    /// The aspect ratio H/B, when the block gives it instead of a height.
    pub aspect: Option<f64>,
    /// The relative density, when the stack gives no masses (mass =
    /// density × width × height).
    pub density: Option<f64>,
}

/// Two stacks are equal when their names and stacks are: how the spec gave
/// a height or a mass ([`StudyStack::forms`]) matters only to a stack's
/// draws, and the canonical text of a stack that draws keeps it
/// ([`StudyStack::to_entry`]).
impl PartialEq for StudyStack {
    fn eq(&self, other: &StudyStack) -> bool {
        self.name == other.name && self.stack == other.stack
    }
}

impl StudyStack {
    /// The stack as a canonical `[[grid.stack]]` table: every value
    /// explicit (heights, masses, offsets, friction); `as_given` writes an
    /// aspect or a density where the spec gave one instead of the height or
    /// mass it makes (what drawn properties of the stack follow).
    pub fn to_entry(&self, as_given: bool) -> StackEntry {
        StackEntry {
            name: Some(self.name.to_string()),
            blocks: self
                .stack
                .bodies
                .iter()
                .zip(&self.forms)
                .map(|(b, form)| {
                    let form = if as_given { *form } else { Default::default() };
                    StackBlockEntry {
                        width: Some(b.width),
                        height: form.aspect.is_none().then_some(b.height),
                        aspect: form.aspect,
                        mass: form.density.is_none().then_some(b.mass),
                        density: form.density,
                        offset: Some(b.offset),
                    }
                })
                .collect(),
            interfaces: self
                .stack
                .interfaces
                .iter()
                .map(|f| match f.friction {
                    Friction::Infinite => StackInterfaceEntry {
                        restitution: Some(f.restitution),
                        friction: Some("inf".into()),
                        ..StackInterfaceEntry::default()
                    },
                    Friction::Coulomb { mu_s, mu_k } => StackInterfaceEntry {
                        restitution: Some(f.restitution),
                        mu_s: Some(mu_s),
                        mu_k: Some(mu_k),
                        ..StackInterfaceEntry::default()
                    },
                })
                .collect(),
        }
    }
}

/// Checks every `[[grid.stack]]` table under gravity `g`; errors name the
/// field (`grid.stack[0].blocks[1].height`), its value and what is accepted.
pub(super) fn stacks(spec: &Origin, entries: &[StackEntry], g: f64) -> Result<Vec<StudyStack>> {
    let mut out: Vec<StudyStack> = Vec::new();
    for (s, entry) in entries.iter().enumerate() {
        let at = |f: &str| format!("grid.stack[{s}].{f}");
        let name_text = entry
            .name
            .clone()
            .unwrap_or_else(|| format!("stack{}", s + 1));
        let Some(name) = StackName::new(&name_text) else {
            return Err(spec.bad(
                &at("name"),
                &format!("{name_text:?}"),
                &format!(
                    "1 to {} ASCII letters, digits or _ (the case id is stack_NAME)",
                    StackName::MAX
                ),
            ));
        };
        if out.iter().any(|o| o.name == name) {
            return Err(spec.bad(
                &at("name"),
                &format!("{name_text:?}"),
                "a name no other stack of the study has",
            ));
        }
        let n = entry.blocks.len();
        if !(2..=crate::solver::stack::MAX_BODIES).contains(&n) {
            return Err(spec.bad(
                &at("blocks"),
                &format!("{n} blocks"),
                "2 or 3 blocks, bottom first (one block on the ground is a case of grid.width \
                 and grid.aspect)",
            ));
        }
        if entry.interfaces.len() != n {
            return Err(spec.bad(
                &at("interfaces"),
                &format!("{} interfaces", entry.interfaces.len()),
                &format!(
                    "one interface under each of the {n} blocks, bottom first (the ground's first)"
                ),
            ));
        }
        let masses = entry.blocks.iter().filter(|b| b.mass.is_some()).count();
        let mut bodies = Vec::with_capacity(n);
        let mut forms = Vec::with_capacity(n);
        for (i, b) in entry.blocks.iter().enumerate() {
            let field = |f: &str| at(&format!("blocks[{i}].{f}"));
            let positive = |f: &str, v: f64, what: &str| {
                if v.is_finite() && v > 0.0 {
                    Ok(v)
                } else {
                    Err(spec.bad(&field(f), &v, what))
                }
            };
            let Some(width) = b.width else {
                return Err(spec.bad(
                    &field("width"),
                    &String::from("missing"),
                    "the block's width 2B in m",
                ));
            };
            let width = positive("width", width, "a width 2B > 0 in m")?;
            let height = match (b.height, b.aspect) {
                (Some(h), None) => positive("height", h, "a height 2H > 0 in m")?,
                (None, Some(a)) => width * positive("aspect", a, "an aspect ratio H/B > 0")?,
                (Some(_), Some(_)) => {
                    return Err(spec.bad(
                        &field("aspect"),
                        &String::from("given with height"),
                        "height or aspect, not both",
                    ));
                }
                (None, None) => {
                    return Err(spec.bad(
                        &field("height"),
                        &String::from("missing"),
                        "the block's height 2H in m (or its aspect H/B)",
                    ));
                }
            };
            let mass = match (b.mass, b.density) {
                (Some(_), Some(_)) => {
                    return Err(spec.bad(
                        &field("density"),
                        &String::from("given with mass"),
                        "mass or density, not both",
                    ));
                }
                (Some(m), None) if masses == n => positive("mass", m, "a relative mass > 0")?,
                (Some(m), None) => {
                    return Err(spec.bad(
                        &field("mass"),
                        &m,
                        "a mass for every block of the stack or for none (masses are \
                         relative; give densities instead to mix)",
                    ));
                }
                (None, d) if masses == 0 => {
                    let d = positive("density", d.unwrap_or(1.0), "a relative density > 0")?;
                    d * width * height
                }
                (None, _) => {
                    return Err(spec.bad(
                        &field("mass"),
                        &String::from("missing"),
                        "a mass for every block of the stack or for none (masses are relative)",
                    ));
                }
            };
            let offset = b.offset.unwrap_or(0.0);
            if !offset.is_finite() || (i == 0 && offset != 0.0) {
                return Err(spec.bad(
                    &field("offset"),
                    &offset,
                    "0 for the base (its place on the ground is the origin); a finite offset \
                     in m above it",
                ));
            }
            bodies.push(StackBody {
                width,
                height,
                mass,
                offset,
            });
            forms.push(BodyForm {
                aspect: b.height.is_none().then_some(b.aspect).flatten(),
                density: (masses == 0).then(|| b.density.unwrap_or(1.0)),
            });
        }
        let mut interfaces = Vec::with_capacity(n);
        for (i, f) in entry.interfaces.iter().enumerate() {
            let field = |x: &str| at(&format!("interfaces[{i}].{x}"));
            let Some(e) = f.restitution else {
                return Err(spec.bad(
                    &field("restitution"),
                    &String::from("missing"),
                    "the coefficient of restitution e in [0, 1] of the interface",
                ));
            };
            if !(0.0..=1.0).contains(&e) {
                return Err(spec.bad(
                    &field("restitution"),
                    &e,
                    "a coefficient of restitution in [0, 1]",
                ));
            }
            let friction = match (f.friction.as_deref(), f.mu_s, f.mu_k) {
                (Some("inf") | None, None, None) => Friction::Infinite,
                (None, Some(mu_s), Some(mu_k)) => {
                    if !(mu_s.is_finite() && mu_s >= 0.0) {
                        return Err(spec.bad(&field("mu_s"), &mu_s, "a finite μs ≥ 0"));
                    }
                    if !(mu_k.is_finite() && (0.0..=mu_s).contains(&mu_k)) {
                        return Err(spec.bad(&field("mu_k"), &mu_k, "a μk in [0, mu_s]"));
                    }
                    Friction::Coulomb { mu_s, mu_k }
                }
                (Some(text), None, None) => {
                    return Err(spec.bad(
                        &field("friction"),
                        &format!("{text:?}"),
                        "\"inf\", or mu_s and mu_k instead of friction",
                    ));
                }
                (Some(_), _, _) => {
                    return Err(spec.bad(
                        &field("friction"),
                        &String::from("given with mu_s or mu_k"),
                        "friction = \"inf\", or mu_s and mu_k, not both",
                    ));
                }
                (None, Some(_), None) => {
                    return Err(spec.bad(&field("mu_k"), &String::from("missing"), "μk beside μs"));
                }
                (None, None, Some(_)) => {
                    return Err(spec.bad(&field("mu_s"), &String::from("missing"), "μs beside μk"));
                }
            };
            interfaces.push(StackInterface {
                restitution: e,
                friction,
            });
        }
        let stack = Stack {
            bodies,
            interfaces,
            initial_tilt: Vec::new(),
            g,
        };
        // the stack's own checks: widths and aspects in range, footprints
        // within the face below
        if let Err(e) = stack.validate() {
            return Err(spec.nested(&format!("grid.stack[{s}]."), body_field(e)));
        }
        out.push(StudyStack { name, stack, forms });
    }
    Ok(out)
}

/// The stack's own error with its field as a spec names it: `body 2
/// width` → `blocks[1].width`, `body 2 footprint` → `blocks[1].offset`.
fn body_field(err: crate::error::Error) -> crate::error::Error {
    match err {
        crate::error::Error::InvalidParameter {
            field,
            value,
            expected,
        } => {
            let mut words = field.split(' ');
            let field = match (
                words.next(),
                words.next().and_then(|k| k.parse::<usize>().ok()),
            ) {
                (Some("body"), Some(k)) => {
                    let rest = words.collect::<Vec<_>>().join(" ");
                    let rest = if rest == "footprint" {
                        "offset".into()
                    } else {
                        rest
                    };
                    format!("blocks[{}].{rest}", k - 1)
                }
                _ => field,
            };
            crate::error::Error::InvalidParameter {
                field,
                value,
                expected,
            }
        }
        other => other,
    }
}

/// What a study with stacks cannot have: the linearised model or the
/// paper's rock-impact reading (the stack solver integrates the full
/// equations and the impact law in full), or an adaptive run.
pub(super) fn settings(
    spec: &Origin,
    solver: &crate::solver::SolverSettings,
    grid: &super::raw::GridFile,
) -> Result<()> {
    if solver.model == crate::solver::Model::Linear {
        return Err(spec.bad(
            "solver.model",
            &String::from("linear"),
            "nonlinear in a study with stacks (the stack solver integrates the full equations)",
        ));
    }
    if solver.rock_impact == crate::solver::RockImpact::Rock {
        return Err(spec.bad(
            "solver.rock_impact",
            &String::from("rock"),
            "bounce in a study with stacks (the impact law in full)",
        ));
    }
    if grid.scale_factors.is_none()
        && grid
            .pga
            .as_ref()
            .is_some_and(|l| matches!(l, super::raw::Levels::Range(_)))
    {
        return Err(spec.bad(
            "grid.pga",
            &String::from("a range"),
            "a list of levels in a study with stacks (adaptive runs of stacks are not supported yet)",
        ));
    }
    Ok(())
}
