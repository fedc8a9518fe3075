//! The right-hand side of the ODE (what the integrator calls) must not
//! allocate: a counting global allocator checks it on every example model
//! (chains, loops with constraints, springs, dampers, forces and signal
//! blocks, quaternion and Euler bodies, point gravity).

mod common;

use common::examples::{example_files, example_name, load_example};
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

/// The system allocator, counting the allocations of the threads that ask.
struct Counting;

thread_local! {
    static COUNTING: Cell<bool> = const { Cell::new(false) };
    static ALLOCATIONS: Cell<usize> = const { Cell::new(0) };
}

fn note_allocation() {
    if COUNTING.with(Cell::get) {
        ALLOCATIONS.with(|n| n.set(n.get() + 1));
    }
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        note_allocation();
        System.alloc(layout)
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        note_allocation();
        System.alloc_zeroed(layout)
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        note_allocation();
        System.realloc(ptr, layout, new_size)
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        System.dealloc(ptr, layout)
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

/// How many allocations `f` makes on this thread.
fn allocations_of(f: impl FnOnce()) -> usize {
    ALLOCATIONS.with(|n| n.set(0));
    COUNTING.with(|c| c.set(true));
    f();
    COUNTING.with(|c| c.set(false));
    ALLOCATIONS.with(Cell::get)
}

#[test]
fn the_counter_sees_allocations() {
    assert!(allocations_of(|| drop(std::hint::black_box(vec![1.0f64; 8]))) >= 1);
}

#[test]
fn the_right_hand_side_allocates_nothing() {
    let mut offenders = Vec::new();
    let files = example_files();
    assert!(files.len() >= 12, "the examples folder holds the reference models");
    for path in files {
        let name = example_name(&path);
        let mechanism = load_example(&path).assemble().unwrap();
        let mut ws = mechanism.workspace();
        let mut y = mechanism.states().start.clone();
        let mut dy = vec![0.0; y.len()];
        // From the start and along a short explicit-Euler path, so that
        // velocities, forces and time-dependent inputs are not all zero.
        for step in 0..20 {
            let t = 1e-3 * step as f64;
            let mut result = Ok(());
            let count = allocations_of(|| result = mechanism.rhs(&mut ws, t, &y, &mut dy));
            result.unwrap_or_else(|e| panic!("{name}: rhs failed at t = {t}: {e:?}"));
            if count > 0 {
                offenders.push(format!("{name}: {count} allocations at t = {t}"));
                break;
            }
            for (yi, dyi) in y.iter_mut().zip(&dy) {
                *yi += 1e-3 * dyi;
            }
        }
    }
    assert!(offenders.is_empty(), "the right-hand side allocated:\n{}", offenders.join("\n"));
}

/// A long algebraic loop is factored sparse (its Jacobian has two entries
/// a row), on the layout laid out when it compiled: no allocation either.
#[test]
fn a_long_algebraic_loop_allocates_nothing() {
    let text = "component BigLoop\n  variable x::Real[500]\n  variable v::Real\nrelations\n  \
                x[1] = 0.5 * x[500] + sin(time) * v\n  for i in 2:500\n    x[i] = 0.5 * x[i - 1] + 1\n  end\n  \
                der(v) = -x[500]\nend\n";
    let mut package = multibody_dyad::Package::new();
    package.add_source("loop.dyad", text).unwrap();
    let mechanism = package.lower_component("BigLoop").unwrap().assemble().unwrap();
    let mut ws = mechanism.workspace();
    let y = mechanism.states().start.clone();
    let mut dy = vec![0.0; y.len()];
    for step in 0..20 {
        let t = 0.1 * step as f64;
        let mut result = Ok(());
        let count = allocations_of(|| result = mechanism.rhs(&mut ws, t, &y, &mut dy));
        result.unwrap_or_else(|e| panic!("rhs failed at t = {t}: {e:?}"));
        assert_eq!(count, 0, "{count} allocations at t = {t}");
    }
    // x[500] = 2 + (x[1] - 2) / 2^499 = 2 to rounding, whatever v is.
    assert!((dy[0] + 2.0).abs() < 1e-12, "der(v) = {}", dy[0]);
}
