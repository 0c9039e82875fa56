//! The stack solver: two or three rigid blocks stacked bottom first on the
//! ground (2-D), event-driven over the contact state of every interface.
//!
//! A single block keeps its own fast solver ([`simulate`](super::simulate));
//! a stack gets this one, made for several bodies, and the two agree when the
//! stack reduces to one block (tests/stack.rs). `docs/stack.md` describes the
//! model, its modes, impact laws, rules and what is not modelled.
//!
//! The files, one concept each:
//! - `scene.rs`: what a stack is ([`Stack`], [`StackBody`],
//!   [`StackInterface`]) and the constants derived from it;
//! - `kinematics.rs`: the contact state of each interface and the chain of
//!   bodies' poses, velocities and Jacobians in the free coordinates;
//! - `dynamics.rs`: the equations of motion of a state and its contact forces;
//! - `select.rs`: which state follows an event (enumeration over the touching
//!   corners' states: a small linear complementarity problem);
//! - `impact.rs`: impacts at any interface (Newton, energetic, Stronge);
//! - `driver.rs`: the event loop (Dormand–Prince with dense output);
//! - `rest.rs`: a stack at rest, its contact forces affine in the ground's
//!   acceleration (a sample passed without the chain where no event can be);
//! - `outcome.rs`: what an analysis of a stack gives ([`StackOutcome`]) and
//!   its history ([`StackHistory`]).

// the linear algebra runs over small fixed-size arrays by index, as the
// equations are written
#![allow(clippy::needless_range_loop)]

mod driver;
mod dynamics;
mod impact;
mod kinematics;
mod outcome;
mod rest;
mod scene;
mod select;

pub use driver::simulate_stack;
pub use outcome::{BodyOutcome, StackHistory, StackOutcome, StackRow};
pub use scene::{MAX_BODIES, Stack, StackBody, StackInterface};
