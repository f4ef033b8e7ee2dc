//! The caster does not allocate per leaf, search or refinement once its
//! per-thread scratch is warm: with several threads, allocations go through
//! the allocator's locks, and a view with many thin-feature searches (rays
//! parallel to a cylinder's wall) used to serialise 2-thread renders there.
//! Its own test binary: it installs a global allocator that counts the
//! allocations of the thread that asks.
#![allow(unsafe_code)]

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

use frep_core::Model;
use frep_render::camera::Projection;
use frep_render::tiles::tiles;
use frep_render::{Aabb, Camera, ModelCaster, TileCaster};

thread_local! {
    static COUNTING: Cell<bool> = const { Cell::new(false) };
    static COUNT: Cell<usize> = const { Cell::new(0) };
}

struct CountingThread;

fn counted() {
    // `try_with`: the thread-locals may be gone while a thread exits.
    if COUNTING.try_with(Cell::get).unwrap_or(false) {
        let _ = COUNT.try_with(|n| n.set(n.get() + 1));
    }
}

// SAFETY: every call is forwarded to the system allocator with the caller's
// pointer and layout; the counters are thread-local cells that never allocate.
unsafe impl GlobalAlloc for CountingThread {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        counted();
        // SAFETY: same contract as ours.
        unsafe { System.alloc(layout) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: `ptr` came from `alloc` or `realloc` above with `layout`.
        unsafe { System.dealloc(ptr, layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        counted();
        // SAFETY: same contract as ours.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static ALLOC: CountingThread = CountingThread;

/// Allocations made by this thread while `f` runs.
fn allocations(f: impl FnOnce()) -> usize {
    COUNT.with(|n| n.set(0));
    COUNTING.with(|c| c.set(true));
    f();
    COUNTING.with(|c| c.set(false));
    COUNT.with(Cell::get)
}

#[test]
fn a_warm_caster_allocates_next_to_nothing_per_tile() {
    let p = format!(
        "{}/../../examples/closed_cylinder.hf",
        env!("CARGO_MANIFEST_DIR")
    );
    let src = std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{p}: {e}"));
    let model = Model::compile(&src).expect("example compiles");
    // Looking down the cylinder's axis: the rays along its wall are the ones
    // that need thin-feature searches.
    let (h, size) = (1.2, 256);
    let cam = Camera::look_at(
        [0.0, 0.0, 3.0 * h],
        [0.0; 3],
        [0.0, 1.0, 0.0],
        Projection::Orthographic { half_extent: h },
    );
    let caster = ModelCaster::new(&model, Default::default(), Aabb::new([-h; 3], [h; 3]));
    let ts = tiles(size, size, 32);
    let mut out = vec![None; 32 * 32];
    let pass = |out: &mut Vec<_>| {
        let mut hits = 0;
        for t in &ts {
            let o = &mut out[..(t.w() * t.h()) as usize];
            o.fill(None);
            caster.cast_tile(&cam, t, o);
            hits += o.iter().filter(|h| h.is_some()).count();
        }
        hits
    };
    let first = pass(&mut out);
    assert!(first > 5_000, "the cap is in view ({first} hits)");
    let searches_before = caster.stats().interval_evals;
    let mut second = 0;
    let n = allocations(|| second = pass(&mut out));
    assert_eq!(first, second, "same hits from a warm caster");
    assert!(
        caster.stats().interval_evals > 2 * searches_before - searches_before / 10,
        "the second pass did the same work"
    );
    // Before the spare buffers: thousands (several per search and per leaf).
    assert!(
        n <= 2 * ts.len(),
        "{n} allocations for {} tiles of a warm caster",
        ts.len()
    );
}
