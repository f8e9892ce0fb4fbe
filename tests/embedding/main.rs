//! The embedding API (aograph-embed) against aograph's own path: an application hands over the
//! depth, normals and projection of the frame aograph's g-buffer drew, in its own conventions,
//! and gets the AO aograph computes from its own g-buffer.
//!
//! The application's depth buffer is written from the g-buffer's linear depth through the
//! application's projection (`common::user_frame`), so the inputs differ from aograph's only
//! by the convention and its rounding; a convention misread (reversed Z taken as standard,
//! say) gives depths off by orders of magnitude and fails every comparison here.
//!
//! Files: `harness.rs` (the application's frame, aograph's own, the comparisons), and one per
//! concern: `conventions.rs` (depth conventions, formats, projections), `techniques.rs`
//! (every screen-space technique on five scenes), `normals.rs` (normal encodings and normals
//! rebuilt from depth), `plans_and_errors.rs` (named errors, plan switching and resizing,
//! motion vectors), `user_technique.rs` (a user technique through both front ends), `engine.rs` (plans prepared
//! ahead, matrices as arrays).

#[path = "../common/mod.rs"]
mod common;

mod conventions;
mod engine;
mod harness;
mod normals;
mod plans_and_errors;
mod techniques;
mod user_technique;

use harness::*;
