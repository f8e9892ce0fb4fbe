//! A count of the graph's lookups by name (an import's name, a history's name), so a test can
//! check that a frame which reuses a plan looks nothing up by name: names are resolved to
//! slots when a plan is compiled or first bound, and frames index those slots.
//!
//! Invariant: every place in this crate that finds a resource, import or history by comparing
//! or hashing its name calls [`count_name_lookup`] once per lookup. The count is per thread
//! (an executor records on its caller's thread), so tests running side by side do not mix.

use std::cell::Cell;

thread_local! {
    static NAME_LOOKUPS: Cell<u64> = const { Cell::new(0) };
}

/// Records one lookup by name on this thread.
pub(crate) fn count_name_lookup() {
    NAME_LOOKUPS.with(|c| c.set(c.get() + 1));
}

/// Lookups by name this thread's executors and compilers have made so far: the difference
/// across a span of frames is what those frames looked up by name.
pub fn name_lookup_count() -> u64 {
    NAME_LOOKUPS.with(Cell::get)
}
